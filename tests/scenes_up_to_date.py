#!/usr/bin/env python3
"""Fails when a scene in scenes/ differs from what tools/make_scenes.py generates."""

import filecmp
import os
import subprocess
import sys
import tempfile

root = sys.argv[1]
with tempfile.TemporaryDirectory() as folder:
    subprocess.run([sys.executable, os.path.join(root, "tools", "make_scenes.py"), folder], check=True)
    generated = sorted(os.listdir(folder))
    stale = [name for name in generated
             if not filecmp.cmp(os.path.join(folder, name), os.path.join(root, "scenes", name), shallow=False)]
    if stale:
        print("out of date (run python3 tools/make_scenes.py):", ", ".join(stale))
        sys.exit(1)
    print("up to date:", ", ".join(generated))
