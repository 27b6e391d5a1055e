//! Textures as the shaders read them (`glsl/textures.glsl`): every texture's RGBA8 texels
//! concatenated in one texel buffer (`TextureAtlas`, bound at `BINDING_TEXTURE_TEXELS` as
//! R8G8B8A8_UINT), and per use of a texture a `GpuTextureSlot` (`texture_slot_t`) that says
//! where its texels start, its size, wrap modes, filter, colour space and
//! KHR_texture_transform.

use bytemuck::{Pod, Zeroable};

use crate::contract::{
    TEXTURE_FLAG_NEAREST, TEXTURE_FLAG_SRGB, TEXTURE_WRAP_S_SHIFT, TEXTURE_WRAP_T_SHIFT,
    WRAP_CLAMP_TO_EDGE, WRAP_MIRRORED_REPEAT, WRAP_REPEAT,
};
use crate::scene::textures::{Texture, TextureError, TextureTransform, WrapMode};

/// `texture_slot_t` of `glsl/textures.glsl` as packed: `TEXTURE_SLOT_TEXEL_COUNT` (3)
/// RGBA32_UINT texels, 48 bytes, unpacked by `unpack_texture_slot`.
#[repr(C)]
#[derive(Pod, Zeroable, Clone, Copy, Debug, PartialEq)]
pub struct GpuTextureSlot {
    /// Index of the texture's texel (0, 0) in the atlas.
    pub first_texel: u32,
    /// Width in texels, at least 1.
    pub width: u32,
    /// Height in texels, at least 1.
    pub height: u32,
    /// `TEXTURE_FLAG_SRGB`, `TEXTURE_FLAG_NEAREST` and the wrap modes (`WRAP_*` at
    /// `TEXTURE_WRAP_S_SHIFT` and `TEXTURE_WRAP_T_SHIFT`).
    pub flags: u32,
    /// xyz: row 0 of the texture transform (u' = row 0 · (u, v, 1)); w: 0.
    pub transform_row0: [f32; 4],
    /// xyz: row 1 of the texture transform (v' = row 1 · (u, v, 1)); w: 0.
    pub transform_row1: [f32; 4],
}

/// The `WRAP_*` value of a wrap mode.
pub fn wrap_mode_code(mode: WrapMode) -> u32 {
    match mode {
        WrapMode::Repeat => WRAP_REPEAT,
        WrapMode::ClampToEdge => WRAP_CLAMP_TO_EDGE,
        WrapMode::MirroredRepeat => WRAP_MIRRORED_REPEAT,
    }
}

impl GpuTextureSlot {
    /// The slot of `texture`, whose texels start at `atlas_first_texel` in the atlas
    /// (`TextureAtlas::first_texels`); `srgb` for colour textures (base colour, emission),
    /// false for data (metallic-roughness, normals).
    pub fn new(
        atlas_first_texel: u32,
        texture: &Texture,
        srgb: bool,
        transform: &TextureTransform,
    ) -> GpuTextureSlot {
        let mut flags = (wrap_mode_code(texture.wrap_s) << TEXTURE_WRAP_S_SHIFT)
            | (wrap_mode_code(texture.wrap_t) << TEXTURE_WRAP_T_SHIFT);
        if srgb {
            flags |= TEXTURE_FLAG_SRGB;
        }
        if texture.nearest {
            flags |= TEXTURE_FLAG_NEAREST;
        }
        let [row0, row1] = transform.matrix;
        GpuTextureSlot {
            first_texel: atlas_first_texel,
            width: texture.width,
            height: texture.height,
            flags,
            transform_row0: [row0[0], row0[1], row0[2], 0.0],
            transform_row1: [row1[0], row1[1], row1[2], 0.0],
        }
    }

    /// The three uvec4s that `unpack_texture_slot(a, b, c)` takes (floats as their bits).
    pub fn to_texels(&self) -> [[u32; 4]; 3] {
        bytemuck::cast(*self)
    }
}

/// Every texture's texels, concatenated in the order of the textures.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextureAtlas {
    /// All texels, texture after texture; at least one (a zero texel when there are no
    /// textures), since a Vulkan buffer cannot be empty.
    pub texels: Vec<[u8; 4]>,
    /// Index in `texels` of each texture's texel (0, 0).
    pub first_texels: Vec<u32>,
}

