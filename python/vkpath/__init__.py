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

import contextvars
import inspect
import json
import math
import numbers
import os
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Iterable, Iterator, Optional, Sequence, Tuple, Union

import numpy as np

from . import _vkpath
from ._vkpath import LIGHT_KEYS, MATERIAL_KEYS, Camera, Scene, VkpathError


class ArgumentError(VkpathError, ValueError):
    """An argument of the wrong shape, type or value (a ``ValueError``, and a
    :class:`VkpathError` like every vkpath error); the message names the parameter."""


__all__ = [
    "ArgumentError",
    "Camera",
    "LIGHT_KEYS",
    "MATERIAL_KEYS",
    "Medium",
    "RenderResult",
    "Scene",
    "VkpathError",
    "check",
    "compare",
    "cryptomatte_mask",
    "default_settings",
    "read_exr",
    "render",
    "render_frames",
    "render_result",
    "save",
]
__version__: str = _vkpath.__version__

PathLike = Union[str, "os.PathLike[str]"]
#: ``progress(spp_done, spp_total)``, called after each batch of samples (about every 250 ms);
#: returning ``False`` stops the render, raising stops it and propagates. A callback of three
#: parameters, ``progress(spp_done, spp_total, image_so_far)``, may call ``image_so_far()``
#: for the current estimate, (H, W, 4) (the render then reads its state back after every
#: batch).
ProgressCallback = Callable[..., Optional[bool]]


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
    #: The samples of every pixel's sequence taken, (start, end): (0, spp) for a whole
    #: render, a shard's range with ``sample_range=`` (what ``vkpath merge`` adds up).
    sample_range: Tuple[int, int]
    #: Why the render ended: "done", "time-limit" or "stopped" (the progress callback).
    stop: str
    #: Seconds the frames took (the kernel build and read-back excluded).
    seconds: float
    #: The Vulkan device's name.
    device: str
    #: The settings it was rendered with, by the command line's names.
    settings: Dict[str, Any]
    #: What ``aovs=`` asked for, by name ("albedo", "normal", "material", "position",
    #: "uv", "object_position", and "motion_forward" and "motion_backward" for "motion":
    #: (H, W, 3) float32; "depth", "z": (H, W) float32;
    #: "object_id", "instance_id", "material_id": (H, W) uint32, 0 where nothing is hit),
    #: and with ``denoise=True`` the image before denoising ("noisy", (H, W, 3)): the EXR
    #: layers ``--aov`` and ``--denoise`` write.
    #: With ``aovs=["cryptomatte"]``: the Cryptomatte layers "CryptoObject00", ...,
    #: "CryptoMaterial00", ... ((H, W, 4) float32: ID, coverage, ID, coverage, the IDs the
    #: float bits of the names' MurmurHash3, 6 ranks in 3 layers per kind).
    layers: Dict[str, np.ndarray] = field(default_factory=dict)
    #: With ``aovs=["cryptomatte"]``: each kind's manifest by type name ("CryptoObject",
    #: "CryptoMaterial"): name -> the ID's float bits as 8 hex digits, as the EXR header's
    #: ``cryptomatte/<key>/manifest``. :func:`cryptomatte_mask` makes a name's matte.
    cryptomatte: Dict[str, Dict[str, str]] = field(default_factory=dict)
    #: The camera as datasets take it (``render --json``'s ``camera_data``): "k" (3x3,
    #: pixels, OpenCV: the top-left pixel's centre at (0, 0)), "camera_to_world_opencv"
    #: (4x4, x right, y down, z forward), "camera_to_world_opengl" (4x4, x right, y up,
    #: z backward), "near", "far" (None: infinite), "fov_x_degrees", "fov_y_degrees",
    #: "sensor_width_mm", "sensor_height_mm", "focal_length_mm", "aperture_radius",
    #: "focus_distance", "width", "height"; matrices as numpy arrays.
    camera: Dict[str, Any] = field(default_factory=dict)


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


#: The open device `render_frames` renders its frames on (None: each render opens its own).
_SESSION: "contextvars.ContextVar[Optional[_vkpath.Session]]" = contextvars.ContextVar(
    "vkpath_session", default=None
)


