"""Tests of the vkpath Python package against the command line (lavapipe, tiny images).

The command line is the reference: ``VKPATH_CLI`` names its binary (scripts/test.sh sets it
to the one ``cargo test`` built); the test fails, never skips, without it. Its EXRs are read
with the OpenEXR package, not with vkpath, so that a mistake in vkpath's own EXR code cannot
hide one in the bindings.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import OpenEXR
import pytest

import vkpath

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli() -> str:
    binary = os.environ.get("VKPATH_CLI")
    assert binary and os.access(binary, os.X_OK), (
        "set VKPATH_CLI to the vkpath binary (scripts/test.sh uses target/debug/vkpath)"
    )
    # The binary and this module must come from the same Cargo profile for the bit-for-bit
    # tests: a release build compiles the kernels with shaderc's optimizer (spirv-opt), a
    # dev build without it, and lavapipe's last bits differ between the two SPIR-V forms
    # (measured: 12 of 192 pixels of a 16x12, 4 spp default render).
    return binary


def run_cli(cli: str, *args: str, expect: int = 0) -> subprocess.CompletedProcess:
    done = subprocess.run([cli, *args], capture_output=True, text=True, timeout=600)
    assert done.returncode == expect, done.stderr
    return done


def read_exr_rgba(path: Path) -> np.ndarray:
    """The R, G, B, A channels of an EXR as an (H, W, 4) float32 array (OpenEXR's reader)."""
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        channels = exr.channels()
        planes = [channels[name].pixels for name in ("R", "G", "B", "A")]
    image = np.stack(planes, axis=-1)
    assert image.dtype == np.float32
    return image


def bits(image: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(image, dtype=np.float32).view(np.uint32)


def test_default_render_equals_the_command_lines_exr_bit_for_bit(cli, tmp_path):
    output = tmp_path / "cli.exr"
    run_cli(cli, "render", "--width", "32", "--height", "32", "--spp", "4", "--seed", "1",
            "-o", str(output))
    expected = read_exr_rgba(output)
    image = vkpath.render(width=32, height=32, spp=4, seed=1)
    assert image.shape == (32, 32, 4) and image.dtype == np.float32
    # Not trivially equal: the box is lit, so most pixels are not black.
    assert np.count_nonzero(image[..., :3].sum(axis=-1)) > 0.5 * 32 * 32
    assert np.array_equal(bits(image), bits(expected))


def test_a_region_is_the_full_renders_pixels_bit_for_bit():
    full = vkpath.render(width=16, height=12, spp=4, seed=1)
    part = vkpath.render(width=16, height=12, spp=4, seed=1, region=(3, 2, 11, 9))
    assert part.shape == (7, 8, 4)
    assert np.array_equal(bits(part), bits(full[2:9, 3:11]))
    with pytest.raises(vkpath.VkpathError, match="reaches outside the 16x12 image"):
        vkpath.render(width=16, height=12, spp=1, region=(0, 0, 17, 12))
    with pytest.raises(vkpath.VkpathError, match="is not"):
        vkpath.render(width=16, height=12, spp=1, region=(0, 0, 4))


def test_a_scene_file_and_a_look_at_camera_equal_the_command_line(cli, tmp_path):
    scene_file = REPO / "scenes" / "materials.gltf"
    output = tmp_path / "cli.exr"
    position, target = (0.5, 1.5, 4.0), (0.0, 0.5, 0.0)
    run_cli(cli, "render", str(scene_file), "--width", "24", "--height", "16", "--spp", "2",
            "--integrator", "mis", "--camera-position", "0.5,1.5,4", "--look-at", "0,0.5,0",
            "--fov", "50", "-o", str(output))
    scene = vkpath.Scene.load(scene_file)
    own = vkpath.render(scene, width=24, height=16, spp=2, integrator="mis")
    scene.look_at(position, target, fov=50.0)
    moved = vkpath.render(scene, width=24, height=16, spp=2, integrator="mis")
    assert moved.shape == (16, 24, 4)
    assert np.array_equal(bits(moved), bits(read_exr_rgba(output)))
    # The camera did change what is seen.
    assert not np.array_equal(own, moved)
    scene.camera = None
    assert scene.camera is not None  # back to the file's own camera
    assert np.array_equal(bits(vkpath.render(scene, width=24, height=16, spp=2,
                                             integrator="mis")), bits(own))


def test_a_thin_lens_camera_equals_the_command_lines_depth_of_field(cli, tmp_path):
    scene_file = REPO / "scenes" / "materials.gltf"
    # Inside the showcase's closed room (x, z in [-2, 2]): from outside it every pixel is black.
    position, target = (0.3, 1.4, 1.8), (0.0, 0.6, 0.0)
    view = ["--camera-position", "0.3,1.4,1.8", "--look-at", "0,0.6,0", "--fov", "50"]
    size = dict(width=24, height=16, spp=2, integrator="mis")
    cli_size = ["--width", "24", "--height", "16", "--spp", "2", "--integrator", "mis"]
    output = tmp_path / "cli.exr"
    run_cli(cli, "render", str(scene_file), *cli_size, *view, "--aperture-radius", "0.2",
            "--focus-distance", "2.5", "--aperture-blades", "6", "--aperture-rotation", "15",
            "-o", str(output))
    scene = vkpath.Scene.load(scene_file)
    scene.camera = vkpath.Camera(position, target, fov=50.0, aperture_radius=0.2,
                                 focus_distance=2.5, blades=6, aperture_rotation=15.0)
    assert scene.camera.aperture_radius == pytest.approx(0.2)
    assert scene.camera.focus_distance == pytest.approx(2.5) and scene.camera.blades == 6
    blurred = vkpath.render(scene, **size)
    assert np.array_equal(bits(blurred), bits(read_exr_rgba(output)))
    scene.look_at(position, target, fov=50.0)
    assert scene.camera.focus_distance is None
    sharp = vkpath.render(scene, **size)
    # The lens moved the image (a radius of 0.2 blurs the shelf 2 m behind the focus by
    # several pixels), and neither render is black.
    assert sharp[..., :3].mean() > 0.01 and blurred[..., :3].mean() > 0.01
    assert not np.array_equal(bits(sharp), bits(blurred))
    # An f-number and autofocus on a pixel: the command line's --f-stop and --focus-at.
    output = tmp_path / "f_stop.exr"
    run_cli(cli, "render", str(scene_file), *cli_size, *view, "--f-stop", "0.5",
            "--sensor-width", "24", "--focus-at", "5,11", "-o", str(output))
    scene.camera = vkpath.Camera(position, target, fov=50.0, f_stop=0.5, sensor_width=24.0)
    assert scene.camera.f_stop == 0.5 and scene.camera.focus_distance is None
    autofocused = vkpath.render(scene, focus_at=(5, 11), **size)
    assert np.array_equal(bits(autofocused), bits(read_exr_rgba(output)))
    for bad in ({"aperture_radius": -1.0, "focus_distance": 1.0},
                {"aperture_radius": 0.1, "focus_distance": 0.0},
                {"aperture_radius": 0.1, "f_stop": 2.0},
                {"f_stop": -2.0}, {"f_stop": 2.0, "sensor_width": 0.0},
                {"aperture_radius": 0.1, "focus_distance": 1.0, "blades": 2}):
        with pytest.raises(vkpath.VkpathError):
            vkpath.Camera(position, target, **bad)
    with pytest.raises(vkpath.VkpathError, match="outside the 24x16 image"):
        vkpath.render(scene, focus_at=(24, 0), **size)
    scene.look_at(position, target, fov=50.0)
    with pytest.raises(vkpath.VkpathError, match="needs a camera with a lens"):
        vkpath.render(scene, focus_at=(5, 11), **size)


def test_a_material_variant_is_chosen_by_name_as_on_the_command_line(cli, tmp_path):
    import base64
    import json
    import struct
    # One triangle facing the camera (+Z), red; blue in KHR_materials_variants' "Beach",
    # green in "Midnight"; lit by a white background.
    positions = struct.pack("<9f", -1, -1, 0, 1, -1, 0, 0, 1, 0)
    uri = "data:application/octet-stream;base64," + base64.b64encode(positions).decode()

    def lambert(r, g, b):
        return {"pbrMetallicRoughness": {"baseColorFactor": [r, g, b, 1], "metallicFactor": 0}}

    gltf = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_variants"],
        "extensions": {"KHR_materials_variants": {
            "variants": [{"name": "Beach"}, {"name": "Midnight"}]}},
        "buffers": [{"byteLength": 36, "uri": uri}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [-1, -1, 0], "max": [1, 1, 0]}],
        "materials": [lambert(0.8, 0.1, 0.1), lambert(0.1, 0.1, 0.8), lambert(0.1, 0.8, 0.1)],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0,
                                    "extensions": {"KHR_materials_variants": {"mappings": [
                                        {"material": 1, "variants": [0]},
                                        {"material": 2, "variants": [1]}]}}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 3]}],
        "scenes": [{"nodes": [0, 1]}],
    }
    path = tmp_path / "shoe.gltf"
    path.write_text(json.dumps(gltf))
    size = dict(width=8, height=8, spp=2, integrator="mis", background=(1.0, 1.0, 1.0))
    own = vkpath.Scene.load(path)
    assert own.variants == ["Beach", "Midnight"] and own.variant is None
    beach = vkpath.Scene.load(path, variant="Beach")
    assert beach.variant == "Beach"
    centre = (slice(3, 5), slice(3, 5))
    red = vkpath.render(own, **size)[centre][..., :3].mean(axis=(0, 1))
    blue = vkpath.render(beach, **size)[centre][..., :3].mean(axis=(0, 1))
    assert red[0] > 2 * red[2] and blue[2] > 2 * blue[0], (red, blue)
    output = tmp_path / "beach.exr"
    run_cli(cli, "render", str(path), "--width", "8", "--height", "8", "--spp", "2",
            "--integrator", "mis", "--background", "1,1,1", "--variant", "Beach",
            "-o", str(output))
    assert np.array_equal(bits(vkpath.render(beach, **size)), bits(read_exr_rgba(output)))
    with pytest.raises(vkpath.VkpathError, match="its variants: Beach, Midnight"):
        vkpath.Scene.load(path, variant="Street")


