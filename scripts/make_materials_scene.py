#!/usr/bin/env python3
"""Generate scenes/materials.gltf: a self-contained glTF 2.0 showcase of vkpath's materials.

A closed 4 m room (y up, x and z in [-2, 2], y in [0, 4]) with Lambertian walls
(metallic 0, KHR_materials_specular specularFactor 0), an emissive ceiling light
(KHR_materials_emissive_strength) and a perspective camera, holding:

  * a floor with a checkerboard baseColorTexture, REPEAT-wrapped 4x by KHR_texture_transform;
  * a row of spheres: polished gold, rough copper, glossy red plastic, rough white
    dielectric, and one with a metallicRoughnessTexture (G = roughness, B = metallic);
  * a brick panel with a tangent-space normalTexture and no TANGENT attribute (the
    renderer generates MikkTSpace tangents);
  * an alpha-MASK leaf (alphaCutoff 0.5) and an alpha-BLEND gradient pane;
  * a small panel with an emissiveTexture;
  * in front, the second round's layers: a smooth glass sphere (KHR_materials_transmission,
    KHR_materials_volume with a faint blue attenuation, KHR_materials_ior 1.5), a clear-coated
    red car-paint panel (KHR_materials_clearcoat over a rough metallic base) and a velvet
    cushion (KHR_materials_sheen over a dark blue base).

Standard library only. The buffer and the PNG textures are embedded as base64 data URIs.

Usage: python3 scripts/make_materials_scene.py [output.gltf]   (default scenes/materials.gltf)
"""

import base64
import json
import math
import os
import struct
import sys
import zlib

# ---------------------------------------------------------------------------
# PNG writing


def png_bytes(width, height, channels, pixel):
    """An 8-bit PNG (channels 3: RGB, 4: RGBA); pixel(x, y) -> tuple of ints in [0, 255],
    (0, 0) the top-left pixel."""
    color_type = {3: 2, 4: 6}[channels]
    raw = bytearray()
    for y in range(height):
        raw.append(0)  # filter type 0 (None) for every row
        for x in range(width):
            values = pixel(x, y)
            assert len(values) == channels
            raw.extend(max(0, min(255, int(round(v)))) for v in values)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
            + chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b""))


def smoothstep(e0, e1, x):
    t = max(0.0, min(1.0, (x - e0) / (e1 - e0)))
    return t * t * (3.0 - 2.0 * t)


