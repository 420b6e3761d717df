#!/usr/bin/env python3
"""Writes a glTF scene drawn at random from a seed, for rendering on the GPU and by the CPU reference and
comparing the two (tests/gpu_image_test.cpp's GpuRandomScene): a ground of any material under 2 to 7 objects
(triangle boxes and spheres with normals, VKRT_sphere spheres, VKRT_shape shapes and VKRT_csg objects of two or
three shapes), each of one material kind (Lambertian, metal, glass with or without absorption, thin transmission,
clear coat, sheen, emission, BLEND or MASK coverage, KHR_materials_specular, unlit), rough or smooth, some with
a checker texture (with holes in its alpha), a normal map or vertex colours; 0 to 3 punctual lights of each kind,
a perspective camera over it all, now and then with a lens, and now and then an object moving while the shutter
is open. The same seed writes the same file; --scale and --offset scale and move all of it (camera, lights and
lens too, a point light's intensity by the scale's square), so that the same image should come out of the same
scene far smaller, larger or further from the origin: a check of numerical stability.

Usage: python3 tools/random_scenes.py SEED OUTPUT.gltf [--scale S] [--offset X Y Z]
"""

import argparse
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gltf_builder import GltfBuilder, box, dome_normals, look_at_rotation, uv_sphere  # noqa: E402


def sphere_with_uvs(radius, rings=10, segments=16):
    """gltf_builder's UV sphere about the origin, with texture coordinates (u around, v down)."""
    positions, normals, indices = uv_sphere([0.0, 0.0, 0.0], radius, rings, segments)
    uvs = [[s / segments, r / rings] for r in range(rings + 1) for s in range(segments + 1)]
    return positions, normals, indices, uvs


def normalized(v):
    length = math.sqrt(sum(x * x for x in v))
    return [x / length for x in v]


