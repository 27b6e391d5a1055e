//! The materials, per-triangle shading data and textures of `glsl/materials.glsl`, byte for
//! byte: `GpuTriangleShading` (`SHADING_TEXEL_COUNT` RGBA32 texels per triangle) and
//! `GpuMaterial` (`MATERIAL_TEXEL_COUNT` texels per material, laid out by the `MATERIAL_TEXEL_*`
//! of `glsl/shared.h`), with layout tests.

use bytemuck::{Pod, Zeroable};

use crate::contract::{
    MATERIAL_FACTOR_TEXEL_COUNT, MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK,
    MATERIAL_TEXTURE_SLOT_COUNT,
};
use crate::cpu::sheen_albedo_table::SHEEN_ALBEDO;
use crate::render::gpu_textures::{GpuTextureSlot, TextureAtlas};
use crate::scene::material_params::{MATERIAL_PARAMS, MATERIAL_TEXTURES};
use crate::scene::materials::{PbrMaterial, SceneMaterials, TextureBinding, TriangleShading};

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
    /// The factor texels: each parameter of `MATERIAL_PARAMS` at its `gpu` words (texel
    /// `MATERIAL_TEXEL_*`, components), 0 where none is.
    pub factors: [[u32; 4]; MATERIAL_FACTOR_TEXEL_COUNT as usize],
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
    /// Packs a material by the parameter table; `atlas` gives where each texture's texels
    /// start.
    pub fn new(
        material: &PbrMaterial,
        scene: &SceneMaterials,
        atlas: &TextureAtlas,
    ) -> GpuMaterial {
        let mut factors = [[0; 4]; MATERIAL_FACTOR_TEXEL_COUNT as usize];
        for gpu in MATERIAL_PARAMS
            .iter()
            .filter_map(|param| param.gpu.as_ref())
        {
            let words = (gpu.pack)(material);
            let texel = &mut factors[gpu.texel as usize];
            for k in 0..gpu.count as usize {
                texel[gpu.component as usize + k] = words[k];
            }
        }
        let mut textures = [GpuTextureSlot::zeroed(); MATERIAL_TEXTURE_SLOT_COUNT as usize];
        for slot in MATERIAL_TEXTURES {
            if let Some(TextureBinding { texture, transform }) = (slot.get)(material) {
                let index = texture as usize;
                textures[slot.slot as usize] = GpuTextureSlot::new(
                    atlas.first_texels[index],
                    &scene.textures[index],
                    slot.srgb,
                    &transform,
                );
            }
        }
        GpuMaterial { factors, textures }
    }

    /// Bit (1 << `MATERIAL_TEXTURE_*`) per texture slot that holds a texture (the
    /// `texture_mask` parameter's word).
    pub fn texture_mask(&self) -> u32 {
        self.factors[MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK as usize][1]
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
    materials
        .iter()
        .fold(0, |slots, material| slots | material.texture_mask())
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
        // The layout of glsl/shared.h: the factor texels, then the texture slots, three
        // texels each (where each parameter lies is `material_params`' tests').
        let texel = |t: u32| 16 * t as usize;
        assert_eq!(
            MATERIAL_TEXEL_COUNT,
            MATERIAL_FACTOR_TEXEL_COUNT + 3 * MATERIAL_TEXTURE_SLOT_COUNT
        );
        assert_eq!(size_of::<GpuMaterial>(), texel(MATERIAL_TEXEL_COUNT));
        assert_eq!(offset_of!(GpuMaterial, factors), 0);
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
        let mask = MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK as usize;
        materials[0].factors[mask][1] = 1 << MATERIAL_TEXTURE_BASE_COLOR;
        materials[2].factors[mask] = [
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
