"""A small glTF 2.0 writer for vkrt's generated scenes: meshes, materials, cameras, punctual lights and vkrt's
analytic node extensions, with all binary data embedded as one base64 data URI so each scene is a single
self-contained file."""

import base64
import json
import math
import struct
import zlib


class GltfBuilder:
    def __init__(self, generator):
        self.gltf = {
            "asset": {"version": "2.0", "generator": generator},
            "scenes": [{"nodes": []}],
            "scene": 0,
            "nodes": [],
            "meshes": [],
            "materials": [],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }
        self.data = bytearray()
        self.extensions = set()
        self.required = set()  # extensions a viewer must know to show the scene (also listed as used)

    # Binary data -----------------------------------------------------------------------------------
    def _view(self, payload, target):
        while len(self.data) % 4:
            self.data.append(0)
        view = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(payload)}
        if target is not None:
            view["target"] = target
        self.gltf["bufferViews"].append(view)
        self.data.extend(payload)
        return len(self.gltf["bufferViews"]) - 1

    def _accessor(self, view, component_type, count, kind, **extra):
        self.gltf["accessors"].append(
            {"bufferView": view, "componentType": component_type, "count": count, "type": kind, **extra})
        return len(self.gltf["accessors"]) - 1

    def vec3_accessor(self, vectors, with_bounds=False):
        payload = b"".join(struct.pack("<3f", *v) for v in vectors)
        extra = {}
        if with_bounds:  # POSITION accessors must carry min and max
            extra["min"] = [min(v[i] for v in vectors) for i in range(3)]
            extra["max"] = [max(v[i] for v in vectors) for i in range(3)]
        return self._accessor(self._view(payload, 34962), 5126, len(vectors), "VEC3", **extra)

    def index_accessor(self, indices):
        payload = struct.pack("<%dI" % len(indices), *indices)
        return self._accessor(self._view(payload, 34963), 5125, len(indices), "SCALAR")

    def vec4_accessor(self, vectors):
        payload = b"".join(struct.pack("<4f", *v) for v in vectors)
        return self._accessor(self._view(payload, 34962), 5126, len(vectors), "VEC4")

    def vec2_accessor(self, vectors):
        payload = b"".join(struct.pack("<2f", *v) for v in vectors)
        return self._accessor(self._view(payload, 34962), 5126, len(vectors), "VEC2")

    # Textures ----------------------------------------------------------------------------------------
    def texture(self, name, width, height, rgba, nearest=False, mipmaps=True):
        """A texture from RGBA8 pixels (rows top to bottom, a list of (r, g, b, a) tuples), stored as a PNG
        in the buffer; `mipmaps` False samples the image itself however small it is seen (minFilter NEAREST or
        LINEAR)."""
        rows = b"".join(b"\0" + bytes(c for pixel in rgba[y * width:(y + 1) * width] for c in pixel)
                        for y in range(height))

        def chunk(kind, data):
            return (struct.pack(">I", len(data)) + kind + data +
                    struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))
        png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)) +
               chunk(b"IDAT", zlib.compress(rows, 0)) + chunk(b"IEND", b""))
        self.gltf.setdefault("images", []).append(
            {"name": name, "bufferView": self._view(png, None), "mimeType": "image/png"})
        # Magnified: NEAREST or LINEAR; minified: the same within the two nearest mipmap levels, blended.
        mag_filter, min_filter = (9728, 9986) if nearest else (9729, 9987)
        if not mipmaps:
            min_filter = mag_filter
        self.gltf.setdefault("samplers", []).append({"magFilter": mag_filter, "minFilter": min_filter})
        self.gltf.setdefault("textures", []).append(
            {"name": name, "source": len(self.gltf["images"]) - 1, "sampler": len(self.gltf["samplers"]) - 1})
        return len(self.gltf["textures"]) - 1

    def texture_info(self, texture, offset=None, rotation=None, scale=None, tex_coord=None):
        """A material's reference to a texture, with a KHR_texture_transform when any of its parts is given."""
        info = {"index": texture}
        if tex_coord is not None:
            info["texCoord"] = tex_coord
        transform = {key: value for key, value in (("offset", offset), ("rotation", rotation), ("scale", scale))
                     if value is not None}
        if transform:
            info["extensions"] = {"KHR_texture_transform": transform}
            self.extensions.add("KHR_texture_transform")
        return info

    # Scene objects -----------------------------------------------------------------------------------
    def material(self, name, base_color=(0.8, 0.8, 0.8), metallic=0.0, roughness=1.0, emission=None,
                 emission_strength=None, transmission=None, ior=None, thickness=None,
                 attenuation_color=None, attenuation_distance=None, base_color_texture=None,
                 metallic_roughness_texture=None, specular=None, specular_color=None, normal_texture=None,
                 normal_scale=None, alpha=1.0, alpha_mode=None, alpha_cutoff=None, double_sided=None,
                 transmission_texture=None, unlit=False, clearcoat=None, clearcoat_roughness=None,
                 sheen_color=None, sheen_roughness=None, emissive_texture=None):
        """Texture arguments are texture_info() dictionaries."""
        material = {"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": list(base_color) + [alpha], "metallicFactor": metallic, "roughnessFactor": roughness}}
        if normal_texture is not None:
            material["normalTexture"] = dict(normal_texture)
            if normal_scale is not None:
                material["normalTexture"]["scale"] = normal_scale
        if alpha_mode is not None:
            material["alphaMode"] = alpha_mode
        if alpha_cutoff is not None:
            material["alphaCutoff"] = alpha_cutoff
        if double_sided is not None:
            material["doubleSided"] = double_sided
        if base_color_texture is not None:
            material["pbrMetallicRoughness"]["baseColorTexture"] = base_color_texture
        if metallic_roughness_texture is not None:
            material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = metallic_roughness_texture
        extensions = {}
        if emission is not None:
            material["emissiveFactor"] = list(emission)
        if emissive_texture is not None:
            material["emissiveTexture"] = emissive_texture
        if emission_strength is not None:
            extensions["KHR_materials_emissive_strength"] = {"emissiveStrength": emission_strength}
        if transmission is not None:
            extensions["KHR_materials_transmission"] = {"transmissionFactor": transmission}
            if transmission_texture is not None:
                extensions["KHR_materials_transmission"]["transmissionTexture"] = transmission_texture
        if unlit:
            extensions["KHR_materials_unlit"] = {}
        if sheen_color is not None:
            extensions["KHR_materials_sheen"] = {"sheenColorFactor": list(sheen_color)}
            if sheen_roughness is not None:
                extensions["KHR_materials_sheen"]["sheenRoughnessFactor"] = sheen_roughness
        if clearcoat is not None:
            extensions["KHR_materials_clearcoat"] = {"clearcoatFactor": clearcoat}
            if clearcoat_roughness is not None:
                extensions["KHR_materials_clearcoat"]["clearcoatRoughnessFactor"] = clearcoat_roughness
        if specular is not None or specular_color is not None:
            extensions["KHR_materials_specular"] = {}
            if specular is not None:
                extensions["KHR_materials_specular"]["specularFactor"] = specular
            if specular_color is not None:
                extensions["KHR_materials_specular"]["specularColorFactor"] = list(specular_color)
        if ior is not None:
            extensions["KHR_materials_ior"] = {"ior": ior}
        if thickness is not None:
            volume = {"thicknessFactor": thickness}
            if attenuation_color is not None:
                volume["attenuationColor"] = list(attenuation_color)
                volume["attenuationDistance"] = attenuation_distance
            extensions["KHR_materials_volume"] = volume
        if extensions:
            material["extensions"] = extensions
            self.extensions.update(extensions)
        self.gltf["materials"].append(material)
        return len(self.gltf["materials"]) - 1

    def mesh(self, name, primitives):
        """primitives: list of (positions, normals or None, indices, material[, texture coordinates or None[,
        vertex colours (RGB) or None[, second texture coordinates or None[, tangents (XYZW)]]]])."""
        out = []
        for positions, normals, indices, material, *extra in primitives:
            attributes = {"POSITION": self.vec3_accessor(positions, with_bounds=True)}
            if normals is not None:
                attributes["NORMAL"] = self.vec3_accessor(normals)
            if extra and extra[0] is not None:
                attributes["TEXCOORD_0"] = self.vec2_accessor(extra[0])
            if len(extra) > 1 and extra[1] is not None:
                attributes["COLOR_0"] = self.vec3_accessor(extra[1])
            if len(extra) > 2 and extra[2] is not None:
                attributes["TEXCOORD_1"] = self.vec2_accessor(extra[2])
            if len(extra) > 3:
                attributes["TANGENT"] = self.vec4_accessor(extra[3])
            out.append({"attributes": attributes, "indices": self.index_accessor(indices), "material": material})
        self.gltf["meshes"].append({"name": name, "primitives": out})
        return len(self.gltf["meshes"]) - 1

    def deforming_mesh(self, name, positions, normals, indices, material, joints=None, weights=None, targets=(),
                       target_weights=None, uvs=None, uvs1=None):
        """A one-primitive mesh that deforms: `joints` and `weights` (four per vertex: JOINTS_0 as unsigned
        shorts, WEIGHTS_0) for a skin, `targets` a list of (position displacements, normal displacements or
        None) morph targets, `target_weights` the mesh's default weights, `uvs` and `uvs1` its first and second
        texture coordinates."""
        attributes = {"POSITION": self.vec3_accessor(positions, with_bounds=True)}
        if normals is not None:
            attributes["NORMAL"] = self.vec3_accessor(normals)
        for key, values in (("TEXCOORD_0", uvs), ("TEXCOORD_1", uvs1)):
            if values is not None:
                attributes[key] = self.vec2_accessor(values)
        if joints is not None:
            payload = b"".join(struct.pack("<4H", *j) for j in joints)
            attributes["JOINTS_0"] = self._accessor(self._view(payload, 34962), 5123, len(joints), "VEC4")
            attributes["WEIGHTS_0"] = self.vec4_accessor(weights)
        primitive = {"attributes": attributes, "indices": self.index_accessor(indices), "material": material}
        if targets:
            primitive["targets"] = []
            for displacements, normal_displacements in targets:
                target = {"POSITION": self.vec3_accessor(displacements, with_bounds=True)}
                if normal_displacements is not None:
                    target["NORMAL"] = self.vec3_accessor(normal_displacements)
                primitive["targets"].append(target)
        mesh = {"name": name, "primitives": [primitive]}
        if target_weights is not None:
            mesh["weights"] = list(target_weights)
        self.gltf["meshes"].append(mesh)
        return len(self.gltf["meshes"]) - 1

    def skin(self, joints, inverse_bind_matrices):
        """A skin over the nodes `joints`, with one column-major 4x4 inverse bind matrix (16 numbers) each."""
        flat = [c for m in inverse_bind_matrices for c in m]
        view = self._view(struct.pack("<%df" % len(flat), *flat), None)
        accessor = self._accessor(view, 5126, len(inverse_bind_matrices), "MAT4")
        self.gltf.setdefault("skins", []).append({"joints": list(joints), "inverseBindMatrices": accessor})
        return len(self.gltf["skins"]) - 1

    def node(self, name, parent=None, **fields):
        self.gltf["nodes"].append({"name": name, **fields})
        index = len(self.gltf["nodes"]) - 1
        if parent is None:
            self.gltf["scenes"][0]["nodes"].append(index)
        else:
            self.gltf["nodes"][parent].setdefault("children", []).append(index)
        return index

    def sphere(self, name, center, radius, material, parent=None):
        """An analytic sphere: a node carrying vkrt's VKRT_sphere extension (docs/vkrt_sphere.md)."""
        self.extensions.add("VKRT_sphere")
        return self.node(name, parent=parent, translation=list(center),
                         extensions={"VKRT_sphere": {"radius": radius, "material": material}})

    def shape(self, name, shape, material, parent=None, **transform):
        """An analytic shape ("sphere", "box", "cylinder" or "cone"): a node carrying vkrt's VKRT_shape extension
        (docs/vkrt_shape.md); `transform` is the node's translation, rotation and scale, or matrix."""
        self.extensions.add("VKRT_shape")
        return self.node(name, parent=parent, **transform,
                         extensions={"VKRT_shape": {"shape": shape, "material": material}})

    def csg(self, name, operation, parent=None, **transform):
        """A constructive solid geometry node ("union", "intersection" or "difference", VKRT_csg,
        docs/vkrt_shape.md); its operands are the shape() and csg() nodes made with it as their parent."""
        self.extensions.add("VKRT_csg")
        return self.node(name, parent=parent, **transform, extensions={"VKRT_csg": {"operation": operation}})

    def animate(self, node, path, times, values, interpolation="LINEAR"):
        """One animation channel (translation, rotation, scale or morph-target weights of `node`) with its own
        sampler; `values` holds one vector (for weights: one weight per target) per key."""
        times_view = self._view(struct.pack("<%df" % len(times), *times), None)
        times_accessor = self._accessor(times_view, 5126, len(times), "SCALAR", min=[min(times)], max=[max(times)])
        kind = {"rotation": "VEC4", "weights": "SCALAR"}.get(path, "VEC3")
        flat = [c for v in values for c in v]
        values_view = self._view(struct.pack("<%df" % len(flat), *flat), None)
        values_accessor = self._accessor(values_view, 5126, len(flat) if path == "weights" else len(values), kind)
        animations = self.gltf.setdefault("animations", [])
        if not animations:
            animations.append({"name": "motion", "channels": [], "samplers": []})
        animation = animations[0]
        animation["samplers"].append({"input": times_accessor, "output": values_accessor,
                                      "interpolation": interpolation})
        animation["channels"].append({"sampler": len(animation["samplers"]) - 1,
                                      "target": {"node": node, "path": path}})

    def perspective_camera(self, name, yfov, aspect_ratio=None, znear=0.01, aperture=None, focus_distance=None):
        camera = {"type": "perspective", "name": name, "perspective": {"yfov": yfov, "znear": znear}}
        if aspect_ratio:
            camera["perspective"]["aspectRatio"] = aspect_ratio
        if aperture is not None:  # vkrt's depth-of-field convention: lens radius and focus distance in extras
            camera["extras"] = {"aperture": aperture, "focusDistance": focus_distance}
        self.gltf.setdefault("cameras", []).append(camera)
        return len(self.gltf["cameras"]) - 1

    def orthographic_camera(self, name, xmag, ymag, znear=0.01, zfar=1000.0):
        camera = {"type": "orthographic", "name": name,
                  "orthographic": {"xmag": xmag, "ymag": ymag, "znear": znear, "zfar": zfar}}
        self.gltf.setdefault("cameras", []).append(camera)
        return len(self.gltf["cameras"]) - 1

    def light(self, light):
        self.extensions.add("KHR_lights_punctual")
        lights = self.gltf.setdefault("extensions", {}).setdefault("KHR_lights_punctual", {"lights": []})
        lights["lights"].append(light)
        return len(lights["lights"]) - 1

    def write(self, path):
        # glTF's arrays hold at least one element where present: a scene of analytic shapes alone has no
        # buffer (one of 0 bytes is invalid), views, accessors or meshes.
        if self.data:
            self.gltf["buffers"] = [{
                "byteLength": len(self.data),
                "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.data)).decode("ascii")}]
        for key in ("buffers", "bufferViews", "accessors", "meshes", "materials"):
            if not self.gltf.get(key, True):
                del self.gltf[key]
        if self.extensions or self.required:
            self.gltf["extensionsUsed"] = sorted(self.extensions | self.required)
        if self.required:
            self.gltf["extensionsRequired"] = sorted(self.required)
        with open(path, "w") as f:
            json.dump(self.gltf, f, indent=1)
            f.write("\n")


# Geometry helpers --------------------------------------------------------------------------------------
def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def quad(corners, facing):
    """Two triangles over four corners (in order around the quad), wound so the front faces `facing`."""
    a, b, c, d = corners
    normal = cross(sub(b, a), sub(c, a))
    if dot(normal, facing) < 0:
        a, b, c, d = d, c, b, a
    return [a, b, c, d], [0, 1, 2, 0, 2, 3]


def merge(parts):
    """Concatenates (positions, indices) parts into one indexed triangle list."""
    positions, indices = [], []
    for part_positions, part_indices in parts:
        indices += [i + len(positions) for i in part_indices]
        positions += part_positions
    return positions, indices


def box(center, half):
    """An axis-aligned box about `center` with half-extents `half` (x, y, z), faces outward, four corners a face:
    positions, normals, indices and texture coordinates (0 to 1 across each face)."""
    positions, normals, indices, uvs = [], [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            corners = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = sign * half[axis]
                p[(axis + 1) % 3] = a * half[(axis + 1) % 3]
                p[(axis + 2) % 3] = b * half[(axis + 2) % 3]
                corners.append([center[i] + p[i] for i in range(3)])
            facing = [0.0, 0.0, 0.0]
            facing[axis] = sign
            wound, face = quad(corners, facing)
            face_uvs = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
            indices += [i + len(positions) for i in face]
            positions += wound
            normals += [facing] * 4
            uvs += face_uvs if wound[0] == corners[0] else face_uvs[::-1]
    return positions, normals, indices, uvs


def uv_sphere(center, radius, rings, segments):
    """Positions, smooth normals and indices of a UV sphere, outward-facing."""
    positions, normals, indices = [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            n = [math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi)]
            normals.append(n)
            positions.append([center[i] + radius * n[i] for i in range(3)])
    for r in range(rings):
        for s in range(segments):
            a = r * (segments + 1) + s
            b = a + segments + 1
            if r != 0:
                indices += [a, a + 1, b]
            if r != rings - 1:
                indices += [a + 1, b + 1, b]
    return positions, normals, indices


def look_at_rotation(eye, target):
    """Quaternion (x, y, z, w) turning a glTF camera (looking down -z, +y up) to look from eye at target."""
    f = [target[i] - eye[i] for i in range(3)]
    n = math.sqrt(sum(c * c for c in f))
    f = [c / n for c in f]
    yaw = math.atan2(-f[0], -f[2])
    pitch = math.asin(max(-1.0, min(1.0, f[1])))
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    # yaw about y, then pitch about the rotated x: q = q_yaw * q_pitch
    return [cy * sp, sy * cp, -sy * sp, cy * cp]


def dome_normals(size, cells):
    """A normal texture of cells x cells domes (hemispheres of radius 0.8 of a cell's half width), +Y up in
    the image as glTF's normal textures have it."""
    texels = []
    for row in range(size):
        for col in range(size):
            x = ((col + 0.5) * cells / size) % 1.0 * 2.0 - 1.0
            y = -(((row + 0.5) * cells / size) % 1.0 * 2.0 - 1.0)  # up in the image
            r2 = x * x + y * y
            n = [x / 0.8, y / 0.8, math.sqrt(0.64 - r2) / 0.8] if r2 < 0.64 else [0.0, 0.0, 1.0]
            texels.append(tuple(round((c + 1.0) * 0.5 * 255.0) for c in n) + (255,))
    return texels