def _whole(name: str, value: Any) -> Optional[int]:
    """``value`` as an int >= 0 (or None), else an ArgumentError naming ``name=``."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
        raise ArgumentError(f"{name}={value!r} is not a whole number >= 0")
    if value >= 2**32:
        raise ArgumentError(f"{name}={value!r} is larger than vkpath takes (below 2^32)")
    return int(value)


def _rgb(name: str, value: Optional[Sequence[float]]) -> Optional[Tuple[float, float, float]]:
    """``value`` as three floats (or None), else an ArgumentError naming ``name=``."""
    if value is None:
        return None
    try:
        rgb = tuple(float(c) for c in value)
    except (TypeError, ValueError):
        rgb = ()
    if isinstance(value, str) or len(rgb) != 3:
        raise ArgumentError(f"{name}={value!r} is not three numbers (R, G, B)")
    return rgb  # type: ignore[return-value]


_Coefficients = Union[float, Sequence[float]]


def _coefficient_text(name: str, value: Any) -> str:
    """A coefficient as ``--medium`` writes it: one number for all channels, or R,G,B."""
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return repr(float(value))
    try:
        rgb = [float(c) for c in value]
    except (TypeError, ValueError):
        rgb = []
    if isinstance(value, str) or len(rgb) != 3:
        raise ArgumentError(f"medium: {name}={value!r} is not a number or three numbers (R, G, B)")
    return ",".join(repr(c) for c in rgb)


@dataclass(frozen=True)
class Medium:
    """A homogeneous participating medium (fog, haze) that fills the space outside closed
    refracting volumes, the camera's included: ``vkpath render --medium`` (docs/media.md).

    ``sigma_a`` and ``sigma_s`` are the absorption and scattering coefficients per scene unit
    of length, linear RGB: one number for all three channels, or (R, G, B); each finite and
    at least 0. ``g`` is the Henyey-Greenstein anisotropy in (-1, 1): 0 isotropic, > 0
    forward scattering. The constructor checks them as the command line does (a bad value
    raises :class:`ArgumentError`, a ``ValueError``) and stores each coefficient as the
    renderer does: three float32 values, as Python floats. ``str(medium)`` is the command
    line's text, ``sigma_a=R,G,B:sigma_s=R,G,B:g=G``.

    >>> fog = vkpath.Medium(sigma_a=0.05, sigma_s=(0.5, 0.4, 0.3), g=0.6)
    >>> image = vkpath.render(integrator="mis", medium=fog)
    """

    sigma_a: _Coefficients = 0.0
    sigma_s: _Coefficients = 0.0
    g: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.g, bool) or not isinstance(self.g, numbers.Real):
            raise ArgumentError(f"medium: g={self.g!r} is not a number in (-1, 1)")
        text = (f"sigma_a={_coefficient_text('sigma_a', self.sigma_a)}"
                f":sigma_s={_coefficient_text('sigma_s', self.sigma_s)}:g={float(self.g)!r}")
        sigma_a, sigma_s, g = _vkpath.parse_medium(text)
        object.__setattr__(self, "sigma_a", tuple(sigma_a))
        object.__setattr__(self, "sigma_s", tuple(sigma_s))
        object.__setattr__(self, "g", g)

    @classmethod
    def parse(cls, text: str) -> "Medium":
        """The medium of ``--medium``'s text, ``"sigma_a=R,G,B:sigma_s=R,G,B:g=G"`` (parts in
        any order, a part left out 0); raises :class:`ArgumentError` where the command line
        would refuse it."""
        sigma_a, sigma_s, g = _vkpath.parse_medium(text)
        return cls(sigma_a=sigma_a, sigma_s=sigma_s, g=g)

    def __str__(self) -> str:
        return (f"sigma_a={_coefficient_text('sigma_a', self.sigma_a)}"
                f":sigma_s={_coefficient_text('sigma_s', self.sigma_s)}:g={float(self.g)!r}")


def _medium_of(medium: Union[None, str, Medium, Dict[str, Any]]) -> Optional[str]:
    """``medium=`` as the extension takes it: ``--medium``'s text (checked there)."""
    if medium is None:
        return None
    if isinstance(medium, Medium):
        return str(medium)
    if isinstance(medium, str):
        return str(Medium.parse(medium))
    if isinstance(medium, dict):
        unknown = sorted(set(medium) - {"sigma_a", "sigma_s", "g"})
        if unknown:
            raise ArgumentError(f"medium: {', '.join(map(str, unknown))} is not one of sigma_a, sigma_s, g")
        return str(Medium(**medium))
    raise ArgumentError(f"medium={medium!r} is not a vkpath.Medium, a dict of sigma_a, sigma_s "
                        "and g, or --medium's text")


