"""What the tools that time vkrt share: one render's `--stats`, and the median, minimum and maximum of a series."""
import json
import os
import statistics
import subprocess
import sys


def render_stats(tool, command, folder):
    """vkrt's `--stats` for one quiet render by `command` (the binary and its options), with its files in `folder`.
    A render that fails ends the tool, named `tool`, with vkrt's error."""
    stats = os.path.join(folder, "stats.json")
    full = command + ["--quiet", "--stats", stats, "--out", os.path.join(folder, "image.pfm")]
    result = subprocess.run(full, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{tool}: {' '.join(full)} failed: {result.stderr.strip()}")
    if not os.path.isfile(stats):
        sys.exit(f"{tool}: {' '.join(full)} rendered nothing (options after -- such as --help or --list-devices "
                 "end vkrt before it renders)")
    with open(stats) as file:
        return json.load(file)


def summary(values):
    return {"median": statistics.median(values), "min": min(values), "max": max(values)}
