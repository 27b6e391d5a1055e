//! `vkpath.Scene` and `vkpath.Camera`: a loaded scene (the library's `Scene`) with the camera
//! a render uses, which Python may replace.

use std::path::PathBuf;
use std::sync::Mutex;

use glam::Vec3;
use pyo3::prelude::*;
use vkpath::camera::DEFAULT_VERTICAL_FOV_DEGREES;
use vkpath::lens_request::{Aperture, Focus, LensRequest, DEFAULT_SENSOR_WIDTH_MM};
use vkpath::scene::animation::AnimationPick;
use vkpath::scene::arrays::ARRAYS_DESCRIPTION;
use vkpath::scene::files::LoadOptions;
use vkpath::scene::gltf_file::{is_gltf_path, GltfFile};
use vkpath::scene::{framing_camera_of, SceneArrays, SceneError, SceneSource};

use crate::arrays::{
    float_rows, index_triples, material_factors, punctual_light, vec2s, vec3s, whole_number_list,
};
use crate::errors::{argument_error, message, to_py};

/// A camera: where it is and where it looks (world space), and its thin lens if any.
#[pyclass(module = "vkpath", frozen, from_py_object)]
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    /// The library's camera (its lens resolved where it needs no image: a radius and a
    /// focus distance).
    pub inner: vkpath::Camera,
    /// The thin lens asked for, resolved for each render's image (an f-number needs its
    /// aspect, autofocus its pixels); `None` for a pinhole.
    pub lens_request: Option<LensRequest>,
}

#[pymethods]
impl Camera {
    /// A camera at `position` looking at `look_at`, `up` giving the image's up direction
    /// (not parallel to the view direction) and `fov` the vertical field of view in degrees,
    /// in (0, 180): the command line's --camera-position, --look-at, --up and --fov. With an
    /// `aperture_radius` above 0 (world units) or an f-number `f_stop` (with `sensor_width`
    /// in millimetres across the image's longer side, as Blender takes it), a thin lens gives
    /// depth of field, focused at `focus_distance` (along the view axis) or, without one, on
    /// what the image's centre sees (or `render(focus_at=)`'s pixel); `blades` shapes its
    /// aperture (0: a disc, else a regular polygon of 3 or more corners, turned by
    /// `aperture_rotation` degrees): the command line's --aperture-radius, --f-stop,
    /// --sensor-width, --focus-distance, --aperture-blades and --aperture-rotation.
    #[new]
    #[pyo3(signature = (position, look_at, up = (0.0, 1.0, 0.0), fov = DEFAULT_VERTICAL_FOV_DEGREES,
        aperture_radius = 0.0, focus_distance = None, blades = 0, aperture_rotation = 0.0,
        f_stop = None, sensor_width = DEFAULT_SENSOR_WIDTH_MM),
        text_signature = "(position, look_at, up=(0.0, 1.0, 0.0), fov=45.0, aperture_radius=0.0, focus_distance=None, blades=0, aperture_rotation=0.0, f_stop=None, sensor_width=36.0)")]
    #[allow(clippy::too_many_arguments)]
    fn new(
        position: (f32, f32, f32),
        look_at: (f32, f32, f32),
        up: (f32, f32, f32),
        fov: f32,
        aperture_radius: f32,
        focus_distance: Option<f32>,
        blades: u32,
        aperture_rotation: f32,
        f_stop: Option<f32>,
        sensor_width: f32,
    ) -> PyResult<Camera> {
        let mut camera = Camera::pinhole(position, look_at, up, fov)?;
        let aperture = aperture(aperture_radius, f_stop, sensor_width)?;
        camera.lens_request = lens_request(aperture, focus_distance, blades, aperture_rotation)?;
        if let Some(lens) = camera.lens_request.and_then(|r| r.lens_without_image()) {
            camera.inner.lens = lens;
        }
        Ok(camera)
    }

    /// The thin lens's aperture radius, world units (0: a pinhole, or a lens given by
    /// `f_stop`, whose radius each render's image decides).
    #[getter]
    fn aperture_radius(&self) -> f32 {
        self.inner.lens.aperture_radius
    }

    /// The lens's f-number (None unless the lens was given by one).
    #[getter]
    fn f_stop(&self) -> Option<f32> {
        match self.lens_request?.aperture {
            Aperture::FStop { f_stop, .. } => Some(f_stop),
            Aperture::Radius(_) => None,
        }
    }

    /// The distance in focus along the view axis (None for a pinhole, or for a lens that
    /// focuses on what a pixel sees).
    #[getter]
    fn focus_distance(&self) -> Option<f32> {
        match self.lens_request?.focus {
            Focus::Distance(distance) => Some(distance),
            Focus::Pixel(_) | Focus::ImageCentre => None,
        }
    }

    /// The aperture's blades (0: a disc).
    #[getter]
    fn blades(&self) -> u32 {
        self.lens_request.map_or(0, |request| request.blades)
    }

    /// The pinhole, world space.
    #[getter]
    fn position(&self) -> (f32, f32, f32) {
        self.inner.position.into()
    }

    /// The unit direction the camera looks in (to the image's centre), world space.
    #[getter]
    fn direction(&self) -> (f32, f32, f32) {
        (self.inner.image_plane_middle - self.inner.position)
            .normalize()
            .into()
    }

    /// The unit direction that is up in the image, world space.
    #[getter]
    fn up(&self) -> (f32, f32, f32) {
        self.inner.up.normalize().into()
    }

    /// The vertical field of view in degrees.
    #[getter]
    fn fov(&self) -> f32 {
        let distance = (self.inner.image_plane_middle - self.inner.position).length();
        (2.0 * (0.5 * self.inner.up.length() / distance).atan()).to_degrees()
    }

    fn __repr__(&self) -> String {
        let (p, d) = (self.position(), self.direction());
        format!(
            "vkpath.Camera(position=({:.4}, {:.4}, {:.4}), direction=({:.4}, {:.4}, {:.4}), fov={:.3})",
            p.0,
            p.1,
            p.2,
            d.0,
            d.1,
            d.2,
            self.fov()
        )
    }
}

