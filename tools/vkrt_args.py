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


def executable_file(parser, path):
    """`path` made absolute, or a usage error unless it names an executable file. A folder passed os.access's
    test and failed later with a traceback; a bare name (`vkrt`) is the file in the current folder, as the
    check read it, not one found on PATH."""
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        parser.error(f"{path} is not an executable file")
    return os.path.abspath(path)


def check_scenes(parser, scenes):
    """A usage error unless every scene is a file: checked before any run, so none is wasted."""
    for scene in scenes:
        if not os.path.isfile(scene):
            parser.error(f"{scene}: no such file")


def check_writable(parser, path, option="--out"):
    """A usage error unless a file can be written at `path` (None: not asked for): its folder exists and takes
    files, and it is not a folder itself. Checked before any run, whose results were lost to a traceback when the
    output could not be written at the end."""
    if path is None:
        return
    folder = os.path.dirname(os.path.abspath(path))
    if os.path.isdir(path):
        parser.error(f"{option} {path}: is a folder")
    if not os.path.isdir(folder):
        parser.error(f"{option} {path}: no folder {folder}")
    if not os.access(folder, os.W_OK):
        parser.error(f"{option} {path}: the folder {folder} cannot be written")


# vkrt's own limits on --width (and --height) and --spp (host/app/options.cpp).
MAX_IMAGE_SIDE = 16384
MAX_SPP = 1 << 24


def check_range(parser, option, value, low, high):
    """A usage error unless low <= value <= high: a number vkrt would refuse, checked before any run, so that no
    run before the one given it is wasted (convergence_report rendered its reference for minutes first)."""
    if not low <= value <= high:
        parser.error(f"{option} {value}: must be from {low} to {high}")


def check_vkrt_and_scenes(parser, vkrt, scenes):
    """`vkrt` made absolute, or a usage error unless it is an executable file and every scene is a file."""
    vkrt = executable_file(parser, vkrt)
    check_scenes(parser, scenes)
    return vkrt
