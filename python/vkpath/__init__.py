"""vkpath: a headless, progressive path tracer (the Path Tracing Workshop's GLSL on Vulkan).

>>> import vkpath
>>> image = vkpath.render(width=64, height=64, spp=16)   # the workshop's Cornell box
>>> image.shape, image.dtype
((64, 64, 4), dtype('float32'))
>>> vkpath.save(image, "cornell.png")

Renders are linear RGBA float32 numpy arrays of shape (height, width, 4), rows top-down,
alpha 1. Every setting left out takes the command line's default (`vkpath render`), which
``vkpath.default_settings()`` lists; the same settings give the same pixels as the command
line's EXR, bit for bit. Errors raise :class:`VkpathError` with the one-line message the
command line prints.
"""

from __future__ import annotations

import json
import os
import warnings
from dataclasses import dataclass
from typing import Any, Callable, Dict, Optional, Sequence, Tuple, Union

import numpy as np

from . import _vkpath
from ._vkpath import Camera, Scene, VkpathError

__all__ = [
    "Camera",
    "RenderResult",
    "Scene",
    "VkpathError",
    "check",
    "compare",
    "default_settings",
    "read_exr",
    "render",
    "render_result",
    "save",
]
__version__: str = _vkpath.__version__

PathLike = Union[str, "os.PathLike[str]"]
#: ``progress(spp_done, spp_total)``, called after each batch of samples (about every 250 ms);
#: returning ``False`` stops the render, raising stops it and propagates.
ProgressCallback = Callable[[int, int], Optional[bool]]


@dataclass(frozen=True)
class RenderResult:
    """A render with what statistics need (what ``vkpath render --moments`` writes)."""

    #: Mean radiance per pixel, linear RGBA float32, shape (height, width, 4), rows top-down.
    image: np.ndarray
    #: Mean of the squared radiance samples per pixel, RGB float32, (height, width, 3).
    second_moment: np.ndarray
    #: Samples per pixel, float32, (height, width).
    sample_count: np.ndarray
    #: Samples per pixel taken (fewer than ``spp_requested`` when stopped early).
    spp: int
    #: Samples per pixel asked for.
    spp_requested: int
    #: Why the render ended: "done", "time-limit" or "stopped" (the progress callback).
    stop: str
    #: Seconds the frames took (the kernel build and read-back excluded).
    seconds: float
    #: The Vulkan device's name.
    device: str
    #: The settings it was rendered with, by the command line's names.
    settings: Dict[str, Any]


def default_settings() -> Dict[str, Any]:
    """The settings a render takes where a call says nothing: the command line's defaults
    (the library's ``production_settings()``), by the command line's names."""
    return dict(_vkpath.default_settings())


def _region_of(region: Sequence[int]) -> Tuple[int, int, int, int]:
    """``region`` as the four ints (x0, y0, x1, y1) the extension takes."""
    values = tuple(int(v) for v in region)
    if len(values) != 4 or min(values) < 0:
        raise VkpathError(
            f"region={tuple(region)!r} is not (x0, y0, x1, y1): four whole numbers >= 0"
        )
    return values  # type: ignore[return-value]


def _scene_of(scene: Union[None, PathLike, Scene]) -> Scene:
    if scene is None:
        return Scene.cornell_box()
    if isinstance(scene, Scene):
        return scene
    loaded = Scene.load(os.fspath(scene))
    for warning in loaded.warnings:
        warnings.warn(warning, stacklevel=3)
    return loaded


def _array(data: bytearray, height: int, width: int, channels: int) -> np.ndarray:
    shape = (height, width, channels) if channels > 1 else (height, width)
    return np.frombuffer(data, dtype=np.float32).reshape(shape)


