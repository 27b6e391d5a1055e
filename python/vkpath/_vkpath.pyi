"""Type stubs of vkpath's native module (``vkpath._vkpath``). ``Camera``, ``Scene`` and
``VkpathError`` are re-exported by ``vkpath``; the functions here take and return the raw
dicts that ``vkpath/__init__.py`` turns into numpy arrays and reports."""

from typing import Any, Callable, Dict, List, Optional, Tuple, Union
import os

__version__: str

_Vec3 = Tuple[float, float, float]
_Path = Union[str, "os.PathLike[str]"]

class VkpathError(RuntimeError):
    """What went wrong in vkpath, in the one line the command line prints after
    ``vkpath: error: ``."""

#: The keys of ``Scene.from_arrays``'s material dicts: glTF's factors in snake case.
MATERIAL_KEYS: List[str]
#: The keys of ``Scene.from_arrays``'s light dicts (KHR_lights_punctual's).
LIGHT_KEYS: List[str]

class Camera:
    """A camera (world space): a pinhole, or a thin lens for depth of field."""

    def __init__(
        self,
        position: _Vec3,
        look_at: _Vec3,
        up: _Vec3 = (0.0, 1.0, 0.0),
        fov: float = 45.0,
        aperture_radius: float = 0.0,
        focus_distance: Optional[float] = None,
        blades: int = 0,
        aperture_rotation: float = 0.0,
        f_stop: Optional[float] = None,
        sensor_width: float = 36.0,
    ) -> None:
        """A camera at ``position`` looking at ``look_at``; ``up`` is the image's up direction
        (not parallel to the view), ``fov`` the vertical field of view in degrees, in (0, 180).
        Depth of field: a thin lens of ``aperture_radius`` (world units; 0 is a pinhole), or
        of f-number ``f_stop`` with a ``sensor_width`` (mm) across the image's longer side,
        focused at ``focus_distance`` along the view axis (without one, on what the image's
        centre or ``render(focus_at=)``'s pixel sees), its aperture a disc (``blades`` 0)
        or a regular polygon of 3 to 64 corners turned by ``aperture_rotation`` degrees.
        Raises VkpathError for a field of view out of range, no view direction, or a lens
        with bad values."""
    @property
    def aperture_radius(self) -> float:
        """The thin lens's aperture radius (0: a pinhole, or a lens given by ``f_stop``)."""
    @property
    def f_stop(self) -> Optional[float]:
        """The lens's f-number (None unless given by one)."""
    @property
    def focus_distance(self) -> Optional[float]:
        """The distance in focus along the view axis (None for a pinhole or autofocus)."""
    @property
    def blades(self) -> int:
        """The aperture's blades (0: a disc)."""
    @property
    def position(self) -> _Vec3:
        """The pinhole."""
    @property
    def direction(self) -> _Vec3:
        """The unit direction to the image's centre."""
    @property
    def up(self) -> _Vec3:
        """The unit direction that is up in the image."""
    @property
    def fov(self) -> float:
        """The vertical field of view in degrees."""

