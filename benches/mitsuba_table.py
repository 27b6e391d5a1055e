#!/usr/bin/env python3
"""vkpath against Mitsuba 3 on four scenes, whole processes, warm caches, two sampler pairings.

Each row renders one scene with both renderers at the same resolution, spp, maximum path
length (5), box pixel filter and no Russian roulette, and scores both images against a
high-spp vkpath reference (MIS, --moments, seed 7919, cached in the work directory):

    relMSE      = mean over pixels and RGB of (x - r)^2 / (r^2 + 0.01)     (as `vkpath bench`)
    efficiency  = 1 / (relMSE * seconds)
    seconds     = wall seconds of the WHOLE process that writes the image: for vkpath
                  `vkpath render ... -o out.exr` (Vulkan start-up, scene loading, BVH,
                  kernels, frames, the EXR); for Mitsuba `python3 <this script> --worker ...`
                  (interpreter, `import mitsuba`, scene loading, JIT, the render, the EXR).

Each renderer first runs once untimed (its "first run": it fills vkpath's pipeline cache and
Mesa's shader cache, or drjit's kernel cache in ~/.drjit), then --repeats timed runs with the
same seed, the fastest of which counts (a second run, warm caches).

Two sampler pairings per row (--pairings; issue 39, item 5), both reported:

    independent      vkpath --sampler pcg (PCG2D)  against Mitsuba `independent`: plain random
                     numbers on both sides, the like-with-like pairing of the algorithm
    low-discrepancy  vkpath --sampler sobol (Owen-scrambled Sobol, vkpath's default) against
                     Mitsuba `ldsampler` (scrambled (0,2)-sequences): each renderer's best sampler

The table is a regression guard for the CPU build (lavapipe against llvm_ad_rgb), not a target:
issue 39 dropped issue 20's CPU targets (Cornell box >= 4x, 10^6 triangles >= 1.5x, ...); the
targets against Mitsuba are now for a lent GPU (benches/mitsuba_compare.py --variant
cuda_ad_rgb, scripts/gpu-peer.sh).

The rows (issue 20's four scenes, with scenes of our own where that issue measured public assets):

    cornell    the workshop's Cornell box (vkpath's built-in scene), 256x256, 64 spp
    generated  vkpath's generated scale-test scene, about 10^6 triangles, 320x180, 64 spp
    spheres    a glTF of our own in place of the 121k-triangle engine: 24 flat-shaded
               icospheres (122 882 triangles) in 25 glTF metallic-roughness materials, a white
               sky (vkpath --background 1,1,1; Mitsuba a `constant` emitter), 64x64, 64 spp
    textured   benches/mitsuba_textured.py's textured box (12 triangles, two checker textures
               with KHR_texture_transform, an emissive quad), 64x64, 64 spp

Mitsuba gets the same triangles: rows cornell and generated through `vkpath export` (PLY meshes
and a manifest), rows spheres and textured from the same Python arrays this script writes the
glTF from, as binary PLY files (with uv for the textured box). Materials: Lambertian as
`twosided` `diffuse`, glTF metallic-roughness as benches/mitsuba_gltf_bsdf.py's plugin (glTF's
BRDF written for Mitsuba), textures as `bitmap` with the glTF sampler's filter, wrap mode and
texture transform.

The gate: the speeds count only if both images are consistent with the reference
(`vkpath compare`; Mitsuba's per-pixel variance is estimated from --batches further renders,
as benches/mitsuba_compare.py does; vkpath's from one more, untimed run with --moments, the same
image). The script prints CONSISTENT / NOT CONSISTENT per row and exits 1 if any gate fails.
With Sobol / ldsampler the gate is more lenient, never stricter: vkpath's per-pixel moments and
Mitsuba's batch spread both treat stratified samples as independent, which overestimates the
noise of the image they judge.

Usage (from the repository root; the first run renders the references, about 10 minutes on
2 cores):
    python3 benches/mitsuba_table.py                     # all four rows
    python3 benches/mitsuba_table.py --scenes cornell,textured --repeats 2
    python3 benches/mitsuba_table.py --pairings low-discrepancy    # one pairing only
Setup as benches/mitsuba_compare.py (libllvm19, mitsuba 3.9.1; --no-setup only checks).
"""

