"""Renders an independent reference image of a vkrt glTF scene with Blender's Cycles path tracer.

Made for scenes/cornell.gltf, outdoor.gltf, rough.gltf, tinted.gltf, punctual.gltf, lamps.gltf, lens.gltf,
streaks.gltf and spots.gltf, whose materials and lights are each one that Cycles means the same by: the scene's geometry, camera and lights' places
come through Blender's own glTF importer, and every material and light is then rebuilt from the glTF file itself
(read here as JSON, matched to Blender's by name), so nothing of the importer's conversions is left:

- purely Lambertian (KHR_materials_specular with specularFactor 0), with an optional emission:
  Diffuse BSDF (colour = baseColorFactor's RGB, roughness 0: Lambert)
    + Emission (colour = emissiveFactor x KHR_materials_emissive_strength, strength 1);
- white metal (metallicFactor 1, baseColorFactor 1, 1, 1): Glossy BSDF, white, sharp at roughnessFactor 0 and
  else multiple-scattering GGX of the same roughness (Cycles squares it to GGX's alpha, as glTF does). glTF's
  metal takes its Fresnel term from its base colour, which is 1 at every angle for white;
- glass (KHR_materials_transmission factor 1, metallicFactor 0, a white base colour, KHR_materials_ior,
  KHR_materials_volume of some thickness: refraction into a solid, not a thin wall): Glass BSDF, white, the
  same index, sharp or multiple-scattering GGX of the same roughness; the volume's attenuation (colour c at
  distance d, Beer's law: transmittance c^(x / d) over a length x) as a homogeneous Volume Absorption of
  coefficient -ln(c) / d per channel.
  Both are the exact dielectric Fresnel term with refraction by Snell's law. A rough lobe keeps in Cycles the
  energy that single-scattering GGX loses by its random walk among the microfacets, in vkrt by its
  compensation (docs/materials.md): the same energy, not quite the same distribution of it.

A Lambertian material may have a base colour texture (multiplied by baseColorFactor, as glTF says) and an
emissive texture (multiplied by emissiveFactor and the strength), each where
Cycles samples it as vkrt does: TEXCOORD_0, no KHR_texture_transform, a sampler of magFilter and minFilter
NEAREST (the nearest texel, no mipmaps: Cycles' Closest interpolation) that repeats (REPEAT both ways), an image
in sRGB. Other textures, other metals, thin or textured transmission and the other extensions are not
supported: the script stops on a material that has them.

Punctual lights (KHR_lights_punctual), each named: a point light of intensity I candela is taken as I watts
per steradian (vkrt's convention: irradiance I / d^2), which is a Cycles point light of radius 0 and power
4 pi I watts; a directional light of intensity E lux as E watts per square metre, a Cycles sun of angle 0 and
strength E (a Lambertian surface of albedo 1 facing it reads E / pi). Both were measured in Blender 3.4.1: a
white Lambertian plane 2 below a 100 W point light reads 0.6237 (100 / (4 pi 4) / pi = 0.633 at the middle,
0.629 averaged over the pixel), under a sun of strength 1 it reads 0.3183. A spot light is a point light whose
intensity glTF's cone scales; Cycles 3.4's spot light is dimmed by the cosine of the angle to its axis instead
(the same measurement: 0.87 of the point light's at 30 degrees off its axis), so its cone is opened and its
emission shaped by nodes into glTF's (gltf_falloff). Measured: a white plane 2 below a spot light of 10
candela (inner cone 20 degrees, outer 45) turned 25 degrees off the vertical read glTF's irradiance / pi within
0.1% across the cone (0.74035 against 0.74086 at its brightest, 0.02424 against 0.02424 far out), except where
the cone's edge crosses a pixel (0.03519 against 0.03354 at the pixel's middle). glTF's range window on a point
or spot light is made by nodes too (gltf_falloff): a white plane 1.5 below a point light of 10 candela and range 3
read glTF's irradiance / pi within 0.9% (1.24472 against 1.24563 near the middle, 0.07821 against 0.07756 near
the range's end, at the pixels' middles) and 0 beyond. The importer places each light; its power, colour, cone
and range are set here from the glTF file.

Motion blur: vkrt's shutter (--shutter OPEN CLOSE as vkrt's option, else the scene's extras {"shutter": [open,
close]}) as Cycles' motion blur of the same interval. The importer keys the file's animation at one frame a
second (render.fps 1), Cycles' shutter opens at that frame (position START) and lasts as many frames, with a box
shutter curve, and each object's transform is taken at 2^6 steps. Only LINEAR translation, rotation and scale of
nodes without a camera or a light may move (gltf_shutter says why).

A lens (vkrt's camera extras `aperture` and `focusDistance`) is Cycles' depth of field of the same radius and
plane in focus, a round aperture.

Emission: vkrt's glTF emission is one-sided (only the front face emits), Cycles' Emission shader emits from
both sides. In the Cornell box the lamp's back side faces the empty space above the hole in the ceiling,
where there is nothing to light, so the two agree there; a scene whose emitters' backs can be seen or light
something would not.

Cycles' Emission of strength 1 and colour C makes a surface whose radiance is C (a pixel that sees it
directly reads C), which is what glTF's emissiveFactor x emissiveStrength means.

The world is black, or with --environment FILE (and --environment-strength, --environment-rotation, as
vkrt's options) the equirectangular map as an Environment Texture with the closest texel (vkrt's lookup, so
both mean the same piecewise-constant radiance), in the mapping docs/environment.md gives.

Run it with Blender (Debian 12's blender 3.4.1 and python3-numpy, which Blender's glTF importer needs):

    blender -b --factory-startup -P tools/cycles_reference.py -- \\
        --scene scenes/cornell.gltf --out tests/references/cornell-cycles.exr \\
        --width 128 --height 128 --spp 16384 --seed 0

The output is an OpenEXR file of scene-linear RGB (no view transform, no compositing, no denoising),
32-bit float unless --half is given, ZIP-compressed, rows top to bottom as in any image file; --png FILE also
writes it as an sRGB PNG, clamped, to look at.
"""

