#!/usr/bin/env python3
"""Write scenes/opening.gltf: light through a narrow opening, the scene path guiding is for
(issue 22, item 3; not yet rendered with --guiding, which is still to come).

Two rooms side by side under one ceiling, 3 m high and 4 m deep (z from 0 to 4, y up): the
camera's room (x from 0 to 5) and a side room (x from 5 to 8), parted by a wall at x = 5
with one opening, a door ajar: a slit 0.15 m wide (z from 1.9 to 2.05) and 2.1 m high. The
only light is a lamp in the side room, a 1 m square at table height (y = 0.8) that shines
up at the side room's ceiling, so that no light reaches the camera's room without first
bouncing in the side room and then passing the slit: next-event estimation finds the lamp
from almost nowhere, and BSDF sampling finds the slit rarely. All surfaces are Lambertian
(glTF metallic 0, KHR_materials_specular specularFactor 0, so vkpath renders them with its
plain kernels); walls are single quads, seen from both sides. The camera stands in a corner
of its room looking at the dividing wall and the slit.

Standard library only, no randomness: the same bytes on every run.
Usage: python3 scripts/make_opening_scene.py [OUTPUT.gltf]
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
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/opening.gltf"
    depth, height, wall, far = 4.0, 3.0, 5.0, 8.0
    slit_z0, slit_z1, slit_top = 1.9, 2.05, 2.1
    # (material, four corners; the winding does not matter for Lambertian walls)
    quads = [
        (0, [(0, 0, 0), (0, 0, depth), (far, 0, depth), (far, 0, 0)]),                  # floor
        (1, [(0, height, 0), (far, height, 0), (far, height, depth), (0, height, depth)]),  # ceiling
        (1, [(0, 0, 0), (0, height, 0), (0, height, depth), (0, 0, depth)]),            # x = 0
        (1, [(far, 0, 0), (far, 0, depth), (far, height, depth), (far, height, 0)]),    # x = 8
        (1, [(0, 0, 0), (far, 0, 0), (far, height, 0), (0, height, 0)]),                # z = 0
        (1, [(0, 0, depth), (0, height, depth), (far, height, depth), (far, 0, depth)]),  # z = 4
        # The dividing wall at x = 5, around the slit
        (2, [(wall, 0, 0), (wall, 0, slit_z0), (wall, height, slit_z0), (wall, height, 0)]),
        (2, [(wall, 0, slit_z1), (wall, 0, depth), (wall, height, depth), (wall, height, slit_z1)]),
        (2, [(wall, slit_top, slit_z0), (wall, slit_top, slit_z1), (wall, height, slit_z1), (wall, height, slit_z0)]),
    ]
    # The lamp: one-sided, facing up (+y): corners counter-clockwise seen from above.
    lamp = [(6.5, 0.8, 2.5), (6.5, 0.8, 3.5), (7.5, 0.8, 3.5), (7.5, 0.8, 2.5)]

    blob = bytearray()
    gltf = {"asset": {"version": "2.0", "generator": "scripts/make_opening_scene.py"},
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
                                  "min": [float(v) for v in lo], "max": [float(v) for v in hi]})
        return len(gltf["accessors"]) - 1

    def triangles(q):
        return [q[0], q[1], q[2], q[0], q[2], q[3]]

    gltf["materials"] += [lambertian("floor", (0.6, 0.55, 0.5)), lambertian("walls", (0.75, 0.75, 0.75)),
                          lambertian("dividing wall", (0.7, 0.72, 0.75)),
                          {"name": "lamp", "emissiveFactor": [1.0, 0.85, 0.6],
                           "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                           "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 40.0},
                                          "KHR_materials_specular": {"specularFactor": 0.0}}}]
    rooms = [{"attributes": {"POSITION": positions(triangles(q))}, "material": m} for m, q in quads]
    gltf["meshes"].append({"name": "rooms", "primitives": rooms})
    gltf["meshes"].append({"name": "lamp", "primitives": [
        {"attributes": {"POSITION": positions(triangles(lamp))}, "material": 3}]})
    gltf["nodes"] += [{"name": "rooms", "mesh": 0}, {"name": "lamp", "mesh": 1}]
    # The camera in the corner (0.4, 1.5, 0.4), looking at the slit's middle (5, 1.05, 1.975):
    # yaw about +y, then pitch about the camera's x (glTF cameras look along -z).
    eye, target = (0.4, 1.5, 0.4), (wall, 1.05, 0.5 * (slit_z0 + slit_z1))
    dx, dy, dz = (target[i] - eye[i] for i in range(3))
    yaw = math.atan2(-dx, -dz)
    pitch = math.atan2(dy, math.hypot(dx, dz))
    rotation = quaternion_product([0.0, math.sin(yaw / 2), 0.0, math.cos(yaw / 2)],
                                  [math.sin(pitch / 2), 0.0, 0.0, math.cos(pitch / 2)])
    gltf["cameras"].append({"type": "perspective",
                            "perspective": {"yfov": math.radians(60.0), "znear": 0.05, "zfar": 100.0}})
    gltf["nodes"].append({"name": "camera", "camera": 0, "translation": list(eye), "rotation": rotation})
    gltf["scenes"][0]["nodes"] = [0, 1, 2]
    gltf["buffers"].append({"byteLength": len(blob),
                            "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()})
    with open(out, "w") as f:
        json.dump(gltf, f, separators=(",", ":"))
        f.write("\n")
    print(f"wrote {out}: {len(quads) + 1} quads, {len(blob)} bytes of geometry")


if __name__ == "__main__":
    main()
