#!/usr/bin/env python3
"""Render the workshop's Cornell box with Mitsuba 3 and with vkpath; compare their efficiency.

Both renderers get the same scene (the built-in Cornell box, or with --generated N vkpath's
generated scale-test scene of about N triangles), the same pinhole camera, resolution, box
pixel filter, maximum path length and no Russian roulette. Mitsuba reads the triangles that
`vkpath export` writes (one PLY mesh per material and a JSON manifest). Each image at a fixed spp is scored against a high-spp vkpath reference:

    relMSE      = mean over pixels and RGB of (x - r)^2 / (r^2 + 0.01)
    efficiency  = 1 / (relMSE * seconds)               (higher is better)
    s to 0.005  = seconds * relMSE / 0.005             (time to reach relMSE 0.005)

The correctness gate: a speed counts only if `vkpath compare <image> <reference>` finds the
image consistent with the common reference, for every image (Mitsuba's, vkpath mis's, vkpath
workshop's); the script prints each verdict and exits 1 when any fails. The thresholds are
compare's: the image is cut into 8x8-pixel blocks, and each block's mean difference per channel
is a z-test whose variance comes from both images' per-pixel moments (the noise of the image
AND of the reference enter); the family of tests is held at alpha 0.01 in all with Sidak's
correction (alpha per test = 1 - 0.99^(1/tests), e.g. 2.1e-4 for 48 tests), so a consistent
pair fails about once in a hundred runs whatever the image size (at 1920x1080, 97 200 tests,
a block fails beyond |z| ~ 5.3), while a bias shows once it exceeds about that many standard
errors of a block's mean. Blocks rather than pixels: a pixel's 64-sample mean is too skewed
for a z-test, a block's 4096 samples much less so; at ~1000 samples per block (8x8 at 16 spp)
heavy-tailed images failed single blocks by chance in lavapipe checks, so give low-spp runs
larger blocks (--gate-block 16 at 16 spp: 4096 samples again). A mismatch of
conventions (Mitsuba max_depth one less: --mitsuba-max-depth 4) fails it. Stratified samplers
(Sobol, ldsampler) make the gate more lenient, never stricter: their moments and batch spread
overestimate the noise of the image they judge.

Setup (done by the script itself when missing; needs root for apt, skip it with --no-setup):
    apt-get install -y libllvm19          # Debian 12 bookworm: 1:19.1.7-3~deb12u1
    pip install mitsuba==3.9.1            # pulls drjit (1.5.0)
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so   (set before importing drjit)
    cargo build --release                 # when target/release/vkpath is missing (or --build)
Mitsuba runs the `llvm_ad_rgb` variant on --threads CPU threads (default 2, dr.set_thread_count);
vkpath runs on whatever Vulkan device it picks (lavapipe on a machine without a GPU).

Timing:
  * Mitsuba: one warm-up mi.render first (JIT tracing and LLVM or CUDA/OptiX compilation;
    reported as "cold"), then --repeats timed mi.renders at --spp (the first of them is
    Mitsuba's second render), timed around mi.render and the evaluation of its result only.
    The seed is an opaque value in drjit's traced kernel (checked with drjit's kernel history:
    a render at another seed is a kernel-cache hit, a render at another spp is not), so the
    timed renders run the warm-up's compiled kernel. Drjit caches compiled kernels on disk
    (~/.drjit), so the cold time of a second run of this script is smaller.
  * vkpath: the render seconds of its stderr summary line ('..., setup T s, render S s,
    M M samples/s'), which cover the frames only (not device start-up or pipeline creation);
    its pipeline cache makes every render after the first warm, like Mitsuba's second.

Moments for the gate: `vkpath compare` needs each image's per-pixel variance. vkpath stores
it with --moments; for Mitsuba the script renders --batches more independent images at
spp/batches each, estimates the variance of the timed image's pixel means from their spread,
and stores it in mitsuba.exr as vkpath's `second_moment.{R,G,B}` / `sample_count.Y` channels
(sample count = number of batches; the mean channels are the timed image's).

Variants (--variant): `llvm_ad_rgb` (the default: drjit's LLVM back end on --threads CPU
threads) or `cuda_ad_rgb` (CUDA and OptiX loaded from the NVIDIA driver, no toolkit; OptiX's
software traversal on GPUs without RT cores, such as the H100/H200 the device lends). With
`cuda_ad_rgb` no libLLVM is needed, and the script stops at once with one line starting
"PEER STOP:" when the variant cannot start (no libcuda.so / libnvoptix.so, no GPU), so that a
device call spends no time on a run that cannot work. scripts/gpu-peer.sh runs it that way.

Participating media (--medium TEXT, `vkpath render --medium`'s text, e.g.
"sigma_a=0.02:sigma_s=0.3:g=0.6"): the Cornell box in a homogeneous global medium. vkpath's
renders and the reference get --medium; `vkpath export --medium` writes it into scene.json, and
Mitsuba gets a `homogeneous` medium (sigma_t = sigma_a + sigma_s, albedo = sigma_s / sigma_t per
channel, an `hg` phase function of the same g) as the sensor's medium and as the interior AND
the exterior of every shape (vkpath's medium fills all space outside closed refracting volumes:
a ray reflected on either side of a wall stays in it, and it reaches to infinity, as Mitsuba's
homogeneous medium does), rendered by `volpath` (max_depth = --max-path-length: both count a
medium scattering event as one vertex, like a surface hit; no Russian roulette). The workshop
integrator renders no media, so there is no `vkpath workshop` row, and the work files' <name>
gets a `-medium-<text>` suffix so that references of other media are not reused.

Scenes (--scene): `cornell` (the built-in box, or with --generated N the scale-test scene, both
through `vkpath export`) or `spheres`: benches/mitsuba_table.py's material glTF scene (24 flat
icospheres, 122 882 triangles, 25 glTF metallic-roughness materials, a white sky; Mitsuba gets
benches/mitsuba_gltf_bsdf.py's BSDF). The workshop integrator renders Lambertian scenes only,
so the spheres get no `vkpath workshop` row.

Rays/s: vkpath counts the rays it traces (camera, path and shadow rays); the script runs
`vkpath bench --reference <the same reference>` at the same settings and reports its rays/s and
rays per sample. Mitsuba counts none: its rays/s is an ESTIMATE, labelled so everywhere, from
vkpath `mis`'s rays per sample (the same algorithm: a BSDF ray and a shadow ray per bounce,
power-heuristic MIS, the same path length, no roulette).

Usage (from the repository root):
    python3 benches/mitsuba_compare.py                       # 256x256, path length 5, 64 spp
    python3 benches/mitsuba_compare.py --width 128 --height 128 --max-path-length 3 --spp 16
    python3 benches/mitsuba_compare.py --generated 1000000 --width 128 --height 128
    python3 benches/mitsuba_compare.py --scene spheres --width 64 --height 64 --sampler low-discrepancy
    python3 benches/mitsuba_compare.py --variant cuda_ad_rgb --require-gpu --no-setup \
        --width 1920 --height 1080 --spp 64 --reference-spp 1024      # on an NVIDIA GPU
Outputs go to --workdir (default target/mitsuba_compare): the exported scene (scene_<name>/),
the reference (cached by scene and parameters; --force-reference renders it again),
mitsuba_<tag>.exr, vkpath_mis_<tag>.exr, vkpath_workshop_<tag>.exr, bench_<tag>.json and
results_<tag>.json, where <tag> is <name>_<sampler> (e.g. cornell_independent,
generated1000000_low-discrepancy, spheres_independent).
"""

