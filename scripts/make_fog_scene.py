#!/usr/bin/env python3
"""Write scenes/fog.gltf: light shafts in fog, the README's picture of `render --medium`
(issue 57).

A closed room, 6 m long (x), 3 m high (y, up) and 4 m deep (z), parted near its back wall by
a slatted screen at x = 1.5: six vertical slits, each 0.1 m wide, from the floor to 2.6 m.
The only light is a KHR_lights_punctual point light behind the screen at (0.5, 2.0, 2.0), so
everything lit in front of the screen is lit through the slits: in fog
(`--medium sigma_s=...`) the slits throw bright shafts across the room. Walls, floor and
screen are dark Lambertian (glTF metallic 0, KHR_materials_specular specularFactor 0), so the
fog's single scattering carries the picture; every surface is a one-sided quad list seen from
inside. The camera stands near the front wall looking back at the screen.

Standard library only, no randomness: the same bytes on every run.
Usage: python3 scripts/make_fog_scene.py [OUTPUT.gltf]
"""

import base64
import json
import math
import struct
import sys


def lambertian(name, color):
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": list(color) + [1.0], "metallicFactor": 0.0},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}


def quaternion_product(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/fog.gltf"
    length, height, depth, screen = 6.0, 3.0, 4.0, 1.5
    slit_top, slit_width = 2.6, 0.1
    slit_centres = [0.9, 1.4, 1.8, 2.2, 2.6, 3.1]
    # (material, four corners; Lambertian quads are seen from both sides)
    quads = [
        (0, [(0, 0, 0), (0, 0, depth), (length, 0, depth), (length, 0, 0)]),              # floor
        (1, [(0, height, 0), (length, height, 0), (length, height, depth), (0, height, depth)]),
        (1, [(0, 0, 0), (0, height, 0), (0, height, depth), (0, 0, depth)]),              # x = 0
        (1, [(length, 0, 0), (length, 0, depth), (length, height, depth), (length, height, 0)]),
        (1, [(0, 0, 0), (length, 0, 0), (length, height, 0), (0, height, 0)]),            # z = 0
        (1, [(0, 0, depth), (0, height, depth), (length, height, depth), (length, 0, depth)]),
        # The screen above the slits' tops
        (2, [(screen, slit_top, 0), (screen, slit_top, depth), (screen, height, depth), (screen, height, 0)]),
    ]
    # The screen's slats between the slits, floor to slit_top
    edges = [0.0]
    for c in slit_centres:
        edges += [c - 0.5 * slit_width, c + 0.5 * slit_width]
    edges.append(depth)
    for z0, z1 in zip(edges[0::2], edges[1::2]):
        quads.append((2, [(screen, 0, z0), (screen, 0, z1), (screen, slit_top, z1), (screen, slit_top, z0)]))

    blob = bytearray()
    gltf = {"asset": {"version": "2.0", "generator": "scripts/make_fog_scene.py"},
            "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
            "extensions": {"KHR_lights_punctual": {"lights": [
                {"name": "lamp", "type": "point", "color": [1.0, 0.85, 0.65], "intensity": 40.0}]}},
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
                                  "min": [float(v) for v in lo], "max": [float(v) for v in hi]})
        return len(gltf["accessors"]) - 1

    def triangles(q):
        return [q[0], q[1], q[2], q[0], q[2], q[3]]

    gltf["materials"] += [lambertian("floor", (0.25, 0.22, 0.2)), lambertian("walls", (0.2, 0.2, 0.22)),
                          lambertian("screen", (0.1, 0.1, 0.1))]
    primitives = [{"attributes": {"POSITION": positions(triangles(q))}, "material": m} for m, q in quads]
    gltf["meshes"].append({"name": "room", "primitives": primitives})
    gltf["nodes"] += [{"name": "room", "mesh": 0},
                      {"name": "lamp", "translation": [0.5, 2.0, 2.0],
                       "extensions": {"KHR_lights_punctual": {"light": 0}}}]
    # The camera near the front wall, looking back at the screen: yaw about +y, then pitch
    # about the camera's x (glTF cameras look along -z).
    eye, target = (5.4, 1.6, 0.25), (2.6, 1.0, 2.6)
    dx, dy, dz = (target[i] - eye[i] for i in range(3))
    yaw = math.atan2(-dx, -dz)
    pitch = math.atan2(dy, math.hypot(dx, dz))
    rotation = quaternion_product([0.0, math.sin(yaw / 2), 0.0, math.cos(yaw / 2)],
                                  [math.sin(pitch / 2), 0.0, 0.0, math.cos(pitch / 2)])
    gltf["cameras"].append({"type": "perspective",
                            "perspective": {"yfov": math.radians(55.0), "znear": 0.05, "zfar": 100.0}})
    gltf["nodes"].append({"name": "camera", "camera": 0, "translation": list(eye), "rotation": rotation})
    gltf["scenes"][0]["nodes"] = [0, 1, 2]
    gltf["buffers"].append({"byteLength": len(blob),
                            "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()})
    with open(out, "w") as f:
        json.dump(gltf, f, separators=(",", ":"))
        f.write("\n")
    print(f"wrote {out}: {len(quads)} quads, one point light, {len(blob)} bytes of geometry")


if __name__ == "__main__":
    main()
