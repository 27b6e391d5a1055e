"""Arguments that used to fail obscurely (issue 43): each is now an ``ArgumentError`` (a
``ValueError`` and a ``VkpathError``) naming the parameter as Python spells it, or a
warning where the call can go on."""

from __future__ import annotations

import numpy as np
import pytest

import vkpath


@pytest.mark.parametrize(
    "settings, words",
    [
        (dict(spp=-3), "spp=-3 is not a whole number >= 0"),
        (dict(width=2.5), "width=2.5 is not a whole number >= 0"),
        (dict(seed=2**40), "seed=1099511627776 is larger than vkpath takes"),
        (dict(background="red"), "background='red' is not three numbers (R, G, B)"),
        (dict(background=(1, 2)), "background=(1, 2) is not three numbers"),
        (dict(device="all"), "rendering on several devices is the command line's"),
        (dict(device="0,1"), "sample_range= and device=INDEX"),
        (dict(sample_range=(4, 2)), "sample_range=(4, 2) is not (start, end) with start < end"),
    ],
)
def test_bad_arguments_are_argument_errors_that_name_the_parameter(settings, words):
    with pytest.raises(vkpath.ArgumentError) as raised:
        vkpath.render(**{**dict(width=4, height=4, spp=1), **settings})
    assert words in str(raised.value)
    assert isinstance(raised.value, ValueError) and isinstance(raised.value, vkpath.VkpathError)


def test_save_refuses_integer_images(tmp_path):
    with pytest.raises(vkpath.ArgumentError, match="not uint8"):
        vkpath.save(np.full((2, 2, 3), 255, np.uint8), tmp_path / "a.png")
    assert not (tmp_path / "a.png").exists()


def test_save_writes_nan_as_black_with_a_warning(tmp_path):
    image = np.ones((2, 3, 3), np.float32)
    image[1, 2, 0] = np.nan
    with pytest.warns(UserWarning, match="1 pixels hold NaN or infinity"):
        vkpath.save(image, tmp_path / "a.exr")
    back = vkpath.read_exr(tmp_path / "a.exr")
    assert back[1, 2, 0] == 0.0 and back[0, 0, 0] == 1.0


def test_camera_errors_name_pythons_parameters():
    with pytest.raises(vkpath.ArgumentError, match=r"^fov=200 is outside \(0, 180\) degrees$"):
        vkpath.Camera((0, 0, 0), (0, 0, 1), fov=200)
    with pytest.raises(vkpath.ArgumentError, match="position, look_at and up do not define"):
        vkpath.Camera((0, 0, 0), (0, 0, 0))


def test_signatures_show_their_defaults_not_ellipsis():
    import inspect

    functions = [vkpath.Camera, vkpath.Scene.look_at, vkpath.Scene.from_arrays,
                 vkpath._vkpath.compare, vkpath._vkpath.render, vkpath._vkpath.save,
                 vkpath.render, vkpath.render_result, vkpath.render_frames, vkpath.save]
    for function in functions:
        text = str(inspect.signature(function))
        assert "Ellipsis" not in text and "..." not in text, (function, text)
    # The written-out defaults are the library's.
    assert "fov=45.0" in str(inspect.signature(vkpath.Camera))
    assert vkpath.Camera((0, 0, 0), (0, 0, 1)).fov == pytest.approx(45.0, abs=1e-4)
    assert "alpha=0.01, block_size=8" in str(inspect.signature(vkpath._vkpath.compare))