def test_progress_is_called_and_false_stops_without_losing_samples():
    calls = []

    def progress(done: int, total: int) -> bool:
        calls.append((done, total))
        return False

    result = vkpath.render_result(width=16, height=16, spp=4096, seed=3, progress=progress)
    assert calls and calls[0][1] == 4096
    assert result.stop == "stopped"
    assert 0 < result.spp < 4096 and result.spp == calls[-1][0]
    assert np.all(result.sample_count == result.spp)
    # What was rendered before the stop is exactly the render of that many samples.
    whole = vkpath.render(width=16, height=16, spp=result.spp, seed=3)
    assert np.array_equal(bits(result.image), bits(whole))


def test_progress_that_returns_nothing_goes_on_to_the_end():
    calls = []
    result = vkpath.render_result(width=8, height=8, spp=32,
                                  progress=lambda done, total: calls.append(done))
    assert result.stop == "done" and result.spp == 32
    assert calls == sorted(calls) and calls[-1] == 32


def test_an_exception_in_progress_stops_the_render_and_propagates():
    class Enough(Exception):
        pass

    def progress(done: int, total: int) -> None:
        raise Enough(done)

    with pytest.raises(Enough):
        vkpath.render(width=16, height=16, spp=4096, progress=progress)


@pytest.mark.parametrize("delay", [0.0, 0.05, 0.3])
def test_ctrl_c_stops_the_render_with_keyboard_interrupt(tmp_path, delay):
    # The child installs Python's own SIGINT handler, as an interactive interpreter has it: a
    # process started with SIGINT ignored (a background job of a non-interactive shell, e.g.
    # `nohup ... &`, POSIX) inherits the ignore, and Python then installs no KeyboardInterrupt
    # handler at all -- which is how this test "lost" its Ctrl-C on a CI run launched that way.
    # The signal comes at varied moments after the first batch: at once, during the next
    # batch, and after several.
    script = tmp_path / "interrupted.py"
    script.write_text(
        "import signal, sys, vkpath\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "def progress(done, total):\n"
        "    print('progress', done, flush=True)\n"
        "try:\n"
        "    vkpath.render(width=32, height=32, spp=1 << 20, progress=progress)\n"
        "except KeyboardInterrupt:\n"
        "    print('KeyboardInterrupt', flush=True)\n"
        "    sys.exit(3)\n"
    )
    child = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().startswith("progress")
        time.sleep(delay)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        # A batch lasts about 250 ms; 60 s only bounds a hang on a loaded 2-core machine.
        status = child.wait(timeout=60)
        waited = time.monotonic() - sent
    finally:
        child.kill()
    assert status == 3, f"exit status {status}"
    assert "KeyboardInterrupt" in child.stdout.read()
    # Stopping waits for the current batch, not for the 2^20 samples (hours on lavapipe).
    assert waited < 30