def _device_of(device: Optional[Union[int, str]]) -> Optional[str]:
    """``device`` as the extension takes it; several devices are the command line's."""
    if device is None:
        return None
    text = str(_whole("device", device) if isinstance(device, (int, np.integer)) else device)
    if text.strip() == "all" or "," in text:
        raise ArgumentError(
            f"device={device!r}: rendering on several devices is the command line's "
            "(vkpath render --device all); from Python render one shard per device with "
            "sample_range= and device=INDEX"
        )
    return text


def _aov_names(aovs: Union[str, Sequence[str]]) -> list:
    """``aovs`` as a list of names (one name alone is a list of one)."""
    names = [aovs] if isinstance(aovs, str) else list(aovs)
    if not all(isinstance(name, str) for name in names):
        raise ArgumentError(f"aovs={aovs!r} is not a list of names (albedo, normal, depth, material)")
    return names


def _progress_of(progress: Optional[Callable[..., Optional[bool]]]) -> Tuple[Any, bool]:
    """The callback the extension calls, and whether it hands it the image so far: a
    ``progress`` of three (or more) positional parameters gets, as its third argument, a
    function of none that returns the current estimate (H, W, 4)."""
    if progress is None:
        return None, False
    try:
        parameters = inspect.signature(progress).parameters.values()
    except (TypeError, ValueError):
        return progress, False
    positional = [p for p in parameters
                  if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    if len(positional) < 3:
        return progress, False

    def call(done: int, total: int, so_far: Any) -> Optional[bool]:
        def image_so_far() -> np.ndarray:
            raw = so_far()
            return _array(raw["mean"], raw["height"], raw["width"], 4)

        return progress(done, total, image_so_far)

    return call, True


def _pixel_of(pixel: Sequence[int]) -> Tuple[int, int]:
    values = tuple(pixel)
    if len(values) != 2:
        raise ArgumentError(f"focus_at={pixel!r} is not a pixel (x, y)")
    x, y = (_whole("focus_at", value) for value in values)
    return x, y


def _sample_range_of(sample_range: Sequence[int]) -> Tuple[int, int]:
    """``sample_range`` as the two ints (start, end) the extension takes."""
    values = tuple(int(v) for v in sample_range)
    if len(values) != 2 or min(values) < 0:
        raise ArgumentError(
            f"sample_range={tuple(sample_range)!r} is not (start, end): two whole numbers >= 0"
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
    time: Optional[float] = None,
    sample_range: Optional[Tuple[int, int]] = None,
    noise_threshold: Optional[float] = None,
    noise_min_spp: Optional[int] = None,
    aovs: Sequence[str] = (),
    denoise: bool = False,
    focus_at: Optional[Sequence[int]] = None,
    fps: Optional[float] = None,
    shutter: Optional[float] = None,
    shutter_position: Optional[str] = None,
    motion_steps: Optional[int] = None,
    medium: Union[None, str, Medium, Dict[str, Any]] = None,
) -> RenderResult:
    """:func:`render`, returning the image with its moments, the samples taken and why the
    render stopped."""
    world = _scene_of(scene)
    callback, with_image = _progress_of(progress)
    raw = _vkpath.render(
        world,
        width=_whole("width", width),
        height=_whole("height", height),
        spp=_whole("spp", spp),
        seed=_whole("seed", seed),
        integrator=integrator,
        sampler=sampler,
        light_sampling=light_sampling,
        light_selection=light_selection,
        pixel_filter=pixel_filter,
        accel=accel,
        max_path_length=_whole("max_path_length", max_path_length),
        samples_per_frame=_whole("samples_per_frame", samples_per_frame),
        russian_roulette_start=_whole("russian_roulette_start", russian_roulette_start),
        environment_map=None if environment is None else os.fspath(environment),
        environment_strength=float(environment_strength),
        environment_rotation=float(environment_rotation),
        background=_rgb("background", background),
        time_limit=None if time_limit is None else float(time_limit),
        progress=callback,
        progress_image=with_image,
        session=_SESSION.get(),
        device=_device_of(device),
        validate=validate,
        region=None if region is None else _region_of(region),
        guiding=bool(guiding),
        guide_training_spp=_whole("guide_training_spp", guide_training_spp),
        time=None if time is None else float(time),
        sample_range=None if sample_range is None else _sample_range_of(sample_range),
        noise_threshold=None if noise_threshold is None else float(noise_threshold),
        noise_min_spp=_whole("noise_min_spp", noise_min_spp),
        aovs=_aov_names(aovs),
        denoise=bool(denoise),
        focus_at=None if focus_at is None else _pixel_of(focus_at),
        fps=None if fps is None else float(fps),
        shutter=None if shutter is None else float(shutter),
        shutter_position=shutter_position,
        motion_steps=_whole("motion_steps", motion_steps),
        medium=_medium_of(medium),
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
        sample_range=tuple(raw["sample_range"]),
        stop=raw["stop"],
        seconds=raw["seconds"],
        device=raw["device"],
        settings=dict(raw["settings"]),
        layers={name: _layer(name, pixels, h, w) for name, pixels in raw["layers"].items()},
        camera=_camera(raw["camera"]),
        cryptomatte={kind: json.loads(text) for kind, text in raw.get("cryptomatte", {}).items()},
    )


def cryptomatte_mask(result: "RenderResult", name: str, kind: str = "CryptoObject") -> np.ndarray:
    """The matte of ``name`` (an object's or material's, as ``result.cryptomatte[kind]``
    names it) from a render with ``aovs=["cryptomatte"]``: (H, W) float32, each pixel's
    coverage by that name (the sum over the ranks whose ID is the name's)."""
    bits = np.uint32(int(result.cryptomatte[kind][name], 16))
    mask = None
    index = 0
    while f"{kind}{index:02d}" in result.layers:
        layer = result.layers[f"{kind}{index:02d}"]
        for id_channel, coverage_channel in ((0, 1), (2, 3)):
            ids = np.ascontiguousarray(layer[..., id_channel]).view(np.uint32)
            part = np.where(ids == bits, layer[..., coverage_channel], np.float32(0))
            mask = part if mask is None else mask + part
        index += 1
    if mask is None:
        raise ValueError(f"the result has no {kind} layers: render with aovs=['cryptomatte']")
    return mask.astype(np.float32)


#: The layers with one channel, and of those the integer IDs (exact in the float layer).
_SINGLE_CHANNEL_LAYERS = ("depth", "z")
_ID_LAYERS = ("object_id", "instance_id", "material_id")


def _layer(name: str, pixels: Any, h: int, w: int) -> np.ndarray:
    """A layer's array: (H, W, 3) float32, (H, W) float32 for one channel, (H, W) uint32 IDs."""
    if name.startswith(("CryptoObject", "CryptoMaterial")):
        return _array(pixels, h, w, 4)
    array = _array(pixels, h, w, 3)
    if name in _ID_LAYERS:
        return array[..., 0].astype(np.uint32)
    if name in _SINGLE_CHANNEL_LAYERS:
        return array[..., 0]
    return array


def _camera(text: str) -> Dict[str, Any]:
    """The extension's camera data (JSON text) with its matrices as numpy arrays."""
    camera = json.loads(text)
    for key in ("k", "camera_to_world_opencv", "camera_to_world_opengl"):
        camera[key] = np.array(camera[key], dtype=np.float64)
    return camera


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
    time: Optional[float] = None,
    sample_range: Optional[Tuple[int, int]] = None,
    noise_threshold: Optional[float] = None,
    noise_min_spp: Optional[int] = None,
    aovs: Sequence[str] = (),
    denoise: bool = False,
    focus_at: Optional[Sequence[int]] = None,
    fps: Optional[float] = None,
    shutter: Optional[float] = None,
    shutter_position: Optional[str] = None,
    motion_steps: Optional[int] = None,
    medium: Union[None, str, Medium, Dict[str, Any]] = None,
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
    samples taken so far, raising stops it and re-raises. A callback with a third
    parameter, ``progress(spp_done, spp_total, image_so_far)``, may call
    ``image_so_far()`` for the estimate of those samples, (H, W, 4) (the state is then
    read back from the device after every batch, which costs time on large images). Ctrl-C stops it after the current
    batch and raises KeyboardInterrupt. ``time_limit`` (seconds) stops it and returns what it
    has: a finished render, which ``aovs=`` and ``denoise=`` still apply to. ``device`` is an index, a UUID (``GPU-...``, or a unique prefix) or part of a name, as
    ``vkpath devices`` lists them; without it, ``VKPATH_DEVICE`` and then
    ``CUDA_VISIBLE_DEVICES`` (as Ray sets it for a task with ``num_gpus``) choose, as for the CLI.

    ``region=(x0, y0, x1, y1)`` renders only columns x0..x1 and rows y0..y1 of the image
    (x1 and y1 excluded, from the top-left), as ``--region`` does: the array is
    (y1 - y0, x1 - x0, 4), each pixel bit for bit the full render's.

    ``time`` (seconds, default 0) is ``--time``: a glTF file's animations evaluated then
    (the scene file is loaded again at that time; other scenes do not move).
    ``sample_range=(start, end)`` is ``--sample-range``: only samples start..end of every
    pixel's sequence (``spp`` then has no effect), so that a scheduler can shard one
    render's samples over processes or machines; each shard is bit for bit the command
    line's, and :func:`render_result` gives what averaging them needs (``sample_count``).

    ``noise_threshold=T`` is ``--noise-threshold T`` (adaptive sampling: a pixel stops once
    its relative standard error is at most T, judged every ``noise_min_spp`` samples,
    default 16; ``spp`` is the cap). ``aovs=["albedo", "normal", "depth", "material"]`` is
    ``--aov`` (the arrays come in :func:`render_result`'s ``layers``; the ground truth's
    "object_id", "instance_id", "material_id" as uint32, "position", "uv",
    "object_position", "z" from the ray through each pixel's centre; "motion": the layers
    "motion_forward" and "motion_backward", (H, W, 3) float32 (du, dv, defined), where the
    pixel's surface point is seen one frame later and earlier, in pixels, x right, y down,
    frames 1 / ``fps`` apart (default 24), 0 where nothing moves), ``denoise=True`` is
    ``--denoise`` (Open Image Denoise with the albedo and normal; the image before is
    ``layers["noisy"]``); both after a render that took every sample or reached
    ``time_limit``, not after one the callback or Ctrl-C stopped.

    ``guiding=True`` (nee and mis) is ``--guiding``: path guiding, a guide trained on
    ``guide_training_spp`` samples per pixel (default: about a million paths in all, at least
    4 per pixel, at most a quarter of ``spp``) before the render's ``spp``; the same seed
    gives the same bits as the command line.

    ``focus_at=(x, y)`` is ``--focus-at X,Y``: the scene's camera, which must have a lens
    (``Camera(aperture_radius=...)`` or ``f_stop=``), focuses on what the ray through that
    pixel (column, row from the top) sees. A lens without ``focus_distance`` focuses on what
    the image's centre sees, as the command line's does.

    ``shutter=S`` is ``--shutter S`` (motion blur): the shutter stays open for S frame
    intervals (1 / ``fps`` each, default 24 fps; 0 to 2) around ``time``
    (``shutter_position`` "start", "center" or "end"), and each sample sees the scene
    (camera, node transforms, skins, morph targets) at a time within it; the scene is posed at
    ``motion_steps`` keys (2 to 64, default 2) across it and moves linearly between two.
    :func:`render_frames` takes it too. A scene that does not move across the shutter
    renders the still image, with a warning.

    ``medium`` is ``--medium``: a homogeneous participating medium (fog, haze) filling the
    space the camera is in, a :class:`Medium`, a dict of its keywords
    (``dict(sigma_a=0.05, sigma_s=0.5, g=0.6)``) or the command line's text
    (``"sigma_a=0.05:sigma_s=0.5:g=0.6"``); integrators "cosine", "nee" and "mis" render it.
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
        time=time,
        sample_range=sample_range,
        noise_threshold=noise_threshold,
        noise_min_spp=noise_min_spp,
        aovs=aovs,
        denoise=denoise,
        focus_at=focus_at,
        fps=fps,
        shutter=shutter,
        shutter_position=shutter_position,
        motion_steps=motion_steps,
        medium=medium,
    ).image