def render_result(
    scene: Union[None, PathLike, Scene] = None,
    *,
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    integrator: Optional[str] = None,
    seed: Optional[int] = None,
    sampler: Optional[str] = None,
    light_sampling: Optional[str] = None,
    light_selection: Optional[str] = None,
    pixel_filter: Optional[str] = None,
    accel: Optional[str] = None,
    max_path_length: Optional[int] = None,
    samples_per_frame: Optional[int] = None,
    russian_roulette_start: Optional[int] = None,
    environment: Optional[PathLike] = None,
    environment_strength: float = 1.0,
    environment_rotation: float = 0.0,
    background: Optional[Sequence[float]] = None,
    time_limit: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
    device: Optional[Union[int, str]] = None,
    validate: bool = False,
    region: Optional[Sequence[int]] = None,
    guiding: bool = False,
    guide_training_spp: Optional[int] = None,
) -> RenderResult:
    """:func:`render`, returning the image with its moments, the samples taken and why the
    render stopped."""
    world = _scene_of(scene)
    raw = _vkpath.render(
        world,
        width=width,
        height=height,
        spp=spp,
        seed=seed,
        integrator=integrator,
        sampler=sampler,
        light_sampling=light_sampling,
        light_selection=light_selection,
        pixel_filter=pixel_filter,
        accel=accel,
        max_path_length=max_path_length,
        samples_per_frame=samples_per_frame,
        russian_roulette_start=russian_roulette_start,
        environment_map=None if environment is None else os.fspath(environment),
        environment_strength=float(environment_strength),
        environment_rotation=float(environment_rotation),
        background=None if background is None else tuple(float(c) for c in background),
        time_limit=None if time_limit is None else float(time_limit),
        progress=progress,
        device=None if device is None else str(device),
        validate=validate,
        region=None if region is None else _region_of(region),
        guiding=bool(guiding),
        guide_training_spp=guide_training_spp,
    )
    for warning in raw["warnings"]:
        warnings.warn(warning, stacklevel=2)
    h, w = raw["height"], raw["width"]
    return RenderResult(
        image=_array(raw["mean"], h, w, 4),
        second_moment=_array(raw["second_moment"], h, w, 3),
        sample_count=_array(raw["sample_count"], h, w, 1),
        spp=raw["spp"],
        spp_requested=raw["spp_requested"],
        stop=raw["stop"],
        seconds=raw["seconds"],
        device=raw["device"],
        settings=dict(raw["settings"]),
    )


def render(
    scene: Union[None, PathLike, Scene] = None,
    *,
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    integrator: Optional[str] = None,
    seed: Optional[int] = None,
    sampler: Optional[str] = None,
    light_sampling: Optional[str] = None,
    light_selection: Optional[str] = None,
    pixel_filter: Optional[str] = None,
    accel: Optional[str] = None,
    max_path_length: Optional[int] = None,
    samples_per_frame: Optional[int] = None,
    russian_roulette_start: Optional[int] = None,
    environment: Optional[PathLike] = None,
    environment_strength: float = 1.0,
    environment_rotation: float = 0.0,
    background: Optional[Sequence[float]] = None,
    time_limit: Optional[float] = None,
    progress: Optional[ProgressCallback] = None,
    device: Optional[Union[int, str]] = None,
    validate: bool = False,
    region: Optional[Sequence[int]] = None,
    guiding: bool = False,
    guide_training_spp: Optional[int] = None,
) -> np.ndarray:
    """Renders a scene and returns its linear RGBA image, float32, shape (height, width, 4),
    rows top-down: what ``vkpath render ... -o out.exr`` writes, bit for bit.

    ``scene`` is ``None`` (the workshop's Cornell box), a .gltf/.glb/.obj path, or a
    :class:`Scene` (whose camera you may change). Each setting left as ``None`` takes the
    command line's default (``default_settings()``); names are the command line's:
    ``integrator`` "workshop", "cosine", "nee" or "mis"; ``sampler`` "pcg" or "sobol";
    ``light_sampling`` "solid-angle" or "area"; ``light_selection`` "auto", "power" or
    "tree"; ``pixel_filter`` "box" or "center";
    ``accel`` "auto", "none", "bvh" or "hardware". ``environment`` is an equirectangular .exr/.hdr map
    (``environment_strength``, ``environment_rotation`` in degrees about +Y), ``background``
    a constant R, G, B radiance instead.

    The GIL is released while rendering. ``progress(spp_done, spp_total)`` is called after
    each batch (about every 250 ms); returning ``False`` stops the render and returns the
    samples taken so far, raising stops it and re-raises. Ctrl-C stops it after the current
    batch and raises KeyboardInterrupt. ``time_limit`` (seconds) stops it and returns what it
    has. ``device`` is an index, a UUID (``GPU-...``, or a unique prefix) or part of a name, as
    ``vkpath devices`` lists them; without it, ``VKPATH_DEVICE`` and then
    ``CUDA_VISIBLE_DEVICES`` (as Ray sets it for a task with ``num_gpus``) choose, as for the CLI.

    ``region=(x0, y0, x1, y1)`` renders only columns x0..x1 and rows y0..y1 of the image
    (x1 and y1 excluded, from the top-left), as ``--region`` does: the array is
    (y1 - y0, x1 - x0, 4), each pixel bit for bit the full render's.

    ``guiding=True`` (nee and mis) is ``--guiding``: path guiding, a guide trained on
    ``guide_training_spp`` samples per pixel (default: about a million paths in all, at least
    4 per pixel, at most a quarter of ``spp``) before the render's ``spp``; the same seed
    gives the same bits as the command line.
    """
    return render_result(
        scene,
        width=width,
        height=height,
        spp=spp,
        integrator=integrator,
        seed=seed,
        sampler=sampler,
        light_sampling=light_sampling,
        light_selection=light_selection,
        pixel_filter=pixel_filter,
        accel=accel,
        max_path_length=max_path_length,
        samples_per_frame=samples_per_frame,
        russian_roulette_start=russian_roulette_start,
        environment=environment,
        environment_strength=environment_strength,
        environment_rotation=environment_rotation,
        background=background,
        time_limit=time_limit,
        progress=progress,
        device=device,
        validate=validate,
        region=region,
        guiding=guiding,
        guide_training_spp=guide_training_spp,
    ).image