import argparse
import json
import math
import os
import re
import resource
import struct
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # no __pycache__ next to the imported scripts
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "scripts"))
import mitsuba_compare as mc  # noqa: E402  (setup, relMSE, moments, the gate)
import mitsuba_textured as mt  # noqa: E402  (the textured box)
import make_materials_scene as mms  # noqa: E402  (glTF builder)

REPO = mc.REPO
MAX_PATH_LENGTH = 5
REFERENCE_SEED = 7919
# name: (width, height, spp, reference spp, what the row stands for)
SCENES = {
    "cornell": (256, 256, 64, 2048, "Cornell box (built-in), 30 triangles"),
    "generated": (320, 180, 64, 512, "generated scene, ~10^6 triangles"),
    "spheres": (64, 64, 64, 4096, "24 icospheres, 122 882 triangles, 25 metallic-roughness materials, white sky"),
    "textured": (64, 64, 64, 4096, "textured box, 12 triangles, 2 textures"),
}
GENERATED_TRIANGLES = 1000000
# --pairings: (vkpath --sampler, Mitsuba sampler plugin), as benches/mitsuba_compare.py's SAMPLERS.
PAIRINGS = mc.SAMPLERS


# --------------------------------------------------------------------------------------------
# Scenes: one description for Mitsuba (JSON: PLY files, BSDF dicts, camera) and vkpath's args
# --------------------------------------------------------------------------------------------

def write_ply(path, positions, uvs=None):
    """A binary PLY triangle soup: every three vertices one triangle, counter-clockwise around
    its normal (Mitsuba's face_normals follow the winding)."""
    assert len(positions) % 3 == 0
    header = ["ply", "format binary_little_endian 1.0", "comment written by benches/mitsuba_table.py",
              f"element vertex {len(positions)}", "property float x", "property float y", "property float z"]
    if uvs is not None:
        header += ["property float u", "property float v"]
    header += [f"element face {len(positions) // 3}", "property list uchar int vertex_indices", "end_header"]
    with open(path, "wb") as f:
        f.write(("\n".join(header) + "\n").encode("ascii"))
        for i, p in enumerate(positions):
            f.write(struct.pack("<3f", *p))
            if uvs is not None:
                f.write(struct.pack("<2f", *uvs[i]))
        for t in range(len(positions) // 3):
            f.write(struct.pack("<B3i", 3, 3 * t, 3 * t + 1, 3 * t + 2))


def exported_scene(vkpath, directory, generated):
    """Rows cornell and generated: `vkpath export`, as benches/mitsuba_compare.py reads it."""
    cmd = [vkpath, "export", "--output-dir", directory]
    if generated is not None:
        cmd += ["--generated", str(generated)]
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"vkpath export failed ({result.returncode}):\n{result.stderr}")
    with open(os.path.join(directory, "scene.json")) as f:
        manifest = json.load(f)
    shapes = []
    for mesh in manifest["meshes"]:
        shape = {"ply": os.path.join(directory, mesh["file"]),
                 "bsdf": {"type": "twosided", "material": {
                     "type": "diffuse", "reflectance": {"type": "rgb", "value": mesh["color"]}}}}
        if max(mesh["emission"]) > 0:
            if mesh["double_sided"]:
                sys.exit(f"{mesh['file']}: double-sided emitters have no Mitsuba counterpart here")
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": mesh["emission"]}}
        shapes.append(shape)
    cam = manifest["camera"]
    description = {"shapes": shapes, "camera": cam, "sky": None, "plugin": False,
                   "triangles": sum(mesh["triangles"] for mesh in manifest["meshes"])}
    return description, ([] if generated is None else ["--generated", str(generated)])