import argparse
import base64
import json
import math
import os
import sys
import tempfile
import time

import bpy
from mathutils import Vector


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="blender -b --factory-startup -P tools/cycles_reference.py --",
                                     description="Cycles reference render of a Lambertian glTF scene.")
    parser.add_argument("--scene", required=True, help="the glTF file")
    parser.add_argument("--out", required=True, help="the OpenEXR file to write")
    parser.add_argument("--width", type=int, default=128)
    parser.add_argument("--height", type=int, default=128)
    parser.add_argument("--spp", type=int, default=16384, help="samples per pixel")
    parser.add_argument("--seed", type=int, default=0, help="Cycles' sampling seed")
    parser.add_argument("--threads", type=int, default=2, help="CPU threads")
    parser.add_argument("--bounces", type=int, default=1024, help="most bounces (Cycles allows 0 to 1024)")
    parser.add_argument("--half", action="store_true", help="write 16-bit half floats instead of 32-bit")
    parser.add_argument("--png", help="also write the image here as an 8-bit sRGB PNG, clamped (vkrt's "
                        "--tonemap clamp), for looking at")
    parser.add_argument("--environment", help="an equirectangular .hdr or .exr map lighting the scene (vkrt's "
                        "--environment); without it the world is black")
    parser.add_argument("--environment-strength", type=float, default=1.0, help="the map's factor [1]")
    parser.add_argument("--environment-rotation", type=float, default=0.0,
                        help="degrees about glTF's +Y, as vkrt's option [0]")
    parser.add_argument("--shutter", type=float, nargs=2, metavar=("OPEN", "CLOSE"),
                        help="seconds of the file's animation timeline, as vkrt's option [the scene's extras, "
                        "else closed at 0]")
    return parser.parse_args(argv)


def texture_problems(gltf, info, key):
    """What stops Cycles sampling the texture `info` (the textureInfo `key` of a material) as vkrt does, if
    anything."""
    problems = []
    if info.get("texCoord", 0) != 0 or info.get("extensions"):
        problems.append(key + " read through TEXCOORD_1 or a KHR_texture_transform")
    texture = gltf["textures"][info["index"]]
    sampler = gltf.get("samplers", [])[texture["sampler"]] if "sampler" in texture else {}
    if sampler.get("magFilter") != 9728 or sampler.get("minFilter") != 9728:
        problems.append(key + " not sampled at the nearest texel without mipmaps (NEAREST)")
    if sampler.get("wrapS", 10497) != 10497 or sampler.get("wrapT", 10497) != 10497:
        problems.append(key + " not repeated (REPEAT)")
    return problems