def checker_png():
    """64x64 sRGB checkerboard of 16x16-texel squares: one texture repeat is 4x4 squares."""
    def pixel(x, y):
        light = ((x // 16) + (y // 16)) % 2 == 0
        return (215, 210, 200) if light else (45, 48, 60)
    return png_bytes(64, 64, 3, pixel)


def metallic_roughness_png():
    """64x64 linear texture: G (roughness) in 4 horizontal bands (v) alternating smooth
    0.08 / rough 0.85, B (metallic) in 8 vertical stripes (u) alternating 1 / 0, so the
    sphere shows all four combinations. R unused (occlusion), left at 255."""
    def pixel(x, y):
        rough = 0.85 if (y // 16) % 2 else 0.08
        metal = 1.0 if (x // 8) % 2 == 0 else 0.0
        return (255, rough * 255, metal * 255)
    return png_bytes(64, 64, 3, pixel)


BRICK_W, BRICK_H, MORTAR, BEVEL = 32, 16, 3, 5


def brick_height(x, y):
    """Height in [0, 1] of a running-bond brick wall (bricks 32x16 texels, 128x128 tile
    repeats seamlessly): 1 on brick faces, 0 in the mortar, bevelled edges."""
    row = math.floor(y / BRICK_H)
    xs = x + (BRICK_W / 2 if row % 2 else 0)
    fx = xs - math.floor(xs / BRICK_W) * BRICK_W   # position inside the brick
    fy = y - row * BRICK_H
    # distance to the nearest mortar line centre (at fx = 0 / fy = 0)
    dx = min(fx, BRICK_W - fx)
    dy = min(fy, BRICK_H - fy)
    d = min(dx, dy)
    return smoothstep(MORTAR * 0.5, MORTAR * 0.5 + BEVEL, d)


def normal_png():
    """128x128 tangent-space normal map of the brick wall (glTF convention: +X right,
    +Y up in the image, +Z out of the surface; the image's y axis points down)."""
    size, strength = 128, 2.5

    def h(x, y):
        return brick_height(x % size, y % size)

    def pixel(x, y):
        cx, cy = x + 0.5, y + 0.5
        dh_dx = (h(cx + 1, cy) - h(cx - 1, cy)) * 0.5
        dh_dy_down = (h(cx, cy + 1) - h(cx, cy - 1)) * 0.5
        dh_dy_up = -dh_dy_down
        n = (-strength * dh_dx, -strength * dh_dy_up, 1.0)
        length = math.sqrt(sum(c * c for c in n))
        return tuple((c / length * 0.5 + 0.5) * 255 for c in n)
    return png_bytes(size, size, 3, pixel)


def brick_color_png():
    """128x128 sRGB base colour for the brick panel: terracotta bricks, light mortar
    (same layout as the normal map, per-brick tint variation)."""
    def pixel(x, y):
        hgt = brick_height(x + 0.5, y + 0.5)
        row = y // BRICK_H
        col = (x + (BRICK_W // 2 if row % 2 else 0)) // BRICK_W
        tint = ((row * 7 + col * 13) % 5) / 4.0  # 0..1, deterministic
        brick = (170 + 30 * tint, 80 + 15 * tint, 60 + 10 * tint)
        mortar = (190, 185, 175)
        return tuple(m + (b - m) * hgt for b, m in zip(brick, mortar))
    return png_bytes(128, 128, 3, pixel)


def leaf_png():
    """128x128 sRGB RGBA leaf: alpha 255 inside the leaf (and its stem), 0 outside;
    green with darker veins. The leaf points up (v = 0 is the top of the image)."""
    size = 128

    def pixel(x, y):
        # leaf coordinates: s across in [-1, 1], t along from tip (+1, top) to base (-1)
        s = (x + 0.5) / size * 2.0 - 1.0
        t = 1.0 - (y + 0.5) / size * 2.0
        t_leaf = (t - 0.1) / 0.85          # the blade spans t in [-0.75, 0.95]
        inside = False
        if -1.0 < t_leaf < 1.0:
            half_width = 0.62 * (1.0 - t_leaf * t_leaf) ** 0.75 * (1.0 - 0.25 * t_leaf)
            inside = abs(s) < half_width
        stem = -0.97 < t <= -0.6 and abs(s - 0.02 * (t + 0.6)) < 0.035
        if not (inside or stem):
            return (40, 90, 30, 0)
        green = (70, 150, 45)
        midrib = abs(s) < 0.025
        # side veins: lines running up-and-out from the midrib
        vein_phase = (t_leaf - 0.9 * abs(s)) * 7.0
        side_vein = abs(vein_phase - round(vein_phase)) < 0.07 and abs(s) > 0.03
        if stem or midrib or side_vein:
            green = (150, 190, 80)
        return green + (255,)
    return png_bytes(size, size, 4, pixel)


def gradient_png():
    """64x8 sRGB RGBA: a light blue whose alpha rises from 0.1 (left) to 0.9 (right)."""
    def pixel(x, y):
        alpha = 0.1 + 0.8 * x / 63.0
        return (90, 170, 255, alpha * 255)
    return png_bytes(64, 8, 4, pixel)


def emissive_png():
    """128x128 sRGB emissive pattern: concentric glowing rings (orange and cyan) around
    a bright core, and a thin square frame, on black."""
    size = 128

    def pixel(x, y):
        u = (x + 0.5) / size * 2.0 - 1.0
        v = (y + 0.5) / size * 2.0 - 1.0
        r = math.sqrt(u * u + v * v)
        core = math.exp(-(r / 0.12) ** 2)
        ring_orange = math.exp(-((r - 0.45) / 0.05) ** 2)
        ring_cyan = math.exp(-((r - 0.75) / 0.04) ** 2)
        frame = 1.0 if max(abs(u), abs(v)) > 0.93 else 0.0
        rgb = [0.0, 0.0, 0.0]
        for weight, color in ((core, (1.0, 0.95, 0.8)), (ring_orange, (1.0, 0.45, 0.05)),
                              (ring_cyan, (0.1, 0.8, 1.0)), (frame, (0.9, 0.2, 0.9))):
            for i in range(3):
                rgb[i] += weight * color[i]
        # the values are already perceptual (sRGB-encoded) intensities
        return tuple(min(1.0, c) * 255 for c in rgb)
    return png_bytes(size, size, 3, pixel)


# ---------------------------------------------------------------------------
# Vector helpers


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def add(a, b):
    return [a[i] + b[i] for i in range(3)]


def scale(a, s):
    return [a[i] * s for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def normalize(a):
    length = math.sqrt(dot(a, a))
    return [c / length for c in a]


# ---------------------------------------------------------------------------
# glTF building


class Builder:
    def __init__(self):
        self.buffer = bytearray()
        self.gltf = {
            "asset": {"version": "2.0", "generator": "vkpath scripts/make_materials_scene.py"},
            "extensionsUsed": [],
            "scene": 0,
            "scenes": [{"name": "materials", "nodes": []}],
            "nodes": [],
            "meshes": [],
            "materials": [],
            "textures": [],
            "images": [],
            "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
            "cameras": [],
        }

    def use_extension(self, name):
        if name not in self.gltf["extensionsUsed"]:
            self.gltf["extensionsUsed"].append(name)

    def _view(self, data, target):
        while len(self.buffer) % 4:
            self.buffer.append(0)
        view = {"buffer": 0, "byteOffset": len(self.buffer), "byteLength": len(data),
                "target": target}
        self.buffer.extend(data)
        self.gltf["bufferViews"].append(view)
        return len(self.gltf["bufferViews"]) - 1

    def float_accessor(self, rows, kind, with_bounds=False):
        width = {"VEC2": 2, "VEC3": 3, "VEC4": 4}[kind]
        flat = [float(v) for row in rows for v in row]
        assert len(flat) == width * len(rows)
        view = self._view(struct.pack("<%df" % len(flat), *flat), 34962)
        accessor = {"bufferView": view, "componentType": 5126, "count": len(rows), "type": kind}
        if with_bounds:
            # bounds of the values as stored (rounded to float32)
            stored = [struct.unpack("<f", struct.pack("<f", v))[0] for v in flat]
            accessor["min"] = [min(stored[i::width]) for i in range(width)]
            accessor["max"] = [max(stored[i::width]) for i in range(width)]
        self.gltf["accessors"].append(accessor)
        return len(self.gltf["accessors"]) - 1

    def index_accessor(self, indices):
        if max(indices) < 65536:
            data, component = struct.pack("<%dH" % len(indices), *indices), 5123
        else:
            data, component = struct.pack("<%dI" % len(indices), *indices), 5125
        view = self._view(data, 34963)
        self.gltf["accessors"].append(
            {"bufferView": view, "componentType": component, "count": len(indices), "type": "SCALAR"})
        return len(self.gltf["accessors"]) - 1

    def geometry(self, positions, normals, uvs, indices):
        """Accessors of one indexed triangle list; checks that every triangle is
        counter-clockwise as seen from the side its normals point to, and not degenerate."""
        for t in range(0, len(indices), 3):
            a, b, c = (positions[i] for i in indices[t:t + 3])
            face = cross(sub(b, a), sub(c, a))
            assert dot(face, face) > 1e-14, "degenerate triangle"
            mean_normal = add(add(normals[indices[t]], normals[indices[t + 1]]), normals[indices[t + 2]])
            assert dot(face, mean_normal) > 0, "clockwise triangle"
        for n in normals:
            assert abs(dot(n, n) - 1.0) < 1e-6
        return {
            "POSITION": self.float_accessor(positions, "VEC3", with_bounds=True),
            "NORMAL": self.float_accessor(normals, "VEC3"),
            "TEXCOORD_0": self.float_accessor(uvs, "VEC2"),
        }, self.index_accessor(indices)

    def image(self, name, png):
        self.gltf["images"].append({
            "name": name, "mimeType": "image/png",
            "uri": "data:image/png;base64," + base64.b64encode(png).decode("ascii")})
        self.gltf["textures"].append({"sampler": 0, "source": len(self.gltf["images"]) - 1})
        return len(self.gltf["textures"]) - 1

    def material(self, material):
        self.gltf["materials"].append(material)
        return len(self.gltf["materials"]) - 1

    def mesh(self, name, attributes, indices, material):
        self.gltf["meshes"].append({"name": name, "primitives": [
            {"attributes": dict(attributes), "indices": indices, "material": material, "mode": 4}]})
        return len(self.gltf["meshes"]) - 1

    def node(self, node):
        self.gltf["nodes"].append(node)
        self.gltf["scenes"][0]["nodes"].append(len(self.gltf["nodes"]) - 1)

    def finish(self):
        while len(self.buffer) % 4:
            self.buffer.append(0)
        self.gltf["buffers"].append({
            "byteLength": len(self.buffer),
            "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.buffer)).decode("ascii")})
        return self.gltf


def quad(center, right, up, half_width, half_height, uv_scale=(1.0, 1.0)):
    """A rectangle facing right x up (counter-clockwise from that side); texture
    coordinate (0, 0) at its top-left corner (glTF: the image's top-left)."""
    normal = normalize(cross(right, up))
    r = scale(normalize(right), half_width)
    u = scale(normalize(up), half_height)
    positions = [
        add(sub(center, r), scale(u, -1)),  # bottom-left
        sub(add(center, r), u),             # bottom-right
        add(add(center, r), u),             # top-right
        add(sub(center, r), u),             # top-left
    ]
    su, sv = uv_scale
    uvs = [[0, sv], [su, sv], [su, 0], [0, 0]]
    return positions, [normal] * 4, uvs, [0, 1, 2, 0, 2, 3]


def uv_sphere(segments=32, rings=16):
    """Unit sphere: u = azimuth / 2 pi increasing towards +x from the +z side, v = polar
    angle / pi from the north pole (v = 0, top of the image) to the south pole. A seam
    column is duplicated; the pole rows hold one vertex per segment (their own u)."""
    positions, normals, uvs, indices = [], [], [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        sin_t = 0.0 if i in (0, rings) else math.sin(theta)
        cos_t = 1.0 if i == 0 else (-1.0 if i == rings else math.cos(theta))
        for j in range(segments + 1):
            phi = 2.0 * math.pi * j / segments
            p = [sin_t * math.sin(phi), cos_t, sin_t * math.cos(phi)]
            positions.append(p)
            normals.append(normalize(p))
            # the pole vertices sit in the middle of their segment's span in u
            u = (j + 0.5) / segments if i in (0, rings) else j / segments
            uvs.append([u, i / rings])
    row = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b = i * row + j, i * row + j + 1            # upper edge (smaller theta)
            c, d = (i + 1) * row + j, (i + 1) * row + j + 1  # lower edge
            if i != 0:
                indices += [a, c, b]
            if i != rings - 1:
                indices += [b, c, d]
    return positions, normals, uvs, indices


def lambertian(name, color):
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": list(color) + [1.0], "metallicFactor": 0.0},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}


def look_at_rotation(eye, target):
    """Unit quaternion [x, y, z, w] turning a camera (looking along -Z, +Y up) at eye
    towards target, keeping world +Y up."""
    forward = normalize(sub(target, eye))
    z = scale(forward, -1.0)                  # the camera's +Z points backwards
    x = normalize(cross([0.0, 1.0, 0.0], z))
    y = cross(z, x)
    # rotation matrix with columns x, y, z -> quaternion
    m00, m01, m02 = x[0], y[0], z[0]
    m10, m11, m12 = x[1], y[1], z[1]
    m20, m21, m22 = x[2], y[2], z[2]
    trace = m00 + m11 + m22
    if trace > 0:
        s = 0.5 / math.sqrt(trace + 1.0)
        q = [(m21 - m12) * s, (m02 - m20) * s, (m10 - m01) * s, 0.25 / s]
    elif m00 > m11 and m00 > m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        q = [0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s]
    elif m11 > m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        q = [(m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
        q = [(m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s]
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


# ---------------------------------------------------------------------------
# The scene

ROOM = 2.0          # half size in x and z
HEIGHT = 4.0
X, Y, Z = [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]
NX, NY, NZ = scale(X, -1), scale(Y, -1), scale(Z, -1)


def build():
    b = Builder()
    for name in ("KHR_materials_specular", "KHR_materials_emissive_strength",
                 "KHR_texture_transform"):
        b.use_extension(name)

    def add_quad(name, material, center, right, up, hw, hh, uv_scale=(1.0, 1.0)):
        attributes, indices = b.geometry(*quad(center, right, up, hw, hh, uv_scale))
        mesh = b.mesh(name, attributes, indices, material)
        b.node({"name": name, "mesh": mesh})

    # --- the room: Lambertian walls, each facing inwards
    white = b.material(lambertian("wall white", (0.73, 0.73, 0.73)))
    red = b.material(lambertian("wall red", (0.63, 0.065, 0.05)))
    green = b.material(lambertian("wall green", (0.14, 0.45, 0.091)))
    add_quad("back wall", white, [0, HEIGHT / 2, -ROOM], X, Y, ROOM, HEIGHT / 2)
    add_quad("front wall", white, [0, HEIGHT / 2, ROOM], NX, Y, ROOM, HEIGHT / 2)
    add_quad("left wall", red, [-ROOM, HEIGHT / 2, 0], NZ, Y, ROOM, HEIGHT / 2)
    add_quad("right wall", green, [ROOM, HEIGHT / 2, 0], Z, Y, ROOM, HEIGHT / 2)
    add_quad("ceiling", white, [0, HEIGHT, 0], X, Z, ROOM, ROOM)

    # --- the light: a quad just below the ceiling, facing down
    light = b.material({
        "name": "ceiling light",
        "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0},
        "emissiveFactor": [1.0, 1.0, 1.0],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 12.0},
                       "KHR_materials_specular": {"specularFactor": 0.0}}})
    add_quad("ceiling light", light, [0, HEIGHT - 0.01, -0.2], X, Z, 0.6, 0.6)

    # --- floor: checkerboard texture repeated 4x4 by KHR_texture_transform (REPEAT sampler)
    checker = b.image("checkerboard", checker_png())
    floor = b.material({
        "name": "floor checkerboard",
        "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6,
            "baseColorTexture": {"index": checker, "extensions": {
                "KHR_texture_transform": {"scale": [4.0, 4.0]}}}}})
    add_quad("floor", floor, [0, 0, 0], X, NZ, ROOM, ROOM)

    # --- spheres
    sphere_attributes, sphere_indices = b.geometry(*uv_sphere(32, 16))
    mr_texture = b.image("metallic-roughness stripes", metallic_roughness_png())
    spheres = [
        ("gold", {"baseColorFactor": [1.0, 0.78, 0.34, 1.0], "metallicFactor": 1.0,
                  "roughnessFactor": 0.15}),
        ("rough copper", {"baseColorFactor": [0.95, 0.64, 0.54, 1.0], "metallicFactor": 1.0,
                          "roughnessFactor": 0.5}),
        ("red plastic", {"baseColorFactor": [0.8, 0.05, 0.04, 1.0], "metallicFactor": 0.0,
                         "roughnessFactor": 0.2}),
        ("rough white dielectric", {"baseColorFactor": [0.85, 0.85, 0.85, 1.0], "metallicFactor": 0.0,
                                    "roughnessFactor": 0.9}),
        ("metallic-roughness texture", {"baseColorFactor": [0.35, 0.55, 0.95, 1.0], "metallicFactor": 1.0,
                                        "roughnessFactor": 1.0,
                                        "metallicRoughnessTexture": {"index": mr_texture}}),
    ]
    radius = 0.3
    for k, (name, pbr) in enumerate(spheres):
        material = b.material({"name": name, "pbrMetallicRoughness": pbr})
        mesh = b.mesh("sphere " + name, sphere_attributes, sphere_indices, material)
        x = (k - 2) * 0.66
        b.node({"name": "sphere " + name, "mesh": mesh,
                "translation": [x, radius, -0.35], "scale": [radius] * 3})

    # --- brick panel on the back wall: normalTexture, no TANGENT (MikkTSpace generated)
    bricks_normal = b.image("brick normal map", normal_png())
    bricks_color = b.image("brick colour", brick_color_png())
    bricks = b.material({
        "name": "normal-mapped bricks",
        "pbrMetallicRoughness": {"baseColorTexture": {"index": bricks_color}, "metallicFactor": 0.0,
                                 "roughnessFactor": 0.7},
        "normalTexture": {"index": bricks_normal, "scale": 1.0}})
    add_quad("normal-mapped panel", bricks, [-0.95, 1.75, -ROOM + 0.01], X, Y, 0.8, 0.8, (1.5, 1.5))

    # --- emissive-texture panel on the back wall
    glow = b.image("glow pattern", emissive_png())
    glow_material = b.material({
        "name": "emissive texture",
        "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.05, 1.0], "metallicFactor": 0.0},
        "emissiveFactor": [1.0, 1.0, 1.0],
        "emissiveTexture": {"index": glow},
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3.0}}})
    add_quad("emissive-texture panel", glow_material, [0.95, 2.3, -ROOM + 0.01], X, Y, 0.45, 0.45)

    # --- alpha MASK: a leaf cut out of a quad, standing in the room (double-sided)
    leaf = b.image("leaf", leaf_png())
    leaf_material = b.material({
        "name": "alpha mask leaf",
        "pbrMetallicRoughness": {"baseColorTexture": {"index": leaf}, "metallicFactor": 0.0,
                                 "roughnessFactor": 0.6},
        "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True})
    add_quad("alpha-mask leaf", leaf_material, [1.15, 1.1, -1.7], X, Y, 0.55, 0.55)

    # --- alpha BLEND: a pane whose alpha rises from 0.1 to 0.9 left to right
    pane = b.image("alpha gradient", gradient_png())
    pane_material = b.material({
        "name": "alpha blend pane",
        "pbrMetallicRoughness": {"baseColorTexture": {"index": pane}, "metallicFactor": 0.0,
                                 "roughnessFactor": 0.3},
        "alphaMode": "BLEND", "doubleSided": True})
    add_quad("alpha-blend pane", pane_material, [-1.0, 0.5, -1.6], X, Y, 0.7, 0.45)

    # --- the layered materials, in front of the spheres
    for name in ("KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
                 "KHR_materials_clearcoat", "KHR_materials_sheen"):
        b.use_extension(name)
    glass = b.material({
        "name": "glass",
        "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0,
                                 "roughnessFactor": 0.0},
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                       "KHR_materials_volume": {"thicknessFactor": 0.5,
                                                "attenuationColor": [0.8, 0.9, 1.0],
                                                "attenuationDistance": 0.5},
                       "KHR_materials_ior": {"ior": 1.5}}})
    glass_radius = 0.22
    b.node({"name": "glass sphere", "mesh": b.mesh("glass sphere", sphere_attributes,
                                                   sphere_indices, glass),
            "translation": [-0.7, glass_radius, 0.3], "scale": [glass_radius] * 3})
    velvet = b.material({
        "name": "velvet",
        "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.06, 0.25, 1.0], "metallicFactor": 0.0,
                                 "roughnessFactor": 0.9},
        "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.85, 1.0],
                                               "sheenRoughnessFactor": 0.4}}})
    b.node({"name": "velvet cushion", "mesh": b.mesh("velvet cushion", sphere_attributes,
                                                     sphere_indices, velvet),
            "translation": [0.0, 0.09, 0.3], "scale": [0.28, 0.09, 0.2]})
    paint = b.material({
        "name": "clear-coated car paint",
        "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.04, 0.03, 1.0], "metallicFactor": 0.6,
                                 "roughnessFactor": 0.5},
        "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                                   "clearcoatRoughnessFactor": 0.05}}})
    tilt = math.radians(-25.0)
    panel_normal = [math.sin(tilt), 0.0, math.cos(tilt)]
    add_quad("clear-coated panel", paint, [0.7, 0.25, 0.3], normalize(cross(Y, panel_normal)), Y,
             0.22, 0.25)

    # --- camera
    eye = [0.0, 1.5, 1.95]
    pitch = math.radians(-12.0)
    target = add(eye, [0.0, math.sin(pitch), -math.cos(pitch)])
    b.gltf["cameras"].append({"name": "camera", "type": "perspective", "perspective": {
        "yfov": math.radians(70.0), "aspectRatio": 4.0 / 3.0, "znear": 0.05, "zfar": 20.0}})
    b.node({"name": "camera", "camera": 0, "translation": eye,
            "rotation": look_at_rotation(eye, target)})
    return b.finish()


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "scenes", "materials.gltf")
    gltf = build()
    text = json.dumps(gltf, indent=1)
    with open(out, "w") as f:
        f.write(text + "\n")
    print("wrote %s (%d bytes)" % (os.path.normpath(out), len(text) + 1))


if __name__ == "__main__":
    main()
