//! Scenes: triangles with the workshop's diffuse material and an optional camera, loaded
//! from the built-in Cornell box, glTF 2.0 or OBJ + MTL.

use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::camera::Camera;
use crate::lights::{Environment, EnvironmentSource, PunctualLight};

pub mod animation;
pub mod arrays;
pub mod cornell;
pub(crate) mod error;
pub mod export;
pub mod files;
mod gltf_animation;
mod gltf_deform;
mod gltf_extensions;
pub mod gltf_file;
mod gltf_instancing;
pub mod gltf_loader;
mod gltf_materials;
mod gltf_spec_gloss;
mod gltf_variants;
pub mod instances;
pub mod material_factors;
pub mod material_params;
pub mod materials;
pub mod meshes;
pub mod morph_targets;
pub mod motion;
pub mod obj_loader;
mod obj_materials;
pub mod procedural;
pub mod skinning;
pub mod source;
pub mod tangents;
mod texture_source;
pub mod textures;

pub use arrays::SceneArrays;
pub use error::{printable, SceneError};
pub use instances::MeshInstance;
pub use material_factors::MaterialFactors;
pub use source::SceneSource;

/// A triangle with the workshop's shading parameters (`triangle_t`), world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// The vertices v_0, v_1, v_2.
    pub positions: [Vec3; 3],
    /// Unit normal, on the side from which the vertices are counter-clockwise.
    pub normal: Vec3,
    /// Albedo, linear RGB in [0, 1].
    pub color: Vec3,
    /// Emitted radiance, linear RGB, from the front side (or both with `double_sided`).
    pub emission: Vec3,
    /// Whether the triangle emits from its back side too.
    pub double_sided: bool,
}

/// A scene: triangles, and the camera it brings (the built-in scene and glTF files have one).
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// All triangles; degenerate ones were dropped when loading.
    pub triangles: Vec<Triangle>,
    /// The scene's own camera, if it has one: the first of `cameras`.
    pub camera: Option<Camera>,
    /// Every perspective camera of the file, in the order of its nodes (`--camera N`).
    pub cameras: Vec<Camera>,
    /// Things the loader ignored that the user should know about (e.g. textures).
    pub warnings: Vec<String>,
    /// Materials, textures and per-vertex shading data, for scenes that need more than the
    /// workshop's flat diffuse triangles; `None` for scenes that do not (they render with
    /// the workshop's kernels, bit for bit as before).
    pub materials: Option<materials::SceneMaterials>,
    /// KHR_lights_punctual's lights (glTF).
    pub punctual_lights: Vec<PunctualLight>,
    /// What rays that leave the scene see; `None`: black. Part of the scene's description
    /// though no scene file has one: the front ends (`--environment`, `--background`,
    /// Python's `environment=`, `background=`) give it as an `EnvironmentSource`, which
    /// `with_environment` loads into the scene.
    pub environment: Option<Environment>,
    /// The ranges of `triangles` that are copies of a mesh (glTF nodes; empty for other
    /// formats): what the device's acceleration structures instance.
    pub mesh_instances: Vec<MeshInstance>,
    /// Motion blur: the scene at the shutter's keys (`motion::SceneMotion`, its triangles in
    /// the order of `triangles`), or `None` for a scene seen at one instant.
    pub motion: Option<motion::SceneMotion>,
}

impl Triangle {
    /// A triangle whose normal is computed from its counter-clockwise vertices; `None` when
    /// the triangle has (numerically) zero area, since then it has no normal.
    pub fn new(
        positions: [Vec3; 3],
        color: Vec3,
        emission: Vec3,
        double_sided: bool,
    ) -> Option<Triangle> {
        // In float64: the cross product of a triangle 1e10 wide (or with corners near
        // f32::MAX) overflows f32, that of one 1e-12 across underflows, and both have a
        // perfectly good normal.
        let [a, b, c] = positions.map(|p| p.as_dvec3());
        let normal = (b - a).cross(c - a);
        let length = normal.length();
        if !(length > 0.0) || !length.is_finite() {
            return None;
        }
        Some(Triangle {
            positions,
            normal: (normal / length).as_vec3(),
            color,
            emission,
            double_sided,
        })
    }
}

