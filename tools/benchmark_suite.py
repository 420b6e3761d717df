#!/usr/bin/env python3
"""The standard ray benchmark set: procedural spheres of 100k, 1M and 2M triangles over a ground quad, and
real models when present (2CylinderEngine from Debian's assimp-testmodels, the Cornell box). Runs
build/ray_benchmark on each, writes all results to one JSON file and prints a Markdown table with vkrt and
Embree (when ray_benchmark was built with it) side by side: medians over runs, ratios from the same run.

Usage: tools/benchmark_suite.py [--ray-benchmark build/ray_benchmark] [--runs 5] [--size 1024] [--out FILE]
                                [--model FILE]...
"""

import argparse
import json
import os
import subprocess
import sys
import time

from vkrt_args import check_writable, executable_file

# The Cornell box is the repository's, wherever the suite is run from.
MODELS = ["/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
          os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "cornell.gltf")]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ray-benchmark", default="build/ray_benchmark")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--out", default="benchmark.json")
    parser.add_argument("--model", action="append",
                        help="a glTF model to trace, in place of the default ones (2CylinderEngine where Debian's "
                             "assimp-testmodels put it, the Cornell box); repeatable")
    args = parser.parse_args()
    args.ray_benchmark = executable_file(parser, args.ray_benchmark)
    check_writable(parser, args.out)

    inputs = [["--triangles", str(n)] for n in (100_000, 1_000_000, 2_000_000)]
    for m in args.model or []:
        if not os.path.exists(m):
            parser.error("no such model: %s" % m)
    for m in MODELS if not args.model else []:
        if not os.path.exists(m):
            print("benchmark_suite: note: %s is missing (Debian: assimp-testmodels); left out" % m, file=sys.stderr)
    inputs += [["--scene", m] for m in (args.model or MODELS) if os.path.exists(m)]
    results = []
    for extra in inputs:
        command = [args.ray_benchmark, "--runs", str(args.runs), "--width", str(args.size), "--height", str(args.size)]
        started = time.time()
        output = subprocess.run(command + extra, stdout=subprocess.PIPE, text=True)
        if output.returncode != 0:
            sys.exit("benchmark_suite: %s failed" % " ".join(command + extra))
        # When each input ran (Unix seconds), to set beside a log of the GPU's clocks (gpu_check.sh).
        results.append({**json.loads(output.stdout), "started_unix_s": round(started, 3),
                        "finished_unix_s": round(time.time(), 3)})
    with open(args.out, "w") as f:
        json.dump(results, f, indent=1)

    print("Device: %s (%s); host threads: %d" % (results[0]["device"], results[0]["driver"], results[0]["host_threads"]))
    print()
    print("| input | triangles | BVH build ms | SAH cost | ray kind | vkrt Mrays/s (min-max) | Embree Mrays/s | vkrt / Embree |")
    print("|---|---|---|---|---|---|---|---|")
    for r in results:
        for kind, k in r["kinds"].items():
            if not k["rays"]:  # no camera ray hit anything, so there were none of this kind
                print("| %s | %d | %.0f | %.2f | %s | no rays | - | - |" % (
                    os.path.basename(r["input"]), r["triangles"], r["bvh"]["build_ms"], r["bvh"]["sah_cost"], kind))
                continue
            v = k["mrays_per_s"]
            e = k.get("embree_mrays_per_s")
            print("| %s | %d | %.0f | %.2f | %s | %.2f (%.2f-%.2f) | %s | %s |" % (
                os.path.basename(r["input"]), r["triangles"], r["bvh"]["build_ms"], r["bvh"]["sah_cost"], kind,
                v["median"], v["min"], v["max"], "%.2f" % e["median"] if e else "-",
                "%.3f" % k["vkrt_over_embree"] if e else "-"))


if __name__ == "__main__":
    main()
