#!/usr/bin/env python3
"""tools/gltf_builder.py writes valid glTF whatever the scene holds: a scene of analytic shapes alone (no
triangles, so no buffer data) loads and renders. It wrote a buffer of 0 bytes, which glTF forbids and vkrt
refused (exit 2).

    gltf_builder_check.py TOOLS_FOLDER VKRT
"""
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, sys.argv[1])
from gltf_builder import GltfBuilder  # noqa: E402

with tempfile.TemporaryDirectory() as folder:
    builder = GltfBuilder("gltf_builder_check")
    builder.sphere("ball", [0.0, 0.0, 0.0], 1.0, builder.material("white", base_color=(0.8, 0.8, 0.8)))
    builder.node("camera", camera=builder.perspective_camera("camera", math.radians(45), aspect_ratio=1.0),
                 translation=[0.0, 0.0, 5.0])
    scene = os.path.join(folder, "spheres-only.gltf")
    builder.write(scene)
    run = subprocess.run([sys.argv[2], "--scene", scene, "--device", "cpu", "--width", "8", "--spp", "1", "--quiet",
                          "--out", os.path.join(folder, "out.pfm")], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"gltf_builder_check: a scene of spheres alone did not render (exit {run.returncode}): {run.stderr}")
print("gltf_builder_check: a scene of spheres alone renders")
