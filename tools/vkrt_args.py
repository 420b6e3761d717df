"""The command lines of the tools that run vkrt: their own options, then `--` and options passed to vkrt."""
import os
import sys


def split_at_double_dash(argv):
    """(the tool's arguments, vkrt's arguments): argv split at its first `--`, which neither keeps."""
    if "--" not in argv:
        return list(argv), []
    at = argv.index("--")
    return argv[:at], argv[at + 1:]


def parse_with_vkrt_options(parser):
    """(the tool's arguments parsed, vkrt's arguments): the command line split at `--`; a usage error unless the
    tool's `--runs` is at least 1."""
    argv, extra = split_at_double_dash(sys.argv[1:])
    args = parser.parse_args(argv)
    if args.runs < 1:
        parser.error("--runs must be at least 1")
    return args, extra


def given_options(extra):
    """The option names among vkrt's arguments, whether written `--name value` or `--name=value`."""
    return {word.split("=", 1)[0] for word in extra if word.startswith("--")}


def integrators_from(parser, text):
    """The integrators that a comma-separated `--integrators` value names; a usage error unless each is path or
    whitted."""
    integrators = [i for i in text.split(",") if i]
    if not integrators or any(i not in ("path", "whitted") for i in integrators):
        parser.error("--integrators takes path, whitted or path,whitted")
    return integrators


def check_vkrt_and_scenes(parser, vkrt, scenes):
    """A usage error unless `vkrt` is an executable and every scene is a file."""
    if not os.access(vkrt, os.X_OK):
        parser.error(f"{vkrt} is not an executable")
    for scene in scenes:
        if not os.path.exists(scene):
            parser.error(f"{scene}: no such file")
