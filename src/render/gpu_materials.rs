//! The materials, per-triangle shading data and textures of `glsl/materials.glsl`, byte for
//! byte: `GpuTriangleShading` (`SHADING_TEXEL_COUNT` RGBA32 texels per triangle) and
//! `GpuMaterial` (`MATERIAL_TEXEL_COUNT` texels per material, laid out by the `MATERIAL_TEXEL_*`
//! of `glsl/shared.h`), with layout tests.

use bytemuck::{Pod, Zeroable};

use crate::contract::{
    EXTRA_SHADING_TEXEL_COUNT, MATERIAL_FACTOR_TEXEL_COUNT, MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK,
    MATERIAL_TEXTURE_SLOT_COUNT, SHADING_TEXEL_COUNT, TEXTURE_FLAG_TEX_COORD_1,
};
use crate::cpu::sheen_albedo_table::SHEEN_ALBEDO;
use crate::render::gpu_textures::{GpuTextureSlot, TextureAtlas};
use crate::scene::material_params::{MATERIAL_PARAMS, MATERIAL_TEXTURES};
use crate::scene::materials::{
    ExtraVertexAttributes, PbrMaterial, SceneMaterials, TextureBinding, TriangleShading,
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

/// One triangle's extra vertex attributes as `get_vertex_color()` reads them after its
/// `GpuTriangleShading` (`EXTRA_SHADING_TEXEL_COUNT` texels, 48 bytes), in scenes whose
/// `SPEC_SCENE_VERTEX_ATTRIBUTES` is not 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuExtraShading {
    /// COLOR_0 of vertices 0 and 1, each RGBA as two `packUnorm2x16` words (rg, ba).
    pub colors_01: [u32; 4],
    /// COLOR_0 of vertex 2 (two words), TEXCOORD_1 of vertex 0 (float bits).
    pub color_2_tex_coord_1_0: [u32; 4],
    /// TEXCOORD_1 of vertices 1 and 2 (float bits).
    pub tex_coords_1_12: [u32; 4],
}

impl GpuExtraShading {
    /// Packs a triangle's extra vertex attributes (colours clamped to [0, 1] and rounded
    /// to 16 bits, as GLSL's `packUnorm2x16`: 1 stays exactly 1).
    pub fn new(extra: &ExtraVertexAttributes) -> GpuExtraShading {
        let unorm16 = |v: f32| (v.clamp(0.0, 1.0) * 65535.0).round() as u32;
        let pack = |a: f32, b: f32| unorm16(a) | (unorm16(b) << 16);
        let [c0, c1, c2] = extra.colors;
        let [t0, t1, t2] = extra.tex_coords_1;
        GpuExtraShading {
            colors_01: [
                pack(c0.x, c0.y),
                pack(c0.z, c0.w),
                pack(c1.x, c1.y),
                pack(c1.z, c1.w),
            ],
            color_2_tex_coord_1_0: [
                pack(c2.x, c2.y),
                pack(c2.z, c2.w),
                t0.x.to_bits(),
                t0.y.to_bits(),
            ],
            tex_coords_1_12: [t1.x, t1.y, t2.x, t2.y].map(f32::to_bits),
        }
    }
}

