#!/usr/bin/env python3
"""Runs tools/convergence_report.py on one scene at a small size and checks what it writes for both
integrators: a CSV per device, an SVG plot, a table, and error that falls with render time on both devices."""

import json
import os
import subprocess
import sys
import tempfile

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