def test_the_gil_is_released_while_rendering():
    ticks = []
    running = threading.Event()

    def count() -> None:
        running.set()
        while running.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    thread = threading.Thread(target=count)
    thread.start()
    running.wait()
    started = time.monotonic()
    # A time limit makes the call last at least a second however fast the device is.
    vkpath.render(width=32, height=32, spp=1 << 20, time_limit=1.0)
    ended = time.monotonic()
    running.clear()
    thread.join()
    # Without releasing the GIL the other thread could not run at all inside the call; a
    # margin of 0.1 s (20 of Python's 5 ms switch intervals) on each side excludes the
    # switches just before and after it.
    inside = [t for t in ticks if started + 0.1 < t < ended - 0.1]
    assert ended - started > 1.0
    assert len(inside) > 10


def test_a_bad_path_raises_the_command_lines_one_line_message(cli, tmp_path):
    missing = tmp_path / "missing.gltf"
    done = run_cli(cli, "render", str(missing), "-o", str(tmp_path / "out.exr"), expect=1)
    line = done.stderr.strip().splitlines()[-1]
    assert line.startswith("vkpath: error: ")
    with pytest.raises(vkpath.VkpathError) as raised:
        vkpath.render(str(missing))
    assert str(raised.value) == line[len("vkpath: error: "):]
    assert "\n" not in str(raised.value)
    with pytest.raises(vkpath.VkpathError, match="missing.gltf"):
        vkpath.Scene.load(missing)


