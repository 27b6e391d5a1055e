//! The guide's probe (`glsl/probe_guiding.comp`): runs the functions of `glsl/guiding.glsl`
//! on a buffer of inputs against a guide's words (`crate::guiding::Guide::words`), so that
//! tests can compare them with their Rust twins (`crate::cpu::guiding`). It binds the
//! guide's texel buffer (no scene), which it gives `Probe`.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use crate::error::Result;
use crate::kernels::{self, Resource};
use crate::probe::runner::TexelBufferProbe;
use crate::vk::Context;

/// `probe_input_t` of `glsl/probe_guiding.comp` (64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GuidingProbeInput {
    /// xyz: the point whose cell is looked up, world space; w: 0.
    pub position: [f32; 4],
    /// xyz: the unit normal of the surface at that point (its cell's orientation); w: 0.
    pub normal: [f32; 4],
    /// xyz: a unit direction (its bin and density); w: 0.
    pub direction: [f32; 4],
    /// xy: `sample_guide_direction`'s random numbers; zw: 0.
    pub random_numbers: [f32; 4],
}

impl GuidingProbeInput {
    /// The input that looks up the cell of `position` on a surface facing `normal`,
    /// `direction`'s bin and density there, and samples the cell with `random_numbers`.
    pub fn new(position: Vec3, normal: Vec3, direction: Vec3, random_numbers: Vec2) -> Self {
        GuidingProbeInput {
            position: position.extend(0.0).to_array(),
            normal: normal.extend(0.0).to_array(),
            direction: direction.extend(0.0).to_array(),
            random_numbers: [random_numbers.x, random_numbers.y, 0.0, 0.0],
        }
    }
}

/// `probe_output_t` of `glsl/probe_guiding.comp` (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GuidingProbeOutput {
    /// x: `get_guide_cell_index`; y: `is_guided_cell` (1 or 0); z: `get_guide_bin_index`
    /// of the direction; w: the bin `sample_guide_direction` chose (0 where the cell is not
    /// guided).
    pub cell_bin: [u32; 4],
    /// xyz: `sample_guide_direction`; w: `get_guide_density` of the input's direction (all
    /// 0 where the cell is not guided).
    pub sampled_density: [f32; 4],
}

/// Runs the guide's probe against one guide.
pub struct GuidingProbeRunner(TexelBufferProbe);

impl GuidingProbeRunner {
    /// Uploads `words` (`Guide::words`) as the RGBA32_UINT texel buffer the kernel reads.
    pub fn new(context: &Arc<Context>, words: &[u32]) -> Result<GuidingProbeRunner> {
        Ok(GuidingProbeRunner(TexelBufferProbe::new(
            context,
            &kernels::PROBE_GUIDING,
            "the guide functions",
            Resource::Guide,
            words,
        )?))
    }

    /// Evaluates the guide functions on every input and returns the outputs in order.
    pub fn run(&self, inputs: &[GuidingProbeInput]) -> Result<Vec<GuidingProbeOutput>> {
        self.0.run(inputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn structs_match_the_std430_declarations() {
        // vec4 position, normal, direction, random_numbers
        assert_eq!(size_of::<GuidingProbeInput>(), 64);
        assert_eq!(offset_of!(GuidingProbeInput, normal), 16);
        assert_eq!(offset_of!(GuidingProbeInput, direction), 32);
        assert_eq!(offset_of!(GuidingProbeInput, random_numbers), 48);
        // uvec4 cell_bin; vec4 sampled_density
        assert_eq!(size_of::<GuidingProbeOutput>(), 32);
        assert_eq!(offset_of!(GuidingProbeOutput, sampled_density), 16);
    }
}
