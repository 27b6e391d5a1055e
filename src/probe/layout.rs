//! The probe kernels' input and output structs, byte for byte as `glsl/probe_*.comp` declare
//! them (`probe_input_t`, `probe_output_t`): `#[repr(C)]` + `bytemuck::Pod` with 16-byte
//! members only, so that std430 lays them out as Rust does. The tests below check sizes and
//! offsets against the GLSL declarations.

use bytemuck::{Pod, Zeroable};
use glam::{UVec2, Vec2, Vec3};

use crate::render::gpu_types::GpuTriangle;
use crate::scene::Triangle;

/// The probe kernels' push constants, declared beside the kernels.
pub use crate::kernels::push_constants::ProbePushConstants;

fn extend(v: Vec3) -> [f32; 4] {
    [v.x, v.y, v.z, 0.0]
}

fn xyz(v: [f32; 4]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

/// Input of `probe_get_random_numbers.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct RandomNumbersInput {
    /// xy: the seed before the call; zw: 0.
    pub seed: [u32; 4],
}

impl RandomNumbersInput {
    /// The input for one call with `seed`.
    pub fn new(seed: UVec2) -> Self {
        RandomNumbersInput {
            seed: [seed.x, seed.y, 0, 0],
        }
    }
}

/// Output of `probe_get_random_numbers.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct RandomNumbersOutput {
    /// xy: the seed after the call; zw: the bits of the two random numbers.
    pub seed_and_numbers: [u32; 4],
}

impl RandomNumbersOutput {
    /// The seed after the call.
    pub fn seed(&self) -> UVec2 {
        UVec2::new(self.seed_and_numbers[0], self.seed_and_numbers[1])
    }

    /// The two random numbers the call returned.
    pub fn numbers(&self) -> Vec2 {
        Vec2::new(
            f32::from_bits(self.seed_and_numbers[2]),
            f32::from_bits(self.seed_and_numbers[3]),
        )
    }
}

/// Input of the sampler probes (`probe_sample_sphere.comp`, `probe_sample_hemisphere.comp`,
/// `probe_sample_sphere_spherical_coordinates.comp`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SamplerInput {
    /// xy: the random numbers (u_0, u_1) in [0, 1)^2; zw: 0.
    pub random_numbers: [f32; 4],
    /// xyz: the unit normal (`sample_hemisphere` only); w: 0.
    pub normal: [f32; 4],
}

impl SamplerInput {
    /// The input for one call with `random_numbers` (and `normal` for the hemisphere).
    pub fn new(random_numbers: Vec2, normal: Vec3) -> Self {
        SamplerInput {
            random_numbers: [random_numbers.x, random_numbers.y, 0.0, 0.0],
            normal: extend(normal),
        }
    }

    /// The random numbers.
    pub fn random_numbers(&self) -> Vec2 {
        Vec2::new(self.random_numbers[0], self.random_numbers[1])
    }

    /// The normal.
    pub fn normal(&self) -> Vec3 {
        xyz(self.normal)
    }
}

/// Output of the sampler probes and of `probe_get_primary_ray_direction.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct DirectionOutput {
    /// xyz: the direction; w: 0.
    pub direction: [f32; 4],
}

impl DirectionOutput {
    /// The direction.
    pub fn direction(&self) -> Vec3 {
        xyz(self.direction)
    }
}

/// Input of `probe_ray_triangle_intersection.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct RayTriangleInput {
    /// xyz: the ray's origin, world space; w: 0.
    pub ray_origin: [f32; 4],
    /// xyz: the ray's direction, world space; w: 0.
    pub ray_direction: [f32; 4],
    /// The triangle, packed as in the scene buffer.
    pub triangle: GpuTriangle,
}

impl RayTriangleInput {
    /// The input for one ray and triangle.
    pub fn new(ray_origin: Vec3, ray_direction: Vec3, triangle: &Triangle) -> Self {
        RayTriangleInput {
            ray_origin: extend(ray_origin),
            ray_direction: extend(ray_direction),
            triangle: GpuTriangle::new(triangle),
        }
    }

    /// The ray's origin.
    pub fn ray_origin(&self) -> Vec3 {
        xyz(self.ray_origin)
    }

    /// The ray's direction.
    pub fn ray_direction(&self) -> Vec3 {
        xyz(self.ray_direction)
    }

    /// The triangle's vertices.
    pub fn positions(&self) -> [Vec3; 3] {
        self.triangle.positions.map(xyz)
    }
}

/// Output of `probe_ray_triangle_intersection.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct IntersectionOutput {
    /// x: `out_t` as the function left it (meaningful on a hit); yzw: 0.
    pub t: [f32; 4],
    /// x: 1 if the function returned true, else 0; yzw: 0.
    pub hit: [u32; 4],
}

impl IntersectionOutput {
    /// The ray parameter of the hit, `None` on a miss.
    pub fn hit_t(&self) -> Option<f32> {
        (self.hit[0] != 0).then_some(self.t[0])
    }
}

