//! The materials, per-triangle shading data and textures of `glsl/materials.glsl`, byte for
//! byte: `GpuTriangleShading` (`SHADING_TEXEL_COUNT` RGBA32 texels per triangle) and
//! `GpuMaterial` (`MATERIAL_TEXEL_COUNT` texels per material, laid out by the `MATERIAL_TEXEL_*`
//! of `glsl/shared.h`), with layout tests.

use bytemuck::{Pod, Zeroable};

use crate::contract::{
    ALPHA_MODE_BLEND, ALPHA_MODE_MASK, ALPHA_MODE_OPAQUE, MATERIAL_FLAG_UNLIT,
    MATERIAL_TEXTURE_BASE_COLOR, MATERIAL_TEXTURE_CLEARCOAT, MATERIAL_TEXTURE_CLEARCOAT_NORMAL,
    MATERIAL_TEXTURE_CLEARCOAT_ROUGHNESS, MATERIAL_TEXTURE_EMISSIVE,
    MATERIAL_TEXTURE_METALLIC_ROUGHNESS, MATERIAL_TEXTURE_NORMAL, MATERIAL_TEXTURE_SHEEN_COLOR,
    MATERIAL_TEXTURE_SHEEN_ROUGHNESS, MATERIAL_TEXTURE_SLOT_COUNT, MATERIAL_TEXTURE_SPECULAR,
    MATERIAL_TEXTURE_SPECULAR_COLOR, MATERIAL_TEXTURE_THICKNESS, MATERIAL_TEXTURE_TRANSMISSION,
};
use crate::cpu::sheen_albedo_table::SHEEN_ALBEDO;
use crate::render::gpu_textures::{GpuTextureSlot, TextureAtlas};
use crate::scene::materials::{
    AlphaMode, PbrMaterial, SceneMaterials, TextureBinding, TriangleShading,
};

/// One triangle's shading data as `get_shading_texel()` reads it (128 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuTriangleShading {
    /// xyz: vertex normal i (world space, unit); w of the first: the material index's bits.
    pub normals: [[f32; 4]; 3],
    /// uv_0, uv_1.
    pub tex_coords_01: [f32; 4],
    /// uv_2, 0, 0.
    pub tex_coords_2: [f32; 4],
    /// Tangent i (xyz) and bitangent sign (w).
    pub tangents: [[f32; 4]; 3],
}

/// One material as `get_material_texel()` reads it (768 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Base colour factor (linear RGB, alpha).
    pub base_color: [f32; 4],
    /// rgb: emission factor; a: metallic factor.
    pub emission_metallic: [f32; 4],
    /// Roughness factor, specular factor, ior, normal scale.
    pub roughness_specular_ior_normal_scale: [f32; 4],
    /// rgb: specular colour factor; a: alpha cutoff.
    pub specular_color_alpha_cutoff: [f32; 4],
    /// x: ALPHA_MODE_*; y: bit (1 << MATERIAL_TEXTURE_*) per texture present; zw: 0.
    pub alpha_mode_texture_flags: [u32; 4],
    /// Transmission factor, thickness factor, clearcoat factor, clearcoat roughness factor.
    pub transmission_thickness_clearcoat: [f32; 4],
    /// rgb: the volume's absorption coefficient per unit length; a: clearcoat normal scale.
    pub attenuation_clearcoat_normal_scale: [f32; 4],
    /// x: MATERIAL_FLAG_* bits; yzw: 0.
    pub flags: [u32; 4],
    /// rgb: the sheen colour; a: the sheen roughness.
    pub sheen: [f32; 4],
    /// The texture slots in MATERIAL_TEXTURE_* order (zeros where absent).
    pub textures: [GpuTextureSlot; MATERIAL_TEXTURE_SLOT_COUNT as usize],
}

impl GpuTriangleShading {
    /// Packs a triangle's shading data.
    pub fn new(shading: &TriangleShading) -> GpuTriangleShading {
        let [n0, n1, n2] = shading.normals;
        let [t0, t1, t2] = shading.tex_coords;
        GpuTriangleShading {
            normals: [
                [n0.x, n0.y, n0.z, f32::from_bits(shading.material)],
                n1.extend(0.0).to_array(),
                n2.extend(0.0).to_array(),
            ],
            tex_coords_01: [t0.x, t0.y, t1.x, t1.y],
            tex_coords_2: [t2.x, t2.y, 0.0, 0.0],
            tangents: shading.tangents.map(|t| t.to_array()),
        }
    }
}