def texture_image(gltf, info, scene_path):
    """The encoded image (PNG or JPEG bytes) of the textureInfo `info`."""
    image = gltf["images"][gltf["textures"][info["index"]]["source"]]
    if "bufferView" in image:
        view = gltf["bufferViews"][image["bufferView"]]
        buffer = gltf["buffers"][view["buffer"]]
        if not buffer.get("uri", "").startswith("data:"):
            sys.exit("texture images in external or GLB buffers are not supported")
        data = base64.b64decode(buffer["uri"].split(",", 1)[1])
        return data[view.get("byteOffset", 0):view.get("byteOffset", 0) + view["byteLength"]]
    if image["uri"].startswith("data:"):
        return base64.b64decode(image["uri"].split(",", 1)[1])
    with open(os.path.join(os.path.dirname(scene_path), image["uri"]), "rb") as f:
        return f.read()


def material_kind(gltf, material):
    """What `material` (a glTF material) is to Cycles: "lambert", "metal" or "glass", or a list of what stops
    it being any of them."""
    pbr = material.get("pbrMetallicRoughness", {})
    extensions = material.get("extensions", {})
    problems = ["metallicRoughnessTexture"] if "metallicRoughnessTexture" in pbr else []
    if "baseColorTexture" in pbr:
        problems += texture_problems(gltf, pbr["baseColorTexture"], "baseColorTexture")
        if pbr.get("metallicFactor", 1.0) != 0.0 or extensions.get("KHR_materials_transmission"):
            problems.append("baseColorTexture on other than a Lambertian material")
    problems += [key for key in ("normalTexture", "occlusionTexture") if key in material]
    if "emissiveTexture" in material:
        problems += texture_problems(gltf, material["emissiveTexture"], "emissiveTexture")
    if material.get("alphaMode", "OPAQUE") != "OPAQUE":
        problems.append("alphaMode %s" % material["alphaMode"])
    base = list(pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0]))[:3]
    metallic, roughness = pbr.get("metallicFactor", 1.0), pbr.get("roughnessFactor", 1.0)
    specular = extensions.get("KHR_materials_specular", {})
    if "specularColorFactor" in specular or "specularTexture" in specular:
        problems.append("specularColorFactor or specularTexture")
    transmission = extensions.get("KHR_materials_transmission", {})
    volume = extensions.get("KHR_materials_volume", {})
    if problems:
        return problems
    if not transmission and metallic == 0.0 and specular.get("specularFactor", 1.0) == 0.0:
        unknown = [key for key in extensions if key not in ("KHR_materials_emissive_strength",
                                                            "KHR_materials_specular")]
        return ["extension " + key for key in unknown] or "lambert"
    if not transmission and not extensions and metallic == 1.0 and base == [1.0, 1.0, 1.0]:
        return "metal" if not any(material.get("emissiveFactor", [0.0, 0.0, 0.0])) else ["emission"]
    if (transmission.get("transmissionFactor", 0.0) == 1.0 and "transmissionTexture" not in transmission and
            metallic == 0.0 and base == [1.0, 1.0, 1.0] and not specular and
            not any(material.get("emissiveFactor", [0.0, 0.0, 0.0])) and
            volume.get("thicknessFactor", 0.0) > 0.0 and
            set(extensions) <= {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"}):
        return "glass"
    return ["not purely Lambertian (KHR_materials_specular factor 0), white metal or clear glass"]


def gltf_materials(path):
    """What every material of the glTF file is to Cycles, by name: its kind, and for a Lambertian one its
    diffuse colour and emitted radiance, for glass its index of refraction."""
    with open(path) as f:
        gltf = json.load(f)
    materials = {}
    for index, material in enumerate(gltf.get("materials", [])):
        name = material.get("name", "material %d" % index)
        kind = material_kind(gltf, material)
        if isinstance(kind, list):
            sys.exit("material %r is not one Cycles means the same by: %s" % (name, ", ".join(kind)))
        if name in materials:
            sys.exit("two materials are named %r: cannot match them to Blender's by name" % name)
        extensions = material.get("extensions", {})
        strength = extensions.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
        materials[name] = {
            "kind": kind,
            "diffuse": list(material.get("pbrMetallicRoughness", {}).get("baseColorFactor", [1.0, 1.0, 1.0]))[:3],
            "emission": [c * strength for c in material.get("emissiveFactor", [0.0, 0.0, 0.0])],
            "ior": extensions.get("KHR_materials_ior", {}).get("ior", 1.5),
            "roughness": material.get("pbrMetallicRoughness", {}).get("roughnessFactor", 1.0),
        }
        volume = extensions.get("KHR_materials_volume", {})
        if kind == "glass" and "attenuationDistance" in volume:
            materials[name]["absorption"] = [-math.log(c) / volume["attenuationDistance"]
                                             for c in volume.get("attenuationColor", [1.0, 1.0, 1.0])]
        info = material.get("pbrMetallicRoughness", {}).get("baseColorTexture")
        if info is not None:
            materials[name]["texture"] = texture_image(gltf, info, path)
        if "emissiveTexture" in material:
            materials[name]["emissive texture"] = texture_image(gltf, material["emissiveTexture"], path)
    return gltf, materials


def gltf_lights(gltf):
    """Every punctual light of the glTF file by name: its Cycles type, power or strength and colour."""
    lights = {}
    for index, light in enumerate(gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])):
        name = light.get("name")
        if not name or name in lights:
            sys.exit("light %d: every light needs a name of its own, to match it to Blender's" % index)
        intensity = light.get("intensity", 1.0)
        kind = {"point": "POINT", "spot": "SPOT", "directional": "SUN"}[light["type"]]
        lights[name] = {"type": kind, "energy": intensity if kind == "SUN" else 4.0 * math.pi * intensity,
                        "color": list(light.get("color", [1.0, 1.0, 1.0]))}
        if kind == "SPOT":
            spot = light.get("spot", {})
            lights[name]["cone"] = (spot.get("innerConeAngle", 0.0), spot.get("outerConeAngle", math.pi / 4.0))
        if kind != "SUN" and "range" in light:
            lights[name]["range"] = light["range"]
    return lights


