#!/usr/bin/env python3
"""Generates vkrt's own scenes in scenes/.

cornell.gltf: the Cornell box as published by the Cornell University Program of Computer Graphics,
"Cornell Box Data", https://www.graphics.cornell.edu/online/box/data.html: every corner of the walls, the
light and the two blocks in millimetres, and the camera (position 278 273 -800 looking along +z, focal
length 35 mm on a 25 x 25 mm film). The published data gives reflectance spectra; the RGB values used here
are the ones commonly used by renderers (for example Benedikt Bitterli's "Rendering Resources" Cornell box
and the pbrt-v4 and Mitsuba scene ports): white 0.725 0.71 0.68, red 0.63 0.065 0.05, green 0.14 0.45
0.091, and the light's radiance 17 12 4. Every surface is purely Lambertian, as the data defines it
(KHR_materials_specular with specularFactor 0). The published light sits in the ceiling plane (y = 548.8),
so the ceiling is built with a hole where the light is, rather than moving the light.

whitted.gltf: in the spirit of Whitted's 1980 picture: a mirror sphere and a glass sphere (analytic, the
VKRT_sphere extension of docs/vkrt_sphere.md) over a red and yellow checkerboard, lit by one point light.

lights.gltf: one each of KHR_lights_punctual's point, spot and directional lights over a floor with a few
objects.

many-lights.gltf: 144 coloured point lights in two rings around and over three spheres (more than 64 punctual
lights: each light sample picks one by power), and a dim directional light.

glossy.gltf: glossy reflection and transmission: a row of metal spheres and a row of glass spheres with
roughness 0, 0.1, 0.25, 0.5 and 0.8 (GGX), lit by two small emissive spheres (area lights), so the
highlights show multiple importance sampling at work.

motion-blur.gltf: motion blur: over a checkerboard, a cube sliding at 1.5 units/s, a cube spinning at 90
degrees/s (glTF LINEAR animations) and a ball that jumps (STEP) during the half-second shutter given in the
scene's extras.

deform.gltf: skins and morph targets (glTF 2.0 sections 3.7.2.2 and 3.7.3): a tube skinned to two joints, its
upper joint turned 50 degrees at rest so the tube bends where the joints' weights blend, and a ball with two morph
targets (towards a rounded box, and squashed), placed twice: with its mesh's weights (0.6 of the box) and with
its node's (the squash alone). An animation straightens the knee to 10 degrees and moves the first ball's weights
to (0, 0.8) over one second, seen with --shutter 0 1.

environment.gltf and sky.hdr: a scene without lights of its own, for --environment: a Lambertian white, a
rough gold and a mirror sphere and a glass sphere on a grey floor; sky.hdr is a small (64 x 32)
equirectangular Radiance map (top row the zenith, +Y) with a blue gradient sky, a brown ground and a sun
of 2 x 2 texels 34 degrees above the horizon, between +X and +Z (docs/environment.md).

textures.gltf: textures and their transforms: a floor whose 2x2 checker KHR_texture_transform scales by 12
and turns by 20 degrees, and analytic spheres banded by a metallic-roughness texture (blue: metal, green:
roughness) and a base colour texture, under a directional and a point light; in front, three glossy white
spheres with KHR_materials_specular factors 1, 0 (purely Lambertian) and 1 tinted red, and a tile whose
vertex colours (COLOR_0) blend red, green, blue and white under a checker read through TEXCOORD_1.

surfaces.gltf: normal maps and alpha: two panels of domes that exist only in their normal texture (one with
tangents derived from its texture coordinates, one a mirrored instance with TANGENT given: both look alike)
and the same domes on an analytic ball and box (their frames from their own texture coordinates), a MASK screen whose holes let the sun through onto the floor, a BLEND pane of alpha 0.35 in front of a
sphere of red paint under a clear coat (KHR_materials_clearcoat), a velvet ball (KHR_materials_sheen), an unlit sign (KHR_materials_unlit) and a window striped by its transmission texture, under a low sun
and a point light.

dof.gltf: depth of field: a row of spheres receding over a checkerboard, the camera (a thin lens of radius
0.12, described in the camera's extras) focused on the middle one.

outdoor.gltf and soft-sky.hdr: for --environment scenes/soft-sky.hdr, and for a comparison with Blender Cycles
(tests/references/outdoor-cycles.exr): a Lambertian ball, a mirror ball and a glass ball (triangle meshes with
smooth normals) on a Lambertian floor, with no light of their own. Every material is one Cycles means the same
by: Lambertian (KHR_materials_specular factor 0), a white metal of roughness 0 (its Fresnel term is exactly 1)
and smooth glass of index 1.5 (the exact dielectric Fresnel term, and refraction into its volume).

punctual.gltf: a point light and a sun over Lambertian surfaces with textures, for a comparison with Blender
Cycles (tests/references/punctual-cycles.exr): a floor checkered by a 2 x 2 texture, a panel and a turned box
whose texture's four quadrants (red, green, blue and yellow from the top left) show which way up and round
it is read, and a clay ball. Every material is Lambertian (KHR_materials_specular factor 0), the textures
sampled at the nearest texel without mipmaps (as Cycles' Closest interpolation), the point light without a range.

rough.gltf: for --environment scenes/soft-sky.hdr and a comparison with Blender Cycles
(tests/references/rough-cycles.exr): rough white metal (roughness 0.3 and 0.5) and rough glass (roughness 0.15
and 0.3, index 1.5) balls in a row, triangle meshes with smooth normals, on a Lambertian floor. White metal's Fresnel
term is 1 at every angle, so both renderers mean GGX reflection with all its energy kept (vkrt's compensation,
Cycles' multiple-scattering GGX).

tinted.gltf: for --environment scenes/soft-sky.hdr and a comparison with Blender Cycles
(tests/references/tinted-cycles.exr): Beer's law: glass balls of index 1.5 tinted by their volumes'
attenuation (amber at 1 unit and blue at 0.5, smooth, and green at 0.8, of roughness 0.1) on a Lambertian floor.

lens.gltf: for --environment scenes/soft-sky.hdr and a comparison with Blender Cycles
(tests/references/lens-cycles.exr): depth of field: Lambertian balls receding over a checkered Lambertian floor
(a texture read at the nearest texel) under the sky and a sun, seen through a thin lens of radius 0.08 focused
on the second ball.

lamps.gltf: emitters for a comparison with Blender Cycles (tests/references/lamps-cycles.exr): a panel overhead
whose emission is striped by its emissive texture (warm, cool and dark stripes, read at the nearest texel)
and a small glowing ball light a Lambertian floor, wall, box and ball; the panel's back faces the empty space
above it, where the wall ends (vkrt's emission is one-sided, Cycles' two-sided).

streaks.gltf: motion blur for a comparison with Blender Cycles (tests/references/streaks-cycles.exr): over
the scene's one-second shutter, a ball slides 2 units along x (a LINEAR translation) and a box moves 1.2 units
towards the camera while it turns 90 degrees about y (its rotation keyed every 11.25 degrees, so that Blender's
interpolation of the keys by normalised components is glTF's spherical one), beside a still ball on a floor
checkered by a texture read at the nearest texel, under a point light and a sun. Every material is Lambertian.

spots.gltf: spot lights and ranges for a comparison with Blender Cycles (tests/references/spots-cycles.exr): a
warm spot with a soft edge (inner cone 15 degrees, outer 32) over a ball, a cool one soft all the way in (inner
0, outer 22) and of range 7 raking a wall past a box, and a point light whose range of 1.8 ends its pool of
light on the floor; every material Lambertian, nothing lit but by them.

studio.gltf: a large lamp: an orange box and a blue ball on a white floor before a white wall, under a softbox
2.8 x 2.8 hanging 1.5 above the floor, large beside the scene, so its triangles are sampled by the solid angle
they cover (docs/integrators.md). Every surface is Lambertian.

csg.gltf: analytic shapes and constructive solid geometry (VKRT_shape and VKRT_csg, docs/vkrt_shape.md) on a
grey floor, lit by an emissive box (an area light) and a point light. At the back, the classic CSG pieces: a
box minus a sphere (bites in the box's faces, in the sphere's orange), a glass lens (the intersection of two
spheres, tinted by Beer's law) and a sphere drilled by two cylinders (red and yellow bores); in front, each
shape under a non-uniform scale: a mirrored cone with an elliptical base, a tilted gold ellipsoid, a turned
slab with a checker texture and an oblique cylinder (a matrix with shear).

Usage: python3 tools/make_scenes.py [OUTPUT_FOLDER]   (default: the repository's scenes/)
"""

import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gltf_builder import (GltfBuilder, box, cross, dome_normals, dot, look_at_rotation, merge,  # noqa: E402
                          quad, sub, uv_sphere)

SCENES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scenes")


