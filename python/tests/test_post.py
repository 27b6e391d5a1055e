"""Adaptive sampling, AOVs and denoising from Python (``noise_threshold=``, ``aovs=``,
``denoise=``) against ``vkpath render --noise-threshold / --aov / --denoise``, bit for bit
(lavapipe, tiny images)."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

import vkpath
from test_vkpath import bits, cli, read_exr_rgba, run_cli  # noqa: F401 (cli: a fixture)

SIZE = ["--width", "16", "--height", "12", "--seed", "1"]


def read_layer(path, names):
    """The channels ``names`` of an EXR, stacked (OpenEXR's reader)."""
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        channels = exr.channels()
        return np.stack([channels[name].pixels for name in names], axis=-1)


def test_noise_threshold_equals_the_command_lines_adaptive_render(cli, tmp_path):
    output = tmp_path / "adaptive.exr"
    run_cli(cli, "render", *SIZE, "--spp", "32", "--noise-threshold", "0.2",
            "--noise-min-spp", "4", "-o", str(output))
    result = vkpath.render_result(width=16, height=12, seed=1, spp=32, noise_threshold=0.2,
                                  noise_min_spp=4)
    assert np.array_equal(bits(result.image), bits(read_exr_rgba(output)))
    # Some pixels stopped early (else this would be an ordinary render).
    assert result.sample_count.min() < 32
    with pytest.raises(vkpath.ArgumentError, match="noise_min_spp= has no effect"):
        vkpath.render(width=4, height=4, spp=1, noise_min_spp=4)


def test_aovs_and_denoise_equal_the_command_lines_layers(cli, tmp_path):
    output = tmp_path / "aov.exr"
    run_cli(cli, "render", *SIZE, "--spp", "4", "--aov", "albedo", "--aov", "depth",
            "--denoise", "-o", str(output))
    result = vkpath.render_result(width=16, height=12, seed=1, spp=4,
                                  aovs=["albedo", "depth"], denoise=True)
    assert sorted(result.layers) == ["albedo", "depth", "noisy"]
    assert result.layers["depth"].shape == (12, 16)
    assert np.array_equal(bits(result.image), bits(read_exr_rgba(output)))
    for name, channels in (("albedo", ["albedo.R", "albedo.G", "albedo.B"]),
                           ("noisy", ["noisy.R", "noisy.G", "noisy.B"])):
        assert np.array_equal(bits(result.layers[name]), bits(read_layer(output, channels)))
    assert np.array_equal(bits(result.layers["depth"]),
                          bits(read_layer(output, ["depth.Z"])[..., 0]))
    # Denoising changed the image.
    assert not np.array_equal(result.image[..., :3], result.layers["noisy"])
    with pytest.raises(vkpath.ArgumentError, match="aovs='shadow' is not one of"):
        vkpath.render(width=4, height=4, spp=1, aovs=["shadow"])


def test_a_time_limited_render_is_finished_and_keeps_its_aovs_and_denoising():
    # A million spp: the time limit stops it long before its end (issue 58: it used to
    # return the noisy image without its layers, as after a stop).
    result = vkpath.render_result(width=8, height=8, spp=1 << 20, time_limit=0.3,
                                  aovs=["albedo"], denoise=True)
    assert result.stop == "time-limit" and result.spp < 1 << 20
    assert sorted(result.layers) == ["albedo", "noisy"]
    assert not np.array_equal(result.image[..., :3], result.layers["noisy"])
    # A render the callback stopped is returned as it is, with a warning.
    with pytest.warns(UserWarning, match="stopped early"):
        stopped = vkpath.render_result(width=8, height=8, spp=1 << 20, aovs=["albedo"],
                                       progress=lambda done, total: False)
    assert stopped.stop == "stopped" and stopped.layers == {}


def test_read_exr_with_layers_returns_every_layer(cli, tmp_path):
    output = tmp_path / "layers.exr"
    run_cli(cli, "render", *SIZE, "--spp", "2", "--aov", "albedo", "--aov", "depth",
            "--moments", "-o", str(output))
    layers = vkpath.read_exr(output, layers=True)
    assert sorted(layers) == ["albedo", "depth", "image", "sample_count", "second_moment"]
    assert np.array_equal(bits(layers["image"]), bits(read_exr_rgba(output)))
    assert np.array_equal(bits(layers["image"]), bits(vkpath.read_exr(output)))
    assert layers["albedo"].shape == (12, 16, 3) and layers["depth"].shape == (12, 16)
    for name, channels in (("albedo", ["albedo.R", "albedo.G", "albedo.B"]),
                           ("second_moment", ["second_moment.R", "second_moment.G",
                                              "second_moment.B"])):
        assert np.array_equal(bits(layers[name]), bits(read_layer(output, channels)))
    assert np.array_equal(bits(layers["sample_count"]),
                          bits(read_layer(output, ["sample_count.Y"])[..., 0]))
    assert (layers["sample_count"] == 2).all()


def test_a_three_parameter_progress_callback_can_read_the_image_so_far():
    seen = []

    def progress(done, total, image_so_far):
        seen.append((done, total, image_so_far()))

    # One sample per batch (samples_per_frame=1), so that there are batches before the last.
    result = vkpath.render_result(width=16, height=12, seed=1, spp=6, samples_per_frame=1,
                                  progress=progress)
    assert [done for done, _, _ in seen] == sorted({done for done, _, _ in seen})
    assert seen[-1][0] == 6 and all(total == 6 for _, total, _ in seen)
    assert all(image.shape == (12, 16, 4) for _, _, image in seen)
    # The last estimate is the render's image; an earlier one, of fewer samples, is not.
    assert np.array_equal(bits(seen[-1][2]), bits(result.image))
    assert len(seen) >= 2 and not np.array_equal(seen[0][2], result.image)
    # Each estimate is the render of that many samples.
    first_done, _, first_image = seen[0]
    alone = vkpath.render(width=16, height=12, seed=1, spp=first_done, samples_per_frame=1)
    assert np.array_equal(bits(first_image), bits(alone))


def test_returning_false_from_a_three_parameter_callback_stops():
    calls = []
    result = vkpath.render_result(width=8, height=8, seed=1, spp=64, samples_per_frame=1,
                                  progress=lambda done, total, image: calls.append(done) or False)
    assert result.stop == "stopped" and calls == [result.spp]


def test_cryptomatte_equals_the_command_lines_layers_and_masks_sum_to_one(cli, tmp_path):
    output = tmp_path / "matte.exr"
    run_cli(cli, "render", *SIZE, "--spp", "4", "--aov", "cryptomatte", "-o", str(output))
    result = vkpath.render_result(width=16, height=12, seed=1, spp=4, aovs=["cryptomatte"])
    names = ["CryptoMaterial00", "CryptoMaterial01", "CryptoMaterial02",
             "CryptoObject00", "CryptoObject01", "CryptoObject02"]
    assert sorted(result.layers) == names
    for name in names:
        channels = [f"{name}.{c}" for c in "RGBA"]
        assert result.layers[name].shape == (12, 16, 4)
        assert np.array_equal(bits(result.layers[name]), bits(read_layer(output, channels)))
    # The Cornell box has no nodes: one object, "scene"; its materials are "#0", "#1", ...
    assert list(result.cryptomatte["CryptoObject"]) == ["scene"]
    assert len(result.cryptomatte["CryptoMaterial"]) > 1
    # Each of a pixel's 4 samples that hits names one object and one material: the
    # materials' mattes add up to the object's, which is the share of samples that hit
    # (a multiple of 1/4, at most 1)
    scene = vkpath.cryptomatte_mask(result, "scene")
    assert scene.max() == 1.0 and np.array_equal(scene * 4, np.round(scene * 4))
    total = sum(vkpath.cryptomatte_mask(result, name, "CryptoMaterial")
                for name in result.cryptomatte["CryptoMaterial"])
    assert np.allclose(total, scene, atol=1e-6)