class RandomScene:
    def __init__(self, seed, scale=1.0, offset=(0.0, 0.0, 0.0)):
        self.rng = random.Random(seed)
        self.g = GltfBuilder("vkrt tools/random_scenes.py, seed %d" % seed)
        self.checker = None
        self.domes = None
        # Everything, camera and lights included, hangs from one node that scales and moves the whole scene; what
        # glTF gives in world units (a medium's attenuation distance, the lens) is scaled with it, and a point or
        # spot light's intensity by its square, so that every scale should show the same image.
        self.scale = scale
        self.world = self.g.node("world", scale=[scale] * 3, translation=list(offset))

    def number(self, low, high):
        return round(self.rng.uniform(low, high), 3)

    def color(self, low=0.05, high=0.95):
        return [self.number(low, high) for _ in range(3)]

    def rotation(self):
        return [round(c, 6) for c in normalized([self.rng.uniform(-1.0, 1.0) for _ in range(4)])]

    def checker_info(self):
        if self.checker is None:
            rng = self.rng
            texels = []
            for y in range(8):
                for x in range(8):
                    lit = (x + y) % 2 == 0
                    alpha = 255 if rng.random() < 0.7 else 0
                    texels.append((230, 200, 120, alpha) if lit else (40, 60, 200, alpha))
            self.checker = self.g.texture("checker", 8, 8, texels, nearest=rng.random() < 0.5)
        scale = [2.0, 2.0] if self.rng.random() < 0.5 else None
        return self.g.texture_info(self.checker, scale=scale)

    def domes_info(self):
        if self.domes is None:
            self.domes = self.g.texture("domes", 32, 32, dome_normals(32, 4))
        return self.g.texture_info(self.domes)

    def material(self):
        rng = self.rng
        kind = rng.choice(["lambertian", "lambertian", "metal", "glass", "thin", "coat", "sheen", "emissive",
                           "coverage", "specular", "unlit"])
        fields = dict(name=kind, base_color=self.color(), roughness=rng.choice([0.0, 0.05, 0.3, 0.7, 1.0]))
        if kind == "metal":
            fields["metallic"] = 1.0
        elif kind == "glass":
            fields.update(transmission=1.0, ior=self.number(1.1, 2.4), thickness=1.0,
                          base_color=[1.0, 1.0, 1.0] if rng.random() < 0.5 else self.color(0.6, 1.0))
            if rng.random() < 0.5:
                fields.update(attenuation_color=self.color(0.3, 0.95),
                              attenuation_distance=self.number(0.2, 3.0) * self.scale)
        elif kind == "thin":
            fields.update(transmission=self.number(0.3, 1.0), ior=1.5)
        elif kind == "coat":
            fields.update(clearcoat=self.number(0.2, 1.0), clearcoat_roughness=rng.choice([0.0, 0.2, 0.6]))
        elif kind == "sheen":
            fields.update(sheen_color=self.color(), sheen_roughness=rng.choice([0.1, 0.5, 1.0]))
        elif kind == "emissive":
            fields.update(emission=self.color(0.3, 1.0), emission_strength=self.number(1.0, 8.0))
        elif kind == "coverage":
            fields.update(alpha=self.number(0.2, 0.8), alpha_mode=rng.choice(["BLEND", "MASK"]), alpha_cutoff=0.5,
                          double_sided=True)
            if rng.random() < 0.6:
                fields["base_color_texture"] = self.checker_info()
        elif kind == "specular":
            fields.update(specular=self.number(0.0, 1.0), specular_color=self.color(0.3, 1.0))
        elif kind == "unlit":
            fields["unlit"] = True
        if "base_color_texture" not in fields and rng.random() < 0.25:
            fields["base_color_texture"] = self.checker_info()
        if kind not in ("unlit", "emissive") and rng.random() < 0.2:
            fields["normal_texture"] = self.domes_info()
        if "double_sided" not in fields and rng.random() < 0.2:
            fields["double_sided"] = True
        return self.g.material(**fields)

    def write(self, path):
        rng, g = self.rng, self.g
        ground = self.material() if rng.random() < 0.5 else g.material("ground", base_color=[0.7, 0.7, 0.7])
        s = 6.0
        g.node("ground", parent=self.world, mesh=g.mesh("ground", [([[-s, 0, -s], [s, 0, -s], [s, 0, s], [-s, 0, s]], [[0, 1, 0]] * 4,
                                                 [0, 2, 1, 0, 3, 2], ground, [[0, 0], [4, 0], [4, 4], [0, 4]])]))
        moving = False
        for k in range(rng.randint(2, 7)):
            material = self.material()
            at = [self.number(-2.5, 2.5), self.number(0.2, 1.8), self.number(-2.5, 2.5)]
            kind = rng.choice(["box", "box", "mesh sphere", "sphere", "shape", "csg"])
            if kind in ("box", "mesh sphere"):
                positions, normals, indices, uvs = (box([0.0, 0.0, 0.0], [self.number(0.2, 0.9) for _ in range(3)]) if kind == "box"
                                                    else sphere_with_uvs(self.number(0.2, 0.9)))
                colors = ([self.color(0.2, 1.0) for _ in positions] if rng.random() < 0.2 else None)
                mesh = g.mesh("%s %d" % (kind, k), [(positions, normals, indices, material, uvs, colors)])
                node = g.node("%s %d" % (kind, k), parent=self.world, mesh=mesh, translation=at,
                              rotation=self.rotation())
            elif kind == "sphere":
                node = g.sphere("sphere %d" % k, at, self.number(0.2, 0.9), material, parent=self.world)
            elif kind == "shape":
                node = g.shape("shape %d" % k, rng.choice(["sphere", "box", "cylinder", "cone"]), material,
                               parent=self.world, translation=at, rotation=self.rotation(),
                               scale=[self.number(0.2, 0.8) for _ in range(3)])
            else:
                node = g.csg("csg %d" % k, rng.choice(["union", "intersection", "difference"]), parent=self.world,
                             translation=at, rotation=self.rotation())
                for j in range(rng.randint(2, 3)):
                    g.shape("operand %d.%d" % (k, j), rng.choice(["sphere", "box", "cylinder", "cone"]), material,
                            parent=node, translation=[self.number(-0.3, 0.3) for _ in range(3)],
                            scale=[self.number(0.3, 0.7) for _ in range(3)])
            if not moving and rng.random() < 0.15:
                g.animate(node, "translation", [0.0, 1.0], [at, [at[0] + 0.3, at[1], at[2]]])
                g.gltf["scenes"][0]["extras"] = {"shutter": [0.0, 1.0]}
                moving = True
        for k in range(rng.choice([0, 1, 1, 2, 3])):
            kind = rng.choice(["point", "spot", "directional"])
            light = {"type": kind, "color": self.color(0.5, 1.0),
                     "intensity": (self.number(1.0, 4.0) if kind == "directional"
                                   else self.number(2.0, 30.0) * self.scale * self.scale)}
            if kind == "spot":
                outer = self.number(0.3, 1.0)
                light["spot"] = {"innerConeAngle": round(outer * rng.uniform(0.0, 0.9), 3), "outerConeAngle": outer}
            tilt = math.pi / 4 + rng.uniform(-0.25, 0.25)  # half of a turn of 90 degrees about -X, give or take
            g.node("light %d" % k, parent=self.world, translation=[self.number(-3, 3), self.number(2.5, 5), self.number(-3, 3)],
                   rotation=[-round(math.sin(tilt), 6), 0.0, 0.0, round(math.cos(tilt), 6)],
                   extensions={"KHR_lights_punctual": {"light": g.light(light)}})
        eye = [self.number(-5, 5), self.number(1, 4), self.number(4, 7) * rng.choice([-1, 1])]
        camera = g.perspective_camera("camera", self.number(0.5, 1.0),
                                      aperture=0.05 * self.scale if rng.random() < 0.2 else None,
                                      focus_distance=6.0 * self.scale)
        g.node("camera", parent=self.world, camera=camera, translation=eye, rotation=look_at_rotation(eye, [0.0, 0.5, 0.0]))
        g.write(path)


def main():
    parser = argparse.ArgumentParser(description="Writes a glTF scene drawn at random from SEED.")
    parser.add_argument("seed", type=int)
    parser.add_argument("output", help="the .gltf file to write")
    parser.add_argument("--scale", type=float, default=1.0, help="scales the whole scene (default 1)")
    parser.add_argument("--offset", type=float, nargs=3, default=[0.0, 0.0, 0.0], metavar=("X", "Y", "Z"),
                        help="moves the whole scene, after scaling it (default 0 0 0)")
    args = parser.parse_args()
    if not (math.isfinite(args.scale) and args.scale > 0.0) or not all(math.isfinite(c) for c in args.offset):
        parser.error("--scale must be positive and finite, --offset finite")
    folder = os.path.dirname(os.path.abspath(args.output))
    if not os.path.isdir(folder):
        parser.error(f"{args.output}: no folder {folder} to write it in")
    RandomScene(args.seed, args.scale, args.offset).write(args.output)


if __name__ == "__main__":
    main()