def cornell():
    g = GltfBuilder("vkrt tools/make_scenes.py (Cornell Box Data, Cornell University PCG)")
    # The Cornell data defines every surface as a diffuse (Lambertian) reflector: KHR_materials_specular with
    # factor 0 takes away the dielectric's specular layer, which vkrt then shades as pure Lambert.
    white = g.material("white", base_color=(0.725, 0.71, 0.68), specular=0.0)
    red = g.material("red", base_color=(0.63, 0.065, 0.05), specular=0.0)
    green = g.material("green", base_color=(0.14, 0.45, 0.091), specular=0.0)
    light = g.material("light", base_color=(0.78, 0.78, 0.78), emission=(1.0, 12.0 / 17.0, 4.0 / 17.0),
                       emission_strength=17.0, specular=0.0)

    inside = [278.0, 274.4, 279.6]  # the middle of the box; walls face it

    def wall(corners):
        center = [sum(c[i] for c in corners) / 4 for i in range(3)]
        return quad(corners, [inside[i] - center[i] for i in range(3)])

    floor = wall([[552.8, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 559.2], [549.6, 0.0, 559.2]])
    back = wall([[549.6, 0.0, 559.2], [0.0, 0.0, 559.2], [0.0, 548.8, 559.2], [556.0, 548.8, 559.2]])
    right_green = wall([[0.0, 0.0, 559.2], [0.0, 0.0, 0.0], [0.0, 548.8, 0.0], [0.0, 548.8, 559.2]])
    left_red = wall([[552.8, 0.0, 0.0], [549.6, 0.0, 559.2], [556.0, 548.8, 559.2], [556.0, 548.8, 0.0]])

    # Ceiling (556.0 x 559.2 at y = 548.8) with a hole for the light (x 213..343, z 227..332).
    y = 548.8
    down = [0.0, -1.0, 0.0]
    ceiling = merge([
        quad([[0.0, y, 0.0], [556.0, y, 0.0], [556.0, y, 227.0], [0.0, y, 227.0]], down),
        quad([[0.0, y, 332.0], [556.0, y, 332.0], [556.0, y, 559.2], [0.0, y, 559.2]], down),
        quad([[0.0, y, 227.0], [213.0, y, 227.0], [213.0, y, 332.0], [0.0, y, 332.0]], down),
        quad([[343.0, y, 227.0], [556.0, y, 227.0], [556.0, y, 332.0], [343.0, y, 332.0]], down),
    ])
    lamp = quad([[343.0, y, 227.0], [343.0, y, 332.0], [213.0, y, 332.0], [213.0, y, 227.0]], down)

    def block(top, height):
        """A block from its four top corners (published order) and height; faces point outward."""
        center = [sum(c[i] for c in top) / 4 for i in range(3)]
        center[1] = height / 2
        parts = [quad(top, [0.0, 1.0, 0.0])]
        for k in range(4):
            a, b = top[k], top[(k + 1) % 4]
            side = [[a[0], 0.0, a[2]], [a[0], height, a[2]], [b[0], height, b[2]], [b[0], 0.0, b[2]]]
            mid = [(a[0] + b[0]) / 2, height / 2, (a[2] + b[2]) / 2]
            parts.append(quad(side, [mid[i] - center[i] for i in range(3)]))
        return merge(parts)

    short_block = block([[130.0, 165.0, 65.0], [82.0, 165.0, 225.0], [240.0, 165.0, 272.0],
                         [290.0, 165.0, 114.0]], 165.0)
    tall_block = block([[423.0, 330.0, 247.0], [265.0, 330.0, 296.0], [314.0, 330.0, 456.0],
                        [472.0, 330.0, 406.0]], 330.0)

    whites = merge([floor, back, ceiling, short_block, tall_block])
    mesh = g.mesh("cornell-box", [
        (whites[0], None, whites[1], white),
        (left_red[0], None, left_red[1], red),
        (right_green[0], None, right_green[1], green),
        (lamp[0], None, lamp[1], light),
    ])
    # The data is in millimetres; glTF's unit is the metre.
    root = g.node("cornell-box (millimetres)", scale=[0.001, 0.001, 0.001])
    g.node("geometry", parent=root, mesh=mesh)
    # 35 mm focal length on 25 mm film: yfov = 2 atan(12.5 / 35).
    camera = g.perspective_camera("cornell-camera", 2.0 * math.atan(12.5 / 35.0), aspect_ratio=1.0)
    # glTF cameras look down -z; turning half a circle about y makes them look down +z as published.
    g.node("camera", parent=root, camera=camera, translation=[278.0, 273.0, -800.0], rotation=[0.0, 1.0, 0.0, 0.0])
    g.write(os.path.join(OUTPUT, "cornell.gltf"))


def checkerboard(size, cells, height):
    """Two (positions, indices) sets: the light and the dark cells of a square board centred at the origin."""
    light, dark = [], []
    step = 2 * size / cells
    for i in range(cells):
        for j in range(cells):
            x0, z0 = -size + i * step, -size + j * step
            cell = quad([[x0, height, z0], [x0 + step, height, z0], [x0 + step, height, z0 + step],
                         [x0, height, z0 + step]], [0.0, 1.0, 0.0])
            (light if (i + j) % 2 == 0 else dark).append(cell)
    return merge(light), merge(dark)


def checker_texture(g, light, dark, mipmaps=True):
    """A 2 x 2 checker of the RGB colours `light` and `dark`, read at the nearest texel when magnified."""
    return g.texture("checker", 2, 2, [light + (255,), dark + (255,), dark + (255,), light + (255,)], nearest=True,
                     mipmaps=mipmaps)


def look_and_write(g, name, eye, target, yfov_degrees, aspect_ratio=None):
    """Adds the camera `name`-camera at `eye` looking at `target` and writes the scene as `name`.gltf."""
    camera = g.perspective_camera(name + "-camera", math.radians(yfov_degrees), aspect_ratio=aspect_ratio)
    g.node("camera", camera=camera, translation=eye, rotation=look_at_rotation(eye, target))
    g.write(os.path.join(OUTPUT, name + ".gltf"))


def checker_floor(g, name, light, dark):
    """A node `name` with a checkerboard 20 units across of 20 x 20 cells at height 0, in materials light and dark."""
    light_cells, dark_cells = checkerboard(10.0, 20, 0.0)
    return g.node(name, mesh=g.mesh(name, [(light_cells[0], None, light_cells[1], light),
                                           (dark_cells[0], None, dark_cells[1], dark)]))


def whitted():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    yellow = g.material("yellow", base_color=(0.9, 0.75, 0.1))
    red = g.material("red", base_color=(0.8, 0.1, 0.05))
    mirror = g.material("mirror", base_color=(0.9, 0.9, 0.9), metallic=1.0, roughness=0.0)
    glass = g.material("glass", base_color=(1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5,
                       thickness=1.0)
    checker_floor(g, "checkerboard", yellow, red)
    g.sphere("mirror sphere", [0.9, 1.0, -1.2], 1.0, mirror)
    g.sphere("glass sphere", [-0.6, 1.3, 0.8], 0.8, glass)
    eye, target = [0.0, 2.6, 6.5], [0.0, 0.9, 0.0]
    camera = g.perspective_camera("whitted-camera", math.radians(45.0))
    g.node("camera", camera=camera, translation=eye, rotation=look_at_rotation(eye, target))
    light = g.light({"type": "point", "name": "lamp", "color": [1.0, 0.97, 0.9], "intensity": 40.0})
    g.node("lamp", translation=[3.0, 6.0, 4.0], extensions={"KHR_lights_punctual": {"light": light}})
    g.write(os.path.join(OUTPUT, "whitted.gltf"))


def lights():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    floor_material = g.material("floor", base_color=(0.8, 0.8, 0.8))
    object_material = g.material("plastic", base_color=(0.6, 0.6, 0.7), roughness=0.4)
    floor = quad([[-6.0, 0.0, -6.0], [6.0, 0.0, -6.0], [6.0, 0.0, 6.0], [-6.0, 0.0, 6.0]], [0.0, 1.0, 0.0])
    spheres = [uv_sphere([x, 0.6, 0.0], 0.6, 24, 48) for x in (-2.2, 0.0, 2.2)]
    primitives = [(floor[0], None, floor[1], floor_material)]
    primitives += [(s[0], s[1], s[2], object_material) for s in spheres]
    g.node("scene", mesh=g.mesh("lights", primitives))
    eye, target = [0.0, 4.0, 8.0], [0.0, 0.5, 0.0]
    camera = g.perspective_camera("lights-camera", math.radians(45.0))
    g.node("camera", camera=camera, translation=eye, rotation=look_at_rotation(eye, target))
    point = g.light({"type": "point", "name": "warm point", "color": [1.0, 0.6, 0.3], "intensity": 6.0,
                     "range": 8.0})
    g.node("point", translation=[-2.2, 2.0, 1.5], extensions={"KHR_lights_punctual": {"light": point}})
    spot = g.light({"type": "spot", "name": "cool spot", "color": [0.4, 0.6, 1.0], "intensity": 30.0,
                    "spot": {"innerConeAngle": 0.25, "outerConeAngle": 0.45}})
    g.node("spot", translation=[2.2, 4.0, 0.0], rotation=[-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)],
           extensions={"KHR_lights_punctual": {"light": spot}})
    sun = g.light({"type": "directional", "name": "dim sun", "color": [1.0, 1.0, 1.0], "intensity": 0.4})
    g.node("sun", rotation=look_at_rotation([0.0, 0.0, 0.0], [0.5, -1.0, -0.3]),
           extensions={"KHR_lights_punctual": {"light": sun}})
    g.write(os.path.join(OUTPUT, "lights.gltf"))


