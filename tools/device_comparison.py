#!/usr/bin/env python3
"""Whole renders on the GPU path against the CPU reference: the same renders on both devices, run in turn.

    tools/device_comparison.py [--vkrt build/vkrt] [--runs 5] [--integrators path,whitted] [--width 256]
                               [--height WIDTH] [--spp 16] [--out FILE.json] SCENE... [-- EXTRA VKRT OPTIONS]

Each scene is rendered with each integrator on the GPU (`--device gpu`) and by the CPU reference (`--device
cpu`), alternately, `--runs` times each after one warm-up render apiece (which fills the shader cache), so
that the machine's drift hits both alike. From `vkrt --stats`: the render time (`render_ms`: everything after
the scene is loaded and its BVH built, pipeline creation included), and on the GPU its timestamped GPU time
and pipeline creation. Prints a Markdown table of medians, with the GPU / CPU ratio of the median render times
from this one run and, beside it, that of the fastest renders (on a machine whose speed drifts between runs,
the fastest is the least disturbed), and writes every run and the medians to the JSON (`--out`).
"""
import argparse
import json
import os
import sys
import tempfile

from vkrt_args import check_vkrt_and_scenes, check_writable, integrators_from, parse_with_vkrt_options
from vkrt_runs import render_stats, summary

DEVICES = ("gpu", "cpu")


def markdown(rows):
    lines = ["| scene | integrator | GPU render ms (GPU time, pipeline) | CPU render ms | GPU / CPU | of the fastest |",
             "|---|---|---|---|---|---|"]
    for row in rows:
        gpu = row["gpu"]
        lines.append(f"| {os.path.basename(row['scene'])} | {row['integrator']} | "
                     f"{gpu['render_ms']['median']:.0f} ({gpu['gpu_ms']['median']:.0f}, "
                     f"{gpu['pipeline_ms']['median']:.0f}) | {row['cpu']['render_ms']['median']:.0f} | "
                     f"{row['ratio_render_ms']:.2f} | {row['ratio_fastest_render_ms']:.2f} |")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vkrt", default="build/vkrt", help="the vkrt binary [build/vkrt]")
    parser.add_argument("--runs", type=int, default=5, help="timed renders per device, scene and integrator [5]")
    parser.add_argument("--integrators", default="path,whitted", help="comma-separated: path, whitted [path,whitted]")
    parser.add_argument("--width", type=int, default=256, help="image width [256]")
    parser.add_argument("--height", type=int, help="image height [the width]")
    parser.add_argument("--spp", type=int, default=16, help="samples per pixel [16]")
    parser.add_argument("--out", help="also write every run and the medians here as JSON")
    parser.add_argument("scenes", nargs="+", help="glTF scenes; options after -- go to vkrt")
    args, extra = parse_with_vkrt_options(parser)
    if args.width < 1 or (args.height is not None and args.height < 1) or args.spp < 1:
        parser.error("--width, --height and --spp must be at least 1")
    integrators = integrators_from(parser, args.integrators)
    args.vkrt = check_vkrt_and_scenes(parser, args.vkrt, args.scenes)
    check_writable(parser, args.out)
    size = ["--width", str(args.width), "--height", str(args.height or args.width), "--spp", str(args.spp)]

    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for scene in args.scenes:
            for integrator in integrators:
                runs = {device: [] for device in DEVICES}
                for run in range(args.runs + 1):
                    for device in DEVICES:
                        command = [args.vkrt, "--scene", scene, "--device", device, "--integrator", integrator]
                        stats = render_stats("device_comparison", command + size + extra, folder)
                        if run > 0:  # the first is the warm-up: shader cache, file cache
                            runs[device].append(stats)
                row = {"scene": scene, "integrator": integrator, "runs": runs}
                for device in DEVICES:
                    keys = ["render_ms"] + (["gpu_ms"] if device == "gpu" else [])
                    row[device] = {key: summary([stats[key] for stats in runs[device]]) for key in keys}
                row["gpu"]["pipeline_ms"] = summary([stats["shader"]["pipeline_ms"] for stats in runs["gpu"]])
                row["ratio_render_ms"] = row["gpu"]["render_ms"]["median"] / row["cpu"]["render_ms"]["median"]
                row["ratio_fastest_render_ms"] = row["gpu"]["render_ms"]["min"] / row["cpu"]["render_ms"]["min"]
                rows.append(row)
                print(f"device_comparison: {os.path.basename(scene)} {integrator}: GPU / CPU "
                      f"{row['ratio_render_ms']:.2f}", file=sys.stderr)

    first = rows[0]["runs"]["gpu"][0]
    print(f"Device: {first['device_name']} ({first['driver']}); {args.width}x{args.height or args.width}, {args.spp} spp; "
          f"medians of {args.runs} alternate rounds after a warm-up\n")
    print(markdown(rows))
    if args.out:
        report = {"vkrt": args.vkrt, "runs": args.runs, "size": size, "extra_options": extra, "results": rows}
        with open(args.out, "w") as file:
            json.dump(report, file, indent=1)


if __name__ == "__main__":
    main()
