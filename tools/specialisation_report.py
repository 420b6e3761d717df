#!/usr/bin/env python3
"""What specialising the GPU shader to the scene gains: the scene's shader against the one with every feature.

    tools/specialisation_report.py [--vkrt build/vkrt] [--runs 3] [--cold-runs 1] [--width 256] [--spp 16]
                                   [--integrators path] [--out FILE.json] [--markdown FILE.md]
                                   SCENE... [-- EXTRA VKRT OPTIONS]

Each scene is rendered with each integrator by `vkrt --shader-features scene` and `--shader-features all`
(the same seed, size and samples). From `vkrt --stats`:

- Cold (`--cold-runs` pairs of renders per distinct shader): vkrt's SPIR-V cache and the driver's shader
  caches (Mesa's MESA_SHADER_CACHE_DIR, NVIDIA's __GL_SHADER_DISK_CACHE_PATH) hold no copy of the shader for
  the first render of a pair and keep what it left for the second. glslang: the first's `shader.compile_ms`
  (GLSL to SPIR-V); pipeline: its `shader.pipeline_ms` (vkCreateComputePipelines, where a driver compiles
  SPIR-V); first-dispatch JIT: its `gpu_ms` less the second's. Cold renders are 8 pixels wide with 1 sample
  (the same shader: its key is checked), so that little else is in those times. lavapipe (llvmpipe) translates SPIR-V when
  the pipeline is made but compiles it with LLVM only when it is first dispatched, and keeps that in Mesa's
  disk cache: the difference is that compilation (about 0 on drivers that compile up front). Scenes whose
  shaders have the same key (`shader.key`; an integrator's all-features shader is the same for every scene)
  share one cold measurement: the renders of an integrator and variant share caches, and a render that
  finds its shader there is not measured cold again.
- Cached (`--runs` renders per configuration, in interleaved rounds, the two shaders in alternating order,
  with the caches the cold renders filled; with `--cold-runs 0`, the environment's caches): reading the
  SPIR-V from the cache plus creating the pipeline, `render_ms` (everything: shader, upload, tracing), the
  rays per second of that whole render (`mrays_per_s`) and of the dispatches alone (`mrays_per_gpu_s`); in
  the JSON also the dispatches' wall time (`dispatch_total_ms`) and the copies of the sums to the host
  (`host_copy_ms`), which with the pipeline's time say where a render's time outside the GPU went, and the
  renderer's making (`renderer_setup_ms`), of which writing the scene's buffers (`scene_write_ms`, on a
  thread beside the shader's making).

Prints a Markdown table of medians ("scene / all" in each cell, and the ratio of rays per second) and
writes every run to the JSON (`--out`), with the machine's load average before and after each round.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

from vkrt_args import check_vkrt_and_scenes, check_writable, integrators_from, parse_with_vkrt_options
from vkrt_runs import summary

VARIANTS = ("scene", "all")
# Cold renders are this small (width, spp): what making a shader costs does not depend on the image, and the
# difference of two small renders' GPU times is the compilation alone, not the noise of a long render.
COLD_SIZE = (8, 1)


def render(args, scene, integrator, variant, extra, folder, caches=None, size=None):
    """vkrt's stats for one render; `size` (width, spp) instead of the report's."""
    width, spp = size or (args.width, args.spp)
    stats = os.path.join(folder, "stats.json")
    command = [args.vkrt, "--scene", scene, "--quiet", "--width", str(width), "--spp", str(spp),
               "--seed", str(args.seed), "--integrator", integrator, "--shader-features", variant,
               "--stats", stats, "--out", os.path.join(folder, "image.pfm")] + extra
    env = dict(os.environ)
    if caches:
        env.update(VKRT_SHADER_CACHE=os.path.join(caches, "vkrt"), MESA_SHADER_CACHE_DIR=os.path.join(caches, "mesa"),
                   __GL_SHADER_DISK_CACHE_PATH=os.path.join(caches, "nvidia"))
        os.makedirs(os.path.join(caches, "nvidia"), exist_ok=True)
    result = subprocess.run(command, capture_output=True, text=True, env=env)
    if result.returncode != 0:
        sys.exit(f"specialisation_report: {' '.join(command)} failed: {result.stderr.strip()}")
    if not os.path.isfile(stats):
        sys.exit(f"specialisation_report: {' '.join(command)} rendered nothing (options after -- such as --help "
                 "end vkrt before it renders)")
    with open(stats) as file:
        data = json.load(file)
    if data.get("device") != "gpu":
        sys.exit("specialisation_report: the report measures GPU shaders; the options after -- asked for the "
                 f"{data.get('device')} device")
    if data.get("shader", {}).get("features") != variant:
        sys.exit(f"specialisation_report: {args.vkrt} does not record --shader-features in its stats")
    return data


def cold(args, scene, integrator, variant, extra, folder, caches):
    """A render with caches that lack its shader, then one with what it left: what making the shader costs.
    None when the caches held the shader already (it was measured with another scene)."""
    first = render(args, scene, integrator, variant, extra, folder, caches, COLD_SIZE)
    if first["shader"]["from_cache"]:
        return first["shader"]["key"], None
    second = render(args, scene, integrator, variant, extra, folder, caches, COLD_SIZE)
    if not second["shader"]["from_cache"]:
        sys.exit("specialisation_report: the shader cache did not keep the shader")
    return first["shader"]["key"], {
        "measured_on": scene, "glslang_ms": first["shader"]["compile_ms"],
        "pipeline_cold_ms": first["shader"]["pipeline_ms"],
        "first_dispatch_jit_ms": first["gpu_ms"] - second["gpu_ms"], "render_cold_ms": first["render_ms"]}


def cached(args, scene, integrator, variant, extra, folder, caches):
    data = render(args, scene, integrator, variant, extra, folder, caches)
    shader = data["shader"]
    return {"key": shader["key"], "features": data["features"], "spirv_bytes": shader["spirv_bytes"],
            "from_cache": shader["from_cache"], "spirv_from_cache_ms": shader["compile_ms"],
            "pipeline_cached_ms": shader["pipeline_ms"],
            "setup_cached_ms": shader["compile_ms"] + shader["pipeline_ms"], "render_ms": data["render_ms"],
            "gpu_ms": data["gpu_ms"], "dispatch_total_ms": data["dispatches"]["total_ms"],
            "host_copy_ms": data["memory"]["host_copy_ms"], "renderer_setup_ms": data["setup"]["total_ms"],
            "scene_write_ms": data["setup"]["scene_write_ms"], "rays": sum(data["rays"].values()),
            "mrays_per_s": data["mrays_per_s"], "mrays_per_gpu_s": data["mrays_per_gpu_s"],
            "device_name": data["device_name"], "driver": data["driver"]}


def markdown(rows):
    lines = ["| scene | integrator | scene's features | SPIR-V KiB | cold: glslang ms | cold: pipeline ms | "
             "cold: first-dispatch JIT ms | cached: SPIR-V read + pipeline ms | render ms | Mrays/s | "
             "Mrays/s, GPU time | Mrays/s: scene / all |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]

    def pair(row, key, scale=1.0, digits=0):
        cells = [row[v].get(key) for v in VARIANTS]
        return " / ".join("%.*f" % (digits, c["median"] * scale) if c else "-" for c in cells)

    for row in rows:
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %.2f |" % (
            os.path.basename(row["file"]), row["integrator"], ", ".join(row["features"]) or "none",
            pair(row, "spirv_bytes", 1 / 1024), pair(row, "glslang_ms"), pair(row, "pipeline_cold_ms"),
            pair(row, "first_dispatch_jit_ms"), pair(row, "setup_cached_ms"), pair(row, "render_ms"),
            pair(row, "mrays_per_s", digits=2), pair(row, "mrays_per_gpu_s", digits=2), row["ratio_mrays_per_s"]))
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vkrt", default="build/vkrt", help="the vkrt binary [build/vkrt]")
    parser.add_argument("--runs", type=int, default=3, help="cached rounds; each renders every configuration once [3]")
    parser.add_argument("--cold-runs", type=int, default=1, help="cold pairs of renders per distinct shader [1]")
    parser.add_argument("--width", type=int, default=256, help="image width [256]")
    parser.add_argument("--spp", type=int, default=16, help="samples per pixel [16]")
    parser.add_argument("--seed", type=int, default=0, help="vkrt's --seed [0]")
    parser.add_argument("--integrators", default="path", help="comma-separated: path, whitted [path]")
    parser.add_argument("--out", help="write every run and the medians here as JSON")
    parser.add_argument("--markdown", help="also write the table here")
    parser.add_argument("scenes", nargs="+", help="glTF scenes; options after -- go to vkrt")
    args, extra = parse_with_vkrt_options(parser)
    if args.cold_runs < 0:
        parser.error("--cold-runs must be at least 0")
    integrators = integrators_from(parser, args.integrators)
    args.vkrt = check_vkrt_and_scenes(parser, args.vkrt, args.scenes)
    check_writable(parser, args.out)

    configurations = [(s, i, v) for s in args.scenes for i in integrators for v in VARIANTS]
    runs = {c: [] for c in configurations}
    colds = {}  # shader key -> its cold measurements
    caches_of = {}  # configuration -> the caches its cold renders filled (none: the environment's)
    loads = []
    with tempfile.TemporaryDirectory() as folder:
        # Cold, once per distinct shader: each integrator's and variant's renders share caches, so a shader
        # that another scene has made already (every all-features one) is found there and not measured again.
        group_caches = {}
        for scene, integrator, variant in configurations if args.cold_runs > 0 else []:
            caches = group_caches.setdefault((integrator, variant), tempfile.mkdtemp(dir=folder))
            key, figures = cold(args, scene, integrator, variant, extra, folder, caches)
            if figures:
                colds[key] = [figures] + [cold(args, scene, integrator, variant, extra, folder,
                                               tempfile.mkdtemp(dir=folder))[1] for _ in range(args.cold_runs - 1)]
            caches_of[(scene, integrator, variant)] = caches
            print(f"specialisation_report: cold {os.path.basename(scene)} {integrator} {variant}: " +
                  (f"glslang {figures['glslang_ms']:.0f} ms, pipeline {figures['pipeline_cold_ms']:.0f} ms, "
                   f"first-dispatch JIT {figures['first_dispatch_jit_ms']:.0f} ms" if figures
                   else "the same shader as before"), file=sys.stderr)
        for round_index in range(args.runs):
            load_before = os.getloadavg()[0]
            for scene, integrator in [(s, i) for s in args.scenes for i in integrators]:
                for variant in VARIANTS if round_index % 2 == 0 else tuple(reversed(VARIANTS)):
                    configuration = (scene, integrator, variant)
                    runs[configuration].append(
                        cached(args, scene, integrator, variant, extra, folder, caches_of.get(configuration)))
            loads.append({"before": load_before, "after": os.getloadavg()[0]})
            print(f"specialisation_report: round {round_index + 1} of {args.runs} done "
                  f"(load average {load_before:.1f} -> {loads[-1]['after']:.1f})", file=sys.stderr)

    cold_keys = ["glslang_ms", "pipeline_cold_ms", "first_dispatch_jit_ms", "render_cold_ms"]
    keys = ["spirv_bytes", "spirv_from_cache_ms", "pipeline_cached_ms", "setup_cached_ms", "render_ms", "gpu_ms",
            "dispatch_total_ms", "host_copy_ms", "renderer_setup_ms", "scene_write_ms", "mrays_per_s",
            "mrays_per_gpu_s"]
    rows = []
    for scene, integrator in [(s, i) for s in args.scenes for i in integrators]:
        row = {"file": scene, "integrator": integrator, "features": runs[(scene, integrator, "scene")][0]["features"]}
        for variant in VARIANTS:
            samples = runs[(scene, integrator, variant)]
            row[variant] = {key: summary([s[key] for s in samples]) for key in keys}
            row[variant]["runs"] = samples
            measured = colds.get(samples[0]["key"], [])
            if measured:
                row[variant].update({key: summary([m[key] for m in measured]) for key in cold_keys})
                row[variant]["cold_runs"] = measured
        row["ratio_mrays_per_s"] = row["scene"]["mrays_per_s"]["median"] / row["all"]["mrays_per_s"]["median"]
        row["ratio_mrays_per_gpu_s"] = (row["scene"]["mrays_per_gpu_s"]["median"] /
                                        row["all"]["mrays_per_gpu_s"]["median"])
        rows.append(row)

    first = rows[0]["scene"]["runs"][0]
    header = (f"Device: {first['device_name']} ({first['driver']}); {args.width} px wide, {args.spp} spp, "
              f"seed {args.seed}; medians of {args.runs} interleaved cached runs, {args.cold_runs} cold per shader; "
              f"load average {min(l['before'] for l in loads):.1f} to {max(l['after'] for l in loads):.1f}")
    table = markdown(rows)
    print(header + "\n\n" + table)
    report = {"vkrt": args.vkrt, "width": args.width, "spp": args.spp, "seed": args.seed, "runs": args.runs,
              "cold_runs": args.cold_runs, "extra_options": extra, "device_name": first["device_name"],
              "driver": first["driver"], "load_average": loads, "results": rows}
    if args.out:
        with open(args.out, "w") as file:
            json.dump(report, file, indent=1)
            file.write("\n")
    if args.markdown:
        with open(args.markdown, "w") as file:
            file.write(header + "\n\n" + table + "\n")


if __name__ == "__main__":
    main()