def many_lights():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    floor_material = g.material("floor", base_color=(0.7, 0.7, 0.7))
    matte = g.material("matte", base_color=(0.8, 0.8, 0.8))
    plastic = g.material("plastic", base_color=(0.6, 0.6, 0.7), roughness=0.4)
    metal = g.material("metal", base_color=(0.9, 0.8, 0.6), metallic=1.0, roughness=0.3)
    floor = quad([[-6.0, 0.0, -6.0], [6.0, 0.0, -6.0], [6.0, 0.0, 6.0], [-6.0, 0.0, 6.0]], [0.0, 1.0, 0.0])
    primitives = [(floor[0], None, floor[1], floor_material)]
    for x, material in ((-2.2, matte), (0.0, metal), (2.2, plastic)):
        s = uv_sphere([x, 0.6, 0.0], 0.6, 24, 48)
        primitives.append((s[0], s[1], s[2], material))
    g.node("scene", mesh=g.mesh("many lights", primitives))
    eye, target = [0.0, 4.0, 8.0], [0.0, 0.5, 0.0]
    camera = g.perspective_camera("many-lights-camera", math.radians(45.0))
    g.node("camera", camera=camera, translation=eye, rotation=look_at_rotation(eye, target))
    # 144 coloured point lights: a ring of 96 dim bulbs just above the floor around the spheres, their hues going
    # round, and a ring of 48 bright ones over them (more than 64 punctual lights: each light sample picks one).
    def hue_color(hue):
        return [round(0.1 + 0.9 * max(0.0, min(1.0, abs(((6.0 * hue + shift) % 6.0) - 3.0) - 1.0)), 4)
                for shift in (0.0, 4.0, 2.0)]
    rings = [(96, 3.4, 0.25, 0.06), (48, 2.0, 2.6, 0.5)]
    for ring, (count, radius, height, intensity) in enumerate(rings):
        for i in range(count):
            angle = 2.0 * math.pi * (i + 0.5 * ring) / count
            light = g.light({"type": "point", "name": f"bulb {ring}.{i}", "color": hue_color(i / count),
                             "intensity": intensity})
            g.node(f"bulb {ring}.{i}", translation=[round(radius * math.cos(angle), 5), height,
                                                   round(radius * math.sin(angle), 5)],
                   extensions={"KHR_lights_punctual": {"light": light}})
    sun = g.light({"type": "directional", "name": "moon", "color": [0.6, 0.7, 1.0], "intensity": 0.05})
    g.node("moon", rotation=look_at_rotation([0.0, 0.0, 0.0], [0.3, -1.0, -0.4]),
           extensions={"KHR_lights_punctual": {"light": sun}})
    g.write(os.path.join(OUTPUT, "many-lights.gltf"))


def dof():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    yellow = g.material("yellow", base_color=(0.9, 0.75, 0.1))
    red = g.material("red", base_color=(0.8, 0.1, 0.05))
    white = g.material("white", base_color=(0.8, 0.8, 0.8), roughness=0.5)
    light_cells, dark_cells = checkerboard(10.0, 20, 0.0)
    primitives = [(light_cells[0], None, light_cells[1], yellow), (dark_cells[0], None, dark_cells[1], red)]
    for k in range(5):
        sphere = uv_sphere([-1.5 + 1.2 * k, 0.5, 2.0 - 2.5 * k], 0.5, 24, 48)
        primitives.append((sphere[0], sphere[1], sphere[2], white))
    g.node("scene", mesh=g.mesh("dof", primitives))
    eye, target = [0.0, 1.2, 6.0], [0.9, 0.5, -3.0]
    focus = math.dist(eye, [0.9, 0.5, -3.0])
    camera = g.perspective_camera("dof-camera", math.radians(40.0), aperture=0.12, focus_distance=round(focus, 4))
    g.node("camera", camera=camera, translation=eye, rotation=look_at_rotation(eye, target))
    light = g.light({"type": "point", "name": "lamp", "color": [1.0, 0.97, 0.9], "intensity": 60.0})
    g.node("lamp", translation=[3.0, 6.0, 4.0], extensions={"KHR_lights_punctual": {"light": light}})
    g.write(os.path.join(OUTPUT, "dof.gltf"))


def glossy():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    floor_material = g.material("floor", base_color=(0.35, 0.35, 0.38))
    wall_material = g.material("wall", base_color=(0.6, 0.6, 0.6))
    lamp = g.material("lamp", base_color=(0.0, 0.0, 0.0), emission=(1.0, 0.9, 0.75), emission_strength=150.0)
    floor = quad([[-8.0, 0.0, -4.0], [8.0, 0.0, -4.0], [8.0, 0.0, 6.0], [-8.0, 0.0, 6.0]], [0.0, 1.0, 0.0])
    wall = quad([[-8.0, 0.0, -4.0], [8.0, 0.0, -4.0], [8.0, 6.0, -4.0], [-8.0, 6.0, -4.0]], [0.0, 0.0, 1.0])
    g.node("room", mesh=g.mesh("room", [(floor[0], None, floor[1], floor_material),
                                        (wall[0], None, wall[1], wall_material)]))
    for k, roughness in enumerate((0.0, 0.1, 0.25, 0.5, 0.8)):
        x = -2.8 + 1.4 * k
        metal = g.material("metal %.2f" % roughness, base_color=(0.95, 0.8, 0.55), metallic=1.0,
                           roughness=roughness)
        glass = g.material("glass %.2f" % roughness, base_color=(1.0, 1.0, 1.0), roughness=roughness,
                           transmission=1.0, ior=1.5, thickness=1.0)
        g.sphere("metal sphere %d" % k, [x, 0.55, -0.9], 0.55, metal)
        g.sphere("glass sphere %d" % k, [x, 0.55, 0.9], 0.55, glass)
    g.sphere("lamp left", [-2.5, 3.2, -1.5], 0.15, lamp)
    g.sphere("lamp right", [2.0, 2.6, 2.5], 0.1, lamp)
    look_and_write(g, "glossy", [0.0, 3.0, 8.5], [0.0, 0.45, 0.0], 34.0, 1.6)


def motion_blur():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    yellow = g.material("yellow", base_color=(0.9, 0.75, 0.1))
    red = g.material("red", base_color=(0.8, 0.1, 0.05))
    blue = g.material("blue", base_color=(0.1, 0.3, 0.8), roughness=0.5)
    white = g.material("white", base_color=(0.85, 0.85, 0.85), roughness=0.3)
    checker_floor(g, "checkerboard", yellow, red)
    # A cube sliding along x at 1.5 units per second (LINEAR), a cube spinning about y at 90 degrees per
    # second, and a ball that jumps (STEP) a quarter second into the shutter's half second.
    cube_positions, _, cube_indices, _ = box([0.0, 0.0, 0.0], [0.4] * 3)
    box_mesh = g.mesh("cube", [(cube_positions, None, cube_indices, blue)])
    slider = g.node("sliding cube", mesh=box_mesh, translation=[-1.5, 0.4, -1.0])
    g.animate(slider, "translation", [0.0, 1.0], [[-1.5, 0.4, -1.0], [0.0, 0.4, -1.0]])
    spinner = g.node("spinning cube", mesh=box_mesh, translation=[1.6, 0.4, 1.0])
    half = math.radians(45.0)
    g.animate(spinner, "rotation", [0.0, 1.0], [[0.0, 0.0, 0.0, 1.0], [0.0, math.sin(half), 0.0, math.cos(half)]])
    ball = g.sphere("jumping ball", [-1.6, 0.5, 1.0], 0.5, white)
    g.animate(ball, "translation", [0.0, 0.25], [[-1.6, 0.5, 1.0], [-1.6, 1.3, 1.0]], interpolation="STEP")
    g.gltf["scenes"][0]["extras"] = {"shutter": [0.0, 0.5]}
    eye, target = [0.0, 2.8, 6.5], [0.0, 0.5, 0.0]
    camera = g.perspective_camera("motion-camera", math.radians(45.0))
    g.node("camera", camera=camera, translation=eye, rotation=look_at_rotation(eye, target))
    light = g.light({"type": "point", "name": "lamp", "color": [1.0, 0.97, 0.9], "intensity": 60.0})
    g.node("lamp", translation=[3.0, 6.0, 4.0], extensions={"KHR_lights_punctual": {"light": light}})
    g.write(os.path.join(OUTPUT, "motion-blur.gltf"))