impl Scene {
    /// Loads a scene file, choosing the loader by the extension (case-insensitive): `.gltf`
    /// and `.glb` (glTF 2.0), `.obj` (Wavefront OBJ with its MTL libraries).
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        Scene::load_with(path, &files::LoadOptions::default())
    }

    /// `load` with options (whether a glTF file may read buffers outside its folder).
    pub fn load_with(path: &Path, options: &files::LoadOptions) -> Result<Scene, SceneError> {
        let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        match extension.as_deref() {
            Some("gltf") | Some("glb") => gltf_loader::load_gltf_with(path, options),
            Some("obj") => obj_loader::load_obj(path),
            // A folder has no format: say what it is, not that its "extension" is unknown.
            _ => Err(
                files::existing_non_file(path).unwrap_or(SceneError::UnsupportedExtension {
                    path: path.to_owned(),
                    extension,
                }),
            ),
        }
    }

    /// Whether anything lights the scene: an emissive triangle, a punctual light or the
    /// environment (a scene where nothing does renders black).
    pub fn emits_light(&self) -> bool {
        self.triangles
            .iter()
            .any(|t| t.emission.max_element() > 0.0)
            || self.punctual_lights.iter().any(|l| l.emits_light())
            || self.environment.as_ref().is_some_and(|e| e.emits_light())
    }

    /// The scene lit by the environment `source` asks for (`None`: none, black), loaded
    /// here: the one place where a front end's environment enters a scene.
    pub fn with_environment(
        mut self,
        source: Option<&EnvironmentSource>,
    ) -> Result<Scene, SceneError> {
        self.environment = source
            .map(EnvironmentSource::load)
            .transpose()
            .map_err(SceneError::Environment)?;
        Ok(self)
    }

    /// The smallest box (lowest corner, highest corner) that holds every triangle, world
    /// space; `None` without triangles (or with non-finite positions).
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut low = Vec3::splat(f32::INFINITY);
        let mut high = Vec3::splat(f32::NEG_INFINITY);
        for triangle in &self.triangles {
            for position in triangle.positions {
                low = low.min(position);
                high = high.max(position);
            }
        }
        (low.is_finite() && high.is_finite()).then_some((low, high))
    }

    /// A camera that frames the scene's bounding sphere for an image of `aspect` (width /
    /// height), for files without one (`framing_camera_of` its `bounds`). `None` without
    /// triangles.
    pub fn framing_camera(&self, aspect: f32) -> Option<(Camera, Vec3, f32)> {
        let (low, high) = self.bounds()?;
        Some(framing_camera_of(low, high, aspect))
    }

    /// Whether the scene needs the kernels built with USE_MATERIALS: glTF materials, an
    /// environment or punctual lights. The others render with the workshop's kernels.
    pub fn needs_material_kernels(&self) -> bool {
        self.materials.is_some()
            || !self.punctual_lights.is_empty()
            || self.environment.as_ref().is_some_and(|e| e.emits_light())
    }

    /// Whether the material kernels need their layered lobes (`SCENE_HAS_LAYERS`): some
    /// material has transmission, a clear coat, sheen, specular textures or is unlit.
    pub fn needs_layered_kernels(&self) -> bool {
        self.materials.as_ref().is_some_and(|m| m.uses_layers())
    }

    /// Whether some material is alpha-masked or alpha-blended (`SCENE_HAS_ALPHA`): its
    /// candidate hits need the alpha test, which the constant triangles do not run.
    pub fn uses_alpha(&self) -> bool {
        self.materials.as_ref().is_some_and(|m| m.uses_alpha())
    }

    /// The workshop's Cornell box with its camera (`scenes/workshop_cornell_box.json`,
    /// embedded in the binary).
    pub fn builtin_cornell_box() -> Result<Scene, SceneError> {
        cornell::workshop_cornell_box()
    }
}

/// The workshop's material as a loader found it, before it is copied into each triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Material {
    /// Albedo, linear RGB in [0, 1].
    pub color: Vec3,
    /// Emitted radiance, linear RGB, non-negative.
    pub emission: Vec3,
    /// Whether the triangle emits from both sides.
    pub double_sided: bool,
}

impl Material {
    /// A material from file values, made safe for the shaders: the albedo is clamped to
    /// [0, 1] (more would create energy) and the emission to [0, inf); NaN becomes 0.
    #[allow(clippy::manual_clamp)]
    pub fn sanitized(color: Vec3, emission: Vec3, double_sided: bool) -> Material {
        // f32::max/min return the other operand for NaN, so NaN maps to 0 (f32::clamp would
        // keep the NaN).
        let color = Vec3::from(color.to_array().map(|c| c.max(0.0).min(1.0)));
        let emission = Vec3::from(emission.to_array().map(|e| e.max(0.0).min(f32::MAX)));
        Material {
            color,
            emission,
            double_sided,
        }
    }
}

