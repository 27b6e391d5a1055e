#!/usr/bin/env python3
"""Write scenes/many_lights.gltf: a corridor lit by 1000 small emissive triangles of widely
varying power, for the light tree (--light-selection tree; tests/light_tree.rs,
benches/light_tree.sh).

The corridor is 4 m wide, 3 m high and 42 m long (z from 2 down to -40, y up), Lambertian
(glTF metallic 0, KHR_materials_specular specularFactor 0, so vkpath renders it with its
plain kernels). Under its ceiling hang 1000 one-sided triangles facing down, 0.08 to 0.25 m
a side, at random places along the whole corridor, with emissive strengths of 8 levels
spaced by a factor of 10^(4/7) from 0.003 to 30 (a power range of about 10^5 with the
sizes). The camera stands near one end looking down the corridor and at the floor, so that
it sees no light directly (its view's upper edge points below the horizontal): what it sees
is lit by next-event estimation alone, where the power CDF spends most samples on lights
tens of metres away and the tree on the near ones.

Standard library only, a fixed seed: the same bytes on every run.
Usage: python3 scripts/make_many_lights_scene.py [OUTPUT.gltf]
"""

import base64
import json
import math
import random
import struct
import sys

LIGHT_COUNT = 1000
LEVELS = 8


def lambertian(name, color):
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": list(color) + [1.0], "metallicFactor": 0.0},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/many_lights.gltf"
    rng = random.Random(22)
    x0, x1, y1, z0, z1 = -2.0, 2.0, 3.0, -40.0, 2.0
    # The room: (material, four corners counter-clockwise seen from inside).
    quads = [
        (0, [(x0, 0, z1), (x1, 0, z1), (x1, 0, z0), (x0, 0, z0)]),        # floor
        (2, [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)]),    # ceiling
        (1, [(x0, 0, z0), (x1, 0, z0), (x1, y1, z0), (x0, y1, z0)]),      # far end
        (1, [(x1, 0, z1), (x0, 0, z1), (x0, y1, z1), (x1, y1, z1)]),      # near end
        (1, [(x0, 0, z1), (x0, 0, z0), (x0, y1, z0), (x0, y1, z1)]),      # left wall
        (1, [(x1, 0, z0), (x1, 0, z1), (x1, y1, z1), (x1, y1, z0)]),      # right wall
    ]
    lights = [[] for _ in range(LEVELS)]
    for _ in range(LIGHT_COUNT):
        size = rng.uniform(0.08, 0.25)
        x = rng.uniform(x0 + 0.2, x1 - 0.2 - size)
        z = rng.uniform(z0 + 0.5, z1 - 0.5 - size)
        y = y1 - 0.02
        # (x, y, z), (x + s, y, z), (x, y, z + s): the normal cross(+x, +z) points down.
        lights[rng.randrange(LEVELS)].append([(x, y, z), (x + size, y, z), (x, y, z + size)])

    blob = bytearray()
    gltf = {"asset": {"version": "2.0", "generator": "scripts/make_many_lights_scene.py"},
            "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_specular"],
            "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
            "accessors": [], "bufferViews": [], "buffers": [], "cameras": []}

    def positions(points):
        offset = len(blob)
        for p in points:
            blob.extend(struct.pack("<3f", *p))
        gltf["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": 12 * len(points)})
        lo = [min(p[i] for p in points) for i in range(3)]
        hi = [max(p[i] for p in points) for i in range(3)]
        gltf["accessors"].append({"bufferView": len(gltf["bufferViews"]) - 1, "componentType": 5126,
                                  "count": len(points), "type": "VEC3",
                                  "min": [struct.unpack("<f", struct.pack("<f", v))[0] for v in lo],
                                  "max": [struct.unpack("<f", struct.pack("<f", v))[0] for v in hi]})
        return len(gltf["accessors"]) - 1

    gltf["materials"] += [lambertian("floor", (0.7, 0.7, 0.65)), lambertian("walls", (0.6, 0.6, 0.6)),
                          lambertian("ceiling", (0.5, 0.5, 0.5))]
    room = []
    for material, q in quads:
        room.append({"attributes": {"POSITION": positions([q[0], q[1], q[2], q[0], q[2], q[3]])},
                     "material": material})
    gltf["meshes"].append({"name": "corridor", "primitives": room})
    light_primitives = []
    for level, triangles in enumerate(lights):
        strength = 0.003 * 10 ** (4.0 * level / (LEVELS - 1))
        gltf["materials"].append({
            "name": f"light {level}", "emissiveFactor": [1.0, 0.9, 0.8],
            "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": round(strength, 4)},
                           "KHR_materials_specular": {"specularFactor": 0.0}}})
        points = [p for t in triangles for p in t]
        light_primitives.append({"attributes": {"POSITION": positions(points)},
                                 "material": len(gltf["materials"]) - 1})
    gltf["meshes"].append({"name": "lights", "primitives": light_primitives})
    gltf["nodes"] += [{"name": "corridor", "mesh": 0}, {"name": "lights", "mesh": 1}]
    # The camera at (0, 1.6, 1.5) pitched down by atan(1.6 / 4) = 21.8 degrees; its vertical
    # field of view of 40 degrees keeps the upper edge 1.8 degrees below the horizontal.
    pitch = -math.atan2(1.6, 4.0)
    gltf["cameras"].append({"type": "perspective",
                            "perspective": {"yfov": math.radians(40.0), "znear": 0.05, "zfar": 100.0}})
    gltf["nodes"].append({"name": "camera", "camera": 0, "translation": [0.0, 1.6, 1.5],
                          "rotation": [math.sin(pitch / 2), 0.0, 0.0, math.cos(pitch / 2)]})
    gltf["scenes"][0]["nodes"] = [0, 1, 2]
    gltf["buffers"].append({"byteLength": len(blob),
                            "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()})
    with open(out, "w") as f:
        json.dump(gltf, f, separators=(",", ":"))
        f.write("\n")
    print(f"wrote {out}: {LIGHT_COUNT} lights, {len(blob)} bytes of geometry")


if __name__ == "__main__":
    main()