def textures():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    # Uncompressed PNGs (zlib level 0) keep the file the same bytes whatever zlib builds it.
    checker = checker_texture(g, (235, 235, 235), (70, 90, 120))
    # Sixteen bands around a sphere: metal and smooth, then dielectric and rough (blue metal, green roughness).
    bands = g.texture("bands", 16, 1, [(0, 40, 255, 255) if k % 2 == 0 else (0, 230, 0, 255) for k in range(16)],
                      nearest=True)
    rainbow = g.texture("rainbow", 4, 1, [(230, 60, 50, 255), (240, 200, 40, 255), (60, 170, 90, 255),
                                          (60, 110, 220, 255)])
    floor_material = g.material("checker floor", base_color=(1.0, 1.0, 1.0),
                                base_color_texture=g.texture_info(checker, scale=[12.0, 12.0],
                                                                  rotation=math.radians(20.0)))
    floor = quad([[-6.0, 0.0, -6.0], [6.0, 0.0, -6.0], [6.0, 0.0, 6.0], [-6.0, 0.0, 6.0]], [0.0, 1.0, 0.0])
    uvs = [[(p[0] + 6.0) / 12.0, (p[2] + 6.0) / 12.0] for p in floor[0]]
    g.node("floor", mesh=g.mesh("floor", [(floor[0], None, floor[1], floor_material, uvs)]))
    banded = g.material("banded gold", base_color=(0.95, 0.75, 0.45), metallic=1.0, roughness=1.0,
                        metallic_roughness_texture=g.texture_info(bands))
    banded_twice = g.material("banded gold, bands doubled", base_color=(0.95, 0.75, 0.45), metallic=1.0,
                              roughness=1.0, metallic_roughness_texture=g.texture_info(bands, scale=[2.0, 1.0]))
    painted = g.material("painted", metallic=0.0, roughness=0.6,
                         base_color_texture=g.texture_info(rainbow, offset=[0.125, 0.0]))
    g.sphere("banded sphere", [-1.4, 0.7, 0.0], 0.7, banded)
    g.sphere("banded sphere, doubled", [0.0, 0.7, 0.0], 0.7, banded_twice)
    g.sphere("painted sphere", [1.4, 0.7, 0.0], 0.7, painted)
    for k, (label, specular, colour) in enumerate((("specular 1", 1.0, None), ("specular 0", 0.0, None),
                                                   ("specular tinted", 1.0, (1.0, 0.2, 0.2)))):
        glossy_white = g.material(label, base_color=(0.7, 0.7, 0.7), roughness=0.15, specular=specular,
                                  specular_color=colour)
        g.sphere(label, [-0.9 + 0.9 * k, 0.3, 1.6], 0.3, glossy_white)
    tile = quad([[1.6, 0.01, 0.9], [2.6, 0.01, 0.9], [2.6, 0.01, 1.9], [1.6, 0.01, 1.9]], [0.0, 1.0, 0.0])
    corner_colours = {(1.6, 0.9): (1.0, 0.1, 0.1), (2.6, 0.9): (0.1, 1.0, 0.1), (2.6, 1.9): (0.1, 0.1, 1.0),
                      (1.6, 1.9): (1.0, 1.0, 1.0)}
    colours = [corner_colours[(p[0], p[2])] for p in tile[0]]
    second_uvs = [[(p[0] - 1.6) * 3.0, (p[2] - 0.9) * 3.0] for p in tile[0]]
    white = g.material("vertex-coloured tile", base_color=(1.0, 1.0, 1.0),
                       base_color_texture=g.texture_info(checker, tex_coord=1))
    g.node("tile", mesh=g.mesh("tile", [(tile[0], None, tile[1], white, None, colours, second_uvs)]))
    sun = g.light({"type": "directional", "name": "sun", "color": [1.0, 0.96, 0.9], "intensity": 2.5})
    g.node("sun", rotation=look_at_rotation([0.0, 0.0, 0.0], [-0.5, -1.0, -0.6]),
           extensions={"KHR_lights_punctual": {"light": sun}})
    lamp = g.light({"type": "point", "name": "lamp", "color": [0.9, 0.95, 1.0], "intensity": 25.0})
    g.node("lamp", translation=[2.5, 3.0, 3.0], extensions={"KHR_lights_punctual": {"light": lamp}})
    look_and_write(g, "textures", [0.0, 2.4, 5.2], [0.0, 0.5, 0.0], 40.0, 1.6)



def surfaces():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    checker = checker_texture(g, (235, 235, 235), (120, 125, 135))
    floor_material = g.material("floor", base_color=(1.0, 1.0, 1.0),
                                base_color_texture=g.texture_info(checker, scale=[10.0, 10.0]))
    floor = quad([[-5.0, 0.0, -5.0], [5.0, 0.0, -5.0], [5.0, 0.0, 5.0], [-5.0, 0.0, 5.0]], [0.0, 1.0, 0.0])
    uvs = [[(p[0] + 5.0) / 10.0, (p[2] + 5.0) / 10.0] for p in floor[0]]
    g.node("floor", mesh=g.mesh("floor", [(floor[0], None, floor[1], floor_material, uvs)]))

    # Two panels of domes standing at the back, facing +z: texture coordinates u along +x, v down the panel.
    domes = g.texture("domes", 64, 64, dome_normals(64, 4))
    bumps = g.material("bumps", base_color=(0.85, 0.55, 0.3), roughness=0.45,
                       normal_texture=g.texture_info(domes))
    panel = [[0.0, 0.0, 0.0], [1.6, 0.0, 0.0], [1.6, 1.6, 0.0], [0.0, 1.6, 0.0]]
    panel_uvs = [[p[0] / 1.6, 1.0 - p[1] / 1.6] for p in panel]
    normals = [[0.0, 0.0, 1.0]] * 4
    indices = [0, 1, 2, 0, 2, 3]
    derived = g.mesh("panel, tangents derived", [(panel, normals, indices, bumps, panel_uvs)])
    g.node("panel, tangents derived", mesh=derived, translation=[-2.4, 0.0, -1.5])
    given = g.mesh("panel, TANGENT", [(panel, normals, indices, bumps, panel_uvs, None, None,
                                       [[1.0, 0.0, 0.0, 1.0]] * 4)])
    # Mirrored in x: the node's transform flips the frame's handedness, which the loader must follow.
    g.node("panel, TANGENT, mirrored", mesh=given, translation=[0.8, 0.0, -1.5], scale=[-1.0, 1.0, 1.0])

    # The same domes on an analytic ball and a turned box (VKRT_sphere, VKRT_shape): their tangent frames come
    # from their own texture coordinates.
    g.sphere("bumpy ball", [2.05, 0.32, 1.55], 0.32, bumps)
    g.shape("bumpy box", "box", bumps, translation=[-2.2, 0.3, -0.3], scale=[0.3, 0.3, 0.3],
            rotation=[0.0, math.sin(math.radians(15.0)), 0.0, math.cos(math.radians(15.0))])

    # A screen with round holes (alpha 0 inside circles, MASK) casting a dotted shadow.
    holes = []
    for row in range(32):
        for col in range(32):
            x, y = (col % 8) - 3.5, (row % 8) - 3.5
            holes.append((70, 130, 180, 0 if x * x + y * y < 7.0 else 255))
    screen_material = g.material("screen", base_color=(1.0, 1.0, 1.0), alpha_mode="MASK", alpha_cutoff=0.5,
                                 base_color_texture=g.texture_info(g.texture("holes", 32, 32, holes, nearest=True)),
                                 double_sided=True)
    # Turned to face the sun, which comes from the right: its shadow falls on the floor in view.
    screen = [[1.6, 0.0, 0.9], [2.8, 0.0, -0.3], [2.8, 1.2, -0.3], [1.6, 1.2, 0.9]]
    screen_uvs = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]
    facing = [[0.7071, 0.0, 0.7071]] * 4
    g.node("screen", mesh=g.mesh("screen", [(screen, facing, indices, screen_material, screen_uvs)]))

    # A translucent pane (BLEND, alpha 0.35) in front of a sphere.
    pane_material = g.material("pane", base_color=(0.2, 0.5, 0.9), alpha=0.35, alpha_mode="BLEND",
                               roughness=0.3, double_sided=True)
    pane = quad([[-0.9, 0.0, 1.0], [0.3, 0.0, 1.0], [0.3, 1.1, 1.0], [-0.9, 1.1, 1.0]], [0.0, 0.0, 1.0])
    g.node("pane", mesh=g.mesh("pane", [(pane[0], None, pane[1], pane_material)]))
    red = g.material("red paint, clear coat", base_color=(0.8, 0.15, 0.1), roughness=0.6, clearcoat=1.0,
                     clearcoat_roughness=0.05)
    g.sphere("ball", [-0.3, 0.45, 0.3], 0.45, red)
    velvet = g.material("velvet", base_color=(0.06, 0.02, 0.12), roughness=1.0, sheen_color=(0.85, 0.55, 1.0),
                        sheen_roughness=0.5)
    g.sphere("velvet ball", [-1.0, 0.3, 2.0], 0.3, velvet)

    # An unlit sign (KHR_materials_unlit: its colours, lit by nothing) and a window whose transmission
    # texture makes clear and frosted-white stripes.
    bands = g.texture("bands", 4, 1, [(230, 60, 50, 255), (240, 200, 40, 255), (60, 170, 90, 255),
                                      (60, 110, 220, 255)], nearest=True)
    sign_material = g.material("unlit sign", base_color=(1.0, 1.0, 1.0), unlit=True,
                               base_color_texture=g.texture_info(bands))
    sign = [[-2.7, 0.0, 0.9], [-1.7, 0.0, 0.9], [-1.7, 0.5, 0.9], [-2.7, 0.5, 0.9]]
    sign_uvs = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]
    g.node("sign", mesh=g.mesh("sign", [(sign, normals, indices, sign_material, sign_uvs)]))
    stripes = g.texture("stripes", 8, 1, [(255 * (k % 2), 0, 0, 255) for k in range(8)], nearest=True)
    window_material = g.material("striped window", base_color=(1.0, 1.0, 1.0), roughness=0.0, transmission=1.0,
                                 transmission_texture=g.texture_info(stripes), double_sided=True)
    window = [[0.7, 0.0, 1.5], [1.5, 0.0, 1.5], [1.5, 0.9, 1.5], [0.7, 0.9, 1.5]]
    g.node("window", mesh=g.mesh("window", [(window, normals, indices, window_material, sign_uvs)]))

    sun = g.light({"type": "directional", "name": "sun", "color": [1.0, 0.96, 0.9], "intensity": 2.5})
    g.node("sun", rotation=look_at_rotation([0.0, 0.0, 0.0], [-0.8, -0.5, -0.3]),
           extensions={"KHR_lights_punctual": {"light": sun}})
    lamp = g.light({"type": "point", "name": "lamp", "color": [0.9, 0.95, 1.0], "intensity": 12.0})
    g.node("lamp", translation=[-2.5, 2.5, 2.5], extensions={"KHR_lights_punctual": {"light": lamp}})
    look_and_write(g, "surfaces", [0.0, 2.2, 5.0], [0.0, 0.6, -0.3], 45.0, 1.6)