impl TextureAtlas {
    /// Concatenates `textures`. Fails when they need more than `max_texels` texels in all
    /// (the device's `maxTexelBufferElements`) or more than a u32 can index.
    pub fn new(textures: &[Texture], max_texels: u64) -> Result<TextureAtlas, TextureError> {
        let total: u64 = textures.iter().map(|t| t.texels.len() as u64).sum();
        let limit = max_texels.min(u64::from(u32::MAX));
        if total > limit {
            return Err(TextureError::AtlasTooLarge {
                texels: total,
                limit,
            });
        }
        let mut texels = Vec::with_capacity(total.max(1) as usize);
        let mut first_texels = Vec::with_capacity(textures.len());
        for texture in textures {
            // total <= u32::MAX, so every start fits.
            first_texels.push(texels.len() as u32);
            texels.extend_from_slice(&texture.texels);
        }
        if texels.is_empty() {
            texels.push([0; 4]);
        }
        Ok(TextureAtlas {
            texels,
            first_texels,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contract::{TEXTURE_SLOT_TEXEL_COUNT, TEXTURE_WRAP_MASK};
    use crate::scene::textures::DecodedImage;
    use std::mem::{offset_of, size_of};

    fn texture(width: u32, height: u32, value: u8) -> Texture {
        let image = DecodedImage {
            width,
            height,
            texels: vec![[value; 4]; (width * height) as usize],
        };
        Texture::new(image, WrapMode::MirroredRepeat, WrapMode::ClampToEdge, true)
    }

    #[test]
    fn slot_matches_the_texels_of_texture_slot_t() {
        // uvec4(first_texel, width, height, flags); vec4 transform_row0; vec4 transform_row1
        assert_eq!(
            size_of::<GpuTextureSlot>(),
            16 * TEXTURE_SLOT_TEXEL_COUNT as usize
        );
        assert_eq!(offset_of!(GpuTextureSlot, first_texel), 0);
        assert_eq!(offset_of!(GpuTextureSlot, width), 4);
        assert_eq!(offset_of!(GpuTextureSlot, height), 8);
        assert_eq!(offset_of!(GpuTextureSlot, flags), 12);
        assert_eq!(offset_of!(GpuTextureSlot, transform_row0), 16);
        assert_eq!(offset_of!(GpuTextureSlot, transform_row1), 32);
    }

    #[test]
    fn slot_packs_flags_and_transform() {
        let transform = TextureTransform::from_gltf([0.5, -1.0], 0.0, [2.0, 3.0]);
        let slot = GpuTextureSlot::new(7, &texture(4, 2, 0), true, &transform);
        assert_eq!((slot.first_texel, slot.width, slot.height), (7, 4, 2));
        assert_eq!(slot.flags & TEXTURE_FLAG_SRGB, TEXTURE_FLAG_SRGB);
        assert_eq!(slot.flags & TEXTURE_FLAG_NEAREST, TEXTURE_FLAG_NEAREST);
        assert_eq!(
            (slot.flags >> TEXTURE_WRAP_S_SHIFT) & TEXTURE_WRAP_MASK,
            WRAP_MIRRORED_REPEAT
        );
        assert_eq!(
            (slot.flags >> TEXTURE_WRAP_T_SHIFT) & TEXTURE_WRAP_MASK,
            WRAP_CLAMP_TO_EDGE
        );
        assert_eq!(slot.transform_row0, [2.0, 0.0, 0.5, 0.0]);
        assert_eq!(slot.transform_row1, [0.0, 3.0, -1.0, 0.0]);
        let texels = slot.to_texels();
        assert_eq!(texels[0], [7, 4, 2, slot.flags]);
        assert_eq!(texels[1][0], 2.0f32.to_bits());
        // The flags' fields do not overlap.
        let all = TEXTURE_FLAG_SRGB
            | TEXTURE_FLAG_NEAREST
            | (TEXTURE_WRAP_MASK << TEXTURE_WRAP_S_SHIFT)
            | (TEXTURE_WRAP_MASK << TEXTURE_WRAP_T_SHIFT);
        assert_eq!(all.count_ones(), 6);
        let plain = GpuTextureSlot::new(0, &texture(1, 1, 0), false, &TextureTransform::identity());
        assert_eq!(plain.flags & (TEXTURE_FLAG_SRGB), 0);
    }

    #[test]
    fn atlas_concatenates_and_checks_its_limit() {
        let textures = [texture(2, 2, 1), texture(3, 1, 2), texture(1, 1, 3)];
        let atlas = TextureAtlas::new(&textures, 8).expect("fits");
        assert_eq!(atlas.first_texels, vec![0, 4, 7]);
        assert_eq!(atlas.texels.len(), 8);
        assert_eq!(atlas.texels[4], [2; 4]);
        assert_eq!(atlas.texels[7], [3; 4]);
        let error = TextureAtlas::new(&textures, 7).unwrap_err();
        assert_eq!(
            error,
            TextureError::AtlasTooLarge {
                texels: 8,
                limit: 7
            }
        );
        assert_eq!(error.to_string().lines().count(), 1);
        let empty = TextureAtlas::new(&[], 0).expect("no textures");
        assert_eq!((empty.texels.len(), empty.first_texels.len()), (1, 0));
    }
}