impl Camera {
    /// The pinhole camera of `Camera(position, look_at, up, fov)`, checked.
    fn pinhole(
        position: (f32, f32, f32),
        look_at: (f32, f32, f32),
        up: (f32, f32, f32),
        fov: f32,
    ) -> PyResult<Camera> {
        let [position, look_at, up] = [position, look_at, up].map(Vec3::from);
        if !(position.is_finite() && look_at.is_finite() && up.is_finite()) {
            return Err(argument_error(
                "the camera's position, look_at and up must be finite",
            ));
        }
        // Checked here to name Python's parameters (the library's message names the
        // command line's --fov, --look-at and --up).
        if !(fov > 0.0 && fov < 180.0) {
            return Err(argument_error(format!(
                "fov={fov} is outside (0, 180) degrees"
            )));
        }
        let inner = vkpath::Camera::look_at_checked(position, look_at, up, fov).map_err(|_| {
            argument_error(
                "position, look_at and up do not define a view (the view direction is zero or parallel to up)",
            )
        })?;
        Ok(Camera {
            inner,
            lens_request: None,
        })
    }
}

/// The aperture of `Camera(...)`'s `aperture_radius`, `f_stop` and `sensor_width`, checked.
fn aperture(aperture_radius: f32, f_stop: Option<f32>, sensor_width: f32) -> PyResult<Aperture> {
    if !(aperture_radius.is_finite() && aperture_radius >= 0.0) {
        return Err(argument_error(format!(
            "aperture_radius={aperture_radius} is not a finite number at or above 0"
        )));
    }
    let Some(f_stop) = f_stop else {
        return Ok(Aperture::Radius(aperture_radius));
    };
    if aperture_radius != 0.0 {
        return Err(argument_error(
            "aperture_radius= and f_stop= are two ways to give the aperture: give one",
        ));
    }
    for (name, value) in [("f_stop", f_stop), ("sensor_width", sensor_width)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(argument_error(format!(
                "{name}={value} is not a finite number above 0"
            )));
        }
    }
    Ok(Aperture::FStop {
        f_stop,
        sensor_width_mm: sensor_width,
    })
}