def test_bad_settings_raise_with_the_names_to_use():
    with pytest.raises(vkpath.VkpathError, match="workshop, cosine, nee, mis"):
        vkpath.render(width=8, height=8, spp=1, integrator="bdpt")
    # Python's keywords, not the command line's options (issue 58).
    with pytest.raises(vkpath.ArgumentError, match="spp=0 is outside"):
        vkpath.render(width=8, height=8, spp=0)
    with pytest.raises(vkpath.ArgumentError, match="noise_threshold=-1 must be"):
        vkpath.render(width=8, height=8, spp=4, noise_threshold=-1)
    with pytest.raises(vkpath.ArgumentError, match=r"max_path_length=0 is outside"):
        vkpath.render(width=8, height=8, spp=1, max_path_length=0)
    with pytest.raises(vkpath.VkpathError, match="fov"):
        vkpath.Camera((0, 0, 0), (0, 0, -1), fov=180)
    with pytest.raises(vkpath.VkpathError, match="background"):
        vkpath.render(width=8, height=8, spp=1, background=(-1, 0, 0))
    with pytest.raises(vkpath.VkpathError, match="missing.hdr"):
        vkpath.render(width=8, height=8, spp=1, environment=REPO / "missing.hdr")


def test_light_selection_by_name_and_a_bad_name_raises():
    # Each light of emissive_quad.gltf is two triangles with one box, so the tree's choice
    # there is the power CDF's 0.5/0.5: the same bits either way.
    scene = vkpath.Scene.load(REPO / "tests" / "data" / "emissive_quad.gltf")
    images = [vkpath.render(scene, width=12, height=8, spp=2, integrator="nee",
                            light_selection=name) for name in ("power", "tree")]
    assert np.array_equal(bits(images[0]), bits(images[1]))
    # The thousand-light corridor renders with the tree, finite and not black.
    corridor = vkpath.Scene.load(REPO / "scenes" / "many_lights.gltf")
    result = vkpath.render_result(corridor, width=8, height=6, spp=2, integrator="nee",
                                  light_selection="tree")
    assert result.settings["light_selection"] == "tree"
    assert np.isfinite(result.image).all() and result.image[..., :3].max() > 0
    with pytest.raises(vkpath.VkpathError, match="power"):
        vkpath.render(width=8, height=8, spp=1, light_selection="cdf")