def gltf_shutter(gltf, requested):
    """vkrt's shutter (seconds of the file's animation timeline): --shutter, else the scene's extras, else closed
    at 0. Only what Cycles blurs as vkrt does may move: nodes animated by LINEAR translation, rotation and scale
    (Cycles samples each object's transform at 2^6 steps over the shutter and interpolates between them, as
    vkrt follows 16 segments, exact for translation; STEP or CUBICSPLINE keys and morph weights would not mean
    the same), and no camera or light (vkrt keeps them where they are at the shutter's opening)."""
    shutter = requested or gltf["scenes"][gltf.get("scene", 0)].get("extras", {}).get("shutter", [0.0, 0.0])
    animations = gltf.get("animations", [])
    if shutter[1] > shutter[0] and animations:
        parents = {child: parent for parent, node in enumerate(gltf["nodes"]) for child in node.get("children", [])}
        animation = animations[0]  # the one vkrt plays, as Blender's importer leaves it on the objects
        for channel in animation["channels"]:
            sampler = animation["samplers"][channel["sampler"]]
            node = channel["target"].get("node")
            if channel["target"]["path"] == "weights" or sampler.get("interpolation", "LINEAR") != "LINEAR":
                sys.exit("animation channel of node %s: only LINEAR translation, rotation and scale are supported"
                         % node)
            below = [node]
            while below[-1] in parents:
                below.append(parents[below[-1]])
            for index in below:
                if "camera" in gltf["nodes"][index] or "KHR_lights_punctual" in gltf["nodes"][index].get(
                        "extensions", {}):
                    sys.exit("node %d moves a camera or a light, which vkrt keeps where the shutter opens" % node)
    return shutter


def set_motion_blur(scene, shutter):
    """Cycles' motion blur over the shutter [open, close] (the importer made one frame a second: render.fps 1),
    opening at the current frame (position START), a box shutter curve, no rolling shutter; or none where the
    shutter is closed, at its time."""
    render = scene.render
    start = math.floor(shutter[0])
    scene.frame_set(int(start), subframe=shutter[0] - start)
    render.use_motion_blur = shutter[1] > shutter[0]
    if not render.use_motion_blur:
        return
    render.motion_blur_shutter = shutter[1] - shutter[0]
    scene.cycles.motion_blur_position = "START"
    scene.cycles.rolling_shutter_type = "NONE"
    if any(point.location[1] != 1.0 for point in render.motion_blur_shutter_curve.curves[0].points):
        sys.exit("Cycles' shutter curve is not a box")
    for ob in scene.objects:
        ob.cycles.use_motion_blur = True
        ob.cycles.motion_steps = 7  # 2^6 steps
    print("motion blur: shutter %g to %g s, frame %d + %g, %d objects move"
          % (shutter[0], shutter[1], scene.frame_current, scene.frame_subframe,
             sum(1 for ob in scene.objects if ob.animation_data and ob.animation_data.action)))