/// Input of `probe_ray_mesh_intersection.comp`: a ray.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct RayInput {
    /// xyz: the ray's origin, world space; w: 0.
    pub ray_origin: [f32; 4],
    /// xyz: the ray's direction, world space; w: 0.
    pub ray_direction: [f32; 4],
}

impl RayInput {
    /// The input for one ray.
    pub fn new(ray_origin: Vec3, ray_direction: Vec3) -> Self {
        RayInput {
            ray_origin: extend(ray_origin),
            ray_direction: extend(ray_direction),
        }
    }

    /// The ray's origin.
    pub fn ray_origin(&self) -> Vec3 {
        xyz(self.ray_origin)
    }

    /// The ray's direction.
    pub fn ray_direction(&self) -> Vec3 {
        xyz(self.ray_direction)
    }
}

/// Output of `probe_ray_mesh_intersection.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MeshIntersectionOutput {
    /// x: `out_t` (meaningful on a hit); yzw: 0.
    pub t: [f32; 4],
    /// x: 1 on a hit, else 0; y: `g_hit_triangle_index`, which only the reference version
    /// sets (u32::MAX otherwise); zw: 0.
    pub hit: [u32; 4],
    /// `out_triangle` (meaningful on a hit), flags 0.
    pub triangle: GpuTriangle,
}

impl MeshIntersectionOutput {
    /// The ray parameter of the hit, `None` on a miss.
    pub fn hit_t(&self) -> Option<f32> {
        (self.hit[0] != 0).then_some(self.t[0])
    }

    /// The index of the hit triangle in `scene_triangles`: the first triangle whose vertices
    /// equal `out_triangle`'s bit for bit (a user's version cannot set
    /// `g_hit_triangle_index`). `None` on a miss or when no triangle matches.
    pub fn triangle_index(&self, scene_triangles: &[Triangle]) -> Option<usize> {
        if self.hit[0] == 0 {
            return None;
        }
        let positions = self.triangle.positions.map(xyz);
        scene_triangles
            .iter()
            .position(|t| t.positions == positions)
    }
}

/// Input of `probe_get_primary_ray_direction.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PrimaryRayInput {
    /// xy: point of the image in [0, 1]^2; zw: 0.
    pub tex_coord: [f32; 4],
    /// xyz: the pinhole, world space; w: 0.
    pub camera_position: [f32; 4],
    /// xyz: the image plane's left-bottom corner; w: 0.
    pub left_bottom: [f32; 4],
    /// xyz: the image plane's full-width edge vector; w: 0.
    pub right: [f32; 4],
    /// xyz: the image plane's full-height edge vector; w: 0.
    pub up: [f32; 4],
}

impl PrimaryRayInput {
    /// The input for one point of the image plane of `plane`.
    pub fn new(tex_coord: Vec2, plane: &crate::camera::ImagePlane) -> Self {
        PrimaryRayInput {
            tex_coord: [tex_coord.x, tex_coord.y, 0.0, 0.0],
            camera_position: extend(plane.camera_position),
            left_bottom: extend(plane.left_bottom),
            right: extend(plane.right),
            up: extend(plane.up),
        }
    }

    /// The point of the image.
    pub fn tex_coord(&self) -> Vec2 {
        Vec2::new(self.tex_coord[0], self.tex_coord[1])
    }

    /// The camera as `get_primary_ray_direction` takes it: (camera_position, left_bottom,
    /// right, up).
    pub fn camera(&self) -> [Vec3; 4] {
        [
            xyz(self.camera_position),
            xyz(self.left_bottom),
            xyz(self.right),
            xyz(self.up),
        ]
    }
}

/// Input of `probe_compute_direct_illumination.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct DirectIlluminationInput {
    /// xyz: a point on the triangle, world space; w: 0.
    pub shading_position: [f32; 4],
    /// xy: the random state; z: index of the triangle in the scene; w: 0.
    pub seed_and_triangle: [u32; 4],
}

impl DirectIlluminationInput {
    /// The input for one estimate at `shading_position` on scene triangle `triangle_index`.
    pub fn new(shading_position: Vec3, triangle_index: u32, seed: UVec2) -> Self {
        DirectIlluminationInput {
            shading_position: extend(shading_position),
            seed_and_triangle: [seed.x, seed.y, triangle_index, 0],
        }
    }

    /// The shading position.
    pub fn shading_position(&self) -> Vec3 {
        xyz(self.shading_position)
    }

    /// The random state.
    pub fn seed(&self) -> UVec2 {
        UVec2::new(self.seed_and_triangle[0], self.seed_and_triangle[1])
    }

    /// The index of the triangle in the scene.
    pub fn triangle_index(&self) -> usize {
        self.seed_and_triangle[2] as usize
    }
}

/// Input of `probe_get_ray_radiance.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct RayRadianceInput {
    /// xyz: the ray's origin, world space; w: 0.
    pub ray_origin: [f32; 4],
    /// xyz: the ray's direction, world space; w: 0.
    pub ray_direction: [f32; 4],
    /// xy: the random state; zw: 0.
    pub seed: [u32; 4],
}

