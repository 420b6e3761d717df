#!/usr/bin/env python3
"""One render in one process against the same render shared by MPI ranks, each single-threaded.

    tools/mpi_benchmark.py --vkrt build/vkrt [--ranks 2] [--runs 5] [--device cpu] [--out FILE.json]
                           [SCENE] [-- EXTRA VKRT OPTIONS]

The scene (default scenes/cornell.gltf, 128 x 128, 64 spp, path traced) is rendered by one vkrt process with
`--threads 1` and by `mpirun -np RANKS vkrt --threads 1`, alternately, `--runs` times each after one warm-up
run apiece. Prints JSON: the medians, minima and maxima of the render time (`render_ms` of `--stats`: from the
renderer's set-up, for the ranks rank 0's, to the sums reduced on rank 0), of the whole command's wall time (loading, the
BVH and, under mpirun, the launch included) and of its CPU time (every process's, the launcher's too), and the
ratios of the medians, ranks over one process: with N ranks on N free cores the render's ratio approaches 1/N,
and the CPU time's ratio stays near 1 (what sharing costs). On a busy machine the first says little, the
second still something.
"""
import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

from vkrt_args import check_scenes, check_writable, executable_file, given_options, parse_with_vkrt_options
from vkrt_runs import summary

DEFAULT_SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "cornell.gltf")
DEFAULT_RENDER = ["--width", "128", "--height", "128", "--spp", "64"]


def mpirun_prefix(ranks):
    """The launcher's command: Open MPI needs two variables to run as root and --oversubscribe beyond the cores."""
    version = subprocess.run(["mpirun", "--version"], capture_output=True, text=True).stdout
    if "Open MPI" in version:
        return ["mpirun", "--oversubscribe", "--bind-to", "core:overload-allowed", "-np", str(ranks)], {
            "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
    return ["mpirun", "-np", str(ranks)], {}


def run(command, environment, folder, core=None):
    stats = os.path.join(folder, "stats.json")
    full = command + ["--quiet", "--stats", stats, "--out", os.path.join(folder, "image.pfm")]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    pin = (lambda: os.sched_setaffinity(0, {core})) if core is not None else None
    result = subprocess.run(full, capture_output=True, text=True, env={**os.environ, **environment}, preexec_fn=pin)
    wall_ms = (time.perf_counter() - start) * 1000.0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_ms = ((after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)) * 1000.0
    if result.returncode != 0:
        sys.exit(f"mpi_benchmark: {' '.join(full)} failed: {result.stderr.strip()}")
    with open(stats) as file:
        return json.load(file), wall_ms, cpu_ms


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vkrt", required=True, help="the vkrt binary (built with MPI)")
    parser.add_argument("--ranks", type=int, default=2, help="MPI ranks [2]")
    parser.add_argument("--runs", type=int, default=5, help="timed runs of each [5]")
    parser.add_argument("--device", default="cpu", choices=["cpu", "gpu"], help="[cpu]")
    parser.add_argument("--out", help="also write the JSON here")
    parser.add_argument("scene", nargs="?", default=DEFAULT_SCENE, help="glTF scene; options after -- go to vkrt")
    args, extra = parse_with_vkrt_options(parser)
    if args.ranks < 2:
        parser.error("--ranks must be at least 2")
    args.vkrt = executable_file(parser, args.vkrt)
    check_scenes(parser, [args.scene])
    check_writable(parser, args.out)
    if shutil.which("mpirun") is None:
        parser.error("mpirun is not installed (Debian: openmpi-bin)")
    # The default size and samples, except where the options after -- give their own.
    defaults = [DEFAULT_RENDER[i:i + 2] for i in range(0, len(DEFAULT_RENDER), 2)]
    render = [args.vkrt, "--scene", args.scene, "--device", args.device, "--threads", "1"] + \
        [word for option in defaults if option[0] not in given_options(extra) for word in option] + extra
    launcher, environment = mpirun_prefix(args.ranks)

    # Open MPI binds each rank to a core; the one process is pinned to a core too, or the scheduler's moving it
    # between cores makes its time vary by a third (2.4 to 3.3 s measured on a quiet 2-core machine).
    core = min(os.sched_getaffinity(0))
    times = {name: {"render": [], "wall": [], "cpu": []} for name in ("one", "ranks")}
    with tempfile.TemporaryDirectory() as folder:
        run(render, {}, folder, core)  # warm-up: caches, the shader cache on the GPU
        stats, _, _ = run(launcher + render, environment, folder)
        if stats.get("ranks") != args.ranks:
            sys.exit(f"mpi_benchmark: {args.vkrt} did not share the render among {args.ranks} ranks "
                     "(built without MPI?)")
        for _ in range(args.runs):
            for name, command, env, pin in (("one", render, {}, core), ("ranks", launcher + render, environment, None)):
                stats, wall_ms, cpu_ms = run(command, env, folder, pin)
                times[name]["render"].append(stats["render_ms"])
                times[name]["wall"].append(wall_ms)
                times[name]["cpu"].append(cpu_ms)

    result = {
        "scene": os.path.relpath(args.scene),
        "device": args.device,
        "vkrt_options": render[1:],
        "ranks": args.ranks,
        "runs": args.runs,
        "one_process_core": core,
        "one_process": {key + "_ms": summary(times["one"][key]) for key in ("render", "wall", "cpu")},
        "shared": {key + "_ms": summary(times["ranks"][key]) for key in ("render", "wall", "cpu")},
        "load_average": os.getloadavg()[0],
    }
    result["render_ratio"] = result["shared"]["render_ms"]["median"] / result["one_process"]["render_ms"]["median"]
    result["wall_ratio"] = result["shared"]["wall_ms"]["median"] / result["one_process"]["wall_ms"]["median"]
    result["cpu_ratio"] = result["shared"]["cpu_ms"]["median"] / result["one_process"]["cpu_ms"]["median"]
    text = json.dumps(result, indent=2)
    print(text)
    if args.out:
        with open(args.out, "w") as file:
            file.write(text + "\n")


if __name__ == "__main__":
    main()
