//! The push-constant blocks of the kernels, byte for byte as `glsl/` declares them
//! (`#[repr(C)]` + `bytemuck::Pod`): they live here, beside the kernel declarations
//! (`catalog`) that name their sizes, so that `kernels` borrows nothing from the rooms that
//! use it. Those rooms re-export them where their users look (`render::gpu_types`,
//! `probe::layout`, `exercise::view`); constructors that need a room's own types stay in that
//! room. The tests below check sizes and offsets against the GLSL blocks.

use bytemuck::{Pod, Zeroable};

/// `frame_push_constants` of `glsl/path_tracer.comp` (32 bytes): what changes per frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct FramePushConstants {
    /// Index of the first sample this frame adds to each pixel.
    pub first_sample_index: u32,
    /// Samples at or past this index are not taken (the render's total spp).
    pub sample_end: u32,
    /// The full image's pixel (column, row from the top) of the accumulation image's texel
    /// (0, 0): the corner of the region or tile this dispatch renders.
    pub pixel_offset: [u32; 2],
    /// Width and height of that region or tile: texels beyond are not touched.
    pub pixel_extent: [u32; 2],
    /// `--noise-threshold`: a pixel takes no more samples once `is_pixel_converged` says so;
    /// 0 turns adaptive sampling off.
    pub noise_threshold: f32,
    /// Samples a pixel takes before adaptive sampling may stop it, and how often (in
    /// samples) it is judged after that.
    pub noise_min_samples: u32,
}

/// `probe_push_constants` of `glsl/probe_common.glsl` (8 bytes): which inputs a dispatch
/// covers.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct ProbePushConstants {
    /// Index of the input that invocation 0 of the dispatch evaluates.
    pub first: u32,
    /// Number of inputs in the buffer; invocations past it do nothing.
    pub count: u32,
}

/// `exercise_push_constants` of `glsl/exercise_samples.comp` (80 bytes, within the 128 that
/// Vulkan guarantees). All but the first field only matter for `EXERCISE_SAMPLER_BRDF`.
/// Built by `SampleDisplayPushConstants::new` (`crate::exercise::view`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SampleDisplayPushConstants {
    /// Image width and height in pixels, `EXERCISE_SAMPLER_*`, seed of the sample sequence.
    pub resolution_sampler_seed: [u32; 4],
    /// The material's base colour (linear RGB) and metallic factor.
    pub base_color_metallic: [f32; 4],
    /// The material's specular colour (linear RGB) and specular factor.
    pub specular_color_specular: [f32; 4],
    /// Unit view direction (from the surface towards the viewer, world space; the normal is
    /// +z), w = 0.
    pub view_direction: [f32; 4],
    /// The material's perceptual roughness and index of refraction, z = w = 0.
    pub roughness_ior: [f32; 4],
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn frame_push_constants_match_the_shader_block() {
        assert_eq!(size_of::<FramePushConstants>(), 32);
        assert_eq!(offset_of!(FramePushConstants, first_sample_index), 0);
        assert_eq!(offset_of!(FramePushConstants, sample_end), 4);
        // uvec2 members are 8-byte aligned in a push-constant block (std430).
        assert_eq!(offset_of!(FramePushConstants, pixel_offset), 8);
        assert_eq!(offset_of!(FramePushConstants, pixel_extent), 16);
        assert_eq!(offset_of!(FramePushConstants, noise_threshold), 24);
        assert_eq!(offset_of!(FramePushConstants, noise_min_samples), 28);
    }

    #[test]
    fn probe_push_constants_match_the_shader_block() {
        assert_eq!(size_of::<ProbePushConstants>(), 8);
        assert_eq!(offset_of!(ProbePushConstants, first), 0);
        assert_eq!(offset_of!(ProbePushConstants, count), 4);
    }

    #[test]
    fn sample_display_push_constants_match_the_shader_block() {
        // uniform exercise_push_constants { uvec4 g_resolution_sampler_seed;
        //     vec4 g_base_color_metallic; vec4 g_specular_color_specular;
        //     vec4 g_view_direction; vec4 g_roughness_ior; }: five 16-byte members.
        assert_eq!(size_of::<SampleDisplayPushConstants>(), 80);
        assert_eq!(
            offset_of!(SampleDisplayPushConstants, resolution_sampler_seed),
            0
        );
        assert_eq!(
            offset_of!(SampleDisplayPushConstants, base_color_metallic),
            16
        );
        assert_eq!(
            offset_of!(SampleDisplayPushConstants, specular_color_specular),
            32
        );
        assert_eq!(offset_of!(SampleDisplayPushConstants, view_direction), 48);
        assert_eq!(offset_of!(SampleDisplayPushConstants, roughness_ior), 64);
    }
}
