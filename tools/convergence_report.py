#!/usr/bin/env python3
"""Error against run time for vkrt's scenes and integrators: per scene and integrator, renders a reference
with the CPU reference renderer (the double-precision oracle), then renders progressively on the GPU and on
the CPU with `vkrt --reference ... --report ...`, and writes a CSV of every checkpoint and a log-log SVG plot
of RMSE against render time with the fitted slopes, plus a Markdown table of the error at fixed times and the
time to reach an RMSE of 0.01 (stdout and table.md). Monte Carlo noise falls as time^-1/2; stratified
sampling can do better.

Usage: tools/convergence_report.py [--vkrt build/vkrt] [--out-dir DIR] [--width W] [--gpu-spp N]
                                   [--cpu-spp N] [--reference-spp N] [--integrators path,whitted]
                                   SCENE.gltf...
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys
from xml.sax.saxutils import escape

from vkrt_args import MAX_IMAGE_SIDE, MAX_SPP, check_range, check_vkrt_and_scenes, integrators_from

COLORS = {"gpu": "#1f77b4", "cpu": "#d62728"}


def run(command):
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        sys.exit("convergence_report: %s failed:\n%s" % (" ".join(command), result.stderr))


def read_report(path):
    """The report's checkpoints; a field vkrt leaves empty (the CPU's GPU time) is None."""
    with open(path) as f:
        return [{k: float(v) if v != "" else None for k, v in row.items()} for row in csv.DictReader(f)]


def fit_slope(points):
    """Least-squares slope of log(rmse) against log(render time), skipping the first samples."""
    usable = [p for p in points if p["samples"] >= 4 and p["render_ms"] > 0 and p["rmse"] > 0]
    if len(usable) < 2:
        return float("nan")
    xs = [math.log(p["render_ms"]) for p in usable]
    ys = [math.log(p["rmse"]) for p in usable]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


def positive(points):
    """The checkpoints a log-log axis can hold: error and time above 0 (an exact image has RMSE 0)."""
    return [p for p in points if p["rmse"] > 0 and p["render_ms"] > 0]


def error_at(points, milliseconds):
    """RMSE at a given render time, interpolated in log-log between checkpoints (None outside them)."""
    points = positive(points)
    for a, b in zip(points, points[1:]):
        if a["render_ms"] <= milliseconds <= b["render_ms"]:
            t = (math.log(milliseconds) - math.log(a["render_ms"])) / (math.log(b["render_ms"]) - math.log(a["render_ms"]))
            return math.exp(math.log(a["rmse"]) + t * (math.log(b["rmse"]) - math.log(a["rmse"])))
    return None


def time_to(points, rmse):
    """Render time at which the error first falls to `rmse`, interpolated in log-log (None if it never does)."""
    if points and points[0]["rmse"] <= rmse:
        return points[0]["render_ms"]
    points = positive(points)
    for a, b in zip(points, points[1:]):
        if a["rmse"] > rmse >= b["rmse"] and a["render_ms"] > 0:
            t = (math.log(rmse) - math.log(a["rmse"])) / (math.log(b["rmse"]) - math.log(a["rmse"]))
            return math.exp(math.log(a["render_ms"]) + t * (math.log(b["render_ms"]) - math.log(a["render_ms"])))
    if points and points[0]["rmse"] <= rmse:
        return points[0]["render_ms"]
    return None


def output_name(stem, integrator):
    """The name of a scene's outputs under an integrator: Whitted keeps the names the report had before paths
    existed."""
    return stem if integrator == "whitted" else stem + "-path"


def unique_stems(scenes, integrators):
    """Each scene's file name without its extension, with -2, -3, ... where an output name it would have under
    one of `integrators` was met before: two scenes of one stem (glTF/X.gltf and glTF-Binary/X.glb), or X's path
    outputs and X-path's Whitted ones. One scene's outputs would overwrite another's. Each output's file name
    ends with one of a few suffixes none of which ends another, so distinct names make distinct files."""
    stems, taken = [], set()
    for scene in scenes:
        stem = os.path.splitext(os.path.basename(scene))[0]
        name, n = stem, 1
        while any(output_name(name, i) in taken for i in integrators):  # a/X, b/X and X-2: X, X-2 and X-2-2
            n += 1
            name = "%s-%d" % (stem, n)
        taken.update(output_name(name, i) for i in integrators)
        stems.append(name)
    return stems


def svg_plot(path, title, series):
    """A log-log plot of RMSE against render time, one polyline per device, in plain SVG."""
    title = escape(title)  # a scene's name may hold & or <
    width, height, left, right, top, bottom = 640, 420, 70, 20, 40, 50
    points = [p for _, pts, _ in series for p in positive(pts)]
    if not points:  # every error 0 (the image is exact): nothing a log axis can show
        with open(path, "w") as f:
            f.write('<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d"><text x="20" y="40">%s: '
                    'every checkpoint has RMSE 0</text></svg>\n' % (width, height, title))
        return
    x0 = math.floor(math.log10(min(p["render_ms"] for p in points)))
    x1 = math.ceil(math.log10(max(p["render_ms"] for p in points)))
    y0 = math.floor(math.log10(min(p["rmse"] for p in points)))
    y1 = math.ceil(math.log10(max(p["rmse"] for p in points)))
    x1, y1 = max(x1, x0 + 1), max(y1, y0 + 1)

    def px(ms):
        return left + (math.log10(ms) - x0) / (x1 - x0) * (width - left - right)

    def py(e):
        return height - bottom - (math.log10(e) - y0) / (y1 - y0) * (height - top - bottom)

    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">'
           % (width, height), '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="22" font-size="15">%s</text>' % (left, title)]
    for d in range(x0, x1 + 1):
        x = px(10 ** d)
        out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>' % (x, top, x, height - bottom))
        out.append('<text x="%.1f" y="%d" text-anchor="middle">10<tspan dy="-6" font-size="9">%d</tspan></text>'
                   % (x, height - bottom + 18, d))
    for d in range(y0, y1 + 1):
        y = py(10 ** d)
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (left, y, width - right, y))
        out.append('<text x="%d" y="%.1f" text-anchor="end">10<tspan dy="-6" font-size="9">%d</tspan></text>'
                   % (left - 8, y + 4, d))
    out.append('<text x="%d" y="%d" text-anchor="middle">render time (ms)</text>' % ((left + width - right) // 2, height - 10))
    out.append('<text x="16" y="%d" transform="rotate(-90 16 %d)" text-anchor="middle">RMSE against the reference</text>'
               % ((top + height - bottom) // 2, (top + height - bottom) // 2))
    for i, (name, pts, slope) in enumerate(series):
        coords = " ".join("%.1f,%.1f" % (px(p["render_ms"]), py(p["rmse"])) for p in positive(pts))
        out.append('<polyline points="%s" fill="none" stroke="%s" stroke-width="2"/>' % (coords, COLORS[name]))
        for p in positive(pts):  # a log axis has no place for an exact image's 0
            out.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"/>' % (px(p["render_ms"]), py(p["rmse"]), COLORS[name]))
        out.append('<text x="%d" y="%d" fill="%s">%s: slope %s</text>' % (
            width - right - 170, top + 20 + 18 * i, COLORS[name], name.upper(),
            "%.2f" % slope if math.isfinite(slope) else "-"))
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--vkrt", default="build/vkrt")
    parser.add_argument("--out-dir", default="convergence")
    parser.add_argument("--width", type=int, default=256)
    parser.add_argument("--gpu-spp", type=int, default=256)
    parser.add_argument("--cpu-spp", type=int, default=64)
    parser.add_argument("--reference-spp", type=int, default=1024)
    parser.add_argument("--integrators", default="path,whitted",
                        help="comma-separated: path, whitted (each has its own reference and plot)")
    args = parser.parse_args()
    integrators = integrators_from(parser, args.integrators)
    check_range(parser, "--width", args.width, 1, MAX_IMAGE_SIDE)
    for option, spp in (("--gpu-spp", args.gpu_spp), ("--cpu-spp", args.cpu_spp),
                        ("--reference-spp", args.reference_spp)):
        check_range(parser, option, spp, 1, MAX_SPP)
    args.vkrt = check_vkrt_and_scenes(parser, args.vkrt, args.scenes)
    try:
        os.makedirs(args.out_dir, exist_ok=True)
    except OSError as error:  # a file of that name, or a folder that cannot take one
        parser.error(f"--out-dir {args.out_dir}: {error.strerror}")

    times = [100, 1000]
    target = 0.01
    table = ["| scene | integrator | device | slope | " + " | ".join("RMSE at %d ms" % t for t in times) +
             " | ms to RMSE %g |" % target,
             "|---|---|---|---|" + "---|" * (len(times) + 1)]
    summary = {}
    stems = unique_stems(args.scenes, integrators)
    for index, integrator in [(k, i) for k in range(len(args.scenes)) for i in integrators]:
        scene, stem = args.scenes[index], stems[index]
        name = output_name(stem, integrator)
        common = [args.vkrt, "--scene", scene, "--quiet", "--width", str(args.width), "--integrator", integrator]
        reference = os.path.join(args.out_dir, name + "-reference.exr")
        run(common + ["--device", "cpu", "--spp", str(args.reference_spp), "--seed", "1000", "--out", reference])
        # One untimed GPU render first fills the shader caches (vkrt's SPIR-V, the driver's compiled code), as
        # tools/device_comparison.py's warm-up does: the timed render's set-up is then what a user sees from the
        # second render of a scene on (the first compile of glossy.gltf's kernel took 1.4 s on lavapipe).
        warm_up = os.path.join(args.out_dir, name + "-warm-up.exr")
        run(common + ["--device", "gpu", "--spp", "1", "--out", warm_up])
        os.remove(warm_up)
        series = []
        for device, spp in (("gpu", args.gpu_spp), ("cpu", args.cpu_spp)):
            report = os.path.join(args.out_dir, "%s-%s.csv" % (name, device))
            run(common + ["--device", device, "--spp", str(spp), "--reference", reference, "--report", report,
                          "--out", os.path.join(args.out_dir, "%s-%s.exr" % (name, device))])
            points = read_report(report)
            slope = fit_slope(points)
            series.append((device, points, slope))
            errors = [error_at(points, t) for t in times]
            reached = time_to(points, target)
            # No slope where fewer than two checkpoints have an error above 0: "-" here, null in the JSON.
            finite = math.isfinite(slope)
            table.append("| %s | %s | %s | %s | %s | %s |" % (
                stem, integrator, device, "%.2f" % slope if finite else "-", " | ".join("%.4g" % e if e is not None else "-" for e in errors),
                "%.0f" % reached if reached is not None else "-"))
            summary.setdefault(name, {})[device] = {"slope": slope if finite else None, "integrator": integrator,
                                                    "ms_to_rmse_%g" % target: reached, "checkpoints": points}
        svg_plot(os.path.join(args.out_dir, name + ".svg"),
                 "%s, %s, %d px wide: error against render time" % (stem, integrator, args.width), series)
    with open(os.path.join(args.out_dir, "table.md"), "w") as f:
        f.write("\n".join(table) + "\n")
    with open(os.path.join(args.out_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    print("\n".join(table))


if __name__ == "__main__":
    main()