/// The most triangles a scene may have (16 M: about 1.6 GB on the host while loading, and
/// within every device's texel-buffer limit); glTF instancing can make a small file
/// describe far more.
pub const MAX_SCENE_TRIANGLES: usize = 16 << 20;

/// The largest emitted radiance vkpath renders (1e30): a path multiplies it by throughputs
/// of up to about 2^path length, and a pixel adds up to 2^16 and more samples, which must
/// stay below f32's 3.4e38 instead of becoming infinite (and NaN) in the shader.
pub const MAX_EMISSION: f32 = 1e30;

/// Collects a loader's triangles: rejects non-finite positions, drops (and counts) degenerate
/// triangles, and refuses an empty result, the same way for every file format.
pub(crate) struct SceneBuilder {
    path: PathBuf,
    scene: Scene,
    degenerate_count: usize,
    /// Materials and shading of the triangles pushed with `push_shaded`.
    materials: materials::SceneMaterials,
}

impl SceneBuilder {
    /// An empty scene loaded from `path` (named in errors).
    pub fn new(path: &Path) -> SceneBuilder {
        SceneBuilder {
            path: path.to_owned(),
            scene: Scene::default(),
            degenerate_count: 0,
            materials: materials::SceneMaterials::default(),
        }
    }

    /// The scene file, for the loaders' own errors.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Triangles kept so far.
    pub fn triangle_count(&self) -> usize {
        self.scene.triangles.len()
    }

    /// Records a copy of a mesh among the triangles kept so far.
    pub fn add_mesh_instance(&mut self, instance: MeshInstance) {
        self.scene.mesh_instances.push(instance);
    }

    /// Adds a triangle with world-space, counter-clockwise `positions`; `mesh` names its
    /// mesh or object in the error for a non-finite position. (The loaders push shaded
    /// triangles; tests push plain ones.)
    #[cfg(test)]
    pub fn push(
        &mut self,
        mesh: &str,
        positions: [Vec3; 3],
        material: &Material,
    ) -> Result<(), SceneError> {
        self.push_with(mesh, positions, material, None, None)
    }

    /// `push` with the triangle's shading data (its material index into `set_materials`'
    /// list, vertex normals, texture coordinates, tangents). A loader pushes all its
    /// triangles one way or the other.
    pub fn push_shaded(
        &mut self,
        mesh: &str,
        positions: [Vec3; 3],
        material: &Material,
        shading: materials::TriangleShading,
    ) -> Result<(), SceneError> {
        self.push_with(mesh, positions, material, Some(shading), None)
    }

    /// `push_shaded` with the triangle's extra vertex attributes (vertex colours, second
    /// texture coordinates), which the scene keeps in side tables only once some triangle
    /// has a value other than the default (`materials::ExtraAttributeTables`).
    pub fn push_shaded_extra(
        &mut self,
        mesh: &str,
        positions: [Vec3; 3],
        material: &Material,
        shading: materials::TriangleShading,
        extra: &materials::ExtraVertexAttributes,
    ) -> Result<(), SceneError> {
        self.push_with(mesh, positions, material, Some(shading), Some(extra))
    }

    /// The materials (and their textures) that `push_shaded` triangles refer to.
    pub fn set_materials(
        &mut self,
        materials: Vec<materials::PbrMaterial>,
        textures: Vec<textures::Texture>,
    ) {
        self.materials.materials = materials;
        self.materials.textures = textures;
    }

