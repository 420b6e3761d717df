#!/usr/bin/env python3
"""Render speed of two vkrt builds, run alternately so that machine noise hits both alike.

    tools/compare_builds.py --baseline OLD/vkrt --candidate build/vkrt [--runs 5] [--devices gpu,cpu]
                            [--out FILE.json] SCENE... [-- EXTRA VKRT OPTIONS]

Each scene is rendered on each device by the baseline and the candidate in turn, `--runs` times each after
one warm-up run apiece (which fills the shader cache). Prints JSON: per scene and device, the medians,
minima and maxima of the render time (`render_ms` of `vkrt --stats`, the shader's compilation excluded when
it comes from the cache) and, on the GPU, of the timestamped GPU time, and the candidate/baseline ratio of
the medians from this one run.
"""
import argparse
import json
import os
import sys
import tempfile

from vkrt_args import check_scenes, check_writable, executable_file, parse_with_vkrt_options
from vkrt_runs import render_stats, summary


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", required=True, help="the vkrt binary to compare against")
    parser.add_argument("--candidate", required=True, help="the vkrt binary under test")
    parser.add_argument("--runs", type=int, default=5, help="timed runs per build, scene and device [5]")
    parser.add_argument("--devices", default="gpu,cpu", help="comma-separated: gpu, cpu [gpu,cpu]")
    parser.add_argument("--out", help="also write the JSON here")
    parser.add_argument("scenes", nargs="+", help="glTF scenes; options after -- go to vkrt")
    args, extra = parse_with_vkrt_options(parser)
    args.devices = args.devices.split(",")
    if not args.devices or any(device not in ("gpu", "cpu") for device in args.devices):
        parser.error("--devices takes gpu, cpu or gpu,cpu")
    args.baseline = executable_file(parser, args.baseline)
    args.candidate = executable_file(parser, args.candidate)
    check_scenes(parser, args.scenes)
    check_writable(parser, args.out)

    results = []
    with tempfile.TemporaryDirectory() as folder:
        for scene in args.scenes:
            for device in args.devices:
                times = {"baseline": [], "candidate": []}
                gpu_times = {"baseline": [], "candidate": []}
                for run in range(args.runs + 1):
                    for name in ("baseline", "candidate"):
                        stats = render_stats("compare_builds", [getattr(args, name), "--scene", scene, "--device", device] + extra,
                                             folder)
                        if run == 0:
                            continue  # warm-up: shader cache, file cache
                        times[name].append(stats["render_ms"])
                        if "gpu_ms" in stats:
                            gpu_times[name].append(stats["gpu_ms"])
                row = {"scene": scene, "device": device, "runs": args.runs,
                       "render_ms": {name: summary(values) for name, values in times.items()}}
                row["ratio_render_ms"] = (row["render_ms"]["candidate"]["median"] /
                                          row["render_ms"]["baseline"]["median"])
                if gpu_times["baseline"] and gpu_times["candidate"]:
                    row["gpu_ms"] = {name: summary(values) for name, values in gpu_times.items()}
                    row["ratio_gpu_ms"] = row["gpu_ms"]["candidate"]["median"] / row["gpu_ms"]["baseline"]["median"]
                results.append(row)
                print(f"{os.path.basename(scene)} {device}: baseline {row['render_ms']['baseline']['median']:.0f} ms, "
                      f"candidate {row['render_ms']['candidate']['median']:.0f} ms, "
                      f"ratio {row['ratio_render_ms']:.3f}", file=sys.stderr)
    report = {"baseline": args.baseline, "candidate": args.candidate, "extra_options": extra, "results": results}
    text = json.dumps(report, indent=2)
    print(text)
    if args.out:
        with open(args.out, "w") as file:
            file.write(text + "\n")


if __name__ == "__main__":
    main()