def radiance_hdr(path, width, height, texel):
    """Writes an RGBE Radiance .hdr of texel(x, y) -> (r, g, b), rows top to bottom, with run-length
    scanlines of literal runs (the format stb_image and Blender read)."""
    def rgbe(colour):
        m = max(colour)
        if m < 1e-32:
            return (0, 0, 0, 0)
        mantissa, exponent = math.frexp(m)
        scale = mantissa * 256.0 / m
        return tuple(int(c * scale) for c in colour) + (exponent + 128,)

    data = bytearray(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (height, width))
    for y in range(height):
        row = [rgbe(texel(x, y)) for x in range(width)]
        data += bytes((2, 2, width >> 8, width & 255))
        for channel in range(4):
            values = [texel_bytes[channel] for texel_bytes in row]
            for start in range(0, width, 128):
                chunk = values[start:start + 128]
                data += bytes((len(chunk),)) + bytes(chunk)
    with open(path, "wb") as file:
        file.write(bytes(data))


def sky_texel(x, y, width=64, height=32):
    """The sky of sky.hdr: radiance at texel (x, y)."""
    elevation = math.pi / 2.0 - math.pi * (y + 0.5) / height
    if 38 <= x <= 39 and 9 <= y <= 10:  # the sun: u 0.61, 34 degrees up (direction (0.64, 0.56, 0.53))
        return (100.0, 92.0, 80.0)
    if elevation < 0.0:
        return (0.3, 0.24, 0.18)
    t = math.sin(elevation)  # 0 at the horizon, 1 at the zenith
    horizon, zenith = (1.0, 1.05, 1.1), (0.25, 0.45, 1.0)
    return tuple(round(h + (z - h) * t, 4) for h, z in zip(horizon, zenith))


def soft_sky_texel(x, y, width=64, height=32):
    """The sky of soft-sky.hdr: sky.hdr's without its sun, and a hazy glow of radiance about 6 within 20 degrees
    of where the sun was (texel centres; docs/environment.md's mapping, u across and v down)."""
    u, v = (x + 0.5) / width, (y + 0.5) / height
    phi, theta = (u - 0.5) * 2.0 * math.pi, v * math.pi
    direction = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
    sun = (0.64, 0.56, 0.53)
    cosine = sum(d * s for d, s in zip(direction, sun)) / math.sqrt(sum(s * s for s in sun))
    if cosine > math.cos(math.radians(20.0)):
        return (6.0, 5.5, 4.8)
    return sky_texel(x, y, width, height)  # the sun's texels lie inside the glow


