#!/usr/bin/env python3
"""Writes tests/data/skinned_morphed.gltf: the loaders' fuzzer's seed for skins and morph
targets. A strip of two quads skinned to a shoulder and an elbow (JOINTS_0/WEIGHTS_0 and a
second set JOINTS_1/WEIGHTS_1, inverse bind matrices, NORMAL), whose elbow turns LINEAR, and
a quad with two morph targets (POSITION and NORMAL deltas) whose weights are animated
CUBICSPLINE; a camera. Buffers in one base64 data URI."""

import base64
import json
import struct
from pathlib import Path

data = bytearray()
views, accessors = [], []


def accessor(raw, kind, component, count, extra=None):
    while len(data) % 4:
        data.append(0)
    views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(raw)})
    data.extend(raw)
    entry = {"bufferView": len(views) - 1, "componentType": component, "count": count, "type": kind}
    entry.update(extra or {})
    accessors.append(entry)
    return len(accessors) - 1


def floats(kind, width, values, extra=None):
    return accessor(struct.pack(f"<{len(values)}f", *values), kind, 5126, len(values) // width, extra)


def shorts(kind, width, values):
    return accessor(struct.pack(f"<{len(values)}H", *values), kind, 5123, len(values) // width)


def points(values):
    xs, ys, zs = values[0::3], values[1::3], values[2::3]
    bounds = {"min": [min(xs), min(ys), min(zs)], "max": [max(xs), max(ys), max(zs)]}
    return floats("VEC3", 3, values, bounds)


strip = points([0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0, 2, 1, 0])
strip_normals = floats("VEC3", 3, [0, 0, 1] * 6)
strip_indices = shorts("SCALAR", 1, [0, 2, 1, 1, 2, 3, 2, 4, 3, 3, 4, 5])
joints0 = shorts("VEC4", 4, [0, 0, 0, 0] * 2 + [0, 1, 0, 0] * 2 + [1, 0, 0, 0] * 2)
weights0 = floats("VEC4", 4, [1, 0, 0, 0] * 2 + [0.5, 0.25, 0, 0] * 2 + [1, 0, 0, 0] * 2)
joints1 = shorts("VEC4", 4, [0, 0, 0, 0] * 2 + [1, 0, 0, 0] * 2 + [0, 0, 0, 0] * 2)
weights1 = floats("VEC4", 4, [0, 0, 0, 0] * 2 + [0.25, 0, 0, 0] * 2 + [0, 0, 0, 0] * 2)
inverse_binds = floats(
    "MAT4", 16, [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1]
)
quad = points([0, 0, -1, 1, 0, -1, 1, 1, -1, 0, 1, -1])
quad_indices = shorts("SCALAR", 1, [0, 1, 2, 0, 2, 3])
lift = points([0, 0, 0, 0, 0, 0, 0, 0, 0.5, 0, 0, 0.5])
lean = floats("VEC3", 3, [0, 0.3, 0] * 4)
spread = points([-0.5, 0, 0, 0.5, 0, 0, 0.5, 0, 0, -0.5, 0, 0])
times = floats("SCALAR", 1, [0, 1], {"min": [0], "max": [1]})
turns = floats("VEC4", 4, [0, 0, 0, 1, 0, 0, 0.7071068, 0.7071068])
# CUBICSPLINE: per key an in tangent list, the value list and an out tangent list (2 targets).
weight_keys = floats("SCALAR", 1, [0, 0, 0, 1, 0, 0, 1, -1, 1, 0, 0, 0])

document = {
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 3, 4]}],
    "nodes": [
        {"name": "strip", "mesh": 0, "skin": 0},
        {"name": "shoulder", "children": [2]},
        {"name": "elbow", "translation": [1, 0, 0]},
        {"name": "quad", "mesh": 1, "weights": [0.5, 0.0]},
        {"name": "camera", "camera": 0, "translation": [1, 0.5, 4]},
    ],
    "meshes": [
        {"name": "strip", "primitives": [{"indices": strip_indices, "attributes": {
            "POSITION": strip, "NORMAL": strip_normals, "JOINTS_0": joints0, "WEIGHTS_0": weights0,
            "JOINTS_1": joints1, "WEIGHTS_1": weights1}}]},
        {"name": "quad", "primitives": [{"indices": quad_indices, "attributes": {"POSITION": quad},
            "targets": [{"POSITION": lift, "NORMAL": lean}, {"POSITION": spread}]}],
         "weights": [0.0, 0.0]},
    ],
    "skins": [{"name": "arm", "joints": [1, 2], "inverseBindMatrices": inverse_binds}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01}}],
    "animations": [{"name": "move", "channels": [
        {"sampler": 0, "target": {"node": 2, "path": "rotation"}},
        {"sampler": 1, "target": {"node": 3, "path": "weights"}}],
        "samplers": [{"input": times, "output": turns},
                     {"input": times, "output": weight_keys, "interpolation": "CUBICSPLINE"}]}],
    "buffers": [{"byteLength": len(data),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(data)).decode()}],
    "bufferViews": views,
    "accessors": accessors,
}
out = Path(__file__).resolve().parent.parent / "tests" / "data" / "skinned_morphed.gltf"
out.write_text(json.dumps(document, indent=1) + "\n")
print(out)