def gltf_falloff(ob, cone, reach):
    """Gives the Cycles point or spot light `ob` what glTF (and vkrt, punctual_light.h) scales its intensity by
    besides 1 / d^2, as its Emission strength made by nodes: for a spot (`cone`: its inner and outer angles) the
    square of clamp((cos a - cos outer) / max(0.001, cos inner - cos outer), 0, 1) at an angle a off its axis,
    and for a light with a range (`reach`) the window clamp(1 - (d / range)^4, 0, 1) at a distance d.

    Cycles 3.4's own spot factor is cos a times a smoothstep over its blend, cut at half its spot size; with the
    spot size 180 degrees and the blend 0 it is cos a alone, in front of the light, so the strength is glTF's
    factor over cos a. cos a is the dot product of the light shader's Incoming vector (from the light towards the
    lit point) with the light's axis in world space: in a light's shader, object space is not the light's own (a
    spot turned 25 degrees came out as if not turned). d is the Light Path node's Ray Length there."""
    light = ob.data
    light.use_nodes = True
    tree = light.node_tree
    emission = next(node for node in tree.nodes if node.type == "EMISSION")

    def operation(kind, a, b, c=None, clamp=False):
        node = tree.nodes.new("ShaderNodeMath")
        node.operation = kind
        node.use_clamp = clamp
        for socket, value in zip(node.inputs, (a, b, c)):
            if isinstance(value, (int, float)):
                socket.default_value = float(value)
            elif value is not None:
                tree.links.new(value, socket)
        return node.outputs[0]

    factors = []
    if cone is not None:
        inner, outer = cone
        bpy.context.view_layer.update()
        axis = (ob.matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0))).normalized()
        light.spot_size = math.pi
        light.spot_blend = 0.0
        dot = tree.nodes.new("ShaderNodeVectorMath")
        dot.operation = "DOT_PRODUCT"
        tree.links.new(tree.nodes.new("ShaderNodeNewGeometry").outputs["Incoming"], dot.inputs[0])
        dot.inputs[1].default_value = axis
        scale = 1.0 / max(0.001, math.cos(inner) - math.cos(outer))
        cosine = dot.outputs["Value"]
        ramp = operation("MULTIPLY_ADD", cosine, scale, -math.cos(outer) * scale, clamp=True)
        factors.append(operation("DIVIDE", operation("MULTIPLY", ramp, ramp), operation("MAXIMUM", cosine, 1e-6)))
        print("light %r: glTF's spot cone, inner %g and outer %g degrees, about the axis %s (Blender's axes)"
              % (light.name, math.degrees(inner), math.degrees(outer), tuple(round(c, 6) for c in axis)))
    if reach is not None:
        distance = tree.nodes.new("ShaderNodeLightPath").outputs["Ray Length"]
        fourth = operation("POWER", operation("DIVIDE", distance, reach), 4.0)
        factors.append(operation("SUBTRACT", 1.0, fourth, clamp=True))
        print("light %r: glTF's range %g" % (light.name, reach))
    tree.links.new(factors[0] if len(factors) == 1 else operation("MULTIPLY", *factors), emission.inputs["Strength"])


def set_lights(scene, lights):
    """The importer's lights, each given the power (or strength) and colour its glTF light means to vkrt."""
    found = [ob for ob in scene.objects if ob.type == "LIGHT"]
    if sorted(ob.data.name for ob in found) != sorted(lights):
        sys.exit("the importer made lights %s for the file's %s" % (sorted(ob.data.name for ob in found),
                                                                    sorted(lights)))
    for ob in found:
        spec = lights[ob.data.name]
        if ob.data.type != spec["type"]:
            sys.exit("light %r: the importer made a %s light" % (ob.data.name, ob.data.type))
        ob.data.energy = spec["energy"]
        ob.data.color = spec["color"]
        if spec["type"] == "SUN":
            ob.data.angle = 0.0  # parallel rays
        else:
            ob.data.shadow_soft_size = 0.0  # a point: hard shadows, intensity falling as 1 / d^2
        if "cone" in spec or "range" in spec:
            gltf_falloff(ob, spec.get("cone"), spec.get("range"))
        ob.data.cycles.cast_shadow = True
        direction = ob.matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0))
        print("light %r: %s, %s %g, colour %s, at %s, pointing %s (Blender's axes)"
              % (ob.data.name, spec["type"], "strength" if spec["type"] == "SUN" else "power", spec["energy"],
                 spec["color"], tuple(round(c, 6) for c in ob.matrix_world.translation),
                 tuple(round(c, 6) for c in direction)))