def environment():
    radiance_hdr(os.path.join(OUTPUT, "sky.hdr"), 64, 32, sky_texel)
    g = GltfBuilder("vkrt tools/make_scenes.py")
    floor_material = g.material("floor", base_color=(0.5, 0.5, 0.5))
    white = g.material("white", base_color=(0.8, 0.8, 0.8))
    gold = g.material("gold", base_color=(1.0, 0.78, 0.34), metallic=1.0, roughness=0.3)
    mirror = g.material("mirror", base_color=(0.95, 0.95, 0.95), metallic=1.0, roughness=0.0)
    glass = g.material("glass", base_color=(1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5,
                       thickness=1.0)
    floor = quad([[-30.0, 0.0, -30.0], [30.0, 0.0, -30.0], [30.0, 0.0, 30.0], [-30.0, 0.0, 30.0]],
                 [0.0, 1.0, 0.0])
    g.node("floor", mesh=g.mesh("floor", [(floor[0], None, floor[1], floor_material)]))
    for k, material in enumerate((white, gold, mirror, glass)):
        g.sphere("sphere %d" % k, [-2.4 + 1.6 * k, 0.7, 0.0], 0.7, material)
    look_and_write(g, "environment", [0.0, 2.2, 6.5], [0.0, 0.6, 0.0], 40.0, 1.6)


def balls_on_a_floor(g, name, floor_material, balls, radius, eye, target, yfov_degrees, aspect_ratio):
    """Writes `name`.gltf: balls (x, material) of `radius` in a row along x on a floor 60 units across, seen from
    `eye`; the scenes compared with Cycles under soft-sky.hdr."""
    floor = quad([[-30.0, 0.0, -30.0], [30.0, 0.0, -30.0], [30.0, 0.0, 30.0], [-30.0, 0.0, 30.0]],
                 [0.0, 1.0, 0.0])
    primitives = [(floor[0], None, floor[1], floor_material)]
    for x, material in balls:
        sphere = uv_sphere([x, radius, 0.0], radius, 32, 64)
        primitives.append((sphere[0], sphere[1], sphere[2], material))
    g.node(name, mesh=g.mesh(name, primitives))
    look_and_write(g, name, eye, target, yfov_degrees, aspect_ratio)


def outdoor():
    radiance_hdr(os.path.join(OUTPUT, "soft-sky.hdr"), 64, 32, soft_sky_texel)
    g = GltfBuilder("vkrt tools/make_scenes.py")
    floor_material = g.material("floor", base_color=(0.5, 0.5, 0.5), specular=0.0)
    clay = g.material("clay", base_color=(0.8, 0.45, 0.3), specular=0.0)
    mirror = g.material("mirror", base_color=(1.0, 1.0, 1.0), metallic=1.0, roughness=0.0)
    glass = g.material("glass", base_color=(1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5,
                       thickness=1.4)
    balls_on_a_floor(g, "outdoor", floor_material, ((-1.6, clay), (0.0, mirror), (1.6, glass)), 0.7,
                     [0.0, 1.7, 5.6], [0.0, 0.55, 0.0], 40.0, 1.0)


def rough():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    floor_material = g.material("floor", base_color=(0.5, 0.5, 0.5), specular=0.0)
    balls = [("metal 0.3", dict(metallic=1.0, roughness=0.3)), ("metal 0.5", dict(metallic=1.0, roughness=0.5)),
             ("glass 0.15", dict(roughness=0.15, transmission=1.0, ior=1.5, thickness=1.0)),
             ("glass 0.3", dict(roughness=0.3, transmission=1.0, ior=1.5, thickness=1.0))]
    materials = [g.material(name, base_color=(1.0, 1.0, 1.0), **fields) for name, fields in balls]
    balls_on_a_floor(g, "rough", floor_material, zip((-2.1, -0.7, 0.7, 2.1), materials), 0.6,
                     [0.0, 1.6, 5.4], [0.0, 0.45, 0.0], 34.0, 2.0)


def tinted():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    floor_material = g.material("floor", base_color=(0.5, 0.5, 0.5), specular=0.0)
    glasses = [("amber", (0.9, 0.55, 0.25), 1.0, 0.0), ("blue", (0.35, 0.6, 0.95), 0.5, 0.0),
               ("green", (0.45, 0.85, 0.5), 0.8, 0.1)]
    materials = [g.material(name, base_color=(1.0, 1.0, 1.0), roughness=roughness, transmission=1.0, ior=1.5,
                            thickness=1.4, attenuation_color=color, attenuation_distance=distance)
                 for name, color, distance, roughness in glasses]
    balls_on_a_floor(g, "tinted", floor_material, zip((-1.6, 0.0, 1.6), materials), 0.7,
                     [0.0, 1.7, 5.6], [0.0, 0.55, 0.0], 40.0, 1.0)


def lens():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    checker = checker_texture(g, (210, 210, 200), (60, 70, 90), mipmaps=False)
    floor_material = g.material("floor", base_color=(0.9, 0.9, 0.9), specular=0.0,
                                base_color_texture=g.texture_info(checker))
    floor = quad([[-10.0, 0.0, -14.0], [10.0, 0.0, -14.0], [10.0, 0.0, 6.0], [-10.0, 0.0, 6.0]], [0.0, 1.0, 0.0])
    floor_uvs = [[p[0] + 10.0, p[2] + 14.0] for p in floor[0]]  # a cell of the checker half a unit across
    primitives = [(floor[0], None, floor[1], floor_material, floor_uvs)]
    for k, (x, z, color) in enumerate(((-0.8, 1.0, (0.8, 0.3, 0.2)), (0.7, -1.5, (0.2, 0.6, 0.3)),
                                       (-0.6, -4.5, (0.25, 0.35, 0.8)), (2.2, -8.0, (0.85, 0.7, 0.2)))):
        ball = uv_sphere([x, 0.5, z], 0.5, 32, 64)
        primitives.append((ball[0], ball[1], ball[2], g.material("ball %d" % k, base_color=color, specular=0.0)))
    g.node("lens", mesh=g.mesh("lens", primitives))
    sun = g.light({"type": "directional", "name": "sun", "color": [1.0, 0.95, 0.85], "intensity": 1.5})
    g.node("sun", rotation=look_at_rotation([0.0, 0.0, 0.0], [0.6, -1.0, -0.4]),
           extensions={"KHR_lights_punctual": {"light": sun}})
    eye, target = [0.0, 1.0, 4.0], [0.2, 0.5, -2.0]
    forward = [target[i] - eye[i] for i in range(3)]
    ball = [0.7 - eye[0], 0.5 - eye[1], -1.5 - eye[2]]  # the second ball's middle, in focus
    focus = dot(ball, forward) / math.sqrt(dot(forward, forward))
    camera = g.perspective_camera("lens-camera", math.radians(40.0), aspect_ratio=1.5, aperture=0.08,
                                  focus_distance=round(focus, 4))
    g.node("camera", camera=camera, translation=eye, rotation=look_at_rotation(eye, target))
    g.write(os.path.join(OUTPUT, "lens.gltf"))


def lamps():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    warm, cool, dark = (255, 215, 150, 255), (130, 170, 255, 255), (25, 25, 25, 255)
    stripes = g.texture("stripes", 8, 8, [(warm, warm, cool, cool, dark, warm, cool, cool)[x] for y in range(8)
                                          for x in range(8)], nearest=True, mipmaps=False)
    floor_material = g.material("floor", base_color=(0.7, 0.7, 0.7), specular=0.0)
    wall = g.material("wall", base_color=(0.6, 0.6, 0.6), specular=0.0)
    slate = g.material("slate", base_color=(0.35, 0.45, 0.6), specular=0.0)
    chalk = g.material("chalk", base_color=(0.8, 0.8, 0.8), specular=0.0)
    panel_material = g.material("panel", base_color=(0.0, 0.0, 0.0), specular=0.0, emission=(1.0, 1.0, 1.0),
                                emission_strength=4.0, emissive_texture=g.texture_info(stripes))
    glow = g.material("glow", base_color=(0.0, 0.0, 0.0), specular=0.0, emission=(1.0, 0.5, 0.2),
                      emission_strength=6.0)
    floor = quad([[-4.0, 0.0, -2.0], [4.0, 0.0, -2.0], [4.0, 0.0, 6.0], [-4.0, 0.0, 6.0]], [0.0, 1.0, 0.0])
    back = quad([[-4.0, 0.0, -2.0], [4.0, 0.0, -2.0], [4.0, 2.4, -2.0], [-4.0, 2.4, -2.0]], [0.0, 0.0, 1.0])
    panel = quad([[-1.0, 2.4, -0.6], [1.0, 2.4, -0.6], [1.0, 2.4, 0.6], [-1.0, 2.4, 0.6]], [0.0, -1.0, 0.0])
    panel_uvs = [[(p[0] + 1.0) / 2.0, (p[2] + 0.6) / 1.2] for p in panel[0]]
    block, block_normals, block_indices, _ = box([-1.2, 0.45, -0.3], [0.45, 0.45, 0.45])
    ball = uv_sphere([0.3, 0.5, 0.4], 0.5, 32, 64)
    bead = uv_sphere([1.3, 0.25, 1.0], 0.25, 16, 32)
    g.node("lamps", mesh=g.mesh("lamps", [
        (floor[0], None, floor[1], floor_material), (back[0], None, back[1], wall),
        (panel[0], None, panel[1], panel_material, panel_uvs), (block, block_normals, block_indices, slate),
        (ball[0], ball[1], ball[2], chalk), (bead[0], bead[1], bead[2], glow)]))
    look_and_write(g, "lamps", [0.0, 1.4, 5.0], [0.0, 1.0, 0.0], 45.0, 1.0)


def punctual():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    checker = checker_texture(g, (200, 200, 200), (70, 90, 120), mipmaps=False)
    red, green, blue, yellow = (200, 40, 30, 255), (40, 170, 60, 255), (40, 70, 200, 255), (230, 200, 40, 255)
    quadrants = g.texture("quadrants", 4, 4, [(red if x < 2 else green) if y < 2 else (blue if x < 2 else yellow)
                                              for y in range(4) for x in range(4)], nearest=True, mipmaps=False)
    floor_material = g.material("floor", base_color=(0.9, 0.9, 0.9), specular=0.0,
                                base_color_texture=g.texture_info(checker))
    panel_material = g.material("panel", base_color=(1.0, 1.0, 1.0), specular=0.0,
                                base_color_texture=g.texture_info(quadrants))
    clay = g.material("clay", base_color=(0.75, 0.5, 0.35), specular=0.0)
    floor = quad([[-8.0, 0.0, -8.0], [8.0, 0.0, -8.0], [8.0, 0.0, 8.0], [-8.0, 0.0, 8.0]], [0.0, 1.0, 0.0])
    floor_uvs = [[(p[0] + 8.0) / 2.0, (p[2] + 8.0) / 2.0] for p in floor[0]]  # a cell of the checker a unit across
    # The panel's texture coordinates as glTF's: (0, 0) the image's top left, at the panel's top left.
    panel = [[-1.3, 2.6, -1.6], [1.3, 2.6, -1.6], [1.3, 0.0, -1.6], [-1.3, 0.0, -1.6]]
    panel_uvs = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    block, block_normals, block_indices, block_uvs = box([0.0, 0.0, 0.0], [0.5, 0.5, 0.5])
    ball = uv_sphere([-1.6, 0.6, 0.9], 0.6, 32, 64)
    g.node("ground and panel", mesh=g.mesh("ground and panel", [
        (floor[0], None, floor[1], floor_material, floor_uvs),
        (panel, None, [0, 2, 1, 0, 3, 2], panel_material, panel_uvs),
        (ball[0], ball[1], ball[2], clay)]))
    g.node("box", mesh=g.mesh("box", [(block, block_normals, block_indices, panel_material, block_uvs)]),
           translation=[1.5, 0.5, 0.7], rotation=axis_angle([0.0, 1.0, 0.0], 35.0))
    point = g.light({"type": "point", "name": "warm point", "color": [1.0, 0.8, 0.6], "intensity": 6.0})
    g.node("point", translation=[0.6, 2.3, 2.2], extensions={"KHR_lights_punctual": {"light": point}})
    sun = g.light({"type": "directional", "name": "sun", "color": [0.85, 0.9, 1.0], "intensity": 1.2})
    g.node("sun", rotation=look_at_rotation([0.0, 0.0, 0.0], [-0.45, -1.0, -0.6]),
           extensions={"KHR_lights_punctual": {"light": sun}})
    look_and_write(g, "punctual", [0.0, 2.3, 6.4], [0.0, 0.8, 0.0], 40.0, 1.0)


def streaks():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    checker = checker_texture(g, (200, 200, 200), (70, 90, 120), mipmaps=False)
    floor_material = g.material("floor", base_color=(0.9, 0.9, 0.9), specular=0.0,
                                base_color_texture=g.texture_info(checker))
    clay = g.material("clay", base_color=(0.8, 0.45, 0.3), specular=0.0)
    slate = g.material("slate", base_color=(0.3, 0.45, 0.75), specular=0.0)
    chalk = g.material("chalk", base_color=(0.8, 0.8, 0.75), specular=0.0)
    floor = quad([[-8.0, 0.0, -8.0], [8.0, 0.0, -8.0], [8.0, 0.0, 8.0], [-8.0, 0.0, 8.0]], [0.0, 1.0, 0.0])
    floor_uvs = [[(p[0] + 8.0) / 2.0, (p[2] + 8.0) / 2.0] for p in floor[0]]  # a cell of the checker a unit across
    still = uv_sphere([-0.6, 0.4, -1.6], 0.4, 32, 64)
    g.node("floor and still ball", mesh=g.mesh("floor and still ball", [
        (floor[0], None, floor[1], floor_material, floor_uvs), (still[0], still[1], still[2], chalk)]))
    # Over the one-second shutter: a ball sliding 2 units along x (LINEAR translation), and a box moving 1.2
    # units towards the camera while it turns 90 degrees about y, its rotation keyed every 11.25 degrees (so
    # that any interpolation of the keys between them, spherical or by normalised components, is the same turn).
    ball = uv_sphere([0.0, 0.0, 0.0], 0.5, 32, 64)
    slider = g.node("sliding ball", mesh=g.mesh("ball", [(ball[0], ball[1], ball[2], clay)]),
                    translation=[-1.9, 0.5, 0.5])
    g.animate(slider, "translation", [0.0, 1.0], [[-1.9, 0.5, 0.5], [0.1, 0.5, 0.5]])
    block, block_normals, block_indices, _ = box([0.0, 0.0, 0.0], [0.45, 0.45, 0.45])
    turner = g.node("turning box", mesh=g.mesh("box", [(block, block_normals, block_indices, slate)]),
                    translation=[1.5, 0.45, -1.0])
    g.animate(turner, "translation", [0.0, 1.0], [[1.5, 0.45, -1.0], [1.5, 0.45, 0.2]])
    keys = [k / 8.0 for k in range(9)]
    g.animate(turner, "rotation", keys, [axis_angle([0.0, 1.0, 0.0], 90.0 * k) for k in keys])
    g.gltf["scenes"][0]["extras"] = {"shutter": [0.0, 1.0]}
    point = g.light({"type": "point", "name": "warm point", "color": [1.0, 0.85, 0.7], "intensity": 5.0})
    g.node("point", translation=[-1.0, 2.6, 2.4], extensions={"KHR_lights_punctual": {"light": point}})
    sun = g.light({"type": "directional", "name": "sun", "color": [0.9, 0.92, 1.0], "intensity": 1.2})
    g.node("sun", rotation=look_at_rotation([0.0, 0.0, 0.0], [0.5, -1.0, -0.45]),
           extensions={"KHR_lights_punctual": {"light": sun}})
    look_and_write(g, "streaks", [0.0, 2.4, 6.0], [0.0, 0.5, -0.2], 38.0, 1.5)


def spots():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    floor_material = g.material("floor", base_color=(0.75, 0.75, 0.75), specular=0.0)
    wall = g.material("wall", base_color=(0.6, 0.6, 0.6), specular=0.0)
    clay = g.material("clay", base_color=(0.8, 0.45, 0.3), specular=0.0)
    slate = g.material("slate", base_color=(0.3, 0.45, 0.75), specular=0.0)
    floor = quad([[-5.0, 0.0, -2.0], [5.0, 0.0, -2.0], [5.0, 0.0, 6.0], [-5.0, 0.0, 6.0]], [0.0, 1.0, 0.0])
    back = quad([[-5.0, 0.0, -2.0], [5.0, 0.0, -2.0], [5.0, 4.0, -2.0], [-5.0, 4.0, -2.0]], [0.0, 0.0, 1.0])
    block, block_normals, block_indices, _ = box([0.9, 0.4, -0.6], [0.4, 0.4, 0.4])
    ball = uv_sphere([-0.9, 0.5, 0.0], 0.5, 32, 64)
    g.node("spots", mesh=g.mesh("spots", [
        (floor[0], None, floor[1], floor_material), (back[0], None, back[1], wall),
        (block, block_normals, block_indices, slate), (ball[0], ball[1], ball[2], clay)]))
    # Two spot lights: a warm one with a soft edge (inner 15, outer 32 degrees) over the ball, and a cool one
    # with the edge soft all the way in (inner 0, outer 22 degrees) and a range of 7 raking the wall past the box;
    # and a point light whose range of 1.8 ends its pool of light on the floor.
    warm = g.light({"type": "spot", "name": "warm spot", "color": [1.0, 0.85, 0.65], "intensity": 15.0,
                    "spot": {"innerConeAngle": math.radians(15.0), "outerConeAngle": math.radians(32.0)}})
    position = [-1.3, 2.8, 1.4]
    g.node("warm spot", translation=position, rotation=look_at_rotation(position, [-0.7, 0.0, -0.4]),
           extensions={"KHR_lights_punctual": {"light": warm}})
    cool = g.light({"type": "spot", "name": "cool spot", "color": [0.7, 0.8, 1.0], "intensity": 40.0,
                    "range": 7.0, "spot": {"innerConeAngle": 0.0, "outerConeAngle": math.radians(22.0)}})
    position = [2.4, 2.0, 2.2]
    g.node("cool spot", translation=position, rotation=look_at_rotation(position, [0.6, 0.9, -2.0]),
           extensions={"KHR_lights_punctual": {"light": cool}})
    short = g.light({"type": "point", "name": "short point", "color": [1.0, 0.95, 0.9], "intensity": 4.0,
                     "range": 1.8})
    g.node("short point", translation=[0.5, 0.9, 1.2], extensions={"KHR_lights_punctual": {"light": short}})
    look_and_write(g, "spots", [0.0, 1.7, 5.2], [0.0, 0.8, 0.0], 45.0, 1.0)


def studio():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    white = g.material("white", base_color=(0.8, 0.8, 0.8), specular=0.0)
    blue = g.material("blue", base_color=(0.2, 0.35, 0.7), specular=0.0)
    orange = g.material("orange", base_color=(0.85, 0.45, 0.15), specular=0.0)
    panel = g.material("softbox", base_color=(0.0, 0.0, 0.0), emission=(1.0, 0.96, 0.9), emission_strength=2.0,
                       specular=0.0)
    floor = quad([[-2.0, 0.0, -2.0], [2.0, 0.0, -2.0], [2.0, 0.0, 4.5], [-2.0, 0.0, 4.5]], [0.0, 1.0, 0.0])
    back = quad([[-2.0, 0.0, -2.0], [2.0, 0.0, -2.0], [2.0, 2.2, -2.0], [-2.0, 2.2, -2.0]], [0.0, 0.0, 1.0])
    # The softbox: 2.8 x 2.8 at 1.5 above the floor, facing down; each of its triangles covers 6% of the square
    # of the scene's diagonal.
    softbox = quad([[-1.4, 1.5, -1.4], [1.4, 1.5, -1.4], [1.4, 1.5, 1.4], [-1.4, 1.5, 1.4]], [0.0, -1.0, 0.0])
    block, _, block_indices, _ = box([-0.6, 0.35, -0.4], [0.35] * 3)
    ball = uv_sphere([0.65, 0.4, 0.2], 0.4, 24, 48)
    primitives = [(floor[0], None, floor[1], white), (back[0], None, back[1], white),
                  (softbox[0], None, softbox[1], panel), (block, None, block_indices, orange),
                  (ball[0], ball[1], ball[2], blue)]
    g.node("studio", mesh=g.mesh("studio", primitives))
    look_and_write(g, "studio", [0.0, 0.9, 4.2], [0.0, 0.45, 0.0], 36.0, 1.0)


def axis_angle(axis, degrees):
    """Quaternion (x, y, z, w) of a turn by `degrees` about a unit axis."""
    s = math.sin(math.radians(degrees) / 2)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(math.radians(degrees) / 2)]


def quaternion_product(a, b):
    """The quaternion of turning by b, then by a."""
    return [a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
            a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
            a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
            a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]]


