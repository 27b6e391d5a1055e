#!/usr/bin/env python3
"""Write the small glTF scenes that scripts/same-images.sh renders with the material kernels.

Each is a floor, a back wall and a low-resolution sphere (54 triangles or fewer, so the
kernels hold them as constants, except where a scene adds more) with one kind of material
or light, so that each specialization of the material kernels is covered on its own:

  glossy.gltf    untextured, opaque GGX materials (gold, red plastic) lit by an emissive quad
                 (SCENE_HAS_TEXTURES and SCENE_HAS_ALPHA both false);
  textured.gltf  a checkerboard baseColorTexture, a metallicRoughnessTexture and a normal
                 map, lit by an emissive quad (textures, no alpha);
  alpha.gltf     an alpha-MASK leaf and an alpha-BLEND pane in front of the wall (alpha);
  open.gltf      the floor and the glossy sphere, nothing emissive: for --environment and
                 --background;
  punctual.gltf  the glossy scene lit by KHR_lights_punctual point, spot and directional
                 lights, nothing emissive.

Standard library only; the geometry and textures come from scripts/make_materials_scene.py.
Usage: python3 scripts/make_same_images_scenes.py OUTPUT_DIR
"""

import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_materials_scene import (  # noqa: E402
    Builder, X, Y, NZ, checker_png, gradient_png, lambertian, leaf_png, look_at_rotation,
    metallic_roughness_png, normal_png, quad, uv_sphere)


def room(with_light, wall_material=None):
    """A builder with the floor, the back wall, a sphere and (optionally) an emissive quad."""
    b = Builder()
    for name in ("KHR_materials_specular", "KHR_materials_emissive_strength"):
        b.use_extension(name)

    def add_quad(name, material, center, right, up, hw, hh):
        attributes, indices = b.geometry(*quad(center, right, up, hw, hh))
        b.node({"name": name, "mesh": b.mesh(name, attributes, indices, material)})

    b.add_quad = add_quad
    floor = b.material(lambertian("floor", (0.6, 0.6, 0.55)))
    add_quad("floor", floor, [0, 0, 0], X, NZ, 2.0, 2.0)
    if wall_material is None:
        wall_material = {"name": "red plastic", "pbrMetallicRoughness": {
            "baseColorFactor": [0.8, 0.1, 0.05, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.3}}
    add_quad("back wall", b.material(wall_material), [0, 1.0, -1.0], X, Y, 2.0, 1.0)
    if with_light:
        light = b.material({
            "name": "light", "emissiveFactor": [1.0, 0.9, 0.8],
            "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8.0},
                           "KHR_materials_specular": {"specularFactor": 0.0}}})
        add_quad("light", light, [0.3, 2.0, 0.0], X, [0.0, 0.0, 1.0], 0.4, 0.4)
    b.gltf["cameras"].append({"type": "perspective", "perspective": {
        "yfov": math.radians(50.0), "aspectRatio": 1.5, "znear": 0.05, "zfar": 20.0}})
    eye, target = [0.4, 1.2, 2.6], [0.0, 0.5, -0.3]
    b.node({"name": "camera", "camera": 0, "translation": eye,
            "rotation": look_at_rotation(eye, target)})
    return b


def add_sphere(b, material, center, radius=0.45):
    attributes, indices = b.geometry(*uv_sphere(8, 4))
    mesh = b.mesh("sphere", attributes, indices, b.material(material))
    b.node({"name": "sphere", "mesh": mesh, "translation": center, "scale": [radius] * 3})


GOLD = {"name": "gold", "pbrMetallicRoughness": {
    "baseColorFactor": [1.0, 0.78, 0.34, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.2}}


def glossy():
    b = room(True)
    add_sphere(b, GOLD, [0.0, 0.45, -0.2])
    return b.finish()


def textured():
    b = room(True)
    checker = b.image("checkerboard", checker_png())
    stripes = b.image("metallic-roughness stripes", metallic_roughness_png())
    bumps = b.image("normal map", normal_png())
    b.gltf["materials"][0] = {"name": "checker floor", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": checker}, "metallicFactor": 0.0, "roughnessFactor": 0.6}}
    b.gltf["materials"][1] = {"name": "bumpy wall", "normalTexture": {"index": bumps},
                              "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.6, 0.5, 1.0],
                                                       "metallicFactor": 0.0, "roughnessFactor": 0.7}}
    add_sphere(b, {"name": "striped metal", "pbrMetallicRoughness": {
        "baseColorFactor": [0.35, 0.55, 0.95, 1.0], "metallicFactor": 1.0, "roughnessFactor": 1.0,
        "metallicRoughnessTexture": {"index": stripes}}}, [0.0, 0.45, -0.2])
    return b.finish()


def alpha():
    b = room(True)
    leaf = b.material({"name": "alpha mask leaf", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": b.image("leaf", leaf_png())}, "metallicFactor": 0.0,
        "roughnessFactor": 0.6}, "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True})
    b.add_quad("leaf", leaf, [-0.5, 0.6, -0.3], X, Y, 0.5, 0.5)
    pane = b.material({"name": "alpha blend pane", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": b.image("alpha gradient", gradient_png())},
        "metallicFactor": 0.0, "roughnessFactor": 0.3}, "alphaMode": "BLEND", "doubleSided": True})
    b.add_quad("pane", pane, [0.6, 0.4, 0.2], X, Y, 0.5, 0.4)
    return b.finish()


def open_scene():
    b = room(False, lambertian("white wall", (0.7, 0.7, 0.7)))
    add_sphere(b, GOLD, [0.0, 0.45, -0.2])
    return b.finish()


def punctual():
    b = room(False)
    add_sphere(b, GOLD, [0.0, 0.45, -0.2])
    b.use_extension("KHR_lights_punctual")
    b.gltf["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1.0, 0.9, 0.7], "intensity": 3.0},
        {"type": "spot", "color": [0.6, 0.8, 1.0], "intensity": 6.0,
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
        {"type": "directional", "color": [1.0, 1.0, 1.0], "intensity": 0.8},
    ]}}
    down = look_at_rotation([0.0, 0.0, 0.0], [0.0, -1.0, -0.3])
    slant = look_at_rotation([0.0, 0.0, 0.0], [-0.5, -1.0, -0.6])
    b.node({"name": "point", "translation": [0.8, 1.5, 0.5],
            "extensions": {"KHR_lights_punctual": {"light": 0}}})
    b.node({"name": "spot", "translation": [-0.4, 1.8, 0.3], "rotation": down,
            "extensions": {"KHR_lights_punctual": {"light": 1}}})
    b.node({"name": "sun", "rotation": slant, "extensions": {"KHR_lights_punctual": {"light": 2}}})
    return b.finish()


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for name, build in [("glossy", glossy), ("textured", textured), ("alpha", alpha),
                        ("open", open_scene), ("punctual", punctual)]:
        with open(os.path.join(out, name + ".gltf"), "w") as f:
            json.dump(build(), f)
            f.write("\n")


if __name__ == "__main__":
    main()