def textured(tree, encoded, factor, socket):
    """Links into `socket` the image `encoded` (PNG or JPEG bytes, sRGB), read at the nearest texel and repeated,
    times the colour `factor`. The importer's first UV map is glTF's TEXCOORD_0, turned into Blender's (v up) as
    images are."""
    with tempfile.NamedTemporaryFile(suffix=".png", delete=False) as f:
        f.write(encoded)
    image = bpy.data.images.load(f.name)
    image.pack()
    os.unlink(f.name)
    image.colorspace_settings.name = "sRGB"
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = "Closest"
    texture.extension = "REPEAT"
    multiply = tree.nodes.new("ShaderNodeMixRGB")
    multiply.blend_type = "MULTIPLY"
    multiply.inputs["Fac"].default_value = 1.0
    multiply.inputs["Color2"].default_value = list(factor) + [1.0]
    tree.links.new(texture.outputs["Color"], multiply.inputs["Color1"])
    tree.links.new(multiply.outputs["Color"], socket)


def rebuild_material(material, spec):
    material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    output.target = "ALL"
    if spec["kind"] in ("metal", "glass"):
        # Cycles' roughness input is glTF's (GGX's alpha is its square in both); rough lobes keep the energy
        # that single-scattering GGX loses, as vkrt's compensation does.
        node = tree.nodes.new("ShaderNodeBsdfGlossy" if spec["kind"] == "metal" else "ShaderNodeBsdfGlass")
        node.distribution = "SHARP" if spec["roughness"] == 0.0 else "MULTI_GGX"
        node.inputs["Roughness"].default_value = spec["roughness"]
        node.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        if spec["kind"] == "glass":
            node.inputs["IOR"].default_value = spec["ior"]
        tree.links.new(node.outputs["BSDF"], output.inputs["Surface"])
        if "absorption" in spec:
            # Beer's law: Cycles' Volume Absorption absorbs (1 - colour) x density per unit length, so the
            # density is the largest coefficient and each channel's colour 1 - its coefficient / the density.
            density = max(spec["absorption"])
            volume = tree.nodes.new("ShaderNodeVolumeAbsorption")
            volume.inputs["Density"].default_value = density
            volume.inputs["Color"].default_value = [1.0 - a / density for a in spec["absorption"]] + [1.0]
            tree.links.new(volume.outputs["Volume"], output.inputs["Volume"])
            material.cycles.homogeneous_volume = True  # constant density: absorbed in closed form
        return
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = spec["diffuse"] + [1.0]
    if "texture" in spec:
        textured(tree, spec["texture"], spec["diffuse"], diffuse.inputs["Color"])
    diffuse.inputs["Roughness"].default_value = 0.0  # 0: Lambert (above 0 it is Oren-Nayar)
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = spec["emission"] + [1.0]
    emission.inputs["Strength"].default_value = 1.0
    if "emissive texture" in spec:
        textured(tree, spec["emissive texture"], spec["emission"], emission.inputs["Color"])
    add = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(diffuse.outputs["BSDF"], add.inputs[0])
    tree.links.new(emission.outputs["Emission"], add.inputs[1])
    tree.links.new(add.outputs["Shader"], output.inputs["Surface"])
    material.cycles.sample_as_light = any(c > 0.0 for c in spec["emission"])  # emitters are sampled as lights


def black_world(scene):
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    background.inputs["Strength"].default_value = 0.0
    scene.world = world


def environment_world(scene, path, strength, rotation_degrees):
    """The map as vkrt's --environment means it (docs/environment.md): an Environment Texture, equirectangular,
    closest texel, turned by the rotation about Blender's +Z (glTF's +Y) through a Mapping node of type Point
    with Z rotation -R, times the strength."""
    world = bpy.data.worlds.new("environment")
    world.use_nodes = True
    tree = world.node_tree
    background = tree.nodes["Background"]
    background.inputs["Strength"].default_value = strength
    texture = tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = bpy.data.images.load(path)
    texture.image.colorspace_settings.name = "Linear"  # radiance as stored
    texture.interpolation = "Closest"
    texture.projection = "EQUIRECTANGULAR"
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.vector_type = "POINT"
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, -math.radians(rotation_degrees))
    tree.links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    tree.links.new(texture.outputs["Color"], background.inputs["Color"])
    world.cycles.sampling_method = "AUTOMATIC"  # importance sampled; unbiased either way
    scene.world = world
    print("environment %s: %d x %d texels, strength %g, rotation %g degrees"
          % (path, texture.image.size[0], texture.image.size[1], strength, rotation_degrees))