def vertex_normals(positions, indices):
    """Smooth normals: each vertex's faces' area-weighted normals, summed over the vertices at its position (a UV
    sphere's seam and poles repeat positions)."""
    sums = {}
    for t in range(0, len(indices), 3):
        a, b, c = (positions[i] for i in indices[t:t + 3])
        n = cross(sub(b, a), sub(c, a))
        for i in indices[t:t + 3]:
            key = tuple(round(x, 9) for x in positions[i])
            sums[key] = [sums.get(key, [0.0, 0.0, 0.0])[k] + n[k] for k in range(3)]
    normals = []
    for p in positions:
        n = sums[tuple(round(x, 9) for x in p)]
        length = math.sqrt(dot(n, n))
        normals.append([x / length for x in n])
    return normals


def deform():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    light_grey = g.material("light grey", base_color=(0.7, 0.7, 0.7))
    dark_grey = g.material("dark grey", base_color=(0.35, 0.35, 0.38))
    tube_paint = g.material("tube", base_color=(0.15, 0.45, 0.8), roughness=0.35)
    ball_paint = g.material("ball", base_color=(0.85, 0.3, 0.1), roughness=0.4)
    checker_floor(g, "floor", light_grey, dark_grey)

    # The tube, modelled in its bind pose (upright, its foot at `foot`), skinned to a hip at its foot and a knee
    # 1.2 above it: below 0.9 the hip alone, above 1.5 the knee alone, blended linearly between.
    foot, radius, height, rings, segments = [-0.6, 0.0, -0.5], 0.22, 2.4, 24, 20
    positions, normals, joints, weights, indices = [], [], [], [], []
    for r in range(rings + 1):
        y = height * r / rings
        knee = min(max((y - 0.9) / 0.6, 0.0), 1.0)
        for k in range(segments + 1):
            phi = 2 * math.pi * k / segments
            n = [math.cos(phi), 0.0, -math.sin(phi)]
            positions.append([foot[0] + radius * n[0], y, foot[2] + radius * n[2]])
            normals.append(n)
            joints.append([0, 1, 0, 0])
            weights.append([1.0 - knee, knee, 0.0, 0.0])
    for r in range(rings):
        for k in range(segments):
            a = r * (segments + 1) + k
            b = a + segments + 1
            indices += [a, a + 1, b + 1, a, b + 1, b]
    centre = len(positions)  # the top cap: a fan about its centre, on the knee alone
    positions.append([foot[0], height, foot[2]])
    normals.append([0.0, 1.0, 0.0])
    joints.append([0, 1, 0, 0])
    weights.append([0.0, 1.0, 0.0, 0.0])
    for k in range(segments):
        phi0, phi1 = 2 * math.pi * k / segments, 2 * math.pi * (k + 1) / segments
        for phi in (phi0, phi1):
            positions.append([foot[0] + radius * math.cos(phi), height, foot[2] - radius * math.sin(phi)])
            normals.append([0.0, 1.0, 0.0])
            joints.append([0, 1, 0, 0])
            weights.append([0.0, 1.0, 0.0, 0.0])
        indices += [centre, len(positions) - 2, len(positions) - 1]
    tube = g.deforming_mesh("tube", positions, normals, indices, tube_paint, joints=joints, weights=weights)
    hip = g.node("hip", translation=foot)
    knee = g.node("knee", parent=hip, translation=[0.0, 1.2, 0.0], rotation=axis_angle([0.0, 0.0, 1.0], 50.0))
    inverse_binds = [[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -foot[0], -foot[1], -foot[2], 1],
                     [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -foot[0], -foot[1] - 1.2, -foot[2], 1]]
    g.node("bent tube", mesh=tube, skin=g.skin([hip, knee], inverse_binds))
    g.animate(knee, "rotation", [0.0, 1.0], [axis_angle([0.0, 0.0, 1.0], 50.0), axis_angle([0.0, 0.0, 1.0], 10.0)])

    # The ball: a UV sphere of radius 0.55, its targets the displacements to a box (each point moved along its
    # direction onto the box of half-size 0.5) and to a squashed ball (half as high, 1.3 times as wide); each
    # target's normal displacements from its full-weight shape's own normals.
    ball, ball_normals, ball_indices = uv_sphere([0.0, 0.0, 0.0], 0.55, 24, 32)
    boxed, squashed = [], []
    for p in ball:
        largest = max(abs(c) for c in p)
        boxed.append([0.5 * c / largest - c for c in p])
        squashed.append([0.3 * p[0], -0.5 * p[1], 0.3 * p[2]])
    targets = []
    for displacement in (boxed, squashed):
        shape = [[p[k] + d[k] for k in range(3)] for p, d in zip(ball, displacement)]
        shape_normals = vertex_normals(shape, ball_indices)
        targets.append((displacement, [[m[k] - n[k] for k in range(3)] for m, n in zip(shape_normals, ball_normals)]))
    morph = g.deforming_mesh("morphing ball", ball, ball_normals, ball_indices, ball_paint, targets=targets,
                             target_weights=[0.6, 0.0])
    boxy = g.node("boxy ball", mesh=morph, translation=[0.7, 0.55, 0.4])
    g.node("squashed ball", mesh=morph, translation=[1.9, 0.275, -0.7], weights=[0.0, 1.0])
    g.animate(boxy, "weights", [0.0, 1.0], [[0.6, 0.0], [0.0, 0.8]])

    eye, target = [0.3, 2.4, 6.4], [0.3, 0.95, 0.0]
    camera = g.perspective_camera("deform-camera", math.radians(42.0), aspect_ratio=1.5)
    g.node("camera", camera=camera, translation=eye, rotation=look_at_rotation(eye, target))
    light = g.light({"type": "point", "name": "lamp", "color": [1.0, 0.97, 0.9], "intensity": 60.0})
    g.node("lamp", translation=[2.5, 5.0, 4.0], extensions={"KHR_lights_punctual": {"light": light}})
    sun = g.light({"type": "directional", "name": "sun", "color": [0.9, 0.95, 1.0], "intensity": 1.5})
    g.node("sun", rotation=look_at_rotation([0.0, 0.0, 0.0], [-0.4, -1.0, -0.6]),
           extensions={"KHR_lights_punctual": {"light": sun}})
    g.write(os.path.join(OUTPUT, "deform.gltf"))