import argparse
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MITSUBA_VERSION = "3.9.1"
TARGET_RELMSE = 0.005
# --sampler: (vkpath --sampler of the mis render, Mitsuba sampler plugin). "independent" pairs
# plain random numbers on both sides; "low-discrepancy" pairs vkpath's Owen-scrambled Sobol
# points with Mitsuba's ldsampler (scrambled (0,2)-sequences). The workshop render always
# uses PCG2D, the reference always PCG2D.
SAMPLERS = {"independent": ("pcg", "independent"), "low-discrepancy": ("sobol", "ldsampler")}
SUMMARY_RE = re.compile(
    r"device (?P<device>.*?), (?P<w>\d+)x(?P<h>\d+), (?P<spp>\d+) spp, "
    r"(?:setup (?P<setup>[0-9.eE+-]+) s, render )?"
    r"(?P<seconds>[0-9.eE+-]+) s, (?P<msps>[0-9.eE+-]+) M samples/s"
)


# --------------------------------------------------------------------------------------------
# Setup
# --------------------------------------------------------------------------------------------

def find_libllvm():
    """The newest libLLVM >= 19 shared object, or None."""
    candidates = []
    for path in glob.glob("/usr/lib/*/libLLVM*.so*") + glob.glob("/usr/lib/llvm-*/lib/libLLVM*.so*"):
        match = re.search(r"libLLVM[-.](?:so\.)?(\d+)", os.path.basename(path))
        if match and int(match.group(1)) >= 19:
            candidates.append((int(match.group(1)), len(path), path))
    return sorted(candidates, key=lambda c: (-c[0], c[1]))[0][2] if candidates else None


def ensure_setup(allow_install, variant="llvm_ad_rgb"):
    """Installs libllvm19 and mitsuba when missing, sets DRJIT_LIBLLVM_PATH (llvm variants only)."""
    if variant.startswith("llvm") and not os.environ.get("DRJIT_LIBLLVM_PATH"):
        lib = find_libllvm()
        if lib is None:
            if not allow_install:
                sys.exit("libLLVM >= 19 not found; run: apt-get install -y libllvm19 (or drop --no-setup)")
            print("setup: apt-get install -y libllvm19", flush=True)
            apt = ["apt-get", "install", "-y", "libllvm19"]
            if os.geteuid() != 0 and shutil.which("sudo"):
                apt = ["sudo"] + apt
            if subprocess.call(apt) != 0:
                subprocess.call((["sudo"] if apt[0] == "sudo" else []) + ["apt-get", "update"])
                subprocess.check_call(apt)
            lib = find_libllvm()
            if lib is None:
                sys.exit("libllvm19 installed but no libLLVM-19 .so found under /usr/lib")
        os.environ["DRJIT_LIBLLVM_PATH"] = lib
    try:
        import mitsuba  # noqa: F401
        installed = mitsuba.__version__
    except ImportError:
        installed = None
    if installed != MITSUBA_VERSION:
        if not allow_install:
            sys.exit(f"mitsuba {MITSUBA_VERSION} needed (found {installed}); run: pip install mitsuba=={MITSUBA_VERSION}")
        if installed is not None:
            sys.exit(f"mitsuba {installed} is already imported; install {MITSUBA_VERSION} and run again")
        print(f"setup: pip install mitsuba=={MITSUBA_VERSION}", flush=True)
        subprocess.check_call([sys.executable, "-m", "pip", "install", f"mitsuba=={MITSUBA_VERSION}"])


