//! Structs shared with the shaders, byte for byte: `#[repr(C)]` + `bytemuck::Pod`, with
//! 16-byte members only (or members that fill one 16-byte texel), so that std430, std140
//! and RGBA32 texel fetches lay them out exactly as Rust does. The tests below check sizes
//! and offsets against the GLSL declarations. Also the conversions from the scene's types
//! (`crate::scene`, which knows nothing of the GPU) into these structs. The lights' structs
//! are in `crate::lights` (`gpu_emissive`, `gpu_environment`, `gpu_punctual`).

use bytemuck::{Pod, Zeroable};

use crate::camera::ImagePlane;
use crate::contract::TRIANGLE_FLAG_DOUBLE_SIDED;
use crate::scene::Triangle;

/// The path tracer's per-frame push constants, declared beside the kernels.
pub use crate::kernels::push_constants::FramePushConstants;

/// `packed_triangle_t` of `glsl/scene.glsl` (std430, 96 bytes; `TRIANGLE_TEXEL_COUNT` texels
/// of the triangle texel buffer).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuTriangle {
    /// xyz: vertices v_0, v_1, v_2 (world space); w: unused, 0.
    pub positions: [[f32; 4]; 3],
    /// xyz: unit normal (world space, the side the vertices are counter-clockwise from);
    /// w: unused, 0 (MIS reads a triangle's light-selection probability from the lights'
    /// own buffer, `crate::lights::LightBuffers`).
    pub normal: [f32; 4],
    /// rgb: albedo, linear RGB in [0, 1]; a: unused, 0.
    pub color: [f32; 4],
    /// rgb: emitted radiance, linear RGB; a: `TRIANGLE_FLAG_*` bits stored as the float's bits.
    pub emission: [f32; 4],
}

/// `render_uniforms` of `glsl/scene.glsl` (std140, 80 bytes): what stays fixed in a render.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct RenderUniforms {
    /// xyz: the pinhole, world space; w: the lens's aperture radius (0: a pinhole).
    pub camera_position: [f32; 4],
    /// xyz: the image plane's left-bottom corner, world space; w: the lens's focus distance.
    pub left_bottom: [f32; 4],
    /// xyz: the image plane's full-width edge vector; w: the aperture's blades (0: a disc).
    pub right: [f32; 4],
    /// xyz: the image plane's full-height edge vector; w: the aperture's rotation, radians.
    pub up: [f32; 4],
    /// Image width and height in pixels, triangle count, user seed.
    pub resolution_triangle_count_seed: [u32; 4],
}

fn extend(v: glam::Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

impl GpuTriangle {
    /// Packs a scene triangle.
    pub fn new(triangle: &Triangle) -> GpuTriangle {
        let flags = if triangle.double_sided {
            TRIANGLE_FLAG_DOUBLE_SIDED
        } else {
            0
        };
        GpuTriangle {
            positions: triangle.positions.map(|p| extend(p, 0.0)),
            normal: extend(triangle.normal, 0.0),
            color: extend(triangle.color, 0.0),
            emission: extend(triangle.emission, f32::from_bits(flags)),
        }
    }
}

impl RenderUniforms {
    /// The uniforms for one render.
    pub fn new(
        plane: &ImagePlane,
        width: u32,
        height: u32,
        triangle_count: u32,
        seed: u32,
    ) -> Self {
        // The lens rides in the w components (glsl/scene.glsl); a pinhole leaves them 0.
        let lens = &plane.lens;
        let (radius, focus, blades, rotation) = if lens.is_pinhole() {
            (0.0, 0.0, 0.0, 0.0)
        } else {
            (
                lens.aperture_radius,
                lens.focus_distance,
                lens.blades as f32,
                lens.rotation,
            )
        };
        RenderUniforms {
            camera_position: extend(plane.camera_position, radius),
            left_bottom: extend(plane.left_bottom, focus),
            right: extend(plane.right, blades),
            up: extend(plane.up, rotation),
            resolution_triangle_count_seed: [width, height, triangle_count, seed],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn triangle_matches_std430_packed_triangle_t() {
        // struct packed_triangle_t { vec4 positions[3]; vec4 normal; vec4 color; vec4 emission; }
        assert_eq!(size_of::<GpuTriangle>(), 96);
        assert_eq!(offset_of!(GpuTriangle, positions), 0);
        assert_eq!(offset_of!(GpuTriangle, normal), 48);
        assert_eq!(offset_of!(GpuTriangle, color), 64);
        assert_eq!(offset_of!(GpuTriangle, emission), 80);
    }

    #[test]
    fn uniforms_match_std140_render_uniforms() {
        assert_eq!(size_of::<RenderUniforms>(), 80);
        assert_eq!(offset_of!(RenderUniforms, camera_position), 0);
        assert_eq!(offset_of!(RenderUniforms, left_bottom), 16);
        assert_eq!(offset_of!(RenderUniforms, right), 32);
        assert_eq!(offset_of!(RenderUniforms, up), 48);
        assert_eq!(
            offset_of!(RenderUniforms, resolution_triangle_count_seed),
            64
        );
    }

    #[test]
    fn double_sided_flag_survives_packing() {
        let t = Triangle::new(
            [glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y],
            glam::Vec3::splat(0.5),
            glam::Vec3::ONE,
            true,
        )
        .unwrap();
        let packed = GpuTriangle::new(&t);
        assert_eq!(packed.emission[3].to_bits(), TRIANGLE_FLAG_DOUBLE_SIDED);
        assert_eq!(packed.normal, [0.0, 0.0, 1.0, 0.0]);
    }
}