def render_frames(
    scene: Union[None, PathLike, Scene] = None,
    *,
    frames: Union[str, Iterable[int]] = range(1),
    fps: float = 24.0,
    **settings: Any,
) -> Iterator[Tuple[int, Any]]:
    """Renders frames of an animation, one after the other, yielding ``(frame, image)``:
    ``vkpath render --frames START..END --fps FPS``, frame f at time f / fps. ``frames``
    is any iterable of whole numbers at least 0 (``range(2, 5)``, a list), or the command
    line's ``"START..END"`` string (END excluded: ``"2..5"`` is frames 2, 3 and 4). ``settings``
    are :func:`render`'s (``time`` aside). The scene file is read once per frame at its
    time; the device (``device=``, ``validate=``) is opened once for all frames, as the
    command line does, and so are the kernels: each frame takes the kernel, the
    accumulation image and (while the scene's data do not change) the scene upload that
    the frame before it left, building only what changed. As the command line does, the
    sequence decides two things once, from the file: a file without a camera is framed by
    the bounding sphere of its whole animation (the same camera in every frame, where
    :func:`render` frames each time's pose), and where the animation moves geometry
    ``accel="auto"`` takes the BVH for every frame (not the constant triangles, whose
    kernel each frame would build again). With a camera, the images are bit for bit those
    of :func:`render` at each frame's time.

    With ``aovs=[...]`` (a dataset's ground truth), each frame yields ``(frame, outputs)``
    instead: a dict of numpy arrays, "image" (H, W, 4) and each layer of
    :class:`RenderResult`'s ``layers`` by name (the IDs as uint32; ``aovs=["motion"]``
    gives "motion_forward" and "motion_backward", the flow to frame + 1 and frame - 1 at
    ``fps``), and "camera", the frame's camera data (:class:`RenderResult`'s ``camera``)."""
    if "time" in settings:
        raise ArgumentError("render_frames takes frames= and fps=, not time=")
    frames = _frame_numbers(frames)
    fps = float(fps)
    if not (fps > 0.0 and math.isfinite(fps)):
        raise ArgumentError(f"fps={fps} is not a frame rate above 0")
    world = _scene_of(scene)
    device = _device_of(settings.pop("device", None))
    session = _vkpath.Session(device=device, validate=bool(settings.pop("validate", False)))
    with_layers = bool(settings.get("aovs"))
    for frame in frames:
        token = _SESSION.set(session)
        try:
            result = render_result(world, time=frame / fps, fps=fps, **settings)
        finally:
            _SESSION.reset(token)
        if with_layers:
            arrays = {"image": result.image, **result.layers, "camera": result.camera}
            if result.cryptomatte:
                arrays["cryptomatte"] = result.cryptomatte
            yield frame, arrays
        else:
            yield frame, result.image


