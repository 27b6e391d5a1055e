#!/usr/bin/env python3
"""Generate scenes/glass.gltf: vkpath's layered glTF materials (issue: glass and coats).

The room of scripts/make_materials_scene.py (Lambertian walls, a ceiling light, a
checkerboard floor, a brick-coloured panel on the back wall) holding:

  * a smooth glass sphere: KHR_materials_transmission 1, KHR_materials_ior 1.5,
    KHR_materials_volume (thickness 0.6, a faint green attenuation colour);
  * a rough glass sphere: the same with roughness 0.3 and no absorption;
  * a thin-walled pane: transmission 1, no volume (light passes straight through);
  * a clear-coated panel: a rough red dielectric under KHR_materials_clearcoat
    (clearcoat 1, clearcoat roughness 0.03);
  * a small KHR_materials_unlit tile (its base colour as camera rays see it);
  * a velvet ball: a dark red base under KHR_materials_sheen (sheen colour pink, roughness
    0.5).

Standard library only; reuses the builders of make_materials_scene.py.

Usage: python3 scripts/make_glass_scene.py [output.gltf]   (default scenes/glass.gltf)
"""

import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_materials_scene import (  # noqa: E402
    Builder, HEIGHT, NX, NY, NZ, ROOM, X, Y, Z, add, brick_color_png, checker_png, lambertian,
    look_at_rotation, quad, uv_sphere)


def build():
    b = Builder()
    b.gltf["asset"]["generator"] = "vkpath scripts/make_glass_scene.py"
    b.gltf["scenes"][0]["name"] = "glass"
    for name in ("KHR_materials_specular", "KHR_materials_emissive_strength", "KHR_texture_transform",
                 "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
                 "KHR_materials_clearcoat", "KHR_materials_unlit", "KHR_materials_sheen"):
        b.use_extension(name)

    def add_quad(name, material, center, right, up, hw, hh, uv_scale=(1.0, 1.0)):
        attributes, indices = b.geometry(*quad(center, right, up, hw, hh, uv_scale))
        mesh = b.mesh(name, attributes, indices, material)
        b.node({"name": name, "mesh": mesh})

    white = b.material(lambertian("wall white", (0.73, 0.73, 0.73)))
    red = b.material(lambertian("wall red", (0.63, 0.065, 0.05)))
    green = b.material(lambertian("wall green", (0.14, 0.45, 0.091)))
    add_quad("back wall", white, [0, HEIGHT / 2, -ROOM], X, Y, ROOM, HEIGHT / 2)
    add_quad("front wall", white, [0, HEIGHT / 2, ROOM], NX, Y, ROOM, HEIGHT / 2)
    add_quad("left wall", red, [-ROOM, HEIGHT / 2, 0], NZ, Y, ROOM, HEIGHT / 2)
    add_quad("right wall", green, [ROOM, HEIGHT / 2, 0], Z, Y, ROOM, HEIGHT / 2)
    add_quad("ceiling", white, [0, HEIGHT, 0], X, Z, ROOM, ROOM)
    light = b.material({
        "name": "ceiling light",
        "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0},
        "emissiveFactor": [1.0, 1.0, 1.0],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 12.0},
                       "KHR_materials_specular": {"specularFactor": 0.0}}})
    add_quad("ceiling light", light, [0, HEIGHT - 0.01, -0.2], X, Z, 0.6, 0.6)

    checker = b.image("checkerboard", checker_png())
    floor = b.material({
        "name": "floor checkerboard",
        "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6,
            "baseColorTexture": {"index": checker, "extensions": {
                "KHR_texture_transform": {"scale": [4.0, 4.0]}}}}})
    add_quad("floor", floor, [0, 0, 0], X, NZ, ROOM, ROOM)
    bricks = b.image("brick colour", brick_color_png())
    wall_panel = b.material({
        "name": "brick-coloured panel",
        "pbrMetallicRoughness": {"baseColorTexture": {"index": bricks}, "metallicFactor": 0.0,
                                 "roughnessFactor": 0.8},
        "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}})
    add_quad("back panel", wall_panel, [0.0, 1.3, -ROOM + 0.01], X, Y, 1.6, 1.0, (2.0, 1.25))

    sphere_attributes, sphere_indices = b.geometry(*uv_sphere(48, 24))
    spheres = [
        ("smooth glass", 0.0, {"thicknessFactor": 0.6, "attenuationColor": [0.8, 0.95, 0.85],
                               "attenuationDistance": 0.6}, -0.75),
        ("rough glass", 0.3, {"thicknessFactor": 0.6}, 0.75),
    ]
    radius = 0.45
    for name, roughness, volume, x in spheres:
        material = b.material({
            "name": name,
            "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0,
                                     "roughnessFactor": roughness},
            "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                           "KHR_materials_ior": {"ior": 1.5},
                           "KHR_materials_volume": volume}})
        mesh = b.mesh("sphere " + name, sphere_attributes, sphere_indices, material)
        b.node({"name": "sphere " + name, "mesh": mesh,
                "translation": [x, radius, -0.6], "scale": [radius] * 3})

    pane = b.material({
        "name": "thin glass pane",
        "pbrMetallicRoughness": {"baseColorFactor": [0.55, 0.75, 1.0, 1.0], "metallicFactor": 0.0,
                                 "roughnessFactor": 0.0},
        "doubleSided": True,
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}})
    add_quad("thin pane", pane, [0.0, 0.55, 0.2], X, Y, 0.35, 0.55)

    coated = b.material({
        "name": "clear-coated red",
        "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.06, 0.05, 1.0], "metallicFactor": 0.0,
                                 "roughnessFactor": 0.7},
        "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                                   "clearcoatRoughnessFactor": 0.03}}})
    add_quad("coated panel", coated, [-ROOM + 0.01, 1.2, -0.6], NZ, Y, 0.7, 0.6)

    unlit = b.material({
        "name": "unlit tile",
        "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.9, 1.0]},
        "extensions": {"KHR_materials_unlit": {}}})
    add_quad("unlit tile", unlit, [ROOM - 0.01, 1.6, -0.9], Z, Y, 0.25, 0.25)

    velvet = b.material({
        "name": "velvet",
        "pbrMetallicRoughness": {"baseColorFactor": [0.25, 0.02, 0.04, 1.0], "metallicFactor": 0.0,
                                 "roughnessFactor": 0.9},
        "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1.0, 0.55, 0.65],
                                               "sheenRoughnessFactor": 0.5}}})
    velvet_mesh = b.mesh("velvet ball", sphere_attributes, sphere_indices, velvet)
    b.node({"name": "velvet ball", "mesh": velvet_mesh,
            "translation": [-1.25, 0.3, 0.35], "scale": [0.3] * 3})

    eye = [0.0, 1.3, 1.95]
    pitch = math.radians(-12.0)
    target = add(eye, [0.0, math.sin(pitch), -math.cos(pitch)])
    b.gltf["cameras"].append({"name": "camera", "type": "perspective", "perspective": {
        "yfov": math.radians(55.0), "aspectRatio": 4.0 / 3.0, "znear": 0.05, "zfar": 20.0}})
    b.node({"name": "camera", "camera": 0, "translation": eye,
            "rotation": look_at_rotation(eye, target)})
    return b.finish()


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "scenes", "glass.gltf")
    with open(out, "w") as f:
        json.dump(build(), f, indent=1)
        f.write("\n")
    print("wrote", out)


if __name__ == "__main__":
    main()