def set_lens(data, gltf):
    """vkrt's thin lens (the camera's extras: `aperture`, the lens's radius, and `focusDistance`, the distance of
    the plane in focus along the view) as Cycles' depth of field, or none. Cycles' lens radius is the focal
    length (in millimetres, 1e-3 scene units) over twice the f-number, so the f-number is lens x 1e-3 / (2 x
    radius); its plane in focus also lies across the view at the focus distance."""
    extras = gltf["cameras"][0].get("extras", {}) if gltf.get("cameras") else {}
    radius = extras.get("aperture", 0.0)
    data.dof.use_dof = radius > 0.0
    if radius > 0.0:
        data.dof.focus_object = None
        data.dof.focus_distance = extras["focusDistance"]
        data.dof.aperture_fstop = data.lens * 1e-3 / (2.0 * radius)
        data.dof.aperture_blades = 0  # a round lens
        data.dof.aperture_rotation = 0.0
        data.dof.aperture_ratio = 1.0
        print("lens: radius %g (f-number %.9g at focal length %.9g mm), focus distance %g"
              % (radius, data.dof.aperture_fstop, data.lens, data.dof.focus_distance))


def camera_report(scene, gltf):
    camera = scene.camera
    data = camera.data
    # The frame's corners in the camera's own space (top right, bottom right, bottom left, top left), which
    # the camera's eye is the origin of; the fields of view from the middles of its edges.
    frame = data.view_frame(scene=scene)
    eye = camera.matrix_world.translation
    top = (frame[0] + frame[3]) / 2
    bottom = (frame[1] + frame[2]) / 2
    left = (frame[2] + frame[3]) / 2
    right = (frame[0] + frame[1]) / 2
    yfov = top.angle(bottom)
    xfov = left.angle(right)
    forward = (camera.matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0))).normalized()
    up = (camera.matrix_world.to_3x3() @ Vector((0.0, 1.0, 0.0))).normalized()
    expected = gltf["cameras"][0]["perspective"]["yfov"] if gltf.get("cameras") else float("nan")
    print("camera %r: sensor fit %s, angle_y %.16g, vertical fov (from the frame) %.16g, horizontal %.16g, "
          "glTF yfov %.16g" % (camera.name, data.sensor_fit, data.angle_y, yfov, xfov, expected))
    # Blender is Z-up; the glTF importer turns glTF's (x, y, z) into Blender's (x, -z, y).
    print("camera eye (Blender) %s, forward %s, up %s; glTF eye (%.6g, %.6g, %.6g)"
          % (tuple(round(c, 9) for c in eye), tuple(round(c, 9) for c in forward),
             tuple(round(c, 9) for c in up), eye.x, eye.z, -eye.y))
    if abs(yfov - expected) > 1e-6:
        sys.exit("the camera's vertical field of view %.16g is not the glTF's %.16g" % (yfov, expected))


