"""The command lines of the tools that run vkrt: their own options, then `--` and options passed to vkrt."""


def split_at_double_dash(argv):
    """(the tool's arguments, vkrt's arguments): argv split at its first `--`, which neither keeps."""
    if "--" not in argv:
        return list(argv), []
    at = argv.index("--")
    return argv[:at], argv[at + 1:]