ImageLike = Union[np.ndarray, RenderResult]


def _pixels(image: ImageLike) -> Dict[str, Any]:
    """The native module's dict for an array (H, W, 3 or 4) or a RenderResult."""
    moments: Tuple[Optional[np.ndarray], Optional[np.ndarray]] = (None, None)
    if isinstance(image, RenderResult):
        moments = (image.second_moment, image.sample_count)
        image = image.image
    array = np.asarray(image, dtype=np.float32)
    if array.ndim != 3 or array.shape[2] not in (3, 4):
        raise VkpathError(
            f"an image is an array of shape (height, width, 3 or 4), not {array.shape}"
        )
    height, width = array.shape[:2]
    if array.shape[2] == 3:
        array = np.concatenate([array, np.ones((height, width, 1), np.float32)], axis=2)
    pixels: Dict[str, Any] = {
        "width": width,
        "height": height,
        "mean": np.ascontiguousarray(array).tobytes(),
    }
    if moments[0] is not None and moments[1] is not None:
        pixels["second_moment"] = np.ascontiguousarray(moments[0], np.float32).tobytes()
        pixels["sample_count"] = np.ascontiguousarray(moments[1], np.float32).tobytes()
    return pixels


def save(
    image: ImageLike,
    path: PathLike,
    *,
    tonemap: Optional[str] = None,
    exposure: Union[None, float, str] = None,
    moments: bool = False,
) -> None:
    """Writes an image (an array of shape (H, W, 3 or 4), linear radiance, or a
    :class:`RenderResult`) as .exr (float32, untouched by tone mapping; ``moments=True``
    adds a RenderResult's second moment and sample count, for :func:`compare`) or .png
    (sRGB after ``exposure``, stops or "auto", default 0, and ``tonemap`` "agx", "aces" or
    "clamp", default the command line's for ``render``). Written to a temporary file and
    renamed into place, as the command line writes."""
    _vkpath.save(_pixels(image), os.fspath(path), tonemap=tonemap, exposure=exposure, moments=moments)


def read_exr(path: PathLike) -> np.ndarray:
    """Reads an EXR's R, G, B channels as linear RGBA float32, (H, W, 4), alpha 1."""
    raw = _vkpath.read_exr(os.fspath(path))
    return _array(raw["mean"], raw["height"], raw["width"], 4)


def compare(
    a: Union[ImageLike, PathLike],
    b: Union[ImageLike, PathLike],
    *,
    alpha: Optional[float] = None,
    block_size: Optional[int] = None,
) -> Dict[str, Any]:
    """Tests whether image ``a`` is an unbiased estimate of ``b`` (``vkpath compare``): a
    z-test per block and channel, Šidák-corrected at family-wise level ``alpha``. Each is an
    EXR path, an array or a :class:`RenderResult` (whose moments give the variances;
    without moments the noise is estimated within blocks). Returns the report as a dict;
    ``report["consistent"]`` is the verdict, ``report["relative_mse"]`` how far ``a`` is
    from ``b`` (mean of (a - b)^2 / (b^2 + 0.01), as ``vkpath bench`` measures error)."""

    def operand(value: Union[ImageLike, PathLike]) -> Any:
        if isinstance(value, (str, os.PathLike)):
            return os.fspath(value)
        return _pixels(value)

    options: Dict[str, Any] = {}
    if alpha is not None:
        options["alpha"] = float(alpha)
    if block_size is not None:
        options["block_size"] = int(block_size)
    return json.loads(_vkpath.compare(operand(a), operand(b), **options))


def check(
    path: PathLike,
    *,
    output_dir: Optional[PathLike] = None,
    spp: Optional[int] = None,
    size: Optional[int] = None,
    device: Optional[Union[int, str]] = None,
) -> Dict[str, Any]:
    """Judges your versions of the workshop's functions in a GLSL file (``vkpath check``)
    and returns its report as a dict (what ``vkpath check --json`` prints); ``report["passed"]``
    is the verdict. The render comparisons' images go to ``output_dir`` (default
    "vkpath-check")."""
    return json.loads(
        _vkpath.check(
            os.fspath(path),
            output_dir=None if output_dir is None else os.fspath(output_dir),
            spp=spp,
            size=size,
            device=None if device is None else str(device),
        )
    )