    fn push_with(
        &mut self,
        mesh: &str,
        positions: [Vec3; 3],
        material: &Material,
        shading: Option<materials::TriangleShading>,
        extra: Option<&materials::ExtraVertexAttributes>,
    ) -> Result<(), SceneError> {
        if !positions.iter().all(|p| p.is_finite()) {
            return Err(SceneError::NonFinitePosition {
                path: self.path.clone(),
                mesh: mesh.to_owned(),
            });
        }
        if self.scene.triangles.len() + self.degenerate_count >= MAX_SCENE_TRIANGLES {
            return Err(SceneError::TooManyTriangles {
                path: self.path.clone(),
                limit: MAX_SCENE_TRIANGLES,
            });
        }
        let emission = material.emission.max_element();
        if emission > MAX_EMISSION {
            return Err(SceneError::EmissionTooLarge {
                path: self.path.clone(),
                mesh: mesh.to_owned(),
                emission,
                limit: MAX_EMISSION,
            });
        }
        match Triangle::new(
            positions,
            material.color,
            material.emission,
            material.double_sided,
        ) {
            Some(triangle) => {
                self.scene.triangles.push(triangle);
                if let Some(mut shading) = shading {
                    // Vertex normals that are not finite or vanish: the face's normal.
                    for normal in &mut shading.normals {
                        *normal = normal.try_normalize().unwrap_or(triangle.normal);
                    }
                    // The side tables stay parallel to the triangles (a no-op while
                    // they do not exist and the attributes are the defaults)
                    let index = self.materials.triangles.len();
                    let extra = extra.unwrap_or(&materials::ExtraVertexAttributes::NONE);
                    self.materials.extra.push(index, extra);
                    self.materials.triangles.push(shading);
                }
            }
            None => self.degenerate_count += 1,
        }
        Ok(())
    }

    /// Records something the loader ignored (textures, a missing material library, ...).
    pub fn warn(&mut self, warning: String) {
        self.scene.warnings.push(warning);
    }

    /// Adds a punctual light (glTF's KHR_lights_punctual).
    pub fn add_punctual_light(&mut self, light: PunctualLight) {
        self.scene.punctual_lights.push(light);
    }

    /// Adds a camera; the first one is the scene's camera.
    pub fn set_camera(&mut self, camera: Camera) {
        self.scene.camera.get_or_insert(camera);
        self.scene.cameras.push(camera);
    }

    /// How many cameras were added.
    pub fn camera_count(&self) -> usize {
        self.scene.cameras.len()
    }

    /// Whether a camera was set already (loaders take the first one they meet).
    pub fn has_camera(&self) -> bool {
        self.scene.camera.is_some()
    }

    /// The finished scene; an error when it has no triangles. Shading data stays only when
    /// the workshop's flat diffuse triangles cannot describe the scene.
    pub fn finish(mut self) -> Result<Scene, SceneError> {
        let shaded = self.materials.triangles.len() == self.scene.triangles.len()
            && !self.materials.materials.is_empty();
        if shaded
            && !self
                .materials
                .is_plain(self.scene.triangles.iter().map(|t| t.normal))
        {
            self.scene.materials = Some(std::mem::take(&mut self.materials));
        }
        if self.degenerate_count > 0 {
            let warning = format!("dropped {} degenerate triangles", self.degenerate_count);
            self.scene.warnings.push(warning);
        }
        if self.scene.triangles.is_empty() {
            let details = if self.scene.warnings.is_empty() {
                String::new()
            } else {
                format!(" ({})", self.scene.warnings.join("; "))
            };
            return Err(SceneError::NoTriangles {
                path: self.path,
                details,
            });
        }
        Ok(self.scene)
    }
}