class Scene:
    """A scene ready to render: triangles, materials, lights and the camera renders use."""

    @staticmethod
    def load(
        path: _Path, allow_external_paths: bool = False, variant: Optional[str] = None
    ) -> "Scene":
        """Loads a .gltf, .glb or .obj file; a glTF may read buffers outside its folder only
        with ``allow_external_paths``; ``variant`` picks a material variant
        (KHR_materials_variants, ``--variant``). Raises VkpathError with the command line's
        message (an unknown variant's lists the file's)."""
    @property
    def variants(self) -> List[str]:
        """The glTF file's material variants, by name, in file order."""
    @property
    def variant(self) -> Optional[str]:
        """The material variant renders take (None: each primitive's own material)."""
    @staticmethod
    def from_arrays(
        positions: Any,
        indices: Any,
        materials: Optional[List[Dict[str, Any]]] = None,
        material_indices: Any = None,
        normals: Any = None,
        uvs: Any = None,
        camera: Optional[Camera] = None,
        lights: Optional[List[Dict[str, Any]]] = None,
    ) -> "Scene":
        """A scene from numpy arrays, as ``mi.load_dict`` users build one: ``positions``
        (N, 3), ``indices`` (M, 3) or flat; ``materials`` dicts of glTF's factors
        (``MATERIAL_KEYS``: base_color, metallic, roughness, emission, emissive_strength,
        specular, specular_color, ior, transmission, thickness, attenuation_color,
        attenuation_distance, multiscatter_color, scatter_anisotropy, clearcoat,
        clearcoat_roughness, sheen_color, sheen_roughness,
        alpha_mode, alpha_cutoff, double_sided, unlit; glTF's defaults for the rest, glTF's
        default material, white metal, without any); ``material_indices`` (M,) the
        material of each triangle (default: material 0 for all); ``normals`` (N, 3) and
        ``uvs`` (N, 2) per vertex; ``camera`` (default: renders frame the scene);
        ``lights`` dicts of KHR_lights_punctual's values (``LIGHT_KEYS``: type "point",
        "spot" or "directional", color, intensity, position, direction, inner_cone_angle,
        outer_cone_angle). Colours and vectors are any sequence of numbers (a tuple, a list,
        a numpy array). Renders bit for bit as the same data written as a glTF file.
        A wrong shape, type or key, or a negative colour factor or emissive_strength,
        raises ArgumentError (a ValueError) naming it."""
    @staticmethod
    def cornell_box() -> "Scene":
        """The workshop's Cornell box (the command line's scene when none is given)."""
    @staticmethod
    def generated(triangles: int) -> "Scene":
        """The scale-test scene of about ``triangles`` triangles (``--generated``)."""
    @property
    def camera(self) -> Optional[Camera]:
        """The camera renders use: the one set here, else the scene's; ``None`` when the
        scene has none (a render then frames the scene, as the command line does)."""
    @camera.setter
    def camera(self, camera: Optional[Camera]) -> None: ...
    @property
    def cameras(self) -> List[Camera]:
        """The file's perspective cameras, in node order (``--camera N``)."""
    def use_camera(self, index: int) -> None:
        """Renders through the file's ``index``-th camera (from 0)."""
    def look_at(
        self, position: _Vec3, look_at: _Vec3, up: _Vec3 = (0.0, 1.0, 0.0), fov: float = 45.0
    ) -> None:
        """Renders from ``position`` looking at ``look_at`` (see :class:`Camera`)."""
    @property
    def triangle_count(self) -> int:
        """Number of triangles."""
    @property
    def punctual_light_count(self) -> int:
        """Number of glTF punctual lights (only "nee" and "mis" see them)."""
    @property
    def warnings(self) -> List[str]:
        """What the loader ignored that you should know about."""
    @property
    def description(self) -> str:
        """Its path, or "workshop Cornell box"."""

def default_settings() -> Dict[str, Any]: ...
def render(
    scene: Scene,
    *,
    width: Optional[int] = None,
    height: Optional[int] = None,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    integrator: Optional[str] = None,
    sampler: Optional[str] = None,
    light_sampling: Optional[str] = None,
    light_selection: Optional[str] = None,
    pixel_filter: Optional[str] = None,
    accel: Optional[str] = None,
    max_path_length: Optional[int] = None,
    samples_per_frame: Optional[int] = None,
    russian_roulette_start: Optional[int] = None,
    environment_map: Optional[str] = None,
    environment_strength: float = 1.0,
    environment_rotation: float = 0.0,
    background: Optional[_Vec3] = None,
    time_limit: Optional[float] = None,
    progress: Optional[Callable[[int, int], Optional[bool]]] = None,
    device: Optional[str] = None,
    validate: bool = False,
    region: Optional[Tuple[int, int, int, int]] = None,
    guiding: bool = False,
    guide_training_spp: Optional[int] = None,
    time: Optional[float] = None,
    sample_range: Optional[Tuple[int, int]] = None,
    noise_threshold: Optional[float] = None,
    noise_min_spp: Optional[int] = None,
    aovs: Optional[List[str]] = None,
    denoise: bool = False,
    progress_image: bool = False,
    session: Optional["Session"] = None,
    focus_at: Optional[Tuple[int, int]] = None,
    fps: Optional[float] = None,
    shutter: Optional[float] = None,
    shutter_position: Optional[str] = None,
    motion_steps: Optional[int] = None,
    medium: Optional[str] = None,
) -> Dict[str, Any]: ...
def parse_medium(text: str) -> Tuple[Tuple[float, float, float], Tuple[float, float, float], float]:
    """``--medium``'s text read and checked: (sigma_a, sigma_s, g) as float32 values."""

class Session:
    """A device kept open for several renders (``render_frames`` uses one)."""

    def __init__(self, device: Optional[str] = None, validate: bool = False) -> None: ...
def save(
    pixels: Dict[str, Any],
    path: str,
    *,
    tonemap: Optional[str] = None,
    exposure: Union[None, float, str] = None,
    moments: bool = False,
) -> None: ...
def read_exr(path: str) -> Dict[str, Any]: ...
def read_exr_channels(path: str) -> Dict[str, Any]: ...
def compare(
    a: Union[str, Dict[str, Any]], b: Union[str, Dict[str, Any]], *, alpha: float = ..., block_size: int = ...
) -> str: ...
def check(
    path: str,
    *,
    output_dir: Optional[str] = None,
    spp: Optional[int] = None,
    size: Optional[int] = None,
    device: Optional[str] = None,
) -> str: ...