impl GpuMaterial {
    /// Packs a material; `atlas` gives where each texture's texels start.
    pub fn new(
        material: &PbrMaterial,
        scene: &SceneMaterials,
        atlas: &TextureAtlas,
    ) -> GpuMaterial {
        let (alpha_mode, cutoff) = match material.alpha_mode {
            AlphaMode::Opaque => (ALPHA_MODE_OPAQUE, 0.0),
            AlphaMode::Mask { cutoff } => (ALPHA_MODE_MASK, cutoff),
            AlphaMode::Blend => (ALPHA_MODE_BLEND, 0.0),
        };
        let mut flags = 0;
        let mut textures = [GpuTextureSlot::zeroed(); MATERIAL_TEXTURE_SLOT_COUNT as usize];
        let slots = [
            (
                MATERIAL_TEXTURE_BASE_COLOR,
                material.base_color_texture,
                true,
            ),
            (
                MATERIAL_TEXTURE_METALLIC_ROUGHNESS,
                material.metallic_roughness_texture,
                false,
            ),
            (MATERIAL_TEXTURE_NORMAL, material.normal_texture, false),
            (MATERIAL_TEXTURE_EMISSIVE, material.emissive_texture, true),
            (
                MATERIAL_TEXTURE_TRANSMISSION,
                material.transmission.texture,
                false,
            ),
            (
                MATERIAL_TEXTURE_THICKNESS,
                material.transmission.thickness_texture,
                false,
            ),
            (
                MATERIAL_TEXTURE_CLEARCOAT,
                material.clearcoat.texture,
                false,
            ),
            (
                MATERIAL_TEXTURE_CLEARCOAT_ROUGHNESS,
                material.clearcoat.roughness_texture,
                false,
            ),
            (
                MATERIAL_TEXTURE_CLEARCOAT_NORMAL,
                material.clearcoat.normal_texture,
                false,
            ),
            (MATERIAL_TEXTURE_SPECULAR, material.specular_texture, false),
            (
                MATERIAL_TEXTURE_SPECULAR_COLOR,
                material.specular_color_texture,
                true,
            ),
            (
                MATERIAL_TEXTURE_SHEEN_COLOR,
                material.sheen.color_texture,
                true,
            ),
            (
                MATERIAL_TEXTURE_SHEEN_ROUGHNESS,
                material.sheen.roughness_texture,
                false,
            ),
        ];
        for (slot, binding, srgb) in slots {
            if let Some(TextureBinding { texture, transform }) = binding {
                let index = texture as usize;
                flags |= 1 << slot;
                textures[slot as usize] = GpuTextureSlot::new(
                    atlas.first_texels[index],
                    &scene.textures[index],
                    srgb,
                    &transform,
                );
            }
        }
        GpuMaterial {
            base_color: material.base_color.to_array(),
            emission_metallic: material.emission.extend(material.metallic).to_array(),
            roughness_specular_ior_normal_scale: [
                material.roughness,
                material.specular,
                material.ior,
                material.normal_scale,
            ],
            specular_color_alpha_cutoff: material.specular_color.extend(cutoff).to_array(),
            alpha_mode_texture_flags: [alpha_mode, flags, 0, 0],
            transmission_thickness_clearcoat: [
                material.transmission.factor,
                material.transmission.thickness,
                material.clearcoat.factor,
                material.clearcoat.roughness,
            ],
            attenuation_clearcoat_normal_scale: material
                .transmission
                .attenuation
                .extend(material.clearcoat.normal_scale)
                .to_array(),
            flags: [
                if material.unlit {
                    MATERIAL_FLAG_UNLIT
                } else {
                    0
                },
                0,
                0,
                0,
            ],
            sheen: material
                .sheen
                .color
                .extend(material.sheen.roughness)
                .to_array(),
            textures,
        }
    }
}

/// The words of `g_material_texels`: the materials, then the sheen's albedo table
/// (`SHEEN_ALBEDO`, `SHEEN_ALBEDO_TEXEL_COUNT` texels), which `get_sheen_albedo_entry()`
/// reads from the buffer's end.
pub fn material_texel_words(materials: &[GpuMaterial]) -> Vec<u32> {
    let mut words: Vec<u32> = bytemuck::cast_slice(materials).to_vec();
    words.extend(SHEEN_ALBEDO.iter().map(|entry| entry.to_bits()));
    words
}