/// A camera that frames the bounding sphere of the box `low`..`high` for an image of `aspect`
/// (width / height): from the +Z side, 20 degrees above (+Y is up), with the default vertical
/// field of view (45 degrees), at the distance where the sphere fits both the vertical and
/// the horizontal field of view, plus 5%; with the sphere's centre and radius.
pub fn framing_camera_of(low: Vec3, high: Vec3, aspect: f32) -> (Camera, Vec3, f32) {
    let centre = 0.5 * (low + high);
    let radius = (0.5 * (high - low).length()).max(1e-6);
    let vertical = crate::camera::DEFAULT_VERTICAL_FOV_DEGREES.to_radians();
    let half_vertical = 0.5 * vertical;
    let half_horizontal = (half_vertical.tan() * aspect).atan();
    let distance = 1.05 * radius / half_vertical.min(half_horizontal).sin();
    let elevation = 20f32.to_radians();
    let position = centre + distance * Vec3::new(0.0, elevation.sin(), elevation.cos());
    (
        Camera::look_at(position, centre, Vec3::Y, vertical),
        centre,
        radius,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_send_sync<T: Send + Sync + 'static>() {}

    #[test]
    fn scene_error_can_travel_in_anyhow() {
        assert_send_sync::<SceneError>();
    }

    #[test]
    fn load_rejects_unknown_extension_before_reading() {
        let error = Scene::load(Path::new("does/not/exist.ply")).unwrap_err();
        assert!(
            matches!(error, SceneError::UnsupportedExtension { .. }),
            "{error}"
        );
        let error = Scene::load(Path::new("no_extension")).unwrap_err();
        assert!(matches!(
            error,
            SceneError::UnsupportedExtension {
                extension: None,
                ..
            }
        ));
    }

    #[test]
    fn a_directory_is_called_a_directory_not_an_extension() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["scenes", "scenes.v2"] {
            let path = dir.path().join(name);
            std::fs::create_dir(&path).unwrap();
            let error = Scene::load(&path).unwrap_err();
            assert_eq!(
                error.to_string(),
                format!(
                    "cannot read scene '{}': it is a directory, not a file",
                    path.display()
                )
            );
        }
    }

    #[test]
    fn load_reports_missing_file_by_name() {
        for name in ["missing.gltf", "missing.GLB", "missing.obj"] {
            let error = Scene::load(Path::new(name)).unwrap_err();
            assert_eq!(
                error.to_string(),
                format!("cannot read scene '{name}': No such file or directory")
            );
        }
    }

    #[test]
    fn framing_keeps_the_whole_bounding_box_in_view() {
        let material = Material::sanitized(Vec3::ONE, Vec3::ZERO, false);
        let mut builder = SceneBuilder::new(Path::new("t.gltf"));
        let (low, high) = (Vec3::new(-3.0, 1.0, 2.0), Vec3::new(5.0, 2.0, 2.5));
        builder
            .push("m", [low, Vec3::new(high.x, low.y, low.z), high], &material)
            .unwrap();
        let scene = builder.finish().unwrap();
        for aspect in [0.5_f32, 1.0, 16.0 / 9.0] {
            let (camera, _, _) = scene.framing_camera(aspect).unwrap();
            let plane = camera.image_plane(aspect);
            let normal = plane.right.cross(plane.up);
            for i in 0..8 {
                let corner = Vec3::new(
                    if i & 1 == 0 { low.x } else { high.x },
                    if i & 2 == 0 { low.y } else { high.y },
                    if i & 4 == 0 { low.z } else { high.z },
                );
                // Where the ray to the corner crosses the image plane, in (0, 1)^2.
                let direction = corner - plane.camera_position;
                let t =
                    (plane.left_bottom - plane.camera_position).dot(normal) / direction.dot(normal);
                let offset = plane.camera_position + t * direction - plane.left_bottom;
                let (u, v) = (
                    offset.dot(plane.right) / plane.right.length_squared(),
                    offset.dot(plane.up) / plane.up.length_squared(),
                );
                assert!(
                    t > 0.0 && (0.0..1.0).contains(&u) && (0.0..1.0).contains(&v),
                    "aspect {aspect}: corner {corner} at ({u}, {v})"
                );
            }
        }
    }

    #[test]
    fn material_is_sanitized() {
        let material = Material::sanitized(
            Vec3::new(1.5, -0.5, f32::NAN),
            Vec3::new(-1.0, f32::NAN, 7.0),
            true,
        );
        assert_eq!(material.color, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(material.emission, Vec3::new(0.0, 0.0, 7.0));
    }

    #[test]
    fn builder_drops_degenerate_triangles_and_rejects_empty_scenes() {
        let material = Material::sanitized(Vec3::ONE, Vec3::ZERO, false);
        let mut builder = SceneBuilder::new(Path::new("t.obj"));
        builder
            .push("m", [Vec3::ZERO, Vec3::X, Vec3::Y], &material)
            .unwrap();
        builder
            .push("m", [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X], &material)
            .unwrap();
        let error = builder.push("m", [Vec3::ZERO, Vec3::X, Vec3::INFINITY], &material);
        assert!(matches!(error, Err(SceneError::NonFinitePosition { .. })));
        let scene = builder.finish().unwrap();
        assert_eq!(scene.triangles.len(), 1);
        assert_eq!(scene.triangles[0].normal, Vec3::Z);
        assert_eq!(
            scene.warnings,
            vec!["dropped 1 degenerate triangles".to_owned()]
        );

        let mut builder = SceneBuilder::new(Path::new("t.obj"));
        builder.push("m", [Vec3::ZERO; 3], &material).unwrap();
        let error = builder.finish().unwrap_err();
        assert_eq!(
            error.to_string(),
            "scene 't.obj' contains no triangles (dropped 1 degenerate triangles)"
        );
    }
}
