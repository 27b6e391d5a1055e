"""``medium=`` and :class:`vkpath.Medium` against the command line's ``render --medium``
(lavapipe, tiny images). ``VKPATH_CLI`` names the binary, as in test_vkpath.py."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import OpenEXR
import pytest

import vkpath

# A chromatic absorber and a forward-scattering grey scatterer, dense enough that the box's
# pixels change a lot (optical depth ~1 across the 0.56-wide box).
FOG = "sigma_a=0.5,1,2:sigma_s=1.5:g=0.6"
SETTINGS = dict(width=12, height=10, spp=4, seed=3, integrator="mis", sampler="pcg")


def cli_render(tmp_path: Path, *args: str) -> np.ndarray:
    binary = os.environ.get("VKPATH_CLI")
    assert binary and os.access(binary, os.X_OK), "set VKPATH_CLI to the vkpath binary"
    output = tmp_path / "cli.exr"
    done = subprocess.run(
        [binary, "render", "--width", "12", "--height", "10", "--spp", "4", "--seed", "3",
         "--integrator", "mis", "--sampler", "pcg", *args, "-o", str(output)],
        capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    with OpenEXR.File(str(output), separate_channels=True) as exr:
        channels = exr.channels()
        return np.stack([channels[c].pixels for c in "RGBA"], axis=-1)


def bits(image: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(image, dtype=np.float32).view(np.uint32)


def test_a_medium_renders_as_the_command_lines_medium_bit_for_bit(tmp_path):
    expected = cli_render(tmp_path, "--medium", FOG)
    fog = vkpath.Medium(sigma_a=(0.5, 1, 2), sigma_s=1.5, g=0.6)
    result = vkpath.render_result(medium=fog, **SETTINGS)
    assert np.array_equal(bits(result.image), bits(expected))
    assert result.settings["medium"] == "sigma_a=0.5,1,2:sigma_s=1.5,1.5,1.5:g=0.6"
    # The medium changed the picture: the fog absorbs (blue most), so the box is darker.
    clear = vkpath.render(**SETTINGS)
    assert clear[..., 2].mean() > 1.5 * result.image[..., 2].mean()
    # The same medium as a dict, as the option's text, and in a sequence of frames.
    as_dict = dict(sigma_a=[0.5, 1.0, 2.0], sigma_s=1.5, g=0.6)
    assert np.array_equal(bits(vkpath.render(medium=as_dict, **SETTINGS)), bits(expected))
    assert np.array_equal(bits(vkpath.render(medium=FOG, **SETTINGS)), bits(expected))
    [(frame, image)] = list(vkpath.render_frames(frames=[0], medium=fog, **SETTINGS))
    assert frame == 0 and np.array_equal(bits(image), bits(expected))


def test_a_medium_keeps_what_the_renderer_stores():
    fog = vkpath.Medium(sigma_a=0.1, sigma_s=(1, 2, 3))
    assert fog.sigma_a == (np.float32(0.1),) * 3 and fog.sigma_s == (1.0, 2.0, 3.0)
    assert fog.g == 0.0
    assert vkpath.Medium.parse(str(fog)) == fog
    assert vkpath.Medium.parse("g=0.5:sigma_s=2") == vkpath.Medium(sigma_s=2, g=0.5)


@pytest.mark.parametrize("make, needle", [
    (lambda: vkpath.Medium(sigma_s=1, g=1.0), "g=1: the Henyey-Greenstein anisotropy"),
    (lambda: vkpath.Medium(sigma_a=-0.5), "sigma_a has -0.5"),
    (lambda: vkpath.Medium(sigma_s=float("nan")), "sigma_s has NaN"),
    (lambda: vkpath.Medium(sigma_s=(1, 2)), "sigma_s=(1, 2) is not a number or three"),
    (lambda: vkpath.Medium(g="0.5"), "g='0.5' is not a number"),
    (lambda: vkpath.Medium.parse("fog"), "'fog' is not one of"),
    (lambda: vkpath.render(medium=dict(sigma_s=1, density=2), **SETTINGS), "density is not one of"),
    (lambda: vkpath.render(medium=3.0, **SETTINGS), "is not a vkpath.Medium"),
    (lambda: vkpath.render(medium="sigma_s=1", **{**SETTINGS, "integrator": "workshop"}),
     "medium: integrator=workshop renders no media"),
])
def test_a_bad_medium_is_one_value_error(make, needle):
    with pytest.raises(ValueError, match=None) as raised:
        make()
    assert isinstance(raised.value, vkpath.VkpathError)
    message = str(raised.value)
    assert needle in message and "\n" not in message, message