/// The thin lens of `Camera(...)`'s lens parameters, checked (`None`: a pinhole, an aperture
/// of radius 0). Without a focus distance the lens focuses on what the image's centre sees.
fn lens_request(
    aperture: Aperture,
    focus_distance: Option<f32>,
    blades: u32,
    aperture_rotation: f32,
) -> PyResult<Option<LensRequest>> {
    // (the lens's other parameters mean nothing to a pinhole)
    if aperture == Aperture::Radius(0.0) {
        return Ok(None);
    }
    let focus = match focus_distance {
        Some(distance) if !(distance.is_finite() && distance > 0.0) => {
            return Err(argument_error(format!(
                "focus_distance={distance} is not a finite number above 0"
            )))
        }
        Some(distance) => Focus::Distance(distance),
        None => Focus::ImageCentre,
    };
    if blades == 1 || blades == 2 || blades > 64 {
        return Err(argument_error(format!(
            "blades={blades} is not 0 (a disc) or 3 to 64"
        )));
    }
    if !aperture_rotation.is_finite() {
        return Err(argument_error("aperture_rotation must be finite"));
    }
    Ok(Some(LensRequest {
        aperture,
        focus,
        blades,
        rotation_degrees: aperture_rotation,
    }))
}

/// What a sequence of renders of a glTF file (`render_frames`) decides once, from the file
/// alone, as `vkpath render --frames` does.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SequenceFacts {
    /// Whether its geometry moves (`SequenceCache::moving_geometry`: `accel="auto"` keeps
    /// one traversal for every frame).
    pub moving_geometry: bool,
    /// For a file without a camera, the box of its whole animation
    /// (`GltfFile::animation_bounds`), which frames every frame.
    pub animation_box: Option<(Vec3, Vec3)>,
}

impl SequenceFacts {
    /// What `file`'s animations decide; its animation's box where it is `framed`.
    fn of(file: &mut GltfFile, framed: bool) -> Result<SequenceFacts, SceneError> {
        let pick = AnimationPick::All;
        Ok(SequenceFacts {
            moving_geometry: file.moves_geometry(&pick)?,
            animation_box: match framed {
                true => file.animation_bounds(&pick)?,
                false => None,
            },
        })
    }
}

/// A scene ready to render: triangles, materials, lights, and the camera renders use.
#[pyclass(module = "vkpath")]
pub struct Scene {
    /// The library's scene.
    pub inner: vkpath::Scene,
    /// The camera renders use in place of the scene's own, if one was chosen.
    pub camera: Option<vkpath::Camera>,
    /// That camera's thin lens, resolved for each render's image (`Camera::lens_request`).
    pub lens_request: Option<LensRequest>,
    /// What reports call the scene (its path, "workshop Cornell box", ...).
    pub description: String,
    /// Where it came from and whether it may read outside its folder, to load it again at
    /// another time (`render(time=)`); `None` for a scene from arrays.
    pub source: Option<(SceneSource, bool)>,
    /// The file's camera chosen by `use_camera`, by index: at another time its animated
    /// place.
    pub camera_index: Option<usize>,
    /// A glTF file read once for the renders at other times (`at_time`, e.g. each frame of
    /// `render_frames`), opened by the first of them and posed by each.
    pub file: Mutex<Option<GltfFile>>,
    /// The file's material variant renders take (`KHR_materials_variants`), by name.
    pub variant: Option<String>,
    /// The file's material variants, by name.
    pub variants: Vec<String>,
}

impl Scene {
    /// Loads `source` as the command line does (`SceneArgs::load`), errors and all.
    fn from_source(
        source: SceneSource,
        allow_external_paths: bool,
        variant: Option<String>,
    ) -> PyResult<Scene> {
        let options = LoadOptions {
            allow_external_paths,
            variant: variant.clone(),
            ..LoadOptions::default()
        };
        // A glTF file is read once for its scene and its variants' names (what
        // `Scene::load_with` does for it: open, then pose at the options' time).
        let (inner, variants) = match &source {
            SceneSource::File(path) if is_gltf_path(path) => {
                let mut file = GltfFile::open(path, &options).map_err(to_py)?;
                let scene = file.pose(options.time, &options.animation).map_err(to_py)?;
                (scene, file.variant_names())
            }
            _ => (source.load_with(&options).map_err(to_py)?, Vec::new()),
        };
        Ok(Scene {
            inner,
            camera: None,
            lens_request: None,
            description: source.description(),
            source: Some((source, allow_external_paths)),
            camera_index: None,
            file: Mutex::new(None),
            variant,
            variants,
        })
    }