def main():
    args = arguments()
    scene_path = os.path.abspath(args.scene)
    out_path = os.path.abspath(args.out)

    bpy.ops.wm.read_factory_settings(use_empty=True)  # no default cube, lamp or camera
    gltf, specs = gltf_materials(scene_path)
    lights = gltf_lights(gltf)
    # Blender 3.4's glTF importer uses numpy.bool, which numpy 1.24 (Debian 12's) no longer has; it meant
    # the builtin bool.
    import numpy
    if "bool" not in numpy.__dict__:
        numpy.bool = bool
    shutter = gltf_shutter(gltf, args.shutter)
    bpy.context.scene.render.fps = 1  # the importer keys frames at seconds x fps: one frame a second
    bpy.context.scene.render.fps_base = 1.0
    bpy.ops.import_scene.gltf(filepath=scene_path)
    scene = bpy.context.scene

    # Every material in use is rebuilt from the glTF file; one that the file does not name is an error.
    used = {slot.material for ob in scene.objects
            for slot in getattr(ob, "material_slots", []) if slot.material}
    for material in sorted(used, key=lambda m: m.name):
        if material.name not in specs:
            sys.exit("Blender material %r is not a material of %s" % (material.name, args.scene))
        rebuild_material(material, specs[material.name])
        spec = specs[material.name]
        if spec["kind"] == "lambert":
            what = "diffuse %s%s, emission %s%s" % (spec["diffuse"], " x texture" if "texture" in spec else "",
                                                    spec["emission"], " x texture" if "emissive texture" in spec else "")
        elif spec["kind"] == "glass":
            what = "glass of index %g, roughness %g%s" % (spec["ior"], spec["roughness"],
                                                          ", absorbing %s" % spec["absorption"]
                                                          if "absorption" in spec else "")
        else:
            what = "white metal of roughness %g" % spec["roughness"]
        print("material %r: %s" % (material.name, what))
    missing = set(specs) - {m.name for m in used}
    if missing:
        print("note: glTF materials not used by any object:", ", ".join(sorted(missing)))

    set_lights(scene, lights)

    cameras = [ob for ob in scene.objects if ob.type == "CAMERA"]
    if len(cameras) != 1:
        sys.exit("expected one camera in the scene, found %d" % len(cameras))
    scene.camera = cameras[0]
    set_lens(scene.camera.data, gltf)
    if args.environment:
        environment_world(scene, os.path.abspath(args.environment), args.environment_strength,
                          args.environment_rotation)
    else:
        black_world(scene)

    render = scene.render
    render.engine = "CYCLES"
    render.resolution_x, render.resolution_y = args.width, args.height
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    render.use_border = False
    render.film_transparent = False
    render.use_compositing = False
    render.use_sequencer = False
    render.dither_intensity = 0.0
    render.threads_mode = "FIXED"
    render.threads = args.threads
    render.use_persistent_data = False

    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.feature_set = "SUPPORTED"
    cycles.samples = args.spp
    cycles.use_layer_samples = "IGNORE"
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = args.seed
    cycles.use_animated_seed = False
    cycles.sampling_pattern = "PROGRESSIVE_MULTI_JITTER"
    cycles.scrambling_distance = 1.0  # no correlation between pixels
    cycles.auto_scrambling_distance = False
    cycles.sample_clamp_direct = 0.0  # no clamping: unbiased
    cycles.sample_clamp_indirect = 0.0
    cycles.light_sampling_threshold = 0.0
    cycles.min_light_bounces = 0
    cycles.min_transparent_bounces = 0
    cycles.max_bounces = args.bounces
    cycles.diffuse_bounces = args.bounces
    cycles.glossy_bounces = args.bounces
    cycles.transmission_bounces = args.bounces
    cycles.transparent_max_bounces = args.bounces
    cycles.volume_bounces = 0  # volumes only absorb (glass tinted by Beer's law): nothing scatters in them
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    cycles.blur_glossy = 0.0
    cycles.pixel_filter_type = "BOX"  # each sample counts, uniformly, in the one pixel it falls in
    cycles.filter_width = 1.0
    cycles.film_exposure = 1.0  # Cycles' film exposure is a factor: 1 leaves the radiance as it is
    for layer in scene.view_layers:
        layer.use_pass_combined = True
        layer.samples = 0
        layer.cycles.denoising_store_passes = False
        layer.cycles.use_denoising = False

    view = scene.view_settings
    scene.display_settings.display_device = "sRGB"
    view.view_transform = "Standard"
    view.look = "None"
    view.exposure = 0.0
    view.gamma = 1.0
    view.use_curve_mapping = False

    image = render.image_settings
    image.file_format = "OPEN_EXR"
    image.color_mode = "RGB"
    image.color_depth = "16" if args.half else "32"
    image.exr_codec = "ZIP"
    image.use_preview = False
    image.use_zbuffer = False
    image.color_management = "FOLLOW_SCENE"  # EXR: scene-linear, no view transform
    # No date, render time or other notes in the file's header: the same command writes the same bytes.
    for stamp in [p.identifier for p in render.bl_rna.properties if p.identifier.startswith("use_stamp")]:
        setattr(render, stamp, False)
    render.use_file_extension = False
    render.filepath = out_path

    set_motion_blur(scene, shutter)
    camera_report(scene, gltf)
    print("Blender %s, Cycles on CPU with %d threads: %dx%d, %d samples per pixel, seed %d"
          % (bpy.app.version_string, args.threads, args.width, args.height, args.spp, args.seed))
    os.makedirs(os.path.dirname(out_path), exist_ok=True)
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - start
    print("wrote %s (%d bytes); render wall time %.1f s" % (out_path, os.path.getsize(out_path), seconds))
    if args.png:
        # The same pixels through the view transform Standard (the sRGB curve, values above 1 clamped).
        image.file_format = "PNG"
        image.color_mode = "RGB"
        image.color_depth = "8"
        image.compression = 100
        bpy.data.images["Render Result"].save_render(os.path.abspath(args.png), scene=scene)
        print("wrote %s" % args.png)


main()
