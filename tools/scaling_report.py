#!/usr/bin/env python3
"""Scaling against triangle count, beside Embree: BVH build time and rays per second on procedural UV spheres
of 100k, 1M, 2M and 5M triangles. Runs build/bvh_benchmark (vkrt's build and Embree's medium-quality build of
the same triangles on the same threads, interleaved) and build/ray_benchmark (camera, shadow and diffuse
rays through vkrt's GPU traversal and through Embree) on each size, writes all results to one JSON file and
prints a Markdown table: medians over runs, ratios from the same run.

Usage: tools/scaling_report.py [--triangles 100000,1000000,2000000,5000000] [--threads 2] [--build-runs 3]
                               [--runs 3] [--size 256] [--out scaling.json]
"""

import argparse
import json
import os
import subprocess
import sys

from vkrt_args import check_writable, executable_file


def run_json(command):
    output = subprocess.run(command, stdout=subprocess.PIPE, text=True)
    if output.returncode != 0:
        sys.exit("scaling_report: %s failed (exit %d)" % (" ".join(command), output.returncode))
    return json.loads(output.stdout)


def positive_list(text):
    values = [int(v) for v in text.split(",") if v]
    if not values or min(values) < 1:
        raise argparse.ArgumentTypeError("a comma-separated list of positive triangle counts")
    return values


def positive(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError("must be at least 1")
    return value


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bvh-benchmark", default="build/bvh_benchmark")
    parser.add_argument("--ray-benchmark", default="build/ray_benchmark")
    parser.add_argument("--triangles", type=positive_list, default=[100_000, 1_000_000, 2_000_000, 5_000_000],
                        help="sphere sizes, comma-separated (default: 100000,1000000,2000000,5000000)")
    parser.add_argument("--threads", type=int, default=2, help="build threads, vkrt's and Embree's (default 2)")
    parser.add_argument("--build-runs", type=positive, default=3, help="builds timed per size (default 3)")
    parser.add_argument("--runs", type=positive, default=3, help="traces per ray kind (default 3)")
    parser.add_argument("--size", type=positive, default=256, help="camera rays across and down (default 256)")
    parser.add_argument("--embree", default="medium", choices=["low", "medium", "high"],
                        help="Embree build quality to compare with (default medium)")
    parser.add_argument("--out", default="scaling.json")
    args = parser.parse_args()
    args.bvh_benchmark = executable_file(parser, args.bvh_benchmark)
    args.ray_benchmark = executable_file(parser, args.ray_benchmark)
    check_writable(parser, args.out)

    results = []
    for n in args.triangles:
        build = run_json([args.bvh_benchmark, "--triangles", str(n), "--runs", str(args.build_runs), "--threads",
                          str(args.threads), "--embree", args.embree])
        rays = run_json([args.ray_benchmark, "--triangles", str(n), "--runs", str(args.runs), "--width",
                         str(args.size), "--height", str(args.size)])
        results.append({"triangles": n, "build": build, "rays": rays})
        print("scaling_report: %d triangles done" % n, file=sys.stderr)
    with open(args.out, "w") as f:
        json.dump(results, f, indent=1)

    rays0 = results[0]["rays"]
    print("Device: %s (%s); host threads: %d; build threads: %d; Embree %s build; %dx%d camera rays" % (
        rays0["device"], rays0["driver"], rays0["host_threads"], args.threads, args.embree, args.size, args.size))
    print()
    # The builds time a bare UV sphere (bvh_benchmark); the rays are traced over ray_benchmark's sphere over a
    # ground quad of about as many triangles: both counts are given.
    print("| triangles (build / rays) | vkrt build ms | Embree build ms | vkrt / Embree (wall, CPU) | ray kind | "
          "vkrt Mrays/s | Embree Mrays/s | vkrt / Embree |")
    print("|---|---|---|---|---|---|---|---|")
    for r in results:
        build = r["build"]
        embree = build.get("embree", {}).get(args.embree)
        first = True
        for kind, k in r["rays"]["kinds"].items():
            e = k.get("embree_mrays_per_s")
            if first:
                build_cells = "%d / %d | %.0f | %s | %s" % (
                    build["triangles"], r["rays"]["triangles"], build["from_triangles_ms"]["median"],
                    "%.0f" % embree["build_ms"]["median"] if embree else "-",
                    "%.2f, %.2f" % (embree["vkrt_over_embree"], embree["vkrt_over_embree_cpu"]) if embree else "-")
            else:
                build_cells = " | | | "
            first = False
            print("| %s | %s | %.2f | %s | %s |" % (
                build_cells, kind, k["mrays_per_s"]["median"], "%.2f" % e["median"] if e else "-",
                "%.3f" % k["vkrt_over_embree"] if e else "-"))


if __name__ == "__main__":
    main()
