#!/usr/bin/env python3
"""Moving glTF scenes for measuring `vkpath render --frames` per-frame set-up (issue 41).

  make_moving_scenes.py grid TRIANGLES OUT.gltf
      A flat grid of about TRIANGLES triangles (side x side squares, two triangles each) in
      the y = 0 plane, 2 units wide, on a node that slides LINEAR along x from -0.5 at 0 s to
      0.5 at 2 s (animation "slide"), with a camera above it. Writes OUT.gltf and OUT.bin.
  make_moving_scenes.py slide IN.gltf NODE OUT.gltf
      IN.gltf (its buffers data URIs or files beside it, kept as they are) with an animation
      "slide" added that moves node NODE (its name) LINEAR by +0.3 along x in 2 s, its keys
      in a new data-URI buffer. E.g. scenes/materials.gltf "sphere gold": a textured scene
      whose geometry moves while its materials and textures do not.

Commands (README, per-frame set-up):
  python3 scripts/make_moving_scenes.py grid 1000000 /tmp/grid.gltf
  python3 scripts/make_moving_scenes.py slide scenes/materials.gltf "sphere gold" /tmp/moving_materials.gltf
"""
import array
import base64
import json
import math
import os
import sys


def grid(triangles, out):
    side = max(1, int(math.sqrt(triangles / 2)))
    n = side + 1
    positions = array.array("f")
    for j in range(n):
        z = -1.0 + 2.0 * j / side
        for i in range(n):
            positions.extend((-1.0 + 2.0 * i / side, 0.0, z))
    indices = array.array("I")
    for j in range(side):
        row, next_row = j * n, (j + 1) * n
        for i in range(side):
            a, b, c, d = row + i, row + i + 1, next_row + i + 1, next_row + i
            # Counter-clockwise seen from +y
            indices.extend((a, d, c, a, c, b))
    times = array.array("f", [0.0, 2.0])
    slide = array.array("f", [-0.5, 0.0, 0.0, 0.5, 0.0, 0.0])
    blobs = [positions.tobytes(), indices.tobytes(), times.tobytes(), slide.tobytes()]
    views, data = [], b""
    for blob in blobs:
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(blob)})
        data += blob
    bin_name = os.path.splitext(os.path.basename(out))[0] + ".bin"
    document = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "grid", "mesh": 0},
            {"name": "camera", "camera": 0, "translation": [0, 2.5, 0],
             "rotation": [-0.7071068, 0, 0, 0.7071068]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "animations": [{
            "name": "slide",
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
            "samplers": [{"input": 2, "output": 3}],
        }],
        "buffers": [{"uri": bin_name, "byteLength": len(data)}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3",
             "min": [-1, 0, -1], "max": [1, 0, 1]},
            {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR",
             "min": [0.0], "max": [2.0]},
            {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
        ],
    }
    with open(os.path.join(os.path.dirname(out) or ".", bin_name), "wb") as f:
        f.write(data)
    with open(out, "w") as f:
        json.dump(document, f)
    print(f"{out}: {2 * side * side} triangles")


def slide(source, node_name, out):
    with open(source) as f:
        document = json.load(f)
    names = [node.get("name") for node in document["nodes"]]
    if node_name not in names:
        sys.exit(f"{source} has no node '{node_name}' (nodes: {names})")
    node = names.index(node_name)
    start = document["nodes"][node].get("translation", [0.0, 0.0, 0.0])
    end = [start[0] + 0.3, start[1], start[2]]
    keys = array.array("f", [0.0, 2.0] + start + end).tobytes()
    buffer = len(document["buffers"])
    document["buffers"].append({
        "uri": "data:application/octet-stream;base64," + base64.b64encode(keys).decode(),
        "byteLength": len(keys),
    })
    views, accessors = document["bufferViews"], document["accessors"]
    views += [{"buffer": buffer, "byteOffset": 0, "byteLength": 8},
              {"buffer": buffer, "byteOffset": 8, "byteLength": 24}]
    accessors += [
        {"bufferView": len(views) - 2, "componentType": 5126, "count": 2, "type": "SCALAR",
         "min": [0.0], "max": [2.0]},
        {"bufferView": len(views) - 1, "componentType": 5126, "count": 2, "type": "VEC3"},
    ]
    document.setdefault("animations", []).append({
        "name": "slide",
        "channels": [{"sampler": 0, "target": {"node": node, "path": "translation"}}],
        "samplers": [{"input": len(accessors) - 2, "output": len(accessors) - 1}],
    })
    with open(out, "w") as f:
        json.dump(document, f)
    print(f"{out}: node '{node_name}' slides")


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "grid":
        grid(int(sys.argv[2]), sys.argv[3])
    elif len(sys.argv) == 5 and sys.argv[1] == "slide":
        slide(sys.argv[2], sys.argv[3], sys.argv[4])
    else:
        sys.exit(__doc__)