def csg():
    g = GltfBuilder("vkrt tools/make_scenes.py")
    g.required.update(("VKRT_shape", "VKRT_csg"))  # without them a viewer would show an empty floor

    def matte(name, colour):
        return g.material(name, base_color=colour, specular=0.0)

    floor_material = matte("floor", (0.5, 0.5, 0.5))
    floor = quad([[-12.0, 0.0, -12.0], [12.0, 0.0, -12.0], [12.0, 0.0, 12.0], [-12.0, 0.0, 12.0]], [0.0, 1.0, 0.0])
    g.node("floor", mesh=g.mesh("floor", [(floor[0], None, floor[1], floor_material)]))
    up = [0.0, 1.0, 0.0]

    # The back row: the classic CSG pieces, each operand in a colour of its own (a surface of the result keeps
    # its shape's material). A box minus a sphere 1.3 times its half width: the corners and edges remain, each
    # face has a bowl bitten out of it. The csg node's transform places both operands.
    bitten = g.csg("box minus sphere", "difference", translation=[-2.2, 0.7, -1.5], rotation=axis_angle(up, 30.0),
                   scale=[0.7, 0.7, 0.7])
    g.shape("box", "box", matte("blue", (0.15, 0.3, 0.75)), parent=bitten)
    g.shape("bite", "sphere", matte("orange", (0.95, 0.45, 0.1)), parent=bitten, scale=[1.3, 1.3, 1.3])

    # A biconvex lens standing on its rim, facing the camera: two spheres of radius 1.5 whose centres are 2.5
    # apart, so the lens is 0.5 thick at its centre and 0.83 in radius. Glass with a volume: the light blue
    # attenuation deepens towards the thick middle (Beer's law over the distance inside the one solid).
    glass = g.material("tinted glass", base_color=(1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5,
                       thickness=0.5, attenuation_color=(0.45, 0.75, 0.95), attenuation_distance=0.5)
    rim = math.sqrt(1.5 ** 2 - 1.25 ** 2)
    lens = g.csg("lens", "intersection", translation=[0.0, rim, -1.5])
    g.shape("lens, front surface", "sphere", glass, parent=lens, translation=[0.0, 0.0, -1.25], scale=[1.5, 1.5, 1.5])
    g.shape("lens, back surface", "sphere", glass, parent=lens, translation=[0.0, 0.0, 1.25], scale=[1.5, 1.5, 1.5])

    # A sphere drilled from the top by a thin long cylinder and from the side by one turned to lie horizontally
    # and face the camera at an angle (the difference subtracts every operand after the first).
    drilled = g.csg("drilled sphere", "difference", translation=[2.2, 0.85, -1.5])
    g.shape("ball", "sphere", matte("green", (0.2, 0.6, 0.25)), parent=drilled, scale=[0.85, 0.85, 0.85])
    g.shape("vertical bore", "cylinder", matte("red", (0.8, 0.12, 0.08)), parent=drilled,
            scale=[0.3, 1.2, 0.3])
    g.shape("horizontal bore", "cylinder", matte("yellow", (0.9, 0.75, 0.1)), parent=drilled,
            rotation=quaternion_product(axis_angle(up, -35.0), axis_angle([1.0, 0.0, 0.0], 90.0)),
            scale=[0.22, 1.2, 0.22])

    # The front row: each shape under a non-uniform scale, resting on the floor. A cone with an elliptical base,
    # turned, and mirrored in x (a negative determinant: it looks the same, and its outside stays outside).
    g.shape("cone", "cone", matte("teal", (0.1, 0.55, 0.55)), translation=[-2.8, 0.75, 1.1],
            rotation=axis_angle(up, 50.0), scale=[-0.55, 0.75, 0.35])
    # An ellipsoid of semi-axes 0.75, 0.45 and 0.45, tilted 25 degrees about z and turned about y; its lowest
    # point is hypot(0.75 sin 25, 0.45 cos 25) below its centre.
    tilt = math.radians(25.0)
    gold = g.material("gold", base_color=(1.0, 0.78, 0.34), metallic=1.0, roughness=0.3)
    g.shape("ellipsoid", "sphere", gold,
            translation=[-0.8, math.hypot(0.75 * math.sin(tilt), 0.45 * math.cos(tilt)), 1.1],
            rotation=quaternion_product(axis_angle(up, -30.0), axis_angle([0.0, 0.0, 1.0], 25.0)),
            scale=[0.75, 0.45, 0.45])
    # A slab, turned, with a checker (4 x 4 squares a face, in the box's texture coordinates).
    checker = checker_texture(g, (235, 235, 235), (200, 40, 30))
    checked = g.material("checker", base_color=(1.0, 1.0, 1.0), specular=0.0,
                         base_color_texture=g.texture_info(checker, scale=[2.0, 2.0]))
    g.shape("slab", "box", checked, translation=[1.0, 0.3, 1.1], rotation=axis_angle(up, 35.0),
            scale=[0.6, 0.3, 0.4])
    # An oblique cylinder: radius 0.4, 1.6 high, sheared so its top is 0.8 further in -x than its base (x -= 0.5
    # y after the scale); the caps stay level. The matrix is column-major, as glTF stores it.
    g.shape("oblique cylinder", "cylinder", matte("purple", (0.5, 0.25, 0.7)),
            matrix=[0.4, 0.0, 0.0, 0.0,  -0.4, 0.8, 0.0, 0.0,  0.0, 0.0, 0.4, 0.0,  2.9, 0.8, 1.1, 1.0])

    # The area light: a thin emissive box high above the middle (out of the camera's view), and a point light.
    lamp = g.material("lamp", base_color=(0.0, 0.0, 0.0), emission=(1.0, 0.95, 0.85), emission_strength=20.0)
    g.shape("lamp", "box", lamp, translation=[0.5, 5.0, 1.0], scale=[1.0, 0.04, 0.7])
    point = g.light({"type": "point", "name": "fill", "color": [0.9, 0.95, 1.0], "intensity": 40.0})
    g.node("fill", translation=[-4.0, 6.0, 5.0], extensions={"KHR_lights_punctual": {"light": point}})
    look_and_write(g, "csg", [0.0, 3.0, 7.4], [0.0, 0.5, -0.3], 40.0, 1.6)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="Generates vkrt's scenes.")
    parser.add_argument("output", nargs="?", default=SCENES, help="folder to write to (default: scenes/)")
    OUTPUT = parser.parse_args().output
    try:
        os.makedirs(OUTPUT, exist_ok=True)
    except OSError as error:
        parser.error(f"cannot make the folder {OUTPUT}: {error.strerror}")
    if not os.access(OUTPUT, os.W_OK):
        parser.error(f"the folder {OUTPUT} cannot be written")
    cornell()
    whitted()
    lights()
    many_lights()
    dof()
    glossy()
    motion_blur()
    textures()
    surfaces()
    environment()
    outdoor()
    csg()
    deform()
    studio()
    punctual()
    rough()
    lamps()
    tinted()
    lens()
    streaks()
    spots()