def ensure_vkpath(path, build):
    if build or not os.path.exists(path):
        print("setup: cargo build --release", flush=True)
        subprocess.check_call(["cargo", "build", "--release"], cwd=REPO)
    if not os.path.exists(path):
        sys.exit(f"{path} not found after cargo build --release")


# --------------------------------------------------------------------------------------------
# vkpath
# --------------------------------------------------------------------------------------------

def scene_arguments(args):
    """vkpath's scene arguments for the chosen scene (set by main: args.scene_args)."""
    if getattr(args, "scene_args", None) is not None:
        return list(args.scene_args)
    return [] if args.generated is None else ["--generated", str(args.generated)]


def medium_arguments(args):
    """vkpath's --medium for the comparison's medium (--medium), or nothing."""
    return ["--medium", args.medium] if getattr(args, "medium", None) else []


def run_vkpath(vkpath, output, args, spp, integrator, moments=True, seed=None, sampler="pcg"):
    cmd = [vkpath, "render", *scene_arguments(args), *medium_arguments(args), "-o", output, "--width", str(args.width), "--height", str(args.height),
           "--spp", str(spp), "--integrator", integrator, "--russian-roulette-start", "0",
           "--max-path-length", str(args.max_path_length), "--pixel-filter", "box"]
    if integrator != "workshop":  # the workshop's integrator has PCG2D only
        cmd += ["--sampler", sampler]
    if getattr(args, "require_gpu", False):
        cmd.append("--require-gpu")
    if moments:
        cmd.append("--moments")
    if seed is not None:
        cmd += ["--seed", str(seed)]
    # --json: the render's seconds unrounded (the summary line prints 0.01 s; a GPU frame takes ms).
    cmd.append("--json")
    print("  $ " + " ".join(cmd), flush=True)
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"vkpath failed ({result.returncode}):\n{result.stderr}")
    try:
        report = json.loads(result.stdout)
        return {"seconds": report["render_seconds"], "device": report["devices"][0]["name"],
                "msamples_per_s": report["samples_per_second"] / 1e6, "setup_seconds": report["setup_seconds"]}
    except (json.JSONDecodeError, KeyError, IndexError):
        pass
    match = None
    for line in result.stderr.splitlines():
        match = SUMMARY_RE.search(line) or match
    if match is None:
        sys.exit(f"no summary line in vkpath's stderr:\n{result.stderr}")
    return {"seconds": float(match.group("seconds")), "device": match.group("device"),
            "msamples_per_s": float(match.group("msps"))}


def run_compare(vkpath, a, b, block=None):
    cmd = [vkpath, "compare", a, b] + (["--block", str(block)] if block else [])
    print("  $ " + " ".join(cmd), flush=True)
    result = subprocess.run(cmd, capture_output=True, text=True)
    text = (result.stdout + result.stderr).strip()
    verdict = {0: "consistent", 1: "NOT consistent"}.get(result.returncode, f"unusable input (exit {result.returncode})")
    return result.returncode, verdict, text


# --------------------------------------------------------------------------------------------
# Mitsuba
# --------------------------------------------------------------------------------------------

def export_scene(args, directory):
    """`vkpath export` of the scene into `directory`; returns its manifest."""
    cmd = [args.vkpath, "export", "--output-dir", directory, *medium_arguments(args)]
    if args.generated is not None:
        cmd += ["--generated", str(args.generated)]
    print("  $ " + " ".join(cmd), flush=True)
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"vkpath export failed ({result.returncode}):\n{result.stderr}")
    with open(os.path.join(directory, "scene.json")) as f:
        return json.load(f)


def build_mitsuba_scene(mi, args, spp, directory, manifest):
    """The exported scene as a Mitsuba scene dict: one PLY mesh per material."""
    scene = {"type": "scene"}
    for i, mesh in enumerate(manifest["meshes"]):
        entry = {
            "type": "ply",
            "filename": os.path.join(directory, mesh["file"]),
            # A triangle soup: each triangle keeps its own (face) normal.
            "face_normals": True,
            # vkpath flips normals towards the ray: surfaces reflect on both sides.
            "bsdf": {"type": "twosided", "material": {
                "type": "diffuse", "reflectance": {"type": "rgb", "value": mesh["color"]}}},
        }
        if max(mesh["emission"]) > 0:
            # Mitsuba's area emitters shine towards the counter-clockwise side, where the
            # export puts the normal that vkpath's one-sided emission follows.
            if mesh["double_sided"]:
                sys.exit(f"{mesh['file']}: double-sided emitters have no Mitsuba counterpart here")
            entry["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": mesh["emission"]}}
        scene[f"mesh_{i}"] = entry
    medium = mitsuba_medium(manifest)
    if medium is not None:
        # vkpath's global medium fills both sides of every surface (there is no closed glass
        # here): a ray reflected off a wall's back stays in the fog, as a light sample does.
        scene["vkpath_medium"] = medium
        for i in range(len(manifest["meshes"])):
            scene[f"mesh_{i}"]["interior"] = {"type": "ref", "id": "vkpath_medium"}
            scene[f"mesh_{i}"]["exterior"] = {"type": "ref", "id": "vkpath_medium"}
    cam = manifest["camera"]
    if cam is None:
        sys.exit("the exported scene has no camera")
    fov_y = cam["fov_y_degrees"]
    scene["sensor"] = {
        "type": "perspective",
        "fov_axis": "y",
        "fov": fov_y,
        "to_world": mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["target"], up=cam["up"]),
        "film": {"type": "hdrfilm", "width": args.width, "height": args.height,
                 "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        "sampler": {"type": SAMPLERS[args.sampler][1], "sample_count": spp},
    }
    if medium is not None:
        scene["sensor"]["medium"] = {"type": "ref", "id": "vkpath_medium"}
    max_depth = args.mitsuba_max_depth if args.mitsuba_max_depth is not None else args.max_path_length
    scene["integrator"] = {"type": "volpath" if medium is not None else "path", "max_depth": max_depth,
                           "rr_depth": max_depth + 1000, "hide_emitters": False}
    return mi.load_dict(scene), fov_y


