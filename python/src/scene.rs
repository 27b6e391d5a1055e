//! `vkpath.Scene` and `vkpath.Camera`: a loaded scene (the library's `Scene`) with the camera
//! a render uses, which Python may replace.

use std::path::PathBuf;

use glam::Vec3;
use pyo3::prelude::*;
use vkpath::camera::DEFAULT_VERTICAL_FOV_DEGREES;
use vkpath::scene::files::LoadOptions;
use vkpath::scene::SceneSource;

use crate::errors::{message, to_py};

/// A pinhole camera: where it is and where it looks (world space).
#[pyclass(module = "vkpath", frozen, from_py_object)]
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    /// The library's camera.
    pub inner: vkpath::Camera,
}

#[pymethods]
impl Camera {
    /// A camera at `position` looking at `look_at`, `up` giving the image's up direction
    /// (not parallel to the view direction) and `fov` the vertical field of view in degrees,
    /// in (0, 180): the command line's --camera-position, --look-at, --up and --fov.
    #[new]
    #[pyo3(signature = (position, look_at, up = (0.0, 1.0, 0.0), fov = DEFAULT_VERTICAL_FOV_DEGREES))]
    fn new(
        position: (f32, f32, f32),
        look_at: (f32, f32, f32),
        up: (f32, f32, f32),
        fov: f32,
    ) -> PyResult<Camera> {
        let [position, look_at, up] = [position, look_at, up].map(Vec3::from);
        if !(position.is_finite() && look_at.is_finite() && up.is_finite()) {
            return Err(message(
                "the camera's position, look_at and up must be finite",
            ));
        }
        let inner = vkpath::Camera::look_at_checked(position, look_at, up, fov).map_err(to_py)?;
        Ok(Camera { inner })
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

/// A scene ready to render: triangles, materials, lights, and the camera renders use.
#[pyclass(module = "vkpath")]
pub struct Scene {
    /// The library's scene.
    pub inner: vkpath::Scene,
    /// The camera renders use in place of the scene's own, if one was chosen.
    pub camera: Option<vkpath::Camera>,
    /// What reports call the scene (its path, "workshop Cornell box", ...).
    pub description: String,
}

impl Scene {
    /// Loads `source` as the command line does (`SceneArgs::load`), errors and all.
    fn from_source(source: SceneSource, allow_external_paths: bool) -> PyResult<Scene> {
        let inner = source
            .load_with(&LoadOptions {
                allow_external_paths,
                ..LoadOptions::default()
            })
            .map_err(to_py)?;
        Ok(Scene {
            inner,
            camera: None,
            description: source.description(),
        })
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
    /// own folder only with `allow_external_paths`.
    #[staticmethod]
    #[pyo3(signature = (path, allow_external_paths = false))]
    fn load(path: PathBuf, allow_external_paths: bool) -> PyResult<Scene> {
        Scene::from_source(SceneSource::File(path), allow_external_paths)
    }

    /// The workshop's Cornell box (the command line's scene when none is given).
    #[staticmethod]
    fn cornell_box() -> PyResult<Scene> {
        Scene::from_source(SceneSource::CornellBox, false)
    }

    /// The generated scale-test scene (the Cornell box with an icosphere and a displaced
    /// grid) of about `triangles` triangles: the command line's --generated.
    #[staticmethod]
    fn generated(triangles: usize) -> PyResult<Scene> {
        Scene::from_source(SceneSource::Generated(triangles), false)
    }

    /// The camera renders use: the one set here, else the scene's own; `None` when the
    /// scene has none (a render then frames the scene, as the command line does).
    #[getter]
    fn get_camera(&self) -> Option<Camera> {
        self.camera
            .or(self.inner.camera)
            .map(|inner| Camera { inner })
    }

    /// Sets the camera renders use; `None` goes back to the scene's own.
    #[setter]
    fn set_camera(&mut self, camera: Option<Camera>) {
        self.camera = camera.map(|c| c.inner);
    }

    /// The file's perspective cameras, in the order of its nodes (the command line's
    /// --camera N picks the N-th).
    #[getter]
    fn cameras(&self) -> Vec<Camera> {
        self.inner
            .cameras
            .iter()
            .map(|&inner| Camera { inner })
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
        Ok(())
    }

    /// Renders from `position` looking at `look_at` (see `Camera`).
    #[pyo3(signature = (position, look_at, up = (0.0, 1.0, 0.0), fov = DEFAULT_VERTICAL_FOV_DEGREES))]
    fn look_at(
        &mut self,
        position: (f32, f32, f32),
        look_at: (f32, f32, f32),
        up: (f32, f32, f32),
        fov: f32,
    ) -> PyResult<()> {
        self.camera = Some(Camera::new(position, look_at, up, fov)?.inner);
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