impl RayRadianceInput {
    /// The input for one path from a camera ray.
    pub fn new(ray_origin: Vec3, ray_direction: Vec3, seed: UVec2) -> Self {
        RayRadianceInput {
            ray_origin: extend(ray_origin),
            ray_direction: extend(ray_direction),
            seed: [seed.x, seed.y, 0, 0],
        }
    }

    /// The ray's origin.
    pub fn ray_origin(&self) -> Vec3 {
        xyz(self.ray_origin)
    }

    /// The ray's direction.
    pub fn ray_direction(&self) -> Vec3 {
        xyz(self.ray_direction)
    }

    /// The random state.
    pub fn seed(&self) -> UVec2 {
        UVec2::new(self.seed[0], self.seed[1])
    }
}

/// Output of the estimator probes (`probe_compute_direct_illumination.comp`,
/// `probe_get_ray_radiance.comp`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct RadianceOutput {
    /// rgb: the estimate; a: 0.
    pub radiance: [f32; 4],
    /// xy: the random state after the call; zw: 0.
    pub seed: [u32; 4],
}

impl RadianceOutput {
    /// The estimate.
    pub fn radiance(&self) -> Vec3 {
        xyz(self.radiance)
    }

    /// The random state after the call.
    pub fn seed(&self) -> UVec2 {
        UVec2::new(self.seed[0], self.seed[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn structs_match_the_std430_declarations() {
        // uvec4 seed / uvec4 seed_and_numbers
        assert_eq!(size_of::<RandomNumbersInput>(), 16);
        assert_eq!(size_of::<RandomNumbersOutput>(), 16);
        // vec4 random_numbers; vec4 normal
        assert_eq!(size_of::<SamplerInput>(), 32);
        assert_eq!(offset_of!(SamplerInput, normal), 16);
        assert_eq!(size_of::<DirectionOutput>(), 16);
        // vec4 ray_origin; vec4 ray_direction; packed_triangle_t triangle (96 bytes)
        assert_eq!(size_of::<RayTriangleInput>(), 128);
        assert_eq!(offset_of!(RayTriangleInput, ray_direction), 16);
        assert_eq!(offset_of!(RayTriangleInput, triangle), 32);
        // vec4 t; uvec4 hit
        assert_eq!(size_of::<IntersectionOutput>(), 32);
        assert_eq!(offset_of!(IntersectionOutput, hit), 16);
        assert_eq!(size_of::<RayInput>(), 32);
        assert_eq!(offset_of!(RayInput, ray_direction), 16);
        // vec4 t; uvec4 hit; packed_triangle_t triangle
        assert_eq!(size_of::<MeshIntersectionOutput>(), 128);
        assert_eq!(offset_of!(MeshIntersectionOutput, hit), 16);
        assert_eq!(offset_of!(MeshIntersectionOutput, triangle), 32);
        // five vec4
        assert_eq!(size_of::<PrimaryRayInput>(), 80);
        assert_eq!(offset_of!(PrimaryRayInput, camera_position), 16);
        assert_eq!(offset_of!(PrimaryRayInput, left_bottom), 32);
        assert_eq!(offset_of!(PrimaryRayInput, right), 48);
        assert_eq!(offset_of!(PrimaryRayInput, up), 64);
        // vec4 shading_position; uvec4 seed_and_triangle
        assert_eq!(size_of::<DirectIlluminationInput>(), 32);
        assert_eq!(offset_of!(DirectIlluminationInput, seed_and_triangle), 16);
        // vec4 ray_origin; vec4 ray_direction; uvec4 seed
        assert_eq!(size_of::<RayRadianceInput>(), 48);
        assert_eq!(offset_of!(RayRadianceInput, seed), 32);
        // vec4 radiance; uvec4 seed
        assert_eq!(size_of::<RadianceOutput>(), 32);
        assert_eq!(offset_of!(RadianceOutput, seed), 16);
    }

    #[test]
    fn mesh_output_finds_its_triangle_by_vertices() {
        let a = Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], Vec3::ONE, Vec3::ZERO, false)
            .expect("non-degenerate");
        let b = Triangle::new([Vec3::ZERO, Vec3::Y, Vec3::Z], Vec3::ONE, Vec3::ZERO, false)
            .expect("non-degenerate");
        let output = MeshIntersectionOutput {
            t: [1.0, 0.0, 0.0, 0.0],
            hit: [1, u32::MAX, 0, 0],
            triangle: GpuTriangle::new(&b),
        };
        assert_eq!(output.triangle_index(&[a, b]), Some(1));
        assert_eq!(output.hit_t(), Some(1.0));
        let miss = MeshIntersectionOutput {
            hit: [0; 4],
            ..output
        };
        assert_eq!(miss.triangle_index(&[a, b]), None);
        assert_eq!(miss.hit_t(), None);
    }
}