def mitsuba_medium(manifest):
    """scene.json's "medium" (vkpath export --medium) as a Mitsuba `homogeneous` medium dict:
    sigma_t = sigma_a + sigma_s and albedo = sigma_s / sigma_t per channel (0 where sigma_t is
    0), per scene unit of length as vkpath's (scale 1), a Henyey-Greenstein phase function of
    the same g (the same sign convention: g > 0 scatters forwards). None without a medium."""
    medium = manifest.get("medium")
    if medium is None:
        return None
    sigma_t = [a + s for a, s in zip(medium["sigma_a"], medium["sigma_s"])]
    albedo = [s / t if t > 0 else 0.0 for s, t in zip(medium["sigma_s"], sigma_t)]
    return {"type": "homogeneous", "sigma_t": {"type": "rgb", "value": sigma_t},
            "albedo": {"type": "rgb", "value": albedo}, "scale": 1.0,
            "phase": {"type": "hg", "g": medium["g"]}}


def mitsuba_render(mi, dr, scene, spp, seed):
    start = time.perf_counter()
    image = mi.render(scene, spp=spp, seed=seed)
    dr.eval(image)
    dr.sync_thread()
    return image, time.perf_counter() - start


def channel(mi, dr, tensor, c):
    """Channel c of an (H, W, C) tensor as a flat Float."""
    h, w, channels = tensor.shape
    return dr.gather(mi.Float, tensor.array, dr.arange(mi.UInt32, h * w) * channels + c)


def read_rgb(mi, dr, path):
    """R, G, B (and the vkpath moments when present) of an EXR as flat Floats."""
    bitmap = mi.Bitmap(path)
    parts = dict(bitmap.split()) if bitmap.pixel_format() == mi.Bitmap.PixelFormat.MultiChannel else {"<root>": bitmap}
    root = mi.TensorXf(parts["<root>"])
    rgb = [channel(mi, dr, root, c) for c in range(3)]
    moments = None
    if "second_moment" in parts and "sample_count" in parts:
        m2 = mi.TensorXf(parts["second_moment"])
        n = mi.TensorXf(parts["sample_count"])
        moments = ([channel(mi, dr, m2, c) for c in range(3)], channel(mi, dr, n, 0))
    return rgb, moments, tuple(bitmap.size())


def scalar(x):
    return float(x[0]) if hasattr(x, "__len__") else float(x)


def relative_mse(mi, dr, x, r):
    total = 0.0
    for c in range(3):
        total += scalar(dr.mean((x[c] - r[c]) ** 2 / (r[c] * r[c] + 0.01)))
    return total / 3.0


def reference_noise(mi, dr, r, moments):
    """Expected relMSE contribution of the reference's own noise: mean var(r)/(r^2+0.01)."""
    if moments is None:
        return None
    m2, n = moments
    total = 0.0
    for c in range(3):
        var = dr.maximum(m2[c] - r[c] * r[c], 0.0) / dr.maximum(n - 1.0, 1.0)
        total += scalar(dr.mean(var / (r[c] * r[c] + 0.01)))
    return total / 3.0


