"""Scenes from arrays (``vkpath.Scene.from_arrays``) against the same data written as a
glTF file: the same materials (one conversion of glTF's factors serves both), the same
triangles, and so the same pixels bit for bit (lavapipe, tiny images)."""

from __future__ import annotations

import base64
import json

import numpy as np
import pytest

import vkpath

# A floor, a back wall, an emissive ceiling quad, a glass box and a gold wedge, with per
# material the glTF factors that vkpath reads (extensions included), in material order.
MATERIALS = [
    {"base_color": (0.8, 0.8, 0.8), "metallic": 0.0, "roughness": 0.9},
    {"base_color": (0.7, 0.2, 0.1, 1.0), "metallic": 0.0, "roughness": 0.4,
     "specular": 0.5, "specular_color": (1.0, 0.9, 0.8), "clearcoat": 0.6,
     "clearcoat_roughness": 0.2, "sheen_color": (0.2, 0.3, 0.4), "sheen_roughness": 0.5},
    {"base_color": (0.0, 0.0, 0.0), "emission": (1.0, 0.9, 0.7), "emissive_strength": 8.0,
     "double_sided": True},
    {"base_color": (1.0, 1.0, 1.0), "metallic": 0.0, "roughness": 0.05, "transmission": 1.0,
     "ior": 1.45, "thickness": 0.3, "attenuation_color": (0.6, 0.9, 0.7),
     "attenuation_distance": 0.8},
    {"base_color": (1.0, 0.78, 0.34), "metallic": 1.0, "roughness": 0.3},
]


def quad(corner, u, v):
    corner, u, v = (np.asarray(x, np.float32) for x in (corner, u, v))
    return [corner, corner + u, corner + u + v, corner + v]


def box(low, high):
    (x0, y0, z0), (x1, y1, z1) = low, high
    p = np.array([[x, y, z] for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)], np.float32)
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return list(p), [t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))]


def scene_arrays():
    """positions (N, 3) float32, indices (M, 3) uint32 with each material's triangles
    together and in material order, material indices, normals (N, 3), uvs (N, 2)."""
    positions, indices, material_of = [], [], []

    def add(points, triangles, material):
        base = len(positions)
        positions.extend(points)
        indices.extend([(base + a, base + b, base + c) for a, b, c in triangles])
        material_of.extend([material] * len(triangles))

    add(quad((-2, 0, -2), (0, 0, 4), (4, 0, 0)), [(0, 1, 2), (0, 2, 3)], 0)
    add(quad((-2, 0, -2), (4, 0, 0), (0, 3, 0)), [(0, 1, 2), (0, 2, 3)], 1)
    add(quad((-0.5, 2.9, -0.5), (1, 0, 0), (0, 0, 1)), [(0, 1, 2), (0, 2, 3)], 2)
    add(*box((-1.2, 0.0, -0.6), (-0.2, 1.2, 0.4)), 3)
    add([(0.3, 0, 0), (1.5, 0, 0), (0.9, 0, 0.9), (0.9, 1.0, 0.3)],
        [(0, 2, 1), (0, 1, 3), (1, 2, 3), (2, 0, 3)], 4)
    positions = np.array(positions, np.float32)
    normals = positions - positions.mean(axis=0)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    uvs = positions[:, [0, 2]] * 0.5
    return (positions, np.array(indices, np.uint32), np.array(material_of, np.uint32),
            normals.astype(np.float32), uvs.astype(np.float32))