def _frame_numbers(frames: Union[str, Iterable[int]]) -> Iterator[int]:
    """The frame numbers of ``frames``: whole numbers of at least 0, or the command line's
    ``"START..END"`` (END excluded, START < END); anything else raises ArgumentError."""
    if isinstance(frames, str):
        start, dots, end = frames.partition("..")
        try:
            first, last = int(start), int(end)
        except ValueError:
            first, last = 0, -1
        if not dots or not 0 <= first < last:
            raise ArgumentError(
                f"frames={frames!r} is not 'START..END' with 0 <= START < END (END excluded), "
                "nor frame numbers (e.g. range(0, 3))"
            )
        return iter(range(first, last))
    try:
        given = iter(frames)
    except TypeError:
        raise ArgumentError(
            f"frames={frames!r} is not frame numbers (e.g. range(0, 3) or '0..3')"
        ) from None

    def checked() -> Iterator[int]:
        for frame in given:
            if isinstance(frame, bool) or not isinstance(frame, numbers.Integral):
                raise ArgumentError(f"frames: {frame!r} is not a whole frame number")
            if frame < 0:
                raise ArgumentError(f"frames: frame {frame} is negative")
            yield int(frame)

    return checked()


ImageLike = Union[np.ndarray, RenderResult]


def _pixels(image: ImageLike) -> Dict[str, Any]:
    """The native module's dict for an array (H, W, 3 or 4) or a RenderResult."""
    moments: Tuple[Optional[np.ndarray], Optional[np.ndarray]] = (None, None)
    if isinstance(image, RenderResult):
        moments = (image.second_moment, image.sample_count)
        image = image.image
    given = np.asarray(image)
    if given.dtype.kind in "iub":
        raise ArgumentError(
            f"an image is linear radiance in floats, not {given.dtype} (an 8-bit image "
            "divided by 255 is still sRGB-encoded: decode it first)"
        )
    array = np.asarray(given, dtype=np.float32)
    if array.ndim != 3 or array.shape[2] not in (3, 4):
        raise VkpathError(
            f"an image is an array of shape (height, width, 3 or 4), not {array.shape}"
        )
    height, width = array.shape[:2]
    bad = ~np.isfinite(array[..., :3]).all(axis=-1)
    if bad.any():
        warnings.warn(
            f"{int(bad.sum())} pixels hold NaN or infinity; they are written as 0 (black)",
            stacklevel=3,
        )
        array = np.where(np.isfinite(array), array, np.float32(0.0))
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