/// `SCENE_TEXTURE_SLOTS` (`glsl/materials.glsl`): the texture slots (bit
/// 1 << `MATERIAL_TEXTURE_*`) in which some of `materials` has a texture; 0 for none.
pub fn scene_texture_slots(materials: &[GpuMaterial]) -> u32 {
    materials.iter().fold(0, |slots, material| {
        slots | material.alpha_mode_texture_flags[1]
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contract::{MATERIAL_FACTOR_TEXEL_COUNT, MATERIAL_TEXEL_COUNT, SHADING_TEXEL_COUNT};
    use std::mem::{offset_of, size_of};

    #[test]
    fn shading_matches_get_shading_texel() {
        assert_eq!(
            size_of::<GpuTriangleShading>(),
            16 * SHADING_TEXEL_COUNT as usize
        );
        assert_eq!(offset_of!(GpuTriangleShading, normals), 0);
        assert_eq!(offset_of!(GpuTriangleShading, tex_coords_01), 3 * 16);
        assert_eq!(offset_of!(GpuTriangleShading, tex_coords_2), 4 * 16);
        assert_eq!(offset_of!(GpuTriangleShading, tangents), 5 * 16);
    }

    #[test]
    fn material_matches_get_material_texel() {
        use crate::contract::{
            MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK as ALPHA_MODE,
            MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE as ATTENUATION,
            MATERIAL_TEXEL_BASE_COLOR as BASE_COLOR, MATERIAL_TEXEL_EMISSIVE_METALLIC as EMISSIVE,
            MATERIAL_TEXEL_FLAGS as FLAGS,
            MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE as ROUGHNESS,
            MATERIAL_TEXEL_SHEEN as SHEEN, MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF as SPECULAR,
            MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT as TRANSMISSION,
        };
        // The layout of glsl/shared.h: each field at its MATERIAL_TEXEL_* texel, the texture
        // slots after the factors, three texels each.
        let texel = |t: u32| 16 * t as usize;
        assert_eq!(
            MATERIAL_TEXEL_COUNT,
            MATERIAL_FACTOR_TEXEL_COUNT + 3 * MATERIAL_TEXTURE_SLOT_COUNT
        );
        assert_eq!(size_of::<GpuMaterial>(), texel(MATERIAL_TEXEL_COUNT));
        assert_eq!(offset_of!(GpuMaterial, base_color), texel(BASE_COLOR));
        assert_eq!(offset_of!(GpuMaterial, emission_metallic), texel(EMISSIVE));
        assert_eq!(
            offset_of!(GpuMaterial, roughness_specular_ior_normal_scale),
            texel(ROUGHNESS)
        );
        assert_eq!(
            offset_of!(GpuMaterial, specular_color_alpha_cutoff),
            texel(SPECULAR)
        );
        assert_eq!(
            offset_of!(GpuMaterial, alpha_mode_texture_flags),
            texel(ALPHA_MODE)
        );
        assert_eq!(
            offset_of!(GpuMaterial, transmission_thickness_clearcoat),
            texel(TRANSMISSION)
        );
        assert_eq!(
            offset_of!(GpuMaterial, attenuation_clearcoat_normal_scale),
            texel(ATTENUATION)
        );
        assert_eq!(offset_of!(GpuMaterial, flags), texel(FLAGS));
        assert_eq!(offset_of!(GpuMaterial, sheen), texel(SHEEN));
        // The factors fill their texels with no gap: the last factor texel is the last one.
        assert_eq!(
            [
                BASE_COLOR,
                EMISSIVE,
                ROUGHNESS,
                SPECULAR,
                ALPHA_MODE,
                TRANSMISSION,
                ATTENUATION,
                FLAGS,
                SHEEN
            ]
            .iter()
            .max()
            .map(|last| last + 1),
            Some(MATERIAL_FACTOR_TEXEL_COUNT)
        );
        assert_eq!(
            offset_of!(GpuMaterial, textures),
            texel(MATERIAL_FACTOR_TEXEL_COUNT)
        );
        assert_eq!(size_of::<GpuTextureSlot>(), 3 * 16);
    }

    #[test]
    fn the_scenes_texture_slots_are_every_materials_slots() {
        use crate::contract::{MATERIAL_TEXTURE_BASE_COLOR, MATERIAL_TEXTURE_NORMAL};
        let mut materials = [GpuMaterial::zeroed(); 3];
        assert_eq!(scene_texture_slots(&materials), 0);
        materials[0].alpha_mode_texture_flags[1] = 1 << MATERIAL_TEXTURE_BASE_COLOR;
        materials[2].alpha_mode_texture_flags = [
            crate::contract::ALPHA_MODE_MASK,
            1 << MATERIAL_TEXTURE_BASE_COLOR | 1 << MATERIAL_TEXTURE_NORMAL,
            0,
            0,
        ];
        assert_eq!(
            scene_texture_slots(&materials),
            1 << MATERIAL_TEXTURE_BASE_COLOR | 1 << MATERIAL_TEXTURE_NORMAL
        );
    }

    #[test]
    fn the_sheen_table_ends_the_material_texels() {
        use crate::contract::{SHEEN_ALBEDO_SIZE, SHEEN_ALBEDO_TEXEL_COUNT};
        use crate::cpu::layered_bsdf::get_sheen_albedo_entry;
        assert_eq!(
            SHEEN_ALBEDO_TEXEL_COUNT * 4,
            SHEEN_ALBEDO_SIZE * SHEEN_ALBEDO_SIZE
        );
        let materials = [GpuMaterial::zeroed(); 2];
        let words = material_texel_words(&materials);
        let texels = words.len() / 4;
        assert_eq!(
            texels,
            2 * MATERIAL_TEXEL_COUNT as usize + SHEEN_ALBEDO_TEXEL_COUNT as usize
        );
        // get_sheen_albedo_entry(k) reads component k % 4 of texel
        // textureSize - SHEEN_ALBEDO_TEXEL_COUNT + k / 4.
        let first = texels - SHEEN_ALBEDO_TEXEL_COUNT as usize;
        for k in [0usize, 1, 5, 517, 1023] {
            let word = words[4 * (first + k / 4) + k % 4];
            assert_eq!(f32::from_bits(word), get_sheen_albedo_entry(k));
        }
    }
}