def gltf_material(factors):
    """A material dict as glTF JSON with its extensions."""
    out, ext = {"pbrMetallicRoughness": {}}, {}
    pbr = out["pbrMetallicRoughness"]
    color = list(factors.get("base_color", (1, 1, 1)))
    pbr["baseColorFactor"] = color + [1.0] * (4 - len(color))
    for key, name in (("metallic", "metallicFactor"), ("roughness", "roughnessFactor")):
        if key in factors:
            pbr[name] = factors[key]
    if "emission" in factors:
        out["emissiveFactor"] = list(factors["emission"])
    if "emissive_strength" in factors:
        ext["KHR_materials_emissive_strength"] = {"emissiveStrength": factors["emissive_strength"]}
    if "double_sided" in factors:
        out["doubleSided"] = factors["double_sided"]
    if "specular" in factors:
        ext["KHR_materials_specular"] = {"specularFactor": factors["specular"],
                                         "specularColorFactor": list(factors["specular_color"])}
    if "ior" in factors:
        ext["KHR_materials_ior"] = {"ior": factors["ior"]}
    if "transmission" in factors:
        ext["KHR_materials_transmission"] = {"transmissionFactor": factors["transmission"]}
        ext["KHR_materials_volume"] = {
            "thicknessFactor": factors["thickness"],
            "attenuationColor": list(factors["attenuation_color"]),
            "attenuationDistance": factors["attenuation_distance"]}
    if "clearcoat" in factors:
        ext["KHR_materials_clearcoat"] = {
            "clearcoatFactor": factors["clearcoat"],
            "clearcoatRoughnessFactor": factors["clearcoat_roughness"]}
    if "sheen_color" in factors:
        ext["KHR_materials_sheen"] = {"sheenColorFactor": list(factors["sheen_color"]),
                                      "sheenRoughnessFactor": factors["sheen_roughness"]}
    if ext:
        out["extensions"] = ext
    return out


