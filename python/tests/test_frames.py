"""Time, frames and sample ranges (issue 41): ``render(time=)`` against ``vkpath render
--time``, ``render_frames`` against ``render(time=)`` per frame, ``render(sample_range=)``
against ``--sample-range``, each bit for bit (lavapipe, tiny images)."""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest

import vkpath
from test_vkpath import bits, cli, read_exr_rgba, run_cli  # noqa: F401 (cli: a fixture)

SMALL = dict(width=16, height=16, spp=2, seed=1, background=(1.0, 1.0, 1.0))
SMALL_CLI = ["--width", "16", "--height", "16", "--spp", "2", "--seed", "1",
             "--background", "1,1,1"]


def write_animated_quad(directory):
    """tests/frames_cli.rs's scene: a unit quad facing +Z whose node slides LINEAR from
    x = -1 at 0 s to x = 1 at 1 s, seen by a camera at z = 3 looking down -Z."""
    chunks = [struct.pack("<12f", -0.5, -0.5, 0, 0.5, -0.5, 0, 0.5, 0.5, 0, -0.5, 0.5, 0),
              struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0",
              struct.pack("<2f", 0.0, 1.0),
              struct.pack("<6f", -1, 0, 0, 1, 0, 0)]
    views, offset = [], 0
    for chunk in chunks:
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(chunk)})
        offset += len(chunk)
    views[1]["byteLength"] = 12
    document = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "quad", "mesh": 0},
                  {"name": "camera", "camera": 0, "translation": [0, 0, 3]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "animations": [{"name": "slide",
                        "channels": [{"sampler": 0,
                                      "target": {"node": 0, "path": "translation"}}],
                        "samplers": [{"input": 2, "output": 3}]}],
        "buffers": [{"uri": "animated.bin", "byteLength": offset}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-0.5, -0.5, 0.0], "max": [0.5, 0.5, 0.0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR",
             "min": [0.0], "max": [1.0]},
            {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
        ],
    }
    (directory / "animated.bin").write_bytes(b"".join(chunks))
    path = directory / "animated.gltf"
    path.write_text(json.dumps(document))
    return path


def test_time_equals_the_command_lines_time_bit_for_bit(cli, tmp_path):
    scene = write_animated_quad(tmp_path)
    output = tmp_path / "t.exr"
    run_cli(cli, "render", str(scene), *SMALL_CLI, "--time", "0.75", "-o", str(output))
    moved = vkpath.render(scene, time=0.75, **SMALL)
    assert np.array_equal(bits(moved), bits(read_exr_rgba(output)))
    # The quad did move: time 0 sees it elsewhere.
    assert not np.array_equal(moved, vkpath.render(scene, **SMALL))
    with pytest.raises(vkpath.ArgumentError, match="time=-1 is not a time"):
        vkpath.render(scene, time=-1, **SMALL)


def test_render_frames_yields_each_frame_at_frame_over_fps(tmp_path):
    scene = write_animated_quad(tmp_path)
    frames = list(vkpath.render_frames(scene, frames=range(2, 5), fps=4, **SMALL))
    assert [frame for frame, _ in frames] == [2, 3, 4]
    for frame, image in frames:
        assert np.array_equal(bits(image), bits(vkpath.render(scene, time=frame / 4, **SMALL)))
    assert not np.array_equal(frames[0][1], frames[2][1])
    with pytest.raises(vkpath.ArgumentError, match="fps=0.0"):
        next(vkpath.render_frames(scene, frames=[0], fps=0))


def test_render_frames_yields_ground_truth_and_flow_per_frame(tmp_path):
    """Issue 56: with aovs=, each frame is a dict of arrays with the camera data. The quad
    slides 2 units/s along x, 3 units in front of the camera: at 8 fps a frame moves it 0.25
    units, fx * 0.25 / 3 pixels to the right (forward flow) and as far left (backward)."""
    scene = write_animated_quad(tmp_path)
    frames = list(vkpath.render_frames(scene, frames=range(3, 5), fps=8,
                                       aovs=["object_id", "motion"], **SMALL))
    assert [frame for frame, _ in frames] == [3, 4]
    for frame, outputs in frames:
        assert set(outputs) == {"image", "object_id", "motion_forward", "motion_backward",
                                "camera"}
        assert outputs["image"].shape == (16, 16, 4)
        ids = outputs["object_id"]
        assert ids.dtype == np.uint32 and ids.shape == (16, 16)
        hit = ids == 1
        assert 0 < hit.sum() < ids.size, "the quad and the background are both seen"
        shift = outputs["camera"]["k"][0, 0] * 0.25 / 3.0
        forward, backward = outputs["motion_forward"][hit], outputs["motion_backward"][hit]
        assert np.allclose(forward[:, 0], shift, atol=0.05), (frame, forward[:, 0], shift)
        assert np.allclose(backward[:, 0], -shift, atol=0.05), (frame, backward[:, 0])
        assert np.allclose(forward[:, 1], 0.0, atol=0.05)
        assert np.all(forward[:, 2] == 1.0)
        assert not outputs["motion_forward"][~hit].any()
    # A scene that does not move (the Cornell box): 0, with a warning
    with pytest.warns(UserWarning, match="motion vectors are 0"):
        still = vkpath.render_result(width=4, height=4, spp=1, aovs=["motion"])
    assert not still.layers["motion_forward"][..., :2].any()


def write_camera_less(directory):
    """The animated quad without its camera, in front of a static quad twice its size."""
    document = json.loads(write_animated_quad(directory).read_text())
    document["nodes"][1] = {"name": "wall", "mesh": 0, "scale": [2, 2, 1],
                            "translation": [0, 0, -0.5]}
    del document["cameras"]
    path = directory / "framed.gltf"
    path.write_text(json.dumps(document))
    return path


