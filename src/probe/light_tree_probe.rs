//! The light tree's probe (`glsl/probe_light_tree.comp`): runs the functions of
//! `glsl/light_tree.glsl` on a buffer of inputs against the words of a lights' texel buffer
//! with a tree (`crate::lights::gpu_emissive::gpu_light_bytes_with_tree`), so that tests can
//! compare them with their Rust twins (`crate::cpu::light_tree`). It binds the lights' texel
//! buffer (no scene), which it gives `Probe`.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::error::Result;
use crate::kernels::{self, Resource};
use crate::probe::runner::TexelBufferProbe;
use crate::vk::Context;

/// `probe_input_t` of `glsl/probe_light_tree.comp` (48 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LightTreeProbeInput {
    /// xyz: the shading point, world space; w: `sample_light_tree`'s random number.
    pub position_random: [f32; 4],
    /// xyz: the receiving side's unit normal (or 0); w: 0.
    pub normal: [f32; 4],
    /// x: the light of `get_light_tree_probability`; yzw: 0.
    pub light_index: [u32; 4],
}

impl LightTreeProbeInput {
    /// The input that samples with `random` at `position` with `normal` and asks for the
    /// probability of `light_index` there.
    pub fn new(position: Vec3, normal: Vec3, random: f32, light_index: u32) -> Self {
        LightTreeProbeInput {
            position_random: position.extend(random).to_array(),
            normal: normal.extend(0.0).to_array(),
            light_index: [light_index, 0, 0, 0],
        }
    }
}

/// `probe_output_t` of `glsl/probe_light_tree.comp` (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LightTreeProbeOutput {
    /// x: the light `sample_light_tree` chose (`NO_LIGHT`: none); y: the tree's depth; zw: 0.
    pub light: [u32; 4],
    /// x: its probability; y: `get_light_tree_probability` of that light; z: of the input's
    /// light; w: the root's `get_light_bounds_importance`.
    pub probabilities: [f32; 4],
}

/// Runs the light tree's probe against one lights' texel buffer.
pub struct LightTreeProbeRunner(TexelBufferProbe);

impl LightTreeProbeRunner {
    /// Uploads `bytes` (`gpu_light_bytes_with_tree`) as the RGBA32_UINT texel buffer the
    /// kernel reads.
    pub fn new(context: &Arc<Context>, bytes: &[u8]) -> Result<LightTreeProbeRunner> {
        Ok(LightTreeProbeRunner(TexelBufferProbe::new(
            context,
            &kernels::PROBE_LIGHT_TREE,
            "the light tree functions",
            Resource::Lights,
            bytes,
        )?))
    }

    /// Evaluates the light tree functions on every input and returns the outputs in order.
    pub fn run(&self, inputs: &[LightTreeProbeInput]) -> Result<Vec<LightTreeProbeOutput>> {
        self.0.run(inputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn structs_match_the_std430_declarations() {
        // vec4 position_random, normal; uvec4 light_index
        assert_eq!(size_of::<LightTreeProbeInput>(), 48);
        assert_eq!(offset_of!(LightTreeProbeInput, normal), 16);
        assert_eq!(offset_of!(LightTreeProbeInput, light_index), 32);
        // uvec4 light; vec4 probabilities
        assert_eq!(size_of::<LightTreeProbeOutput>(), 32);
        assert_eq!(offset_of!(LightTreeProbeOutput, probabilities), 16);
    }
}