    /// Whether the scene is a glTF file with animations (the only scenes that move with
    /// `time=`); opens the file that `at_time` poses if no render has yet.
    pub fn is_animated(&self) -> PyResult<bool> {
        Ok(self
            .with_gltf_file(|file| Ok(file.has_animations()))?
            .unwrap_or(false))
    }

    /// `use_file` with the scene's glTF file, read once by the first call and kept for the
    /// renders at other times; `None` where the scene is not a glTF file.
    fn with_gltf_file<R>(
        &self,
        use_file: impl FnOnce(&mut GltfFile) -> PyResult<R>,
    ) -> PyResult<Option<R>> {
        let Some((SceneSource::File(path), allow_external_paths)) = &self.source else {
            return Ok(None);
        };
        if !is_gltf_path(path) {
            return Ok(None);
        }
        let options = LoadOptions {
            allow_external_paths: *allow_external_paths,
            variant: self.variant.clone(),
            ..LoadOptions::default()
        };
        // A render that panicked holding the lock left the file as it was.
        let mut file = self.file.lock().unwrap_or_else(|e| e.into_inner());
        let file = match &mut *file {
            Some(file) => file,
            None => file.insert(GltfFile::open(path, &options).map_err(to_py)?),
        };
        use_file(file).map(Some)
    }

    /// The scene at `time` seconds (a glTF file's animations then, as `--time` loads it)
    /// with the camera renders use then: the file's camera of `use_camera`'s index at that
    /// time, else `render_camera`'s choice. Without a time, or for a scene that has no file,
    /// the scene as it is. For a frame of a sequence (`sequence`: `render_frames`'
    /// session), what the sequence decides once is decided by its first frame and kept
    /// there: whether the geometry moves, and for a file without a camera the box of its
    /// whole animation, which frames every frame (as `vkpath render --frames` does).
    pub fn at_time(
        &self,
        time: Option<f64>,
        aspect: f32,
        sequence: Option<&Mutex<Option<SequenceFacts>>>,
    ) -> PyResult<(vkpath::Scene, vkpath::Camera)> {
        let Some(time) = time else {
            return Ok((self.inner.clone(), self.render_camera(aspect)?));
        };
        if !(time.is_finite() && time >= 0.0) {
            return Err(argument_error(format!(
                "time={time} is not a time in seconds at or after 0"
            )));
        }
        let posed = self.with_gltf_file(|file| {
            let scene = file.pose(time as f32, &AnimationPick::All).map_err(to_py)?;
            let Some(sequence) = sequence else {
                return Ok((scene, None));
            };
            let mut kept = sequence.lock().unwrap_or_else(|e| e.into_inner());
            if kept.is_none() {
                let framed =
                    self.camera_index.is_none() && self.camera.is_none() && scene.camera.is_none();
                *kept = Some(SequenceFacts::of(file, framed).map_err(to_py)?);
            }
            Ok((scene, *kept))
        })?;
        let (reloaded, facts) = match (posed, &self.source) {
            (Some((scene, facts)), _) => (Some(scene), facts),
            (None, Some((source @ SceneSource::File(_), allow_external_paths))) => {
                let options = LoadOptions {
                    allow_external_paths: *allow_external_paths,
                    time: time as f32,
                    variant: self.variant.clone(),
                    ..LoadOptions::default()
                };
                (Some(source.load_with(&options).map_err(to_py)?), None)
            }
            (None, _) => (None, None),
        };
        let Some(scene) = reloaded else {
            return Ok((self.inner.clone(), self.render_camera(aspect)?));
        };
        let camera = match self.camera_index {
            Some(index) => scene.cameras.get(index).copied(),
            None => self.camera.or(scene.camera),
        };
        let animation_box = facts.and_then(|f| f.animation_box);
        let camera = match (camera, animation_box) {
            (Some(camera), _) => camera,
            (None, Some((low, high))) => framing_camera_of(low, high, aspect).0,
            (None, None) => scene
                .framing_camera(aspect)
                .map(|(camera, _, _)| camera)
                .ok_or_else(|| message("the scene has no camera and nothing to frame"))?,
        };
        Ok((scene, camera))
    }