def orientation(mi, dr, rgb, width, height):
    """Mean R-G on the left and right fifths, mean luminance of top and bottom rows."""
    idx = dr.arange(mi.UInt32, width * height)
    x = mi.Float(idx % width) / width
    y = mi.Float(idx // width) / height
    red_minus_green = rgb[0] - rgb[1]
    lum = (rgb[0] + rgb[1] + rgb[2]) / 3.0

    def masked_mean(value, mask):
        return scalar(dr.sum(dr.select(mask, value, 0.0))) / max(scalar(dr.sum(dr.select(mask, 1.0, 0.0))), 1.0)

    return {"left_r_minus_g": masked_mean(red_minus_green, x < 0.2),
            "right_r_minus_g": masked_mean(red_minus_green, x > 0.8),
            "top_luminance": masked_mean(lum, y < 0.05),
            "bottom_luminance": masked_mean(lum, y > 0.95)}


def write_with_moments(mi, dr, path, image, batches, spp, batch_spp):
    """Writes the timed image with vkpath's moment channels estimated from the batches."""
    h, w, _ = image.shape
    k = len(batches)
    columns = [channel(mi, dr, image, c) for c in range(3)]
    second = []
    for c in range(3):
        b = [channel(mi, dr, batch, c) for batch in batches]
        mean_b = sum(b) / k
        s2 = sum((bi - mean_b) ** 2 for bi in b) / (k - 1)      # variance of a batch's mean
        var_mean = s2 * (batch_spp / spp)                        # ... of the timed image's mean
        # vkpath reads var = (second - mean^2) / (n - 1) with n = sample count = k.
        second.append(columns[c] * columns[c] + var_mean * (k - 1))
    count = dr.full(mi.Float, float(k), h * w)
    data = columns + second + [count]
    flat = dr.zeros(mi.Float, h * w * 7)
    idx = dr.arange(mi.UInt32, h * w)
    for c, col in enumerate(data):
        dr.scatter(flat, col, idx * 7 + c)
    tensor = mi.TensorXf(flat, shape=(h, w, 7))
    names = ["R", "G", "B", "second_moment.R", "second_moment.G", "second_moment.B", "sample_count.Y"]
    mi.Bitmap(tensor, pixel_format=mi.Bitmap.PixelFormat.MultiChannel, channel_names=names).write(path)


# --------------------------------------------------------------------------------------------

def add_common_arguments(parser, workdir_name):
    """The options every Mitsuba comparison takes: --threads, --workdir (default
    target/WORKDIR_NAME), --vkpath, --build, --force-reference, --no-setup."""
    parser.add_argument("--threads", type=int, default=2,
                        help="Mitsuba (drjit) CPU threads, at least 2: with 1, mi.Bitmap's EXR read "
                             "hangs (drjit 1.5.0, mitsuba 3.9.1; seen here)")
    parser.add_argument("--workdir", default=os.path.join(REPO, "target", workdir_name))
    parser.add_argument("--vkpath", default=os.path.join(REPO, "target", "release", "vkpath"))
    parser.add_argument("--build", action="store_true", help="run cargo build --release first")
    parser.add_argument("--force-reference", action="store_true", help="render the reference(s) even if cached")
    parser.add_argument("--no-setup", action="store_true", help="never apt-get/pip install")


def run_bench(vkpath, args, sampler, reference, integrators):
    """`vkpath bench` at the comparison's settings against the same reference: vkpath's rays/s
    (it counts camera, path and shadow rays) and rays per sample per integrator."""
    scene_args = scene_arguments(args)
    if "--background" in scene_args:
        # `bench` takes no --background. The spheres' white sky is a constant environment, which
        # vkpath never light-samples (stop 24), so the rays per sample are those of the same
        # scene under a black sky: the same camera and BSDF rays, no shadow rays either way
        # (the scene has no emissive triangles). Bench's relMSE is then meaningless: unused.
        i = scene_args.index("--background")
        del scene_args[i:i + 2]
    cmd = [vkpath, "bench", *scene_args, *medium_arguments(args), "--reference", reference, "--width", str(args.width),
           "--height", str(args.height), "--spp", str(args.spp), "--max-path-length", str(args.max_path_length),
           "--russian-roulette-start", "0", "--sampler", sampler, "--integrators", ",".join(integrators),
           "--repeats", str(max(args.repeats, 2)), "--json"]
    if getattr(args, "require_gpu", False):
        cmd.append("--require-gpu")
    print("  $ " + " ".join(cmd), flush=True)
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        print(f"    vkpath bench failed ({result.returncode}); no rays/s:\n{result.stderr[-2000:]}", flush=True)
        return None
    try:
        return json.loads(result.stdout)
    except json.JSONDecodeError:
        print("    vkpath bench printed no JSON; no rays/s", flush=True)
        return None


def check_variant(mi, dr, variant):
    """Sets the variant; for CUDA also renders 16x16 at 1 spp once (OptiX's first use). Stops the
    script with one 'PEER STOP:' line when the variant cannot run here."""
    try:
        if variant not in mi.variants():
            raise RuntimeError(f"this mitsuba build has no {variant} (it has {', '.join(mi.variants())})")
        mi.set_variant(variant)
        if variant.startswith("cuda"):
            box = mi.cornell_box()
            box["sensor"]["film"]["width"] = box["sensor"]["film"]["height"] = 16
            image = mi.render(mi.load_dict(box), spp=1)
            dr.eval(image)
            dr.sync_thread()
    except Exception as error:  # ImportError, RuntimeError from drjit's CUDA/OptiX loader, ...
        first = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        print(f"PEER STOP: Mitsuba's {variant} cannot run here: {first}", flush=True)
        sys.exit(3)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--width", type=int, default=256)
    parser.add_argument("--height", type=int, default=256)
    parser.add_argument("--variant", choices=["llvm_ad_rgb", "cuda_ad_rgb"], default="llvm_ad_rgb",
                        help="Mitsuba's variant: CPU (LLVM, --threads threads) or NVIDIA GPU (CUDA + OptiX)")
    parser.add_argument("--scene", choices=["cornell", "spheres"], default="cornell",
                        help="the built-in Cornell box (or --generated N), or benches/mitsuba_table.py's "
                             "material glTF scene (24 metallic-roughness icospheres, white sky)")
    parser.add_argument("--generated", type=int, default=None,
                        help="vkpath's generated scale-test scene of about this many triangles "
                             "instead of the Cornell box")
    parser.add_argument("--repeats", type=int, default=3,
                        help="timed renders per renderer (same seed, same image); the fastest counts")
    parser.add_argument("--sampler", choices=sorted(SAMPLERS), default="independent",
                        help="random numbers of both renderers' MIS renders (see SAMPLERS)")
    parser.add_argument("--max-path-length", type=int, default=5,
                        help="vkpath --max-path-length n (surface hits) = Mitsuba max_depth n")
    parser.add_argument("--spp", type=int, default=64, help="spp of each timed render")
    parser.add_argument("--reference-spp", type=int, default=2048,
                        help="spp of the vkpath MIS reference (4096 is better where time allows)")
    parser.add_argument("--batches", type=int, default=16,
                        help="independent Mitsuba renders at spp/batches for mitsuba.exr's variance")
    parser.add_argument("--mitsuba-max-depth", type=int, default=None,
                        help="override Mitsuba's max_depth (default: --max-path-length); e.g. one less, "
                             "to see the gate fail on a convention mismatch")
    parser.add_argument("--medium", default=None, metavar="sigma_a=R,G,B:sigma_s=R,G,B:g=G",
                        help="a homogeneous global medium (vkpath render --medium's text); Mitsuba "
                             "renders it with volpath (Cornell box only)")
    parser.add_argument("--require-gpu", action="store_true",
                        help="pass --require-gpu to vkpath (refuse to fall back to a CPU device)")
    parser.add_argument("--no-bench", action="store_true", help="skip `vkpath bench` (no rays/s)")
    parser.add_argument("--gate-block", type=int, default=None,
                        help="side of the gate's pixel blocks (vkpath compare --block; default 8). At "
                             "few spp use larger blocks, so that each block pools ~4000 samples: block "
                             "means of heavy-tailed estimators at ~1000 samples are not yet normal far "
                             "enough into the tail that a 1920x1080 gate's threshold (|z| ~ 5.3) reaches")
    add_common_arguments(parser, "mitsuba_compare")
    args = parser.parse_args()
    if args.threads < 2:
        sys.exit("--threads must be at least 2: with one drjit thread mi.Bitmap's EXR read hangs")
    if args.batches < 2 or args.spp < args.batches or args.spp % args.batches:
        sys.exit("--spp must be a multiple of --batches, and --batches at least 2")
    if args.scene == "spheres" and args.generated is not None:
        sys.exit("--generated goes with --scene cornell only")
    if args.medium and args.scene != "cornell":
        sys.exit("--medium goes with --scene cornell only")

    ensure_setup(not args.no_setup, args.variant)
    ensure_vkpath(args.vkpath, args.build)
    args.vkpath = os.path.abspath(args.vkpath)
    os.makedirs(args.workdir, exist_ok=True)
    import drjit as dr
    import mitsuba as mi
    check_variant(mi, dr, args.variant)
    dr.set_thread_count(args.threads)
    where = (f"{dr.thread_count()} threads, DRJIT_LIBLLVM_PATH={os.environ.get('DRJIT_LIBLLVM_PATH')}"
             if args.variant.startswith("llvm") else "CUDA + OptiX from the driver")
    print(f"mitsuba {mi.__version__}, drjit {dr.__version__}, variant {args.variant}, {where}")
    w, h, n, spp = args.width, args.height, args.max_path_length, args.spp
    vk_sampler, mi_sampler = SAMPLERS[args.sampler]
    if args.scene == "spheres":
        name = "spheres"
    else:
        name = "cornell" if args.generated is None else f"generated{args.generated}"
    if args.medium:
        # The medium in the work files' names, so that no reference of another medium is reused.
        name += "-medium-" + re.sub(r"[^0-9A-Za-z.]+", "-", args.medium).strip("-")
    tag = f"{name}_{args.sampler}"
    scene_dir = os.path.join(args.workdir, f"scene_{name}")
    os.makedirs(scene_dir, exist_ok=True)
    if args.scene == "spheres":
        import mitsuba_table as mt  # its material scene and scene builder (imports this module)
        import mitsuba_gltf_bsdf
        mitsuba_gltf_bsdf.register(mi, dr)
        description, args.scene_args = mt.spheres_scene(scene_dir)
        triangles, materials = description["triangles"], len(description["shapes"])
        integrators = ["mis"]  # the workshop integrator renders Lambertian scenes only
    else:
        manifest = export_scene(args, scene_dir)
        args.scene_args = None
        triangles, materials = sum(mesh["triangles"] for mesh in manifest["meshes"]), len(manifest["meshes"])
        # The workshop integrator renders no media.
        integrators = ["mis"] if args.medium else ["mis", "workshop"]
    if args.medium:
        print(f"medium {args.medium}: Mitsuba homogeneous {json.dumps(mitsuba_medium(manifest))}, volpath")
    print(f"scene {name} ({triangles} triangles, {materials} materials), {w}x{h}, "
          f"max path length {n}, {spp} spp, no Russian roulette, box pixel filter; samplers: vkpath "
          f"{vk_sampler} (mis; workshop always PCG2D), Mitsuba {mi_sampler}")

    # (1) Reference: vkpath MIS with PCG2D (independent samples, so its moments are honest).
    ref = os.path.join(args.workdir, f"ref_{name}_{w}x{h}_L{n}_spp{args.reference_spp}.exr")
    if args.force_reference or not os.path.exists(ref):
        print(f"[1] vkpath reference, MIS, {args.reference_spp} spp (slow on lavapipe)", flush=True)
        info = run_vkpath(args.vkpath, ref + ".tmp.exr", args, args.reference_spp, "mis", seed=7919)
        os.replace(ref + ".tmp.exr", ref)
        print(f"    {info['seconds']:.1f} s")
    else:
        print(f"[1] reusing reference {os.path.relpath(ref, REPO)}")
    r, r_moments, ref_size = read_rgb(mi, dr, ref)
    if ref_size != (w, h):
        sys.exit(f"reference is {ref_size}, expected {(w, h)}")
    ref_noise = reference_noise(mi, dr, r, r_moments)

    # (2) Mitsuba.
    print(f"[2] Mitsuba {args.variant}", flush=True)
    t0 = time.perf_counter()
    if args.scene == "spheres":
        max_depth = args.mitsuba_max_depth if args.mitsuba_max_depth is not None else n
        scene = mt.mitsuba_scene(mi, description, w, h, spp, sampler=mi_sampler, max_depth=max_depth)
        fov_y = description["camera"]["fov_y_degrees"]
    else:
        scene, fov_y = build_mitsuba_scene(mi, args, spp, scene_dir, manifest)
    load_s = time.perf_counter() - t0
    print(f"    scene loaded in {load_s:.2f} s, fov_y {fov_y:.4f} deg")
    _, cold_s = mitsuba_render(mi, dr, scene, spp, seed=1000)
    # The same seed each time, so every repeat computes the same image; the fastest counts.
    # The first of them is Mitsuba's second render: its kernel compiled by the warm-up.
    timings = []
    for _ in range(args.repeats):
        image, seconds = mitsuba_render(mi, dr, scene, spp, seed=0)
        timings.append(seconds)
    mitsuba_s = min(timings)
    print(f"    cold (warm-up) render {cold_s:.2f} s, timed renders "
          f"{', '.join(f'{t:.3f}' for t in timings)} s", flush=True)
    batch_spp = spp // args.batches
    batches = []
    batch_times = []
    for b in range(args.batches):
        batch, seconds = mitsuba_render(mi, dr, scene, batch_spp, seed=2000 + b)
        batches.append(batch)
        batch_times.append(seconds)
    # Mitsuba's fixed cost per render (tracing the integrator and BSDFs into the kernel on the
    # host, the launch), from t = a + b * spp at two spp: the timed renders' and the batches'
    # (the first batch compiles its kernel; the fastest of the others counts).
    t_full, t_batch = mitsuba_s, min(batch_times[1:]) if len(batch_times) > 1 else batch_times[0]
    ratio = spp / batch_spp
    fixed_s = max((ratio * t_batch - t_full) / (ratio - 1.0), 0.0)
    print(f"    batch renders at {batch_spp} spp: fastest {t_batch:.4f} s; fixed cost per render "
          f"~{fixed_s:.4f} s (of the timed {t_full:.4f} s)", flush=True)
    mitsuba_exr = os.path.join(args.workdir, f"mitsuba_{tag}.exr")
    write_with_moments(mi, dr, mitsuba_exr, image, batches, spp, batch_spp)
    x, _, _ = read_rgb(mi, dr, mitsuba_exr)
    mi_integrator = "volpath" if args.medium else "path"
    rows = [{"name": f"Mitsuba {mi_integrator}", "renderer": "mitsuba", "integrator": mi_integrator, "sampler": mi_sampler,
             "seconds": mitsuba_s, "cold": cold_s, "second_render_s": timings[0], "timings": timings,
             "paths_per_s": w * h * spp / mitsuba_s, "relmse": relative_mse(mi, dr, x, r),
             "device": args.variant, "image": mitsuba_exr, "batch_spp": batch_spp, "batch_timings": batch_times,
             "fixed_per_render_s": fixed_s}]
    channel_ratio = [scalar(dr.mean(x[c])) / max(scalar(dr.mean(r[c])), 1e-30) for c in range(3)]
    rows[0]["mean_ratio_rgb_vs_reference"] = channel_ratio
    orient_m = orientation(mi, dr, x, w, h)
    orient_r = orientation(mi, dr, r, w, h)

    # (3) vkpath.
    print("[3] vkpath", flush=True)
    for integrator in integrators:
        out = os.path.join(args.workdir, f"vkpath_{integrator}_{tag}.exr")
        # The same seed each time (the default, 0): the same image; the fastest counts.
        runs = [run_vkpath(args.vkpath, out, args, spp, integrator, sampler=vk_sampler)
                for _ in range(args.repeats)]
        info = min(runs, key=lambda run: run["seconds"])
        xi, _, _ = read_rgb(mi, dr, out)
        ratio_rgb = [scalar(dr.mean(xi[c])) / max(scalar(dr.mean(r[c])), 1e-30) for c in range(3)]
        rows.append({"name": f"vkpath {integrator}", "renderer": "vkpath", "integrator": integrator,
                     "mean_ratio_rgb_vs_reference": ratio_rgb,
                     "sampler": "pcg" if integrator == "workshop" else vk_sampler,
                     "seconds": info["seconds"], "cold": None, "timings": [run["seconds"] for run in runs],
                     "paths_per_s": info["msamples_per_s"] * 1e6, "relmse": relative_mse(mi, dr, xi, r),
                     "device": info["device"], "image": out})

    # (4) vkpath's rays: `vkpath bench` at the same settings against the same reference.
    bench = None
    if not args.no_bench:
        print("[4] vkpath bench (rays/s)", flush=True)
        bench = run_bench(args.vkpath, args, vk_sampler, ref, integrators)
        if bench is not None:
            with open(os.path.join(args.workdir, f"bench_{tag}.json"), "w") as f:
                json.dump(bench, f, indent=1)
    rays_per_sample = {}
    for result in (bench or {}).get("results", []):
        if result["samples_per_second"] > 0:
            rays_per_sample[result["integrator"]] = result["rays_per_second"] / result["samples_per_second"]
    for row in rows:
        if row["renderer"] == "vkpath" and row["integrator"] in rays_per_sample:
            bench_row = next(b for b in bench["results"] if b["integrator"] == row["integrator"])
            row["rays_per_sample"] = rays_per_sample[row["integrator"]]
            row["rays_per_s"] = row["rays_per_sample"] * row["paths_per_s"]
            row["rays_per_s_kind"] = "counted (vkpath bench's rays per sample x this render's samples/s)"
            if args.scene == "spheres":
                row["rays_per_s_kind"] += "; bench under a black sky (it takes no --background)"
            row["bench_rays_per_s"] = bench_row["rays_per_second"]
            row["bench_samples_per_s"] = bench_row["samples_per_second"]
            row["bench_relmse"] = bench_row["relative_mse"]
        elif row["renderer"] == "mitsuba" and "mis" in rays_per_sample:
            # Mitsuba counts no rays: estimated from vkpath mis's rays per sample (same algorithm).
            row["rays_per_sample"] = rays_per_sample["mis"]
            row["rays_per_s"] = row["rays_per_sample"] * row["paths_per_s"]
            row["rays_per_s_kind"] = "ESTIMATE (vkpath mis's rays per sample x Mitsuba's samples/s)"

    # (5) Gates: each image against the same reference; a row's speed counts only if it passes.
    print("[5] correctness gates", flush=True)
    code, verdict, text = run_compare(args.vkpath, mitsuba_exr, ref, args.gate_block)
    rows[0]["gate"] = verdict
    for row in rows[1:]:
        _, row["gate"], _ = run_compare(args.vkpath, row["image"], ref, args.gate_block)
    verdict_v = rows[1]["gate"]

    # (6) Report.
    for row in rows:
        row["efficiency"] = 1.0 / (row["relmse"] * row["seconds"])
        row["s_to_target"] = row["seconds"] * row["relmse"] / TARGET_RELMSE
        row["counts"] = row["gate"] == "consistent"
    m = rows[0]["efficiency"]
    for row in rows[1:]:
        row["efficiency_ratio_vs_mitsuba"] = row["efficiency"] / m
    print()
    print(f"scene {name} ({triangles} triangles) {w}x{h}, max path length {n}, {spp} spp, "
          f"reference vkpath MIS {args.reference_spp} spp; samplers vkpath {vk_sampler} / Mitsuba {mi_sampler}")
    print(f"vkpath device: {rows[1].get('device')}; Mitsuba: {args.variant}"
          + (f", {dr.thread_count()} threads" if args.variant.startswith("llvm") else ""))
    header = (f"{'renderer':<16}{'seconds':>9}{'cold s':>9}{'Mpaths/s':>10}{'Mrays/s':>11}{'relMSE':>11}"
              f"{'efficiency':>12}{'s to 0.005':>12}  gate")
    print(header)
    print("-" * len(header))
    for row in rows:
        cold = f"{row['cold']:.2f}" if row["cold"] is not None else "-"
        rays = "-"
        if "rays_per_s" in row:
            rays = f"{row['rays_per_s'] / 1e6:.4g}" + ("*" if row["renderer"] == "mitsuba" else "")
        print(f"{row['name']:<16}{row['seconds']:>9.3f}{cold:>9}{row['paths_per_s'] / 1e6:>10.4g}{rays:>11}"
              f"{row['relmse']:>11.5f}{row['efficiency']:>12.4g}{row['s_to_target']:>12.3g}  {row['gate']}")
    print("* Mitsuba's rays/s is an estimate (vkpath mis's rays per sample); vkpath's are counted")
    print()
    for row in rows[1:]:
        print(f"efficiency ratio {row['name']} / Mitsuba = {row['efficiency_ratio_vs_mitsuba']:.3f}")
    print(f"Mitsuba paths/s (W*H*spp/seconds)          = {rows[0]['paths_per_s']:.4g}")
    for row in rows:
        ratio = row["mean_ratio_rgb_vs_reference"]
        print(f"mean {row['name']} / reference per channel R, G, B = "
              + ", ".join(f"{v:.4f}" for v in ratio))
    if ref_noise is not None:
        print(f"reference's own noise adds ~{ref_noise:.5f} to every relMSE "
              f"({100 * ref_noise / rows[0]['relmse']:.1f}% of Mitsuba's)")
    print(f"orientation (R-G left/right, luminance top/bottom): Mitsuba "
          f"{orient_m['left_r_minus_g']:+.3f}/{orient_m['right_r_minus_g']:+.3f}, "
          f"{orient_m['top_luminance']:.3f}/{orient_m['bottom_luminance']:.3f}; reference "
          f"{orient_r['left_r_minus_g']:+.3f}/{orient_r['right_r_minus_g']:+.3f}, "
          f"{orient_r['top_luminance']:.3f}/{orient_r['bottom_luminance']:.3f}")
    print()
    print(f"vkpath compare {os.path.basename(mitsuba_exr)} ref:")
    print("  " + text.replace("\n", "\n  "))
    print(f"vkpath compare vkpath_mis ref: {verdict_v}")
    all_pass = all(row["counts"] for row in rows)
    if code == 0:
        print("GATE: Mitsuba's image is CONSISTENT with vkpath's reference: the speed figures count.")
    else:
        print(f"GATE: Mitsuba's image is {verdict.upper()} with vkpath's reference: "
              "the speed figures DO NOT COUNT (the renderers compute different images).")
    if not all_pass:
        print("GATES: not all images are consistent with the reference: "
              + ", ".join(f"{row['name']} {row['gate']}" for row in rows))
    with open(os.path.join(args.workdir, f"results_{tag}.json"), "w") as f:
        json.dump({"scene": name, "tag": tag, "variant": args.variant, "sampler": args.sampler,
                   "samplers": {"vkpath": vk_sampler, "mitsuba": mi_sampler}, "medium": args.medium,
                   "triangles": triangles, "width": w, "height": h, "max_path_length": n, "spp": spp,
                   "reference_spp": args.reference_spp, "reference_noise_relmse": ref_noise,
                   "mitsuba_load_s": load_s, "rows": rows,
                   "gate": {"exit": code, "verdict": verdict, "report": text, "block": args.gate_block or 8},
                   "all_gates_pass": all_pass,
                   "vkpath_mis_gate": verdict_v, "orientation": {"mitsuba": orient_m, "reference": orient_r}},
                  f, indent=1)
    return 0 if all_pass else 1


if __name__ == "__main__":
    sys.exit(main())