def test_render_frames_frames_a_camera_less_file_once_for_all_frames(tmp_path):
    # Issue 58: each frame was framed by its own pose, so the view zoomed and jumped. Now
    # the whole animation frames every frame: frame 1 is the same image in any sequence
    # (a farm's task of one frame included), and not the still at its time, which frames
    # its own pose.
    scene = write_camera_less(tmp_path)
    (_, _), (_, last) = vkpath.render_frames(scene, frames=range(2), fps=1, **SMALL)
    [(_, alone)] = list(vkpath.render_frames(scene, frames=[1], fps=1, **SMALL))
    assert np.array_equal(bits(alone), bits(last))
    assert not np.array_equal(last, vkpath.render(scene, time=1.0, **SMALL))


def test_a_sample_range_equals_the_command_lines_shard_bit_for_bit(cli, tmp_path):
    output = tmp_path / "shard.exr"
    run_cli(cli, "render", "--width", "16", "--height", "12", "--seed", "1",
            "--sample-range", "3..7", "-o", str(output))
    result = vkpath.render_result(width=16, height=12, seed=1, sample_range=(3, 7))
    assert result.sample_range == (3, 7) and result.spp == 4
    assert np.array_equal(bits(result.image), bits(read_exr_rgba(output)))
    # Other samples than the first four.
    first = vkpath.render(width=16, height=12, seed=1, spp=4)
    assert not np.array_equal(first, result.image)
    with pytest.raises(vkpath.ArgumentError, match=r"sample_range=\(5, 5\)"):
        vkpath.render(width=16, height=12, sample_range=(5, 5))


def test_frames_take_the_command_lines_range_or_refuse_in_words(tmp_path):
    """Issue 58: frames="0..3" was a raw ValueError (int('.')); it is the CLI's range now."""
    scene = write_animated_quad(tmp_path)
    as_text = [frame for frame, _ in vkpath.render_frames(scene, frames="2..4", fps=4, **SMALL)]
    assert as_text == [2, 3]
    for bad, words in [("3..3", "is not 'START..END'"), ("0-3", "is not 'START..END'"),
                       ([1.5, 0], "1.5 is not a whole frame number"), (7, "is not frame numbers")]:
        with pytest.raises(vkpath.ArgumentError, match=words):
            next(vkpath.render_frames(scene, frames=bad, fps=4, **SMALL))


def test_a_shutter_blurs_as_the_mean_of_stills_and_equals_the_command_line(cli, tmp_path):
    """Issue 55: ``render(shutter=)`` is ``--shutter``: bit for bit the command line's, and
    the mean over the shutter of the still images. The quad slides 2 units/s; at fps 2 a
    shutter of 1 frame interval around 0.5 s sweeps it from x = -0.5 to 0.5. One bounce
    against a white background makes each sample 0 (quad) or 1 (background), so the image
    is the background's coverage."""
    scene = write_animated_quad(tmp_path)
    common = dict(width=16, height=16, seed=3, background=(1.0, 1.0, 1.0), sampler="pcg",
                  max_path_length=1, fps=2)
    blurred = vkpath.render(scene, spp=256, time=0.5, shutter=1, **common)
    output = tmp_path / "blurred.exr"
    run_cli(cli, "render", str(scene), "--width", "16", "--height", "16", "--seed", "3",
            "--background", "1,1,1", "--sampler", "pcg", "--max-path-length", "1",
            "--fps", "2", "--spp", "256", "--time", "0.5", "--shutter", "1",
            "-o", str(output))
    assert np.array_equal(bits(blurred), bits(read_exr_rgba(output)))
    # Stills at the midpoints of 8 equal parts of the shutter [0.25 s, 0.75 s]
    stills = [vkpath.render(scene, spp=32, time=0.25 + (i + 0.5) / 16, **common)
              for i in range(8)]
    mean = np.mean(stills, axis=0)
    # Column profiles (mean over the 16 rows): each column of the blur averages 16 x 256
    # binary samples, std at most sqrt(0.25 / 4096) = 0.0078; the stills' mean 16 x 256 as
    # well, so their difference's std is at most 0.011. 0.06 is 5.4 of them, with room
    # for the stills' midpoint rule in time (a 1/8 shutter step is 1 pixel of travel).
    blur_profile, mean_profile = blurred[..., 0].mean(axis=0), mean[..., 0].mean(axis=0)
    assert np.max(np.abs(blur_profile - mean_profile)) < 0.06, (blur_profile, mean_profile)
    # The test has teeth: a still near the shutter's opening is far from the blur (more
    # than twice the tolerance).
    opening = stills[0][..., 0].mean(axis=0)
    assert np.max(np.abs(opening - blur_profile)) > 0.12, opening


def test_bad_shutters_are_argument_errors_and_a_still_scene_warns():
    small = dict(width=4, height=4, spp=1)
    for bad, words in [(dict(shutter=3), "shutter=3"), (dict(shutter=-1), "shutter=-1"),
                       (dict(shutter=1, motion_steps=1), "motion_steps=1"),
                       (dict(shutter=1, shutter_position="middle"), "shutter_position")]:
        with pytest.raises(vkpath.ArgumentError, match=words):
            vkpath.render(**small, **bad)
    # The Cornell box does not move: the still image, bit for bit, with a warning
    with pytest.warns(UserWarning, match="nothing in the scene moves across the shutter"):
        blurred = vkpath.render(**small, shutter=1)
    assert np.array_equal(bits(blurred), bits(vkpath.render(**small)))