def write_gltf(path, positions, indices, material_of, normals, uvs, light):
    """The arrays as one mesh with a primitive per material (its triangles), on one node
    without a transform, with the vertex attributes in one base64 buffer."""
    blobs, views, accessors = [], [], []

    def accessor(array, kind, **extra):
        data = np.ascontiguousarray(array).tobytes()
        offset = sum(len(b) for b in blobs)
        blobs.append(data)
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data)})
        component = 5125 if array.dtype == np.uint32 else 5126
        accessors.append({"bufferView": len(views) - 1, "componentType": component,
                          "count": len(array), "type": kind, **extra})
        return len(accessors) - 1

    low, high = positions.min(axis=0).tolist(), positions.max(axis=0).tolist()
    attributes = {"POSITION": accessor(positions, "VEC3", min=low, max=high),
                  "NORMAL": accessor(normals, "VEC3"), "TEXCOORD_0": accessor(uvs, "VEC2")}
    primitives = [{"attributes": attributes, "material": m,
                   "indices": accessor(indices[material_of == m].reshape(-1), "SCALAR")}
                  for m in range(len(MATERIALS))]
    blob = b"".join(blobs)
    extensions = sorted({e for m in MATERIALS for e in gltf_material(m).get("extensions", {})})
    document = {
        "asset": {"version": "2.0"},
        "extensionsUsed": extensions + ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": list(light["color"]), "intensity": light["intensity"]}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        # A point light: its node's translation alone places it, exactly.
        "nodes": [{"mesh": 0},
                  {"translation": list(light["position"]),
                   "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "meshes": [{"primitives": primitives}],
        "materials": [gltf_material(m) for m in MATERIALS],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(blob).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    path.write_text(json.dumps(document))


CAMERA = vkpath.Camera((0.0, 1.5, 4.5), (0.0, 1.0, 0.0), fov=50.0)
LIGHT = {"type": "point", "color": (1.0, 0.8, 0.6), "intensity": 6.0, "position": (1.0, 2.5, 1.0)}


def test_a_scene_from_arrays_renders_as_the_same_gltf_bit_for_bit(tmp_path):
    positions, indices, material_of, normals, uvs = scene_arrays()
    path = tmp_path / "arrays.gltf"
    write_gltf(path, positions, indices, material_of, normals, uvs, LIGHT)
    from_file = vkpath.Scene.load(path)
    from_file.camera = CAMERA
    from_arrays = vkpath.Scene.from_arrays(
        positions, indices, materials=MATERIALS, material_indices=material_of,
        normals=normals, uvs=uvs, camera=CAMERA, lights=[LIGHT])
    assert from_arrays.triangle_count == from_file.triangle_count == len(indices)
    assert from_arrays.punctual_light_count == 1
    settings = dict(width=24, height=16, spp=4, seed=3, integrator="mis", sampler="pcg")
    a = vkpath.render(from_arrays, **settings)
    b = vkpath.render(from_file, **settings)
    # Something is lit (else black equals black and the test could not fail).
    assert a[..., :3].max() > 0.0
    assert np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_without_material_indices_every_triangle_takes_material_0():
    positions = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    flat = [0, 1, 2, 0, 2, 3]
    emissive = {"base_color": (0, 0, 0), "emission": (1, 1, 1)}
    scene = vkpath.Scene.from_arrays(positions, flat, materials=[emissive, {}])
    assert scene.triangle_count == 2
    image = vkpath.render(scene, width=8, height=8, spp=1, integrator="workshop")
    # Both triangles emit: the framing camera sees the whole quad lit, corners aside.
    assert image[4, 4, 0] == 1.0 and image[2, 5, 0] == 1.0 and image[5, 2, 0] == 1.0


@pytest.mark.parametrize(
    "change, words",
    [
        (dict(positions=np.zeros((4, 2))), "positions must have shape (N, 3), not (4, 2)"),
        (dict(indices=np.zeros((2, 4), np.int32)), "indices must have shape (M, 3)"),
        (dict(indices=[0, 1, 2.5]), "indices must hold integers"),
        (dict(indices=[0, 1, 7]), "indices: triangle 0 refers to vertex 7"),
        (dict(indices=[0, 1, -1]), "indices holds -1"),
        (dict(materials=[{"colour": (1, 0, 0)}]), "materials[0]: unknown key 'colour'"),
        (dict(materials=[{"metallic": "shiny"}]), "materials[0]: metallic='shiny' is not a number"),
        (dict(materials=[{}, {"alpha_mode": "fade"}]), "materials[1]: alpha_mode='fade'"),
        (dict(material_indices=[1]), "material_indices: triangle 0 takes material 1"),
        (dict(material_indices=[0, 0]), "material_indices has 2 entries for 1 triangles"),
        (dict(normals=np.zeros((3, 3))), "normals has 3 rows for 4 positions"),
        (dict(uvs=np.zeros((4, 3))), "uvs must have shape (N, 2), not (4, 3)"),
        (dict(lights=[{"type": "area"}]), "lights[0]: type='area' is not one of"),
        (dict(lights=[{"type": "point", "power": 3}]), "lights[0]: unknown key 'power'"),
        # Issue 58: a negative emission would subtract light.
        (dict(materials=[{"emission": [-1, 0, 0]}]), "materials[0]: emission=(-1, 0, 0) has a"),
        (dict(materials=[{"emissive_strength": -2}]), "materials[0]: emissive_strength=-2"),
        (dict(materials=[{"emission": [1, 2]}]), "materials[0]: emission=[1, 2] is not three"),
        (dict(materials=[{"emission": "red"}]), "materials[0]: emission='red' is not three"),
    ],
)
def test_wrong_shapes_and_unknown_keys_are_value_errors_that_name_them(change, words):
    arguments = dict(positions=[(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], indices=[0, 1, 2])
    arguments.update(change)
    with pytest.raises(ValueError) as raised:
        vkpath.Scene.from_arrays(**arguments)
    assert words in str(raised.value)
    assert isinstance(raised.value, vkpath.ArgumentError)
    assert isinstance(raised.value, vkpath.VkpathError)


def test_every_material_key_is_accepted():
    values = {"alpha_mode": "mask", "double_sided": True, "unlit": False}
    for key in vkpath.MATERIAL_KEYS:
        if key not in values:
            colour = key in ("base_color", "emission", "specular_color", "attenuation_color",
                             "multiscatter_color", "sheen_color")
            values[key] = (0.5, 0.5, 0.5) if colour else 0.5
    scene = vkpath.Scene.from_arrays([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [0, 1, 2],
                                     materials=[values])
    assert scene.triangle_count == 1 and scene.description == "arrays"


def test_colours_are_any_sequence_of_numbers():
    """Issue 58: a list (as JSON gives) or an array is as good as a tuple."""
    positions = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    flat = [0, 1, 2, 0, 2, 3]
    as_tuples = {"base_color": (0, 0, 0), "emission": (4, 4, 4)}
    images = []
    for emissive in (as_tuples, {"base_color": [0, 0, 0, 1], "emission": [4, 4, 4]},
                     {"base_color": np.zeros(3), "emission": np.full(3, 4.0, np.float32)}):
        scene = vkpath.Scene.from_arrays(positions, flat, materials=[emissive])
        images.append(vkpath.render(scene, width=8, height=8, spp=1, integrator="workshop"))
    assert images[0][4, 4, 0] == 4.0
    for image in images[1:]:
        assert np.array_equal(image, images[0])
