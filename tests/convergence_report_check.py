#!/usr/bin/env python3
"""Runs tools/convergence_report.py on one scene at a small size and checks what it writes for both
integrators: a CSV per device, an SVG plot, a table, and error that falls with render time on both devices."""

import json
import os
import subprocess
import sys
import tempfile
from xml.etree import ElementTree

tool, vkrt, scene = sys.argv[1:4]
with tempfile.TemporaryDirectory() as out:
    subprocess.run([sys.executable, tool, "--vkrt", vkrt, "--out-dir", out, "--width", "32", "--gpu-spp", "64",
                    "--cpu-spp", "64", "--reference-spp", "1024", scene], check=True, stdout=subprocess.DEVNULL)
    stem = os.path.splitext(os.path.basename(scene))[0]
    table = open(os.path.join(out, "table.md")).read()
    for name, integrator in ((stem + "-path", "path"), (stem, "whitted")):
        for file in (name + ".svg", name + "-gpu.csv", name + "-cpu.csv", "table.md", "summary.json"):
            assert os.path.getsize(os.path.join(out, file)) > 0, file
        with open(os.path.join(out, name + ".svg")) as f:
            assert f.read().startswith("<svg"), "not an SVG"
        assert "| %s | %s | gpu |" % (stem, integrator) in table, table
        summary = json.load(open(os.path.join(out, "summary.json")))[name]
        for device in ("gpu", "cpu"):
            assert summary[device]["integrator"] == integrator, summary[device]["integrator"]
            points = summary[device]["checkpoints"]
            assert len(points) == 7, (device, len(points))
            assert points[-1]["rmse"] < 0.25 * points[0]["rmse"], (device, points[0]["rmse"], points[-1]["rmse"])
            assert summary[device]["slope"] < -0.2, (device, summary[device]["slope"])
        print("convergence report, %s: slopes gpu %.2f, cpu %.2f" % (integrator, summary["gpu"]["slope"],
                                                                    summary["cpu"]["slope"]))

# A scene whose image is exactly black (its one light has intensity 0): every error is 0, which a log-log
# fit and plot cannot hold; the tool writes its table with "-" (it once stopped with a traceback).
dark = {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 0.0}]}},
        "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"camera": 0, "translation": [0, 0, 3]}, {"mesh": 0},
                  {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 2, 2]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [-1, -1, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,"
                                              "AACAvwAAgL8AAAAAAACAPwAAgL8AAAAAAAAAAACAPwAAAAAA"}]}
with tempfile.TemporaryDirectory() as out:
    path = os.path.join(out, "dark.gltf")
    with open(path, "w") as f:
        json.dump(dark, f)
    subprocess.run([sys.executable, tool, "--vkrt", vkrt, "--out-dir", out, "--width", "16", "--gpu-spp", "4",
                    "--cpu-spp", "4", "--reference-spp", "16", "--integrators", "path", path], check=True,
                   stdout=subprocess.DEVNULL)
    summary = json.load(open(os.path.join(out, "summary.json")))["dark-path"]
    for device in ("gpu", "cpu"):
        assert all(p["rmse"] == 0.0 for p in summary[device]["checkpoints"]), summary[device]
        assert summary[device]["slope"] is None, summary[device]["slope"]
    assert "| dark | path | gpu | - |" in open(os.path.join(out, "table.md")).read()
    print("convergence report, an exact black image: table and summary written")

# Two scenes of one file name in two folders (glTF/X.gltf beside glTF-Binary/X.glb), a name XML must escape:
# each keeps its own outputs (the second overwrote the first's), and the plots are well-formed SVG.
with tempfile.TemporaryDirectory() as out:
    paths = []
    for folder in ("a", "b"):
        os.makedirs(os.path.join(out, folder))
        paths.append(os.path.join(out, folder, "R&D.gltf"))
        with open(paths[-1], "w") as f:
            json.dump(dark, f)
    subprocess.run([sys.executable, tool, "--vkrt", vkrt, "--out-dir", out, "--width", "8", "--gpu-spp", "2",
                    "--cpu-spp", "2", "--reference-spp", "4", "--integrators", "path"] + paths, check=True,
                   stdout=subprocess.DEVNULL)
    summary = json.load(open(os.path.join(out, "summary.json")))
    assert sorted(summary) == ["R&D-2-path", "R&D-path"], sorted(summary)
    table = open(os.path.join(out, "table.md")).read()
    assert "| R&D | path | gpu |" in table and "| R&D-2 | path | gpu |" in table, table
    for name in ("R&D-path", "R&D-2-path"):
        ElementTree.parse(os.path.join(out, name + ".svg"))
    print("convergence report, two scenes of one name: each its own outputs, plots well-formed")

# X's path outputs are named X-path, as are the Whitted outputs of a scene X-path: the second scene takes the
# next free name (its outputs overwrote the first's path outputs), and the first keeps its own.
with tempfile.TemporaryDirectory() as out:
    paths = [os.path.join(out, name) for name in ("dark.gltf", "dark-path.gltf")]
    for path in paths:
        with open(path, "w") as f:
            json.dump(dark, f)
    subprocess.run([sys.executable, tool, "--vkrt", vkrt, "--out-dir", out, "--width", "8", "--gpu-spp", "2",
                    "--cpu-spp", "2", "--reference-spp", "4"] + paths, check=True, stdout=subprocess.DEVNULL)
    summary = json.load(open(os.path.join(out, "summary.json")))
    expected = {"dark": "whitted", "dark-path": "path", "dark-path-2": "whitted", "dark-path-2-path": "path"}
    assert sorted(summary) == sorted(expected), sorted(summary)
    for name, integrator in expected.items():
        assert all(summary[name][d]["integrator"] == integrator for d in ("gpu", "cpu")), (name, summary[name])
    table = open(os.path.join(out, "table.md")).read()
    assert "| dark | path | gpu |" in table and "| dark-path-2 | whitted | gpu |" in table, table
    print("convergence report, scenes X and X-path: each its own outputs")
