//! The texture probe (`glsl/probe_sample_texture.comp`): runs the functions of
//! `glsl/textures.glsl` on a buffer of inputs against an atlas and its slots, so that tests
//! can compare them with their Rust twins (`crate::cpu::textures`). It has bindings of its
//! own (an RGBA8 texel buffer and the slots, no scene), which it gives `Probe`.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{IVec2, Vec2, Vec4};

use crate::error::{Error, Result};
use crate::kernels::{self, Bound, Resource};
use crate::probe::runner::Probe;
use crate::render::gpu_textures::{GpuTextureSlot, TextureAtlas};
use crate::vk::{Buffer, Context, TexelBufferView};

/// `probe_input_t` of `glsl/probe_sample_texture.comp` (48 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct TextureProbeInput {
    /// xy: texture coordinates for `sample_texture`; z: the argument of `srgb_to_linear`;
    /// w: 0.
    pub tex_coord: [f32; 4],
    /// xy: the texel of `get_texel`; z, w: coordinate and size for `wrap_texel_coordinate`.
    pub texel_and_wrap: [i32; 4],
    /// x: index of the slot; y: the wrap mode of `wrap_texel_coordinate`; zw: 0.
    pub slot_and_mode: [u32; 4],
}

impl TextureProbeInput {
    /// The input for one evaluation of every function on slot `slot_index`.
    /// \param wrap (coordinate, size, wrap mode) for `wrap_texel_coordinate`.
    pub fn new(
        slot_index: u32,
        tex_coord: Vec2,
        texel: IVec2,
        srgb_value: f32,
        wrap: (i32, i32, u32),
    ) -> TextureProbeInput {
        TextureProbeInput {
            tex_coord: [tex_coord.x, tex_coord.y, srgb_value, 0.0],
            texel_and_wrap: [texel.x, texel.y, wrap.0, wrap.1],
            slot_and_mode: [slot_index, wrap.2, 0, 0],
        }
    }

    /// The texture coordinates of `sample_texture`.
    pub fn tex_coord(&self) -> Vec2 {
        Vec2::new(self.tex_coord[0], self.tex_coord[1])
    }

    /// The texel of `get_texel`.
    pub fn texel(&self) -> IVec2 {
        IVec2::new(self.texel_and_wrap[0], self.texel_and_wrap[1])
    }
}

/// `probe_output_t` of `glsl/probe_sample_texture.comp` (64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct TextureProbeOutput {
    /// `sample_texture(slot, tex_coord.xy)`.
    pub sampled: [f32; 4],
    /// `get_texel(slot, texel_and_wrap.xy)`.
    pub texel: [f32; 4],
    /// xy: `transform_tex_coord(slot, tex_coord.xy)`; z: `srgb_to_linear(tex_coord.z)`;
    /// w: 0.
    pub transformed_and_linear: [f32; 4],
    /// x: `wrap_texel_coordinate(...)`; yzw: 0.
    pub wrapped: [i32; 4],
}

impl TextureProbeOutput {
    /// What `sample_texture` returned.
    pub fn sampled(&self) -> Vec4 {
        Vec4::from_array(self.sampled)
    }

    /// What `get_texel` returned.
    pub fn texel(&self) -> Vec4 {
        Vec4::from_array(self.texel)
    }

    /// What `transform_tex_coord` returned.
    pub fn transformed(&self) -> Vec2 {
        Vec2::new(
            self.transformed_and_linear[0],
            self.transformed_and_linear[1],
        )
    }
}

/// Runs the texture probe against one atlas and its slots.
pub struct TextureProbeRunner {
    probe: Probe,
    texels: TexelBufferView,
    slots: Buffer,
}

impl TextureProbeRunner {
    /// Uploads the atlas's texels (an RGBA8_UINT texel buffer) and `slots` (at least one).
    pub fn new(
        context: &Arc<Context>,
        atlas: &TextureAtlas,
        slots: &[GpuTextureSlot],
    ) -> Result<TextureProbeRunner> {
        if slots.is_empty() {
            return Err(Error::InvalidSettings(
                "the texture probe needs at least one texture slot".into(),
            ));
        }
        let texels = TexelBufferView::rgba8_uint(
            context,
            Buffer::with_data(
                context,
                "probe texture texels",
                &atlas.texels,
                vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            )?,
            "probe textures",
        )?;
        let slots = Buffer::with_data(
            context,
            "probe texture slots",
            slots,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        Ok(TextureProbeRunner {
            probe: Probe::embedded(
                context,
                &kernels::PROBE_SAMPLE_TEXTURE,
                &[],
                "the texture functions",
            )?,
            texels,
            slots,
        })
    }

    /// Evaluates the texture functions on every input and returns the outputs in order.
    pub fn run(&self, inputs: &[TextureProbeInput]) -> Result<Vec<TextureProbeOutput>> {
        let resource = |resource| match resource {
            Resource::TextureTexels => Some(Bound::TexelBuffer(&self.texels)),
            Resource::TextureSlots => Some(Bound::Buffer(&self.slots)),
            _ => None,
        };
        self.probe.run(resource, inputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn structs_match_the_std430_declarations() {
        // vec4 tex_coord; ivec4 texel_and_wrap; uvec4 slot_and_mode
        assert_eq!(size_of::<TextureProbeInput>(), 48);
        assert_eq!(offset_of!(TextureProbeInput, texel_and_wrap), 16);
        assert_eq!(offset_of!(TextureProbeInput, slot_and_mode), 32);
        // vec4 sampled; vec4 texel; vec4 transformed_and_linear; ivec4 wrapped
        assert_eq!(size_of::<TextureProbeOutput>(), 64);
        assert_eq!(offset_of!(TextureProbeOutput, texel), 16);
        assert_eq!(offset_of!(TextureProbeOutput, transformed_and_linear), 32);
        assert_eq!(offset_of!(TextureProbeOutput, wrapped), 48);
    }
}