def read_exr(path: PathLike, layers: bool = False) -> Union[np.ndarray, Dict[str, np.ndarray]]:
    """Reads an EXR's R, G, B channels as linear RGBA float32, (H, W, 4), alpha 1.

    With ``layers=True``, returns every layer of the file as a dict of arrays: "image"
    (R, G, B and A when present, (H, W, 4); alpha 1 when absent), and each other layer by
    its name, its channels in R, G, B (A) or X, Y, Z order, (H, W, channels), a layer of
    one channel (H, W): what ``--aov`` ("albedo", "normal", "depth", "material"),
    ``--denoise`` ("noisy"), ``--moments`` ("second_moment", "sample_count") and a shard's
    state ("state.sum", ...) write, by the names the file gives them."""
    if not layers:
        raw = _vkpath.read_exr(os.fspath(path))
        return _array(raw["mean"], raw["height"], raw["width"], 4)
    raw = _vkpath.read_exr_channels(os.fspath(path))
    height, width = raw["height"], raw["width"]
    groups: Dict[str, Dict[str, np.ndarray]] = {}
    for name, data in raw["channels"]:
        layer, _, channel = name.rpartition(".")
        groups.setdefault(layer, {})[channel] = _array(data, height, width, 1)
    order = "RGBAXYZ"
    result: Dict[str, np.ndarray] = {}
    for layer, channels in groups.items():
        names = sorted(channels, key=lambda c: (order.find(c) if c in order else 99, c))
        if layer == "" and all(c in channels for c in "RGB"):
            alpha = channels.get("A", np.ones((height, width), np.float32))
            result["image"] = np.stack([channels[c] for c in "RGB"] + [alpha], axis=-1)
            names = [c for c in names if c not in "RGBA"]
            for c in names:
                result[c] = channels[c]
            continue
        key = layer or "image"
        if len(names) == 1:
            result[key] = channels[names[0]]
        else:
            result[key] = np.stack([channels[c] for c in names], axis=-1)
    return result


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