def test_a_sampler_the_integrator_ignores_is_a_warning():
    with pytest.warns(UserWarning, match="no effect"):
        result = vkpath.render_result(width=8, height=8, spp=1, integrator="workshop",
                                      sampler="sobol")
    assert result.settings["sampler"] == "pcg"


def test_defaults_are_the_command_lines(cli):
    # The help text shows clap's defaults, which are RenderSettings::default()'s.
    help_text = run_cli(cli, "render", "--help").stdout
    defaults = vkpath.default_settings()
    # (Not --sampler: its default may depend on the integrator; the bit-for-bit test above
    # covers it.)
    for option in ("width", "height", "spp", "seed", "integrator",
                   "max_path_length", "light_sampling", "light_selection", "pixel_filter",
                   "accel"):
        flag = "--" + option.replace("_", "-")
        block = help_text[help_text.index(flag):]
        block = block[:block.index("\n  -", 1) if "\n  -" in block[1:] else len(block)]
        assert f"[default: {defaults[option]}]" in block, (option, block)


def png_chunks_but_text(path):
    """A PNG's signature and chunks (each with its length, type and CRC), without tEXt ones."""
    data = path.read_bytes()
    chunks, at = [data[:8]], 8
    while at < len(data):
        length = int.from_bytes(data[at:at + 4], "big")
        if data[at + 4:at + 8] != b"tEXt":
            chunks.append(data[at:at + 12 + length])
        at += 12 + length
    return chunks