/// The words of the shading binding for the triangles of `materials` at `order` (indices
/// into `materials.triangles`, in the order the kernels index them): each triangle's
/// `GpuTriangleShading`, followed by its `GpuExtraShading` where
/// `SceneMaterials::vertex_attributes` is not 0 (only then do the extra tables exist).
pub fn shading_texel_words(
    materials: &SceneMaterials,
    order: impl ExactSizeIterator<Item = usize>,
) -> Vec<u32> {
    let extra = materials.vertex_attributes() != 0;
    let stride = if extra {
        SHADING_TEXEL_COUNT + EXTRA_SHADING_TEXEL_COUNT
    } else {
        SHADING_TEXEL_COUNT
    };
    let mut words = Vec::with_capacity(order.len() * 4 * stride as usize);
    for index in order {
        let triangle = &materials.triangles[index];
        words.extend_from_slice(bytemuck::cast_slice(&[GpuTriangleShading::new(triangle)]));
        if extra {
            words.extend_from_slice(bytemuck::cast_slice(&[GpuExtraShading::new(
                &materials.extra.get(index),
            )]));
        }
    }
    words
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
            if let Some(TextureBinding {
                texture,
                transform,
                tex_coord,
            }) = (slot.get)(material)
            {
                let index = texture as usize;
                let mut packed = GpuTextureSlot::new(
                    atlas.first_texels[index],
                    &scene.textures[index],
                    slot.srgb,
                    &transform,
                );
                if tex_coord == 1 {
                    packed.flags |= TEXTURE_FLAG_TEX_COORD_1;
                }
                textures[slot.slot as usize] = packed;
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
    use crate::contract::{MATERIAL_TEXEL_COUNT, VERTEX_ATTRIBUTE_COLOR};
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
    fn extra_shading_matches_get_vertex_color() {
        assert_eq!(
            size_of::<GpuExtraShading>(),
            16 * EXTRA_SHADING_TEXEL_COUNT as usize
        );
        let extra = ExtraVertexAttributes {
            colors: [
                glam::Vec4::new(1.0, 0.0, 0.5, 1.0),
                glam::Vec4::ONE,
                glam::Vec4::new(2.0, -1.0, 0.25, 0.0),
            ],
            tex_coords_1: [glam::Vec2::new(0.5, 0.25), glam::Vec2::X, glam::Vec2::Y],
        };
        let packed = GpuExtraShading::new(&extra);
        // packUnorm2x16: x in the low half; 1 is 65535 and unpacks to 1 exactly
        assert_eq!(packed.colors_01[0], 0xFFFF);
        assert_eq!(packed.colors_01[1], 0x8000 | (0xFFFF << 16));
        assert_eq!(packed.colors_01[2..], [0xFFFF_FFFF; 2]);
        // Out of range: clamped
        assert_eq!(packed.color_2_tex_coord_1_0[0], 0xFFFF);
        assert_eq!(packed.color_2_tex_coord_1_0[1], 0x4000);
        assert_eq!(
            packed.color_2_tex_coord_1_0[2..],
            [0.5f32.to_bits(), 0.25f32.to_bits()]
        );
        assert_eq!(
            packed.tex_coords_1_12,
            [1.0f32, 0.0, 0.0, 1.0].map(f32::to_bits)
        );
    }

    /// The materials of one plain triangle (no extra attribute tables).
    fn one_triangle() -> SceneMaterials {
        SceneMaterials::from_plain(&[crate::scene::Triangle::new(
            [glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y],
            glam::Vec3::ONE,
            glam::Vec3::ZERO,
            false,
        )
        .expect("a triangle")])
    }

    #[test]
    fn shading_words_hold_the_extra_texels_only_where_a_table_exists() {
        let plain_materials = one_triangle();
        let plain = shading_texel_words(&plain_materials, 0..1);
        assert_eq!(plain.len(), 4 * SHADING_TEXEL_COUNT as usize);
        let mut coloured = one_triangle();
        coloured.extra.colors = Some(vec![[glam::Vec4::new(1.0, 0.0, 0.0, 1.0); 3]]);
        assert_eq!(coloured.vertex_attributes(), VERTEX_ATTRIBUTE_COLOR);
        let extended = shading_texel_words(&coloured, 0..1);
        assert_eq!(
            extended.len(),
            4 * (SHADING_TEXEL_COUNT + EXTRA_SHADING_TEXEL_COUNT) as usize
        );
        assert_eq!(extended[..plain.len()], plain[..]);
    }

    #[test]
    fn the_twin_of_get_vertex_color_reads_the_packed_colors_back() {
        use crate::cpu::gltf_surface::{get_vertex_color, SurfaceTexels};
        use glam::{Vec3, Vec4};
        let mut materials = one_triangle();
        let colors = [
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::new(0.0, 1.0, 0.0, 0.5),
            Vec4::new(0.0, 0.0, 1.0, 0.0),
        ];
        materials.extra.colors = Some(vec![colors]);
        let words = shading_texel_words(&materials, 0..1);
        let texels = SurfaceTexels {
            triangles: &[],
            shading: &words,
            materials: &[],
            texture_texels: &[],
            scene_texture_slots: 0,
            scene_has_layers: false,
            scene_vertex_attributes: VERTEX_ATTRIBUTE_COLOR,
        };
        assert_eq!(get_vertex_color(&texels, 0, Vec3::X), colors[0]);
        let middle = get_vertex_color(&texels, 0, Vec3::splat(1.0 / 3.0));
        // 0.5 is 32768 / 65535 after packing
        let expected = Vec4::new(1.0, 1.0, 1.0, 1.0 + 32768.0 / 65535.0) / 3.0;
        assert!(middle.abs_diff_eq(expected, 1e-6), "{middle}");
        // A scene without vertex colours: white, whatever the words hold
        let plain = SurfaceTexels {
            scene_vertex_attributes: 0,
            ..texels
        };
        assert_eq!(get_vertex_color(&plain, 0, Vec3::X), Vec4::ONE);
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
