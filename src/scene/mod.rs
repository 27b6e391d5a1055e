//! Scenes: triangles with the workshop's diffuse material and an optional camera, loaded
//! from the built-in Cornell box, glTF 2.0 or OBJ + MTL.

use glam::Vec3;

use crate::camera::Camera;
use crate::gpu_types::GpuTriangle;

pub mod cornell;
pub mod gltf_loader;
pub mod obj_loader;

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
    /// The scene's own camera, if it has one.
    pub camera: Option<Camera>,
    /// Things the loader ignored that the user should know about (e.g. textures).
    pub warnings: Vec<String>,
}

impl Triangle {
    /// A triangle whose normal is computed from its counter-clockwise vertices; `None` when
    /// the triangle has (numerically) zero area, since then it has no normal.
    pub fn new(positions: [Vec3; 3], color: Vec3, emission: Vec3, double_sided: bool) -> Option<Triangle> {
        let normal = (positions[1] - positions[0]).cross(positions[2] - positions[0]);
        let length = normal.length();
        if !(length > 0.0) || !length.is_finite() {
            return None;
        }
        Some(Triangle { positions, normal: normal / length, color, emission, double_sided })
    }

    /// The triangle as the shaders store it (`packed_triangle_t`).
    pub fn to_gpu(&self) -> GpuTriangle {
        GpuTriangle::new(self)
    }
}

impl Scene {
    /// The triangles as the shaders store them.
    pub fn gpu_triangles(&self) -> Vec<GpuTriangle> {
        self.triangles.iter().map(Triangle::to_gpu).collect()
    }
}
