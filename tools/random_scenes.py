#!/usr/bin/env python3
"""Writes a glTF scene drawn at random from a seed, for rendering on the GPU and by the CPU reference and
comparing the two (tests/gpu_image_test.cpp's GpuRandomScene): a ground of any material under 2 to 7 objects
(triangle boxes and spheres with normals, VKRT_sphere spheres, VKRT_shape shapes and VKRT_csg objects of two or
three shapes), each of one material kind (Lambertian, metal, glass with or without absorption, thin transmission,
clear coat, sheen, emission, BLEND or MASK coverage, KHR_materials_specular, unlit), rough or smooth, some with
a checker texture (with holes in its alpha), a normal map, a metallic-roughness, emissive or transmission texture
or vertex colours, textures now and then through a KHR_texture_transform or read through TEXCOORD_1; meshes now
and then mirrored, shown twice, morphed, skinned or without normals; 0 to 3 punctual lights of each kind, a
perspective or orthographic camera over it all, now and then with a lens, and now and then an object, a morph's
weight or a joint moving while the shutter is open. The same seed writes the same file; --scale and --offset
scale and move all of it (camera, lights and lens too, a point light's intensity by the scale's square), so that
the same image should come out of the same scene far smaller, larger or further from the origin: a check of
numerical stability.

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
        # The features added later (texture transforms and second texture coordinates, metallic-roughness,
        # emissive and transmission textures, mirrored, instanced, morphed and skinned meshes, orthographic
        # cameras) draw from a generator of their own, so that the first generator's draws, and with them a
        # seed's layout, materials and lights, stay as they were.
        self.extra = random.Random(seed * 1000003 + 1)
        self.uv1_materials = set()  # materials whose textures read TEXCOORD_1
        self.metal_rough = None
        self.stripes = None
        self.g = GltfBuilder("vkrt tools/random_scenes.py, seed %d" % seed)
        self.checker = None
        self.domes = None
        # Everything, camera and lights included, hangs from one node that scales and moves the whole scene; what
        # glTF gives in world units (a medium's attenuation distance, the lens) is scaled with it, and a point or
        # spot light's intensity by its square, so that every scale should show the same image.
        self.scale = scale
        self.world = self.g.node("world", scale=[scale] * 3, translation=list(offset))

    def number(self, low, high, rng=None):
        return round((rng or self.rng).uniform(low, high), 3)

    def color(self, low=0.05, high=0.95):
        return [self.number(low, high) for _ in range(3)]

    def rotation(self, rng=None):
        return [round(c, 6) for c in normalized([(rng or self.rng).uniform(-1.0, 1.0) for _ in range(4)])]

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
        return self.texture_info(self.checker, scale)

    def domes_info(self):
        if self.domes is None:
            self.domes = self.g.texture("domes", 32, 32, dome_normals(32, 4))
        return self.texture_info(self.domes)

    def metal_rough_info(self):
        """A texture of roughness (green) and metalness (blue) drawn texel by texel."""
        if self.metal_rough is None:
            texels = [(0, self.extra.randrange(256), self.extra.choice([0, 255, self.extra.randrange(256)]), 255)
                      for _ in range(8 * 8)]
            self.metal_rough = self.g.texture("metal-rough", 8, 8, texels, nearest=self.extra.random() < 0.5)
        return self.texture_info(self.metal_rough)

    def stripes_info(self):
        """Stripes of colour, for emission and transmission."""
        if self.stripes is None:
            colors = [(self.extra.randrange(256), self.extra.randrange(256), self.extra.randrange(256), 255)
                      for _ in range(3)]
            texels = [colors[(x + 2 * y) % 3] for y in range(8) for x in range(8)]
            self.stripes = self.g.texture("stripes", 8, 8, texels, nearest=self.extra.random() < 0.5)
        return self.texture_info(self.stripes)

    def texture_info(self, texture, scale=None):
        """A reference to `texture`, now and then through a KHR_texture_transform (offset, rotation and
        scale, any of them mirroring) and now and then reading the second texture coordinates."""
        extra = self.extra
        offset = rotation = None
        if extra.random() < 0.3:
            offset = [self.number(-1.0, 1.0, extra) for _ in range(2)]
            rotation = self.number(-math.pi, math.pi, extra)
            scale = [self.number(0.5, 3.0, extra) * extra.choice([1, 1, -1]) for _ in range(2)]
        tex_coord = 1 if extra.random() < 0.25 else None
        return self.g.texture_info(texture, offset=offset, rotation=rotation, scale=scale, tex_coord=tex_coord)

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
        extra = self.extra
        if kind not in ("unlit", "emissive") and extra.random() < 0.2:
            fields["metallic_roughness_texture"] = self.metal_rough_info()
            if kind == "lambertian" and extra.random() < 0.5:
                fields["metallic"] = 1.0
        if kind == "emissive" and extra.random() < 0.5:
            fields["emissive_texture"] = self.stripes_info()
        if kind in ("glass", "thin") and extra.random() < 0.3:
            fields["transmission_texture"] = self.stripes_info()
        material = self.g.material(**fields)
        if any(isinstance(v, dict) and v.get("texCoord") == 1 for v in fields.values()):
            self.uv1_materials.add(material)
        return material

    def for_analytic(self, material):
        """`material`, or where its textures read TEXCOORD_1 (which analytic shapes do not have), a copy that
        reads TEXCOORD_0."""
        if material not in self.uv1_materials:
            return material
        def first(value):
            if isinstance(value, dict):
                return {k: first(v) for k, v in value.items() if k != "texCoord"}
            return value
        self.g.gltf["materials"].append(first(self.g.gltf["materials"][material]))
        return len(self.g.gltf["materials"]) - 1

    def second_uvs(self, material, uvs):
        """TEXCOORD_1 for a mesh of `material` where its textures read it: the first set turned and stretched."""
        if material not in self.uv1_materials:
            return None
        return [[round(1.5 * v + 0.25, 6), round(0.5 * u - 0.1, 6)] for u, v in uvs]

    def mesh_object(self, name, at, rotation, primitive, moving):
        """A node of one mesh primitive (positions, normals, indices, material, uvs, colours) at `at`, now and
        then mirrored, shown twice, morphed or skinned, or without its normals (flat). A morph's weights or a
        skin's joint turn while the shutter is open where nothing else moves yet. Returns the node that places
        it, and whether something moves now."""
        g, extra = self.g, self.extra
        positions, normals, indices, material, uvs, colors = primitive
        uvs1 = self.second_uvs(material, uvs)
        form = extra.choice(["plain"] * 6 + ["mirrored", "twice", "morphed", "skinned", "flat"])
        animate = not moving and extra.random() < 0.4
        if form in ("plain", "mirrored", "twice", "flat"):
            mesh = g.mesh(name, [(positions, None if form == "flat" else normals, indices, material, uvs, colors,
                                  uvs1)])
            fields = dict(mesh=mesh, translation=at, rotation=rotation)
            if form == "mirrored":
                signs = extra.choice([[-1, 1, 1], [1, -1, 1], [1, 1, -1], [-1, -1, -1]])
                fields["scale"] = [sign * self.number(0.6, 1.4, extra) for sign in signs]
            node = g.node(name, parent=self.world, **fields)
            if form == "twice":
                g.node(name + " again", parent=self.world, mesh=mesh, rotation=self.rotation(extra),
                       translation=[self.number(-2.5, 2.5, extra), self.number(0.2, 1.8, extra),
                                    self.number(-2.5, 2.5, extra)])
            return node, moving
        if form == "morphed":
            # One target moves the upper half's vertices: the mesh shears, more or less as its weight says.
            shift = [self.number(-0.5, 0.5, extra) for _ in range(3)]
            weight = self.number(0.2, 1.0, extra)
            mesh = g.deforming_mesh(name, positions, normals, indices, material, uvs=uvs, uvs1=uvs1,
                                    targets=[([shift if p[1] > 0 else [0.0, 0.0, 0.0] for p in positions], None)],
                                    target_weights=[weight])
            node = g.node(name, parent=self.world, mesh=mesh, translation=at, rotation=rotation)
            if animate:
                g.animate(node, "weights", [0.0, 1.0], [[weight], [self.number(0.0, 1.0, extra)]])
        else:
            # Two joints, the second a turn of the first: the upper vertices follow the second, the lower the
            # first, those between a blend, so that the mesh twists. The skinned node's own place is ignored
            # (glTF 2.0, 3.7.3.1); the joints place it.
            node = g.node(name + " root", parent=self.world, translation=at, rotation=rotation)
            turn = self.small_turn(0.7)
            tip = g.node(name + " tip", parent=node, rotation=turn)
            top = max(p[1] for p in positions)
            blend = [min(1.0, max(0.0, 0.5 + 0.5 * p[1] / top)) for p in positions]
            identity = [1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0]
            mesh = g.deforming_mesh(name, positions, normals, indices, material, uvs=uvs, uvs1=uvs1,
                                    joints=[[0, 1, 0, 0]] * len(positions),
                                    weights=[[round(1.0 - b, 6), round(b, 6), 0.0, 0.0] for b in blend])
            g.node(name, parent=self.world, mesh=mesh, skin=g.skin([node, tip], [identity, identity]),
                   translation=[self.number(-9.0, 9.0, extra) for _ in range(3)])
            if animate:
                g.animate(tip, "rotation", [0.0, 1.0], [turn, self.small_turn(0.7)])
        if animate:
            g.gltf["scenes"][0]["extras"] = {"shutter": [0.0, 1.0]}
        return node, moving or animate

    def small_turn(self, largest):
        """A quaternion turning by at most `largest` radians about an axis drawn at random."""
        axis = normalized([self.extra.uniform(-1.0, 1.0) for _ in range(3)])
        half = 0.5 * self.extra.uniform(-largest, largest)
        return [round(c * math.sin(half), 6) for c in axis] + [round(math.cos(half), 6)]

    def write(self, path):
        rng, g = self.rng, self.g
        ground = self.material() if rng.random() < 0.5 else g.material("ground", base_color=[0.7, 0.7, 0.7])
        s = 6.0
        ground_uvs = [[0, 0], [4, 0], [4, 4], [0, 4]]
        g.node("ground", parent=self.world, mesh=g.mesh("ground", [([[-s, 0, -s], [s, 0, -s], [s, 0, s], [-s, 0, s]], [[0, 1, 0]] * 4,
                                                 [0, 2, 1, 0, 3, 2], ground, ground_uvs, None,
                                                 self.second_uvs(ground, ground_uvs))]))
        moving = False
        for k in range(rng.randint(2, 7)):
            material = self.material()
            at = [self.number(-2.5, 2.5), self.number(0.2, 1.8), self.number(-2.5, 2.5)]
            kind = rng.choice(["box", "box", "mesh sphere", "sphere", "shape", "csg"])
            if kind in ("box", "mesh sphere"):
                positions, normals, indices, uvs = (box([0.0, 0.0, 0.0], [self.number(0.2, 0.9) for _ in range(3)]) if kind == "box"
                                                    else sphere_with_uvs(self.number(0.2, 0.9)))
                colors = ([self.color(0.2, 1.0) for _ in positions] if rng.random() < 0.2 else None)
                node, moving = self.mesh_object("%s %d" % (kind, k), at, self.rotation(),
                                                (positions, normals, indices, material, uvs, colors), moving)
            elif kind == "sphere":
                node = g.sphere("sphere %d" % k, at, self.number(0.2, 0.9), self.for_analytic(material),
                                parent=self.world)
            elif kind == "shape":
                material = self.for_analytic(material)
                node = g.shape("shape %d" % k, rng.choice(["sphere", "box", "cylinder", "cone"]), material,
                               parent=self.world, translation=at, rotation=self.rotation(),
                               scale=[self.number(0.2, 0.8) for _ in range(3)])
            else:
                material = self.for_analytic(material)
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
        yfov, lens = self.number(0.5, 1.0), rng.random() < 0.2
        if self.extra.random() < 0.15:
            half_height = self.number(1.5, 4.0, self.extra) * self.scale
            camera = g.orthographic_camera("camera", half_height * self.number(0.6, 1.6, self.extra), half_height,
                                           znear=0.01 * self.scale, zfar=100.0 * self.scale)
        else:
            camera = g.perspective_camera("camera", yfov, aperture=0.05 * self.scale if lens else None,
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
