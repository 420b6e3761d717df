#!/usr/bin/env python3
"""The scripts in tools/ refuse what they cannot use before any run, in one line: a folder or a missing file given
as a binary (a folder passed os.access's test, and the run ended in a traceback), an output in a folder that is
not there (the results were lost to a traceback at the end), a missing scene among several (the runs before it
were thrown away), a number vkrt refuses (convergence_report rendered its reference for minutes first); options after -- that end vkrt before it renders are said to, not a traceback; and the shell
scripts answer --help and refuse what is not an argument of theirs (fuzz_loader.sh --help built for minutes, then
fuzzed with no time limit).

    python_tools_check.py REPOSITORY VKRT
"""
import os
import subprocess
import sys
import tempfile

root, vkrt = sys.argv[1], sys.argv[2]
tools = os.path.join(root, "tools")
cornell = os.path.join(root, "scenes", "cornell.gltf")
failures = []


def check(command, exit_code, phrase):
    run = subprocess.run(command, capture_output=True, text=True, cwd=root, timeout=300)
    output = run.stderr if run.returncode != 0 else run.stdout
    last = output.strip().splitlines()[-1] if output.strip() else ""
    if run.returncode != exit_code or phrase not in output or "Traceback" in run.stderr:
        failures.append(f"{' '.join(command)}: exit {run.returncode} (expected {exit_code}), wanted '{phrase}' in: "
                        f"{last or output}")


def python_tool(name, *arguments):
    return [sys.executable, os.path.join(tools, name), *arguments]


with tempfile.TemporaryDirectory() as folder:
    missing = os.path.join(folder, "no-such-folder", "out.json")
    for name, option in [("device_comparison.py", "--vkrt"), ("convergence_report.py", "--vkrt"),
                         ("specialisation_report.py", "--vkrt")]:
        check(python_tool(name, option, folder, cornell), 2, "is not an executable file")
    check(python_tool("mpi_benchmark.py", "--vkrt", folder), 2, "is not an executable file")
    check(python_tool("compare_builds.py", "--baseline", folder, "--candidate", vkrt, cornell), 2,
          "is not an executable file")
    check(python_tool("benchmark_suite.py", "--ray-benchmark", folder), 2, "is not an executable file")
    check(python_tool("scaling_report.py", "--bvh-benchmark", folder), 2, "is not an executable file")
    check(python_tool("device_comparison.py", "--vkrt", vkrt, "--out", missing, cornell), 2, "no folder")
    check(python_tool("random_scenes.py", "1", missing), 2, "no folder")
    check(python_tool("random_scenes.py", "1", os.path.join(folder, "s.gltf"), "--scale", "0"), 2,
          "--scale must be positive")
    open(os.path.join(folder, "a-file"), "w").close()
    check(python_tool("convergence_report.py", "--vkrt", vkrt, "--out-dir", os.path.join(folder, "a-file"), cornell),
          2, "--out-dir")
    # A number vkrt refuses, before the reference is rendered (minutes at the defaults) and the out-dir made.
    small = ["--width", "8", "--gpu-spp", "1", "--cpu-spp", "1", "--reference-spp", "1"]
    unmade = os.path.join(folder, "unmade")
    for option, value in [("--gpu-spp", "0"), ("--cpu-spp", "0"), ("--reference-spp", str((1 << 24) + 1)),
                          ("--width", "0"), ("--width", "16385")]:
        check(python_tool("convergence_report.py", "--vkrt", vkrt, "--out-dir", unmade, *small, option, value,
                          cornell), 2, f"{option} {value}: must be from 1 to")
    if os.path.exists(unmade):
        failures.append(f"convergence_report.py made {unmade} before refusing its numbers")
    check(python_tool("compare_builds.py", "--baseline", vkrt, "--candidate", vkrt, "--out", missing, cornell), 2,
          "no folder")
    check(python_tool("compare_builds.py", "--baseline", vkrt, "--candidate", vkrt, cornell,
                      os.path.join(folder, "nosuch.gltf")), 2, "nosuch.gltf: no such file")
    check(python_tool("device_comparison.py", "--vkrt", vkrt, "--runs", "1", "--width", "8", "--spp", "1",
                      "--integrators", "path", cornell, "--", "--help"), 1, "rendered nothing")
    check(["bash", os.path.join(tools, "fuzz_loader.sh"), "--help"], 0, "Usage: tools/fuzz_loader.sh")
    check(["bash", os.path.join(tools, "fuzz_loader.sh"), "soon"], 2, "SECONDS must be a whole number")
    check(["bash", os.path.join(tools, "sanitize_check.sh"), "--help"], 0, "Usage: tools/sanitize_check.sh")
    check(["bash", os.path.join(tools, "sanitize_check.sh"), "now"], 2, "takes no arguments")
    check(["bash", os.path.join(tools, "readme_pictures.sh"), "--help"], 0, "tools/readme_pictures.sh [OUT_DIR]")
    check(["bash", os.path.join(tools, "readme_pictures.sh"), "-x"], 2, "unknown option -x")
    check(python_tool("make_scenes.py", os.path.join(folder, "a-file")), 2, "cannot make the folder")

if failures:
    sys.exit("python_tools_check:\n" + "\n".join(failures))
print("python_tools_check: every tool refused what it could not use, in one line")