def test_save_writes_what_the_command_line_writes(cli, tmp_path):
    result = vkpath.render_result(width=16, height=16, spp=8, seed=2)
    exr = tmp_path / "py.exr"
    vkpath.save(result, exr, moments=True)
    assert np.array_equal(bits(read_exr_rgba(exr)), bits(result.image))
    # The same pixels as the command line's PNG, tone-mapped the command line's way.
    png, cli_png = tmp_path / "py.png", tmp_path / "cli.png"
    vkpath.save(result.image, png)
    run_cli(cli, "render", "--width", "16", "--height", "16", "--spp", "8", "--seed", "2",
            "-o", str(cli_png))
    # Byte for byte but for the command line's tEXt chunk (its render metadata: settings,
    # samples, how it stopped), which an array saved from Python has none of.
    assert png_chunks_but_text(png) == png_chunks_but_text(cli_png)
    assert b"tEXtvkpath" in cli_png.read_bytes() and b"tEXt" not in png.read_bytes()
    vkpath.save(result.image[..., :3], tmp_path / "clamped.png", tonemap="clamp", exposure=1)
    assert (tmp_path / "clamped.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(vkpath.VkpathError, match="agx"):
        vkpath.save(result.image, png, tonemap="filmic")
    assert np.array_equal(bits(vkpath.read_exr(exr)), bits(result.image))


def test_compare_tells_consistent_from_biased(tmp_path):
    a = vkpath.render_result(width=32, height=32, spp=64, seed=1)
    b = vkpath.render_result(width=32, height=32, spp=64, seed=2)
    report = vkpath.compare(a, b)
    assert report["consistent"], report["worst"]
    assert report["variance_source"] == "both_moments"
    # 20% brighter is far outside the noise of 64 spp per pixel in 8x8 blocks.
    biased = a.image * np.float32(1.2)
    report = vkpath.compare(biased, b)
    assert report["variance_source"] == "moments_of_b" and not report["consistent"]
    vkpath.save(b, tmp_path / "b.exr", moments=True)
    assert vkpath.compare(a, tmp_path / "b.exr")["consistent"]


def test_check_returns_the_command_lines_json_report(cli, tmp_path):
    solution = REPO / "tests" / "solutions" / "pcg2d_typo.glsl"
    report = vkpath.check(solution, output_dir=tmp_path / "py")
    done = run_cli(cli, "check", str(solution), "--json", "--output-dir", str(tmp_path / "cli"),
                   expect=1)
    assert report == json.loads(done.stdout)
    assert report["passed"] is False
    verdicts = {f["function"]: f["passed"] for f in report["functions"]}
    assert verdicts["get_random_numbers"] is False


def test_check_of_a_missing_file_raises_the_command_lines_message(cli, tmp_path):
    missing = tmp_path / "missing.glsl"
    done = run_cli(cli, "check", str(missing), expect=2)
    line = done.stderr.strip().splitlines()[-1]
    with pytest.raises(vkpath.VkpathError) as raised:
        vkpath.check(missing)
    assert str(raised.value) == line[len("vkpath: error: "):]


def test_guiding_equals_the_command_lines_guided_render_bit_for_bit(cli, tmp_path):
    output = tmp_path / "guided.exr"
    # 48 training spp at 24 x 16 teach cells of the box (fewer teach none, and the guided
    # image would be the unguided one).
    run_cli(cli, "render", "--integrator", "mis", "--guiding", "--guide-training-spp", "48",
            "--width", "24", "--height", "16", "--spp", "4", "--seed", "3", "-o", str(output))
    result = vkpath.render_result(width=24, height=16, spp=4, seed=3, integrator="mis",
                                  guiding=True, guide_training_spp=48)
    assert result.settings["guide_training_spp"] == 48
    assert np.array_equal(bits(result.image), bits(read_exr_rgba(output)))
    # Not the unguided image: the guide changed the samples.
    plain = vkpath.render(width=24, height=16, spp=4, seed=3, integrator="mis")
    assert not np.array_equal(bits(plain), bits(result.image))
    with pytest.raises(vkpath.VkpathError, match="guides nee and mis"):
        vkpath.render(width=8, height=8, spp=1, integrator="cosine", guiding=True)


def test_ground_truth_ids_are_integers_and_the_camera_projects_positions(cli, tmp_path):
    # The material showcase: overlapping objects (spheres before walls) and an alpha-masked
    # leaf. IDs come back as uint32 arrays equal to the command line's EXR layers, and the
    # camera's K with its OpenCV camera-to-world matrix projects every hit point onto its
    # pixel's centre (ground truth from the ray through the pixel centre).
    scene = str(REPO / "scenes" / "materials.gltf")
    output = tmp_path / "truth.exr"
    aovs = ["object_id", "material_id", "position"]
    run_cli(cli, "render", scene, "--width", "24", "--height", "18", "--spp", "1",
            "--aov", ",".join(aovs), "-o", str(output))
    result = vkpath.render_result(scene, width=24, height=18, spp=1, aovs=aovs)
    with OpenEXR.File(str(output), separate_channels=True) as exr:
        channels = exr.channels()
        for name in ("object_id", "material_id"):
            ids = result.layers[name]
            assert ids.dtype == np.uint32 and ids.shape == (18, 24)
            assert np.array_equal(ids, channels[f"{name}.Z"].pixels.astype(np.uint32))
    names = json.loads((tmp_path / "truth.ids.json").read_text())
    leaf = [o["id"] for o in names["objects"] if o["name"] == "alpha-mask leaf"]
    assert leaf and leaf[0] in result.layers["object_id"], "the leaf is seen"
    assert len(np.unique(result.layers["object_id"])) > 5, "overlapping objects"
    camera = result.camera
    k, to_world = camera["k"], camera["camera_to_world_opencv"]
    assert k.shape == (3, 3) and to_world.shape == (4, 4)
    points = result.layers["position"].reshape(-1, 3).astype(np.float64)
    hit = result.layers["object_id"].reshape(-1) != 0
    local = (points - to_world[:3, 3]) @ to_world[:3, :3]
    projected = (local @ k.T)[:, :2] / local[:, 2:3]
    rows, columns = np.divmod(np.arange(24 * 18), 24)
    assert np.abs(projected[hit] - np.stack([columns, rows], axis=-1)[hit]).max() < 2e-3