    /// The camera a render of `aspect` (width / height) uses: the chosen one, else the
    /// scene's, else one that frames the scene, as `vkpath render` frames a file without a
    /// camera.
    pub fn render_camera(&self, aspect: f32) -> PyResult<vkpath::Camera> {
        if let Some(camera) = self.camera.or(self.inner.camera) {
            return Ok(camera);
        }
        self.inner
            .framing_camera(aspect)
            .map(|(camera, _, _)| camera)
            .ok_or_else(|| message("the scene has no camera and nothing to frame"))
    }
}

#[pymethods]
impl Scene {
    /// Loads a scene file (.gltf, .glb or .obj). A glTF file may read buffers outside its
    /// own folder only with `allow_external_paths`; `variant` names its material variant
    /// (KHR_materials_variants, `Scene.variants`), as `--variant` does.
    #[staticmethod]
    #[pyo3(signature = (path, allow_external_paths = false, variant = None))]
    fn load(path: PathBuf, allow_external_paths: bool, variant: Option<String>) -> PyResult<Scene> {
        Scene::from_source(SceneSource::File(path), allow_external_paths, variant)
    }

    /// The glTF file's material variants (KHR_materials_variants), by name, in file order.
    #[getter]
    fn variants(&self) -> Vec<String> {
        self.variants.clone()
    }

    /// The material variant renders take (None: each primitive's own material).
    #[getter]
    fn variant(&self) -> Option<String> {
        self.variant.clone()
    }