def icosphere(level):
    """Unit icosphere triangles (counter-clockwise seen from outside), `level` subdivisions."""
    t = (1.0 + 5.0 ** 0.5) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [mms.normalize(p) for p in v]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
             (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    triangles = [tuple(v[i] for i in f) for f in faces]
    for _ in range(level):
        finer = []
        for a, b, c in triangles:
            ab, bc, ca = (mms.normalize(mms.scale(mms.add(p, q), 0.5)) for p, q in ((a, b), (b, c), (c, a)))
            finer += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        triangles = finer
    return triangles


SPHERE_COLUMNS, SPHERE_ROWS, SPHERE_LEVEL, SPHERE_RADIUS = 6, 4, 4, 0.35
SPHERES_CAMERA = (0.0, 1.6, 6.0)  # looking down -z
SPHERES_YFOV = 0.8


def sphere_material(i):
    """Sphere i's glTF factors: base colour, metallic, roughness (a spread of both lobes)."""
    hue = i / (SPHERE_COLUMNS * SPHERE_ROWS)
    base = tuple(0.25 + 0.6 * (0.5 + 0.5 * math.cos(2.0 * math.pi * (hue + k / 3.0))) for k in range(3))
    metallic = 1.0 if i % 3 == 2 else (0.0 if i % 3 == 0 else 0.5)
    roughness = 0.3 + 0.7 * ((i * 7) % 11) / 10.0
    return base, metallic, roughness


def spheres_scene(directory):
    """Row spheres: the glTF for vkpath and the PLY meshes for Mitsuba, from the same arrays."""
    unit = icosphere(SPHERE_LEVEL)
    b = mms.Builder()
    b.gltf["asset"]["generator"] = "vkpath benches/mitsuba_table.py"
    b.gltf["scenes"][0]["name"] = "spheres"
    b.use_extension("KHR_materials_specular")
    meshes = []  # (name, triangles as vertex triples, glTF factors)
    for i in range(SPHERE_COLUMNS * SPHERE_ROWS):
        cx = (i % SPHERE_COLUMNS - (SPHERE_COLUMNS - 1) / 2.0) * 0.8
        cy = 0.4 + 0.8 * (i // SPHERE_COLUMNS)
        triangles = [tuple(mms.add((cx, cy, 0.0), mms.scale(p, SPHERE_RADIUS)) for p in tri) for tri in unit]
        meshes.append((f"sphere_{i}", triangles, sphere_material(i)))
    floor = [((-4.0, 0.0, 3.0), (4.0, 0.0, 3.0), (4.0, 0.0, -3.0)), ((-4.0, 0.0, 3.0), (4.0, 0.0, -3.0), (-4.0, 0.0, -3.0))]
    meshes.append(("floor", floor, ((0.6, 0.6, 0.6), 0.0, 1.0)))
    shapes = []
    for name, triangles, (base, metallic, roughness) in meshes:
        positions = [p for tri in triangles for p in tri]
        normals = []
        for a, c1, c2 in triangles:
            normals += [mms.normalize(mms.cross(mms.sub(c1, a), mms.sub(c2, a)))] * 3
        attributes, indices = b.geometry(positions, normals, [(0.0, 0.0)] * len(positions),
                                         list(range(len(positions))))
        material = b.material({"name": name, "doubleSided": True, "pbrMetallicRoughness": {
            "baseColorFactor": list(base) + [1.0], "metallicFactor": metallic, "roughnessFactor": roughness}})
        b.node({"name": name, "mesh": b.mesh(name, attributes, indices, material)})
        ply = os.path.join(directory, f"{name}.ply")
        write_ply(ply, positions)
        shapes.append({"ply": ply, "bsdf": {"type": "twosided", "material": {
            "type": "gltf_metallic_roughness", "base_color": {"type": "rgb", "value": list(base)},
            "metallic_factor": metallic, "roughness_factor": roughness}}})
    b.gltf["cameras"].append({"type": "perspective", "perspective": {
        "yfov": SPHERES_YFOV, "aspectRatio": 1.0, "znear": 0.01}})
    b.node({"name": "camera", "camera": 0, "translation": list(SPHERES_CAMERA)})
    gltf = os.path.join(directory, "spheres.gltf")
    with open(gltf, "w") as f:
        json.dump(b.finish(), f)
    cx, cy, cz = SPHERES_CAMERA
    camera = {"position": [cx, cy, cz], "target": [cx, cy, cz - 1.0], "up": [0.0, 1.0, 0.0],
              "fov_y_degrees": math.degrees(SPHERES_YFOV)}
    description = {"shapes": shapes, "camera": camera, "sky": [1.0, 1.0, 1.0], "plugin": True,
                   "triangles": sum(len(m[1]) for m in meshes)}
    return description, [gltf, "--background", "1,1,1"]


def textured_scene(directory):
    """Row textured: benches/mitsuba_textured.py's box (its defaults: no metallic-roughness)."""
    png = mt.checker_png()
    png_path = os.path.join(directory, "checker.png")
    with open(png_path, "wb") as f:
        f.write(png)
    gltf = os.path.join(directory, "textured_box.gltf")
    mt.write_gltf(gltf, png)
    shapes = []
    triangles = 0
    for q in mt.scene_description():
        positions = [q["positions"][i] for i in q["indices"]]
        uvs = [q["uvs"][i] for i in q["indices"]]
        triangles += len(q["indices"]) // 3
        ply = os.path.join(directory, f"{q['name']}.ply")
        write_ply(ply, positions, uvs)
        tex = q.get("texture")
        if tex is not None:
            reflectance = {"type": "bitmap", "filename": png_path, "raw": False, "format": "variant",
                           "filter_type": mt.MITSUBA_FILTER[tex["filter"]],
                           "wrap_mode": mt.MITSUBA_WRAP[tex["wrap"]],
                           "to_uv": mt.texture_matrix(tex["offset"], 0.0, tex["scale"])}
        else:
            reflectance = {"type": "rgb", "value": list(q["color"])}
        shape = {"ply": ply, "bsdf": {"type": "twosided", "material": {"type": "diffuse", "reflectance": reflectance}}}
        if "emission" in q:
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": list(q["emission"])}}
        shapes.append(shape)
    cx, cy, cz = mt.CAMERA_POSITION
    camera = {"position": [cx, cy, cz], "target": [cx, cy, cz - 1.0], "up": [0.0, 1.0, 0.0],
              "fov_y_degrees": math.degrees(mt.CAMERA_YFOV)}
    return {"shapes": shapes, "camera": camera, "sky": None, "plugin": False, "triangles": triangles}, [gltf]


def mitsuba_scene(mi, description, width, height, spp, sampler="independent", max_depth=MAX_PATH_LENGTH):
    """The description as a loaded Mitsuba scene (`path`, max_depth 5 unless told, no Russian
    roulette, the given sampler plugin)."""
    scene = {"type": "scene"}
    for i, shape in enumerate(description["shapes"]):
        bsdf = json.loads(json.dumps(shape["bsdf"]))
        reflectance = bsdf.get("material", {}).get("reflectance", {})
        if "to_uv" in reflectance:
            reflectance["to_uv"] = mi.ScalarTransform3f(reflectance["to_uv"])
        entry = {"type": "ply", "filename": shape["ply"], "face_normals": True, "bsdf": bsdf}
        if "emitter" in shape:
            entry["emitter"] = shape["emitter"]
        scene[f"shape_{i}"] = entry
    if description["sky"] is not None:
        scene["sky"] = {"type": "constant", "radiance": {"type": "rgb", "value": description["sky"]}}
    cam = description["camera"]
    scene["sensor"] = {
        "type": "perspective", "fov_axis": "y", "fov": cam["fov_y_degrees"],
        "to_world": mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["target"], up=cam["up"]),
        "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"},
                 "pixel_format": "rgb"},
        "sampler": {"type": sampler, "sample_count": spp},
    }
    scene["integrator"] = {"type": "path", "max_depth": max_depth,
                           "rr_depth": max_depth + 1000, "hide_emitters": False}
    return mi.load_dict(scene)


