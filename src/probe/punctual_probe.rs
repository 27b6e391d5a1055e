//! The punctual lights' probe (`glsl/probe_punctual_lights.comp`): runs the functions of
//! `glsl/punctual_lights.glsl` on a buffer of inputs against the words of a list of
//! punctual lights, so that tests can compare them with their Rust twins
//! (`crate::cpu::punctual_lights`). It binds the lights' texel buffer (no scene), which it
//! gives `Probe`.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::error::Result;
use crate::kernels::{self, Resource};
use crate::probe::runner::TexelBufferProbe;
use crate::vk::Context;

/// `probe_input_t` of `glsl/probe_punctual_lights.comp` (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PunctualProbeInput {
    /// xyz: the shading point of `get_punctual_irradiance`, world space; w: 0.
    pub origin: [f32; 4],
    /// x: the light of `get_punctual_light`; yzw: 0.
    pub light_index: [u32; 4],
}

impl PunctualProbeInput {
    /// The input that evaluates light `light_index` at `origin`.
    pub fn new(light_index: u32, origin: Vec3) -> PunctualProbeInput {
        PunctualProbeInput {
            origin: origin.extend(0.0).to_array(),
            light_index: [light_index, 0, 0, 0],
        }
    }

    /// The shading point.
    pub fn origin(&self) -> Vec3 {
        Vec3::from_slice(&self.origin[..3])
    }
}

/// `probe_output_t` of `glsl/probe_punctual_lights.comp` (112 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PunctualProbeOutput {
    /// rgb: what `get_punctual_irradiance` returned; w: its `out_distance`.
    pub irradiance_distance: [f32; 4],
    /// xyz: its `out_direction`; w: 0.
    pub direction: [f32; 4],
    /// x: the light's kind; y: `get_punctual_light_count()`; zw: 0.
    pub kind_count: [u32; 4],
    /// xyz: the light's position; w: 0.
    pub position: [f32; 4],
    /// xyz: the light's direction; w: 0.
    pub light_direction: [f32; 4],
    /// rgb: the light's intensity; a: 0.
    pub intensity: [f32; 4],
    /// x: the light's cone scale; y: its cone offset; zw: 0.
    pub cone: [f32; 4],
}

impl PunctualProbeOutput {
    /// What `get_punctual_irradiance` returned: (irradiance, direction, distance), as the
    /// twin returns them.
    pub fn irradiance(&self) -> (Vec3, Vec3, f32) {
        (
            Vec3::from_slice(&self.irradiance_distance[..3]),
            Vec3::from_slice(&self.direction[..3]),
            self.irradiance_distance[3],
        )
    }
}

/// Runs the punctual lights' probe against one list of lights.
pub struct PunctualProbeRunner(TexelBufferProbe);

impl PunctualProbeRunner {
    /// Uploads `words` (`gpu_punctual_light_words`: the count, then the lights) as the
    /// RGBA32_UINT texel buffer the kernel reads.
    pub fn new(context: &Arc<Context>, words: &[u32]) -> Result<PunctualProbeRunner> {
        Ok(PunctualProbeRunner(TexelBufferProbe::new(
            context,
            &kernels::PROBE_PUNCTUAL_LIGHTS,
            "the punctual light functions",
            Resource::PunctualLights,
            words,
        )?))
    }

    /// Evaluates the punctual light functions on every input and returns the outputs in
    /// order; each input's light must be one of the uploaded lights.
    pub fn run(&self, inputs: &[PunctualProbeInput]) -> Result<Vec<PunctualProbeOutput>> {
        self.0.run(inputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn structs_match_the_std430_declarations() {
        // vec4 origin; uvec4 light_index
        assert_eq!(size_of::<PunctualProbeInput>(), 32);
        assert_eq!(offset_of!(PunctualProbeInput, light_index), 16);
        // vec4 irradiance_distance, direction; uvec4 kind_count; vec4 position,
        // light_direction, intensity, cone
        assert_eq!(size_of::<PunctualProbeOutput>(), 112);
        assert_eq!(offset_of!(PunctualProbeOutput, direction), 16);
        assert_eq!(offset_of!(PunctualProbeOutput, kind_count), 32);
        assert_eq!(offset_of!(PunctualProbeOutput, position), 48);
        assert_eq!(offset_of!(PunctualProbeOutput, light_direction), 64);
        assert_eq!(offset_of!(PunctualProbeOutput, intensity), 80);
        assert_eq!(offset_of!(PunctualProbeOutput, cone), 96);
    }
}