    /// A scene from arrays, as `mi.load_dict` users build one: `positions` (N, 3) and
    /// `indices` (M, 3) or flat, numpy arrays or anything `numpy.asarray` takes;
    /// `materials` a list of dicts of glTF's factors by snake-case names (see
    /// `vkpath.MATERIAL_KEYS`; glTF's defaults for what a dict leaves out, glTF's default
    /// material when the list is empty); `material_indices` (M,) the material of each
    /// triangle (without it every triangle takes material 0); `normals` (N, 3) and `uvs`
    /// (N, 2) per vertex; `camera` a `Camera` (without one a render frames the scene);
    /// `lights` a list of dicts of KHR_lights_punctual's values (`vkpath.LIGHT_KEYS`).
    /// The same data written as a glTF file (one mesh, a primitive per material in order,
    /// on one node without a transform) renders bit for bit the same.
    #[staticmethod]
    #[pyo3(signature = (positions, indices, materials = None, material_indices = None,
        normals = None, uvs = None, camera = None, lights = None))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        positions: &Bound<'_, PyAny>,
        indices: &Bound<'_, PyAny>,
        materials: Option<Vec<Bound<'_, PyAny>>>,
        material_indices: Option<&Bound<'_, PyAny>>,
        normals: Option<&Bound<'_, PyAny>>,
        uvs: Option<&Bound<'_, PyAny>>,
        camera: Option<Camera>,
        lights: Option<Vec<Bound<'_, PyAny>>>,
    ) -> PyResult<Scene> {
        let positions = vec3s(&float_rows(positions, "positions", 3)?);
        let triangles = index_triples(indices, "indices")?;
        let materials = materials
            .unwrap_or_default()
            .iter()
            .enumerate()
            .map(|(i, m)| material_factors(m, i))
            .collect::<PyResult<Vec<_>>>()?;
        let material_indices = material_indices
            .map(|m| whole_number_list(m, "material_indices"))
            .transpose()?;
        let normals = normals
            .map(|n| float_rows(n, "normals", 3).map(|f| vec3s(&f)))
            .transpose()?;
        let tex_coords = uvs
            .map(|uv| float_rows(uv, "uvs", 2).map(|f| vec2s(&f)))
            .transpose()?;
        let punctual_lights = lights
            .unwrap_or_default()
            .iter()
            .enumerate()
            .map(|(i, l)| punctual_light(l, i))
            .collect::<PyResult<Vec<_>>>()?;
        let inner = vkpath::Scene::from_arrays(&SceneArrays {
            positions: &positions,
            triangles: &triangles,
            materials: &materials,
            material_indices: material_indices.as_deref(),
            normals: normals.as_deref(),
            tex_coords: tex_coords.as_deref(),
            punctual_lights,
            camera: camera.map(|c| c.inner),
        })
        .map_err(|error| match error {
            // The arrays' own mistakes are the caller's arguments.
            SceneError::Arrays(reason) => argument_error(reason),
            other => to_py(other),
        })?;
        Ok(Scene {
            inner,
            camera: None,
            // (the arrays' camera is the scene's own; its lens is kept for its renders)
            lens_request: camera.and_then(|c| c.lens_request),
            description: ARRAYS_DESCRIPTION.to_owned(),
            source: None,
            camera_index: None,
            file: Mutex::new(None),
            variant: None,
            variants: Vec::new(),
        })
    }

    /// The workshop's Cornell box (the command line's scene when none is given).
    #[staticmethod]
    fn cornell_box() -> PyResult<Scene> {
        Scene::from_source(SceneSource::CornellBox, false, None)
    }

    /// The generated scale-test scene (the Cornell box with an icosphere and a displaced
    /// grid) of about `triangles` triangles: the command line's --generated.
    #[staticmethod]
    fn generated(triangles: usize) -> PyResult<Scene> {
        Scene::from_source(SceneSource::Generated(triangles), false, None)
    }

    /// The camera renders use: the one set here, else the scene's own; `None` when the
    /// scene has none (a render then frames the scene, as the command line does).
    #[getter]
    fn get_camera(&self) -> Option<Camera> {
        match self.camera {
            Some(inner) => Some(Camera {
                inner,
                lens_request: self.lens_request,
            }),
            None => self.inner.camera.map(|inner| Camera {
                inner,
                lens_request: None,
            }),
        }
    }

    /// Sets the camera renders use; `None` goes back to the scene's own.
    #[setter]
    fn set_camera(&mut self, camera: Option<Camera>) {
        self.camera_index = None;
        self.camera = camera.map(|c| c.inner);
        self.lens_request = camera.and_then(|c| c.lens_request);
    }

    /// The file's perspective cameras, in the order of its nodes (the command line's
    /// --camera N picks the N-th).
    #[getter]
    fn cameras(&self) -> Vec<Camera> {
        self.inner
            .cameras
            .iter()
            .map(|&inner| Camera {
                inner,
                lens_request: None,
            })
            .collect()
    }

    /// Renders through the file's `index`-th perspective camera (from 0): --camera N.
    fn use_camera(&mut self, index: usize) -> PyResult<()> {
        let camera = self.inner.cameras.get(index).copied().ok_or_else(|| {
            message(format!(
                "camera {index}: the scene has {} perspective camera(s), numbered from 0",
                self.inner.cameras.len()
            ))
        })?;
        self.camera = Some(camera);
        self.camera_index = Some(index);
        self.lens_request = None;
        Ok(())
    }

    /// Renders from `position` looking at `look_at` (see `Camera`).
    #[pyo3(signature = (position, look_at, up = (0.0, 1.0, 0.0), fov = DEFAULT_VERTICAL_FOV_DEGREES),
        text_signature = "($self, position, look_at, up=(0.0, 1.0, 0.0), fov=45.0)")]
    fn look_at(
        &mut self,
        position: (f32, f32, f32),
        look_at: (f32, f32, f32),
        up: (f32, f32, f32),
        fov: f32,
    ) -> PyResult<()> {
        self.camera = Some(Camera::pinhole(position, look_at, up, fov)?.inner);
        self.camera_index = None;
        self.lens_request = None;
        Ok(())
    }

    /// Number of triangles (degenerate ones were dropped when loading).
    #[getter]
    fn triangle_count(&self) -> usize {
        self.inner.triangles.len()
    }

    /// Number of punctual lights (glTF KHR_lights_punctual); only "nee" and "mis" see them.
    #[getter]
    fn punctual_light_count(&self) -> usize {
        self.inner.punctual_lights.len()
    }

    /// What the loader ignored that you should know about (the command line prints these
    /// as warnings).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// What reports call the scene: its path, or "workshop Cornell box".
    #[getter]
    fn description(&self) -> String {
        self.description.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "<vkpath.Scene {}: {} triangles>",
            self.description,
            self.inner.triangles.len()
        )
    }
}