def import_mitsuba(threads, plugin):
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    dr.set_thread_count(threads)
    if plugin:
        import mitsuba_gltf_bsdf
        mitsuba_gltf_bsdf.register(mi, dr)
    return mi, dr


def worker(args):
    """One whole Mitsuba process: load the description, render, write the EXR."""
    with open(args.worker) as f:
        description = json.load(f)
    mi, dr = import_mitsuba(args.threads, description["plugin"])
    scene = mitsuba_scene(mi, description, args.width, args.height, args.spp, sampler=args.mitsuba_sampler)
    image = mi.render(scene, spp=args.spp, seed=args.seed)
    mi.Bitmap(image).write(args.out)
    return 0


# --------------------------------------------------------------------------------------------
# Timed whole processes
# --------------------------------------------------------------------------------------------

def timed(cmd):
    """Runs cmd; returns (wall seconds, CPU seconds of the process and its children, stderr)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode != 0:
        sys.exit(f"failed ({result.returncode}): {' '.join(cmd)}\n{result.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, result.stderr


SETUP_RE = re.compile(r"setup (?P<setup>[0-9.]+) s, render (?P<render>[0-9.]+) s")


def vkpath_command(args, scene_args, width, height, spp, output, seed, moments=False, sampler="pcg"):
    cmd = [args.vkpath, "render", *scene_args, "-o", output, "--width", str(width), "--height", str(height),
           "--spp", str(spp), "--integrator", "mis", "--sampler", sampler, "--russian-roulette-start", "0",
           "--max-path-length", str(MAX_PATH_LENGTH), "--pixel-filter", "box", "--seed", str(seed)]
    return cmd + (["--moments"] if moments else [])


def fastest(cmd, repeats):
    """A first, untimed-for-the-score run (warms the caches), then `repeats` timed runs."""
    first = timed(cmd)
    runs = [timed(cmd) for _ in range(repeats)]
    best = min(runs, key=lambda run: run[0])
    return first, best, runs


def run_row(args, mi, dr, name):
    """One scene: its reference, then each pairing of samplers; a result per pairing."""
    width, height, spp, reference_spp, label = SCENES[name]
    directory = os.path.join(args.workdir, name)
    os.makedirs(directory, exist_ok=True)
    print(f"== {name}: {label}, {width}x{height}, {spp} spp, max path length {MAX_PATH_LENGTH}", flush=True)
    if name in ("cornell", "generated"):
        description, scene_args = exported_scene(args.vkpath, directory, GENERATED_TRIANGLES if name == "generated" else None)
    elif name == "spheres":
        description, scene_args = spheres_scene(directory)
    else:
        description, scene_args = textured_scene(directory)
    description_path = os.path.join(directory, "mitsuba_scene.json")
    with open(description_path, "w") as f:
        json.dump(description, f, indent=1)

    # The reference: PCG2D (independent samples, so that its moments are honest), for both pairings.
    ref = os.path.join(directory, f"ref_{width}x{height}_L{MAX_PATH_LENGTH}_spp{reference_spp}.exr")
    if args.force_reference or not os.path.exists(ref):
        print(f"   reference: vkpath mis, {reference_spp} spp", flush=True)
        timed(vkpath_command(args, scene_args, width, height, reference_spp, ref + ".tmp.exr", REFERENCE_SEED, True))
        os.replace(ref + ".tmp.exr", ref)
    r, r_moments, _ = mc.read_rgb(mi, dr, ref)
    ref_noise = mc.reference_noise(mi, dr, r, r_moments)
    return [run_pairing(args, mi, dr, name, pairing, description, description_path, scene_args, ref, r, ref_noise)
            for pairing in args.pairing_list]


def run_pairing(args, mi, dr, name, pairing, description, description_path, scene_args, ref, r, ref_noise):
    width, height, spp, reference_spp, label = SCENES[name]
    vk_sampler, mi_sampler = PAIRINGS[pairing]
    directory = os.path.join(args.workdir, name)
    print(f"   -- pairing {pairing}: vkpath {vk_sampler} / Mitsuba {mi_sampler}", flush=True)
    rows = {}
    # vkpath: whole processes.
    out = os.path.join(directory, f"vkpath_{pairing}.exr")
    first, best, runs = fastest(vkpath_command(args, scene_args, width, height, spp, out, 0, sampler=vk_sampler),
                                args.repeats)
    match = SETUP_RE.search(best[2])
    x, _, _ = mc.read_rgb(mi, dr, out)
    rows["vkpath"] = {"sampler": vk_sampler, "first_s": first[0], "seconds": best[0], "cpu_s": best[1],
                      "runs": [run[0] for run in runs],
                      "setup_s": float(match.group("setup")) if match else None,
                      "render_s": float(match.group("render")) if match else None,
                      "relmse": mc.relative_mse(mi, dr, x, r)}
    gate_exr = os.path.join(directory, f"vkpath_moments_{pairing}.exr")
    timed(vkpath_command(args, scene_args, width, height, spp, gate_exr, 0, True, sampler=vk_sampler))
    code_v, verdict_v, _ = mc.run_compare(args.vkpath, gate_exr, ref)
    rows["vkpath"]["gate"] = verdict_v

    # Mitsuba: whole processes.
    out = os.path.join(directory, f"mitsuba_timed_{pairing}.exr")
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", description_path, "--out", out,
           "--width", str(width), "--height", str(height), "--spp", str(spp), "--seed", "0",
           "--threads", str(args.threads), "--mitsuba-sampler", mi_sampler]
    first, best, runs = fastest(cmd, args.repeats)
    timed_image = mi.TensorXf(mi.Bitmap(out))
    # The gate's variance: further independent renders at spp / batches (not timed).
    scene = mitsuba_scene(mi, description, width, height, spp, sampler=mi_sampler)
    batch_spp = spp // args.batches
    batches = [mc.mitsuba_render(mi, dr, scene, batch_spp, seed=2000 + b)[0] for b in range(args.batches)]
    mitsuba_exr = os.path.join(directory, f"mitsuba_{pairing}.exr")
    mc.write_with_moments(mi, dr, mitsuba_exr, timed_image, batches, spp, batch_spp)
    x, _, _ = mc.read_rgb(mi, dr, mitsuba_exr)
    code_m, verdict_m, text_m = mc.run_compare(args.vkpath, mitsuba_exr, ref)
    rows["mitsuba"] = {"sampler": mi_sampler, "first_s": first[0], "seconds": best[0], "cpu_s": best[1],
                       "runs": [run[0] for run in runs], "relmse": mc.relative_mse(mi, dr, x, r), "gate": verdict_m}
    for row in rows.values():
        row["efficiency"] = 1.0 / (row["relmse"] * row["seconds"])
    result = {"scene": name, "pairing": pairing, "samplers": {"vkpath": vk_sampler, "mitsuba": mi_sampler},
              "label": label, "width": width, "height": height, "spp": spp,
              "reference_spp": reference_spp, "triangles": description["triangles"],
              "reference_noise_relmse": ref_noise, "rows": rows,
              "ratio": rows["vkpath"]["efficiency"] / rows["mitsuba"]["efficiency"],
              "gates_pass": code_v == 0 and code_m == 0, "mitsuba_gate_report": text_m}
    for who in ("vkpath", "mitsuba"):
        row = rows[who]
        print(f"   {who:<8} ({row['sampler']}) first run {row['first_s']:.2f} s, second runs "
              f"{', '.join(f'{s:.2f}' for s in row['runs'])} s (CPU {row['cpu_s']:.2f} s), relMSE "
              f"{row['relmse']:.5f}, efficiency {row['efficiency']:.2f}, gate: {row['gate']}", flush=True)
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scenes", default=",".join(SCENES), help=f"comma-separated subset of {', '.join(SCENES)}")
    parser.add_argument("--pairings", default=",".join(PAIRINGS),
                        help=f"comma-separated sampler pairings, of {', '.join(PAIRINGS)} (see the top)")
    parser.add_argument("--repeats", type=int, default=3, help="timed whole-process runs per renderer (fastest counts)")
    parser.add_argument("--batches", type=int, default=16, help="Mitsuba renders at spp/batches for the gate's variance")
    mc.add_common_arguments(parser, "mitsuba_table")
    # The worker: one whole Mitsuba process (used by the script itself).
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    parser.add_argument("--out", help=argparse.SUPPRESS)
    parser.add_argument("--width", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--height", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--spp", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--seed", type=int, default=0, help=argparse.SUPPRESS)
    parser.add_argument("--mitsuba-sampler", default="independent", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        return worker(args)
    names = [n for n in args.scenes.split(",") if n]
    unknown = [n for n in names if n not in SCENES]
    if unknown:
        sys.exit(f"unknown scene(s) {', '.join(unknown)}; known: {', '.join(SCENES)}")
    args.pairing_list = [p for p in args.pairings.split(",") if p]
    unknown = [p for p in args.pairing_list if p not in PAIRINGS]
    if unknown or not args.pairing_list:
        sys.exit(f"unknown pairing(s) {', '.join(unknown)}; known: {', '.join(PAIRINGS)}")
    if args.threads < 2:
        sys.exit("--threads must be at least 2: with one drjit thread mi.Bitmap's EXR read hangs")
    if args.repeats < 1 or args.batches < 2:
        sys.exit("--repeats must be at least 1 and --batches at least 2")

    mc.ensure_setup(not args.no_setup)
    mc.ensure_vkpath(args.vkpath, args.build)
    args.vkpath = os.path.abspath(args.vkpath)
    os.makedirs(args.workdir, exist_ok=True)
    mi, dr = import_mitsuba(args.threads, True)
    print(f"mitsuba {mi.__version__} llvm_ad_rgb, {dr.thread_count()} threads; vkpath {args.vkpath}; "
          f"whole processes, fastest of {args.repeats} after a first run; pairings {', '.join(args.pairing_list)}",
          flush=True)
    results = [res for name in names for res in run_row(args, mi, dr, name)]

    print()
    header = (f"{'scene':<10}{'pairing':<17}{'triangles':>10}{'size':>9}{'Mitsuba s':>10}{'relMSE':>9}"
              f"{'vkpath s':>9}{'(setup)':>8}{'relMSE':>9}{'vkpath/Mitsuba':>15}  gates")
    print(header)
    print("-" * len(header))
    for res in results:
        m, v = res["rows"]["mitsuba"], res["rows"]["vkpath"]
        setup = f"{v['setup_s']:.2f}" if v["setup_s"] is not None else "-"
        print(f"{res['scene']:<10}{res['pairing']:<17}{res['triangles']:>10}{res['width']:>5}x{res['height']:<3}"
              f"{m['seconds']:>10.2f}{m['relmse']:>9.5f}{v['seconds']:>9.2f}{setup:>8}{v['relmse']:>9.5f}"
              f"{res['ratio']:>14.2f}x  "
              f"{'pass' if res['gates_pass'] else 'FAIL (' + m['gate'] + ' / ' + v['gate'] + ')'}")
    print("seconds: wall seconds of the whole process (second run, fastest of the repeats); "
          "ratio: efficiency 1/(relMSE*seconds) of vkpath mis over Mitsuba path; pairings: independent = "
          "PCG2D / independent, low-discrepancy = Sobol / ldsampler")
    with open(os.path.join(args.workdir, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
    return 0 if all(res["gates_pass"] for res in results) else 1


if __name__ == "__main__":
    sys.exit(main())
