//! Rust twins of the functions of the surface seam's glTF model (`glsl/gltf_surface.glsl`
//! over `glsl/materials.glsl`) that read the scene's texel buffers:
//! `get_surface`, `get_bsdf`, `get_bsdf_density`, `sample_bsdf`, `has_delta_lobe`, `is_opaque_hit` and the
//! lookups they are made of, reading the same words the GPU reads (the packed triangles, `GpuTriangleShading`,
//! `GpuMaterial` and the texture atlas of `crate::render`), with the same maths. The pure
//! functions they call are twins too: `crate::cpu::materials`, `crate::cpu::textures`,
//! `crate::cpu::brdf`, `crate::cpu::layered_bsdf`, `crate::cpu::workshop::get_random_numbers`.

use glam::{UVec2, UVec4, Vec2, Vec3, Vec4};

use crate::contract::{
    ALPHA_MODE_MASK, ALPHA_MODE_OPAQUE, MATERIAL_FACTOR_TEXEL_COUNT, MATERIAL_FLAG_UNLIT,
    MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK, MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE,
    MATERIAL_TEXEL_BASE_COLOR, MATERIAL_TEXEL_COUNT, MATERIAL_TEXEL_EMISSIVE_METALLIC,
    MATERIAL_TEXEL_FLAGS, MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE, MATERIAL_TEXEL_SHEEN,
    MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF, MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT,
    MATERIAL_TEXTURE_BASE_COLOR, MATERIAL_TEXTURE_CLEARCOAT, MATERIAL_TEXTURE_CLEARCOAT_NORMAL,
    MATERIAL_TEXTURE_CLEARCOAT_ROUGHNESS, MATERIAL_TEXTURE_EMISSIVE,
    MATERIAL_TEXTURE_METALLIC_ROUGHNESS, MATERIAL_TEXTURE_NORMAL, MATERIAL_TEXTURE_SHEEN_COLOR,
    MATERIAL_TEXTURE_SHEEN_ROUGHNESS, MATERIAL_TEXTURE_SLOT_COUNT, MATERIAL_TEXTURE_SPECULAR,
    MATERIAL_TEXTURE_SPECULAR_COLOR, MATERIAL_TEXTURE_THICKNESS, MATERIAL_TEXTURE_TRANSMISSION,
    SHADING_TEXEL_COUNT, TRIANGLE_FLAG_DOUBLE_SIDED, TRIANGLE_TEXEL_COUNT,
};
use crate::contract::{
    EXTRA_SHADING_TEXEL_COUNT, TEXTURE_FLAG_TEX_COORD_1, VERTEX_ATTRIBUTE_COLOR,
    VERTEX_ATTRIBUTE_TEX_COORD_1,
};
use crate::cpu::brdf::{
    get_base_material, get_brdf, get_brdf_density, get_brdf_mirror_probability,
    get_brdf_mirror_weight, get_ggx_alpha, sample_brdf, MaterialSample,
};
use crate::cpu::layered_bsdf::{
    get_absorption, get_layered_bsdf, get_layered_density, is_layered, is_refracting,
    sample_layered_bsdf,
};
use crate::cpu::materials::{apply_normal_map, get_barycentrics};
use crate::cpu::surface::{BsdfSample, BSDF_LOBE_DELTA, BSDF_LOBE_REFLECT, BSDF_LOBE_TRANSMIT};
use crate::cpu::texels::{fetch_float_texel, fetch_texel, uint_bits_to_float};
use crate::cpu::textures::{sample_texture, unpack_texture_slot, TextureSlot};
use crate::cpu::workshop::get_random_numbers;
use crate::scene::Triangle;

/// The texel buffers of `glsl/scene.glsl` and `glsl/materials.glsl` as the twins read them:
/// RGBA32_UINT texels, four words each, and the RGBA8 texture atlas.
pub struct SurfaceTexels<'a> {
    /// `g_triangle_texels`: the packed triangles (`GpuTriangle`).
    pub triangles: &'a [u32],
    /// `g_shading_texels`: per-triangle shading data (`GpuTriangleShading`).
    pub shading: &'a [u32],
    /// `g_material_texels`: the materials (`GpuMaterial`).
    pub materials: &'a [u32],
    /// `g_texture_texels`: the atlas (`TextureAtlas::texels`).
    pub texture_texels: &'a [[u8; 4]],
    /// The specialization constant `SCENE_TEXTURE_SLOTS`: the slots (bit
    /// 1 << `MATERIAL_TEXTURE_*`) in which some material has a texture.
    pub scene_texture_slots: u32,
    /// The specialization constant `SCENE_HAS_LAYERS`.
    pub scene_has_layers: bool,
    /// The specialization constant `SCENE_VERTEX_ATTRIBUTES` (`VERTEX_ATTRIBUTE_*` bits):
    /// where it is not 0, `shading` holds `EXTRA_SHADING_TEXEL_COUNT` more texels per
    /// triangle (`GpuExtraShading`).
    pub scene_vertex_attributes: u32,
}

/// Twin of `get_triangle` (`glsl/scene.glsl`): triangle `index` as the workshop's struct
/// (the albedo, emission and double-sidedness of the packed triangle, its stored normal).
pub fn get_triangle(texels: &SurfaceTexels, index: u32) -> Triangle {
    let first = (TRIANGLE_TEXEL_COUNT * index) as usize;
    let xyz = |j: usize| fetch_float_texel(texels.triangles, first + j).truncate();
    Triangle {
        positions: [xyz(0), xyz(1), xyz(2)],
        normal: xyz(3),
        color: xyz(4),
        emission: xyz(5),
        double_sided: is_double_sided(texels, index),
    }
}

/// Twin of `is_double_sided` (`glsl/scene.glsl`).
pub fn is_double_sided(texels: &SurfaceTexels, index: u32) -> bool {
    let emission = fetch_texel(
        texels.triangles,
        (TRIANGLE_TEXEL_COUNT * index) as usize + 5,
    );
    (emission.w & TRIANGLE_FLAG_DOUBLE_SIDED) != 0
}

/// Twin of `get_shading_texel`: texel `j` of triangle `i`'s shading data.
pub fn get_shading_texel(texels: &SurfaceTexels, triangle_index: u32, j: u32) -> UVec4 {
    let stride = if texels.scene_vertex_attributes == 0 {
        SHADING_TEXEL_COUNT
    } else {
        SHADING_TEXEL_COUNT + EXTRA_SHADING_TEXEL_COUNT
    };
    fetch_texel(texels.shading, (stride * triangle_index + j) as usize)
}

/// Twin of `get_material_texel`: texel `j` of material `i`.
pub fn get_material_texel(texels: &SurfaceTexels, material_index: u32, j: u32) -> UVec4 {
    fetch_texel(
        texels.materials,
        (MATERIAL_TEXEL_COUNT * material_index + j) as usize,
    )
}

/// Twin of `get_material_volume_scattering`.
pub fn get_material_volume_scattering(texels: &SurfaceTexels, material_index: u32) -> Vec4 {
    let flags = get_material_texel(texels, material_index, MATERIAL_TEXEL_FLAGS);
    let alpha = get_material_texel(
        texels,
        material_index,
        MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK,
    );
    Vec4::new(
        f32::from_bits(flags.y),
        f32::from_bits(flags.z),
        f32::from_bits(flags.w),
        f32::from_bits(alpha.z),
    )
}

/// Twin of `get_material_clearcoat_normal_scale`.
pub fn get_material_clearcoat_normal_scale(texels: &SurfaceTexels, material_index: u32) -> f32 {
    f32::from_bits(
        get_material_texel(
            texels,
            material_index,
            MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE,
        )
        .w,
    )
}

/// Twin of `is_unlit_material`.
pub fn is_unlit_material(texels: &SurfaceTexels, material_index: u32) -> bool {
    get_material_texel(texels, material_index, MATERIAL_TEXEL_FLAGS).x & MATERIAL_FLAG_UNLIT != 0
}

/// Twin of `get_material_alpha_mode`.
pub fn get_material_alpha_mode(texels: &SurfaceTexels, material_index: u32) -> u32 {
    get_material_texel(
        texels,
        material_index,
        MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK,
    )
    .x
}

/// Twin of `get_material_alpha_cutoff`.
pub fn get_material_alpha_cutoff(texels: &SurfaceTexels, material_index: u32) -> f32 {
    f32::from_bits(
        get_material_texel(
            texels,
            material_index,
            MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF,
        )
        .w,
    )
}

/// Twin of `get_material_normal_scale`.
pub fn get_material_normal_scale(texels: &SurfaceTexels, material_index: u32) -> f32 {
    f32::from_bits(
        get_material_texel(
            texels,
            material_index,
            MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE,
        )
        .w,
    )
}

/// Twin of `get_material_index`.
pub fn get_material_index(texels: &SurfaceTexels, triangle_index: u32) -> u32 {
    get_shading_texel(texels, triangle_index, 0).w
}

/// Twin of `get_tex_coord`: TEXCOORD_0 at a point with the given barycentrics.
pub fn get_tex_coord(texels: &SurfaceTexels, triangle_index: u32, barycentrics: Vec3) -> Vec2 {
    let first = uint_bits_to_float(get_shading_texel(texels, triangle_index, 3));
    let second = uint_bits_to_float(get_shading_texel(texels, triangle_index, 4));
    barycentrics[0] * Vec2::new(first.x, first.y)
        + barycentrics[1] * Vec2::new(first.z, first.w)
        + barycentrics[2] * Vec2::new(second.x, second.y)
}

/// Twin of `get_tex_coord_1`: TEXCOORD_1 at a point with the given barycentrics; 0 where the
/// scene has no second texture coordinates.
pub fn get_tex_coord_1(texels: &SurfaceTexels, triangle_index: u32, barycentrics: Vec3) -> Vec2 {
    if texels.scene_vertex_attributes & VERTEX_ATTRIBUTE_TEX_COORD_1 == 0 {
        return Vec2::ZERO;
    }
    let second = uint_bits_to_float(get_shading_texel(
        texels,
        triangle_index,
        SHADING_TEXEL_COUNT + 1,
    ));
    let third = uint_bits_to_float(get_shading_texel(
        texels,
        triangle_index,
        SHADING_TEXEL_COUNT + 2,
    ));
    barycentrics[0] * Vec2::new(second.z, second.w)
        + barycentrics[1] * Vec2::new(third.x, third.y)
        + barycentrics[2] * Vec2::new(third.z, third.w)
}

/// Twin of `select_tex_coord`: `tex_coord_1` where the slot reads TEXCOORD_1 (and the scene
/// has it), else `tex_coord`.
pub fn select_tex_coord(
    texels: &SurfaceTexels,
    texture: &TextureSlot,
    tex_coord: Vec2,
    tex_coord_1: Vec2,
) -> Vec2 {
    if texels.scene_vertex_attributes & VERTEX_ATTRIBUTE_TEX_COORD_1 != 0
        && texture.flags & TEXTURE_FLAG_TEX_COORD_1 != 0
    {
        return tex_coord_1;
    }
    tex_coord
}

/// Twin of `get_vertex_color`: glTF's COLOR_0 (linear RGBA) at a point with the given
/// barycentrics; 1 where the scene has no vertex colours.
pub fn get_vertex_color(texels: &SurfaceTexels, triangle_index: u32, barycentrics: Vec3) -> Vec4 {
    if texels.scene_vertex_attributes & VERTEX_ATTRIBUTE_COLOR == 0 {
        return Vec4::ONE;
    }
    let first = get_shading_texel(texels, triangle_index, SHADING_TEXEL_COUNT);
    let second = get_shading_texel(texels, triangle_index, SHADING_TEXEL_COUNT + 1);
    // unpackUnorm2x16: the low half first, each k / 65535
    let unpack = |rg: u32, ba: u32| {
        Vec4::new(
            (rg & 0xFFFF) as f32,
            (rg >> 16) as f32,
            (ba & 0xFFFF) as f32,
            (ba >> 16) as f32,
        ) / 65535.0
    };
    barycentrics[0] * unpack(first.x, first.y)
        + barycentrics[1] * unpack(first.z, first.w)
        + barycentrics[2] * unpack(second.x, second.y)
}

/// Twin of `has_material_texture` (never in a slot outside `scene_texture_slots`).
pub fn has_material_texture(texels: &SurfaceTexels, material_index: u32, slot: u32) -> bool {
    texels.scene_texture_slots & (1 << slot) != 0
        && (get_material_texel(
            texels,
            material_index,
            MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK,
        )
        .y & (1 << slot))
            != 0
}

/// Twin of `sample_material_texture`: slot `MATERIAL_TEXTURE_*` of material `i` at
/// `tex_coord` or `tex_coord_1` (TEXCOORD_0 and TEXCOORD_1, as the slot's set says), 1
/// without a texture.
pub fn sample_material_texture(
    texels: &SurfaceTexels,
    material_index: u32,
    slot: u32,
    tex_coord: Vec2,
    tex_coord_1: Vec2,
) -> Vec4 {
    if !has_material_texture(texels, material_index, slot) {
        return Vec4::ONE;
    }
    let first = MATERIAL_FACTOR_TEXEL_COUNT + 3 * slot;
    let texture = unpack_texture_slot(
        get_material_texel(texels, material_index, first),
        get_material_texel(texels, material_index, first + 1),
        get_material_texel(texels, material_index, first + 2),
    );
    let tex_coord = select_tex_coord(texels, &texture, tex_coord, tex_coord_1);
    sample_texture(texels.texture_texels, &texture, tex_coord)
}

/// Twin of `material_textures_t`: the value of each texture slot `MATERIAL_TEXTURE_*` of a
/// material at a point (1 without a texture, and in the layered slots of scenes without
/// layered materials).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialTextures {
    /// Indexed by `MATERIAL_TEXTURE_*`.
    pub slots: [Vec4; MATERIAL_TEXTURE_SLOT_COUNT as usize],
}

/// Twin of `sample_material_textures`: every texture slot of material `i` at `tex_coord`
/// (or `tex_coord_1` where the slot reads TEXCOORD_1) that has a texture (the layered
/// materials' slots only in scenes with them), lowest slot first.
pub fn sample_material_textures(
    texels: &SurfaceTexels,
    material_index: u32,
    tex_coord: Vec2,
    tex_coord_1: Vec2,
) -> MaterialTextures {
    let mut textures = MaterialTextures {
        slots: [Vec4::ONE; MATERIAL_TEXTURE_SLOT_COUNT as usize],
    };
    if texels.scene_texture_slots == 0 {
        return textures;
    }
    let slot_count = if texels.scene_has_layers {
        MATERIAL_TEXTURE_SLOT_COUNT
    } else {
        MATERIAL_TEXTURE_EMISSIVE + 1
    };
    let mut slots = get_material_texel(
        texels,
        material_index,
        MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK,
    )
    .y & texels.scene_texture_slots
        & ((1 << slot_count) - 1);
    while slots != 0 {
        let slot = slots.trailing_zeros();
        slots &= slots - 1;
        let first = MATERIAL_FACTOR_TEXEL_COUNT + 3 * slot;
        let texture = unpack_texture_slot(
            get_material_texel(texels, material_index, first),
            get_material_texel(texels, material_index, first + 1),
            get_material_texel(texels, material_index, first + 2),
        );
        let uv = select_tex_coord(texels, &texture, tex_coord, tex_coord_1);
        textures.slots[slot as usize] = sample_texture(texels.texture_texels, &texture, uv);
    }
    textures
}

/// Twin of `get_base_color`: base colour and alpha, factor times `texture` (the base colour
/// slot's value).
pub fn get_base_color(texels: &SurfaceTexels, material_index: u32, texture: Vec4) -> Vec4 {
    uint_bits_to_float(get_material_texel(
        texels,
        material_index,
        MATERIAL_TEXEL_BASE_COLOR,
    )) * texture
}

/// Twin of `get_surface_base_color`: `get_base_color` times the vertex colour (exactly
/// `get_base_color` where the scene has no vertex colours).
pub fn get_surface_base_color(
    texels: &SurfaceTexels,
    triangle_index: u32,
    material_index: u32,
    barycentrics: Vec3,
    texture: Vec4,
) -> Vec4 {
    let base_color = get_base_color(texels, material_index, texture);
    if texels.scene_vertex_attributes & VERTEX_ATTRIBUTE_COLOR == 0 {
        return base_color;
    }
    base_color * get_vertex_color(texels, triangle_index, barycentrics)
}

/// Twin of `get_material_emission`: emitted radiance (front side), factor times `texture`
/// (the emissive slot's value).
pub fn get_material_emission(texels: &SurfaceTexels, material_index: u32, texture: Vec4) -> Vec3 {
    uint_bits_to_float(get_material_texel(
        texels,
        material_index,
        MATERIAL_TEXEL_EMISSIVE_METALLIC,
    ))
    .truncate()
        * texture.truncate()
}

/// Twin of `is_opaque_hit`: whether a candidate hit at ray parameter `t` on triangle `i`
/// counts. `alpha_seed` and `ray_count` are the GLSL globals `g_alpha_seed` and
/// `g_ray_count` at the call.
pub fn is_opaque_hit(
    texels: &SurfaceTexels,
    triangle_index: u32,
    ray_origin: Vec3,
    ray_direction: Vec3,
    t: f32,
    alpha_seed: UVec2,
    ray_count: u32,
) -> bool {
    let material_index = get_material_index(texels, triangle_index);
    let alpha_mode = get_material_alpha_mode(texels, material_index);
    if alpha_mode == ALPHA_MODE_OPAQUE {
        return true;
    }
    let barycentrics = get_barycentrics(
        ray_origin + t * ray_direction,
        &get_triangle(texels, triangle_index),
    );
    let tex_coord = get_tex_coord(texels, triangle_index, barycentrics);
    let tex_coord_1 = get_tex_coord_1(texels, triangle_index, barycentrics);
    let alpha = get_surface_base_color(
        texels,
        triangle_index,
        material_index,
        barycentrics,
        sample_material_texture(
            texels,
            material_index,
            MATERIAL_TEXTURE_BASE_COLOR,
            tex_coord,
            tex_coord_1,
        ),
    )
    .w;
    if alpha_mode == ALPHA_MODE_MASK {
        return alpha >= get_material_alpha_cutoff(texels, material_index);
    }
    let mut hash_state =
        alpha_seed ^ UVec2::new(ray_count.wrapping_mul(2654435769), triangle_index);
    get_random_numbers(&mut hash_state)[0] < alpha
}

/// Twin of `get_front_mapped_normal`: the interpolated vertex normal of triangle `i` (front
/// side), perturbed by the normal map in texture slot `slot`, whose value at the point is
/// `texture`, with `scale`; the face normal where the interpolation vanishes.
#[allow(clippy::too_many_arguments)]
pub fn get_front_mapped_normal(
    texels: &SurfaceTexels,
    triangle_index: u32,
    material_index: u32,
    barycentrics: Vec3,
    texture: Vec4,
    face_normal: Vec3,
    slot: u32,
    scale: f32,
) -> Vec3 {
    let vertex_normal =
        |j: u32| uint_bits_to_float(get_shading_texel(texels, triangle_index, j)).truncate();
    let mut normal = barycentrics[0] * vertex_normal(0)
        + barycentrics[1] * vertex_normal(1)
        + barycentrics[2] * vertex_normal(2);
    if !(normal.dot(normal) > 1.0e-12) {
        return face_normal;
    }
    normal = normal.normalize();
    if has_material_texture(texels, material_index, slot) {
        let tangent_0 = uint_bits_to_float(get_shading_texel(texels, triangle_index, 5));
        let tangent = barycentrics[0] * tangent_0.truncate()
            + barycentrics[1]
                * uint_bits_to_float(get_shading_texel(texels, triangle_index, 6)).truncate()
            + barycentrics[2]
                * uint_bits_to_float(get_shading_texel(texels, triangle_index, 7)).truncate();
        normal = apply_normal_map(
            normal,
            tangent.extend(tangent_0.w),
            texture.truncate(),
            scale,
        );
    }
    normal
}

/// Twin of `get_front_shading_normal`: the vertex normals and the material's normalTexture.
pub fn get_front_shading_normal(
    texels: &SurfaceTexels,
    triangle_index: u32,
    material_index: u32,
    barycentrics: Vec3,
    textures: &MaterialTextures,
    face_normal: Vec3,
) -> Vec3 {
    get_front_mapped_normal(
        texels,
        triangle_index,
        material_index,
        barycentrics,
        textures.slots[MATERIAL_TEXTURE_NORMAL as usize],
        face_normal,
        MATERIAL_TEXTURE_NORMAL,
        get_material_normal_scale(texels, material_index),
    )
}

/// Twin of `get_front_clearcoat_normal`: the vertex normals and the clearcoatNormalTexture.
pub fn get_front_clearcoat_normal(
    texels: &SurfaceTexels,
    triangle_index: u32,
    material_index: u32,
    barycentrics: Vec3,
    textures: &MaterialTextures,
    face_normal: Vec3,
) -> Vec3 {
    get_front_mapped_normal(
        texels,
        triangle_index,
        material_index,
        barycentrics,
        textures.slots[MATERIAL_TEXTURE_CLEARCOAT_NORMAL as usize],
        face_normal,
        MATERIAL_TEXTURE_CLEARCOAT_NORMAL,
        get_material_clearcoat_normal_scale(texels, material_index),
    )
}

/// Twin of `surface_t`: a hit point as the integrators shade it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// Unit geometric normal, on the side the ray came from.
    pub geometric_normal: Vec3,
    /// Unit shading normal, on the same side, with the view direction above it.
    pub shading_normal: Vec3,
    /// The material after texture lookups.
    pub material: MaterialSample,
    /// Emitted radiance towards the ray's origin (0 from the back of one-sided emitters).
    pub emission: Vec3,
    /// The clear coat's unit normal on the view's side.
    pub clearcoat_normal: Vec3,
    /// The far side's index of refraction over the ray's.
    pub eta: f32,
    /// Whether the ray hit the triangle's back.
    pub back_face: bool,
    /// KHR_materials_unlit: the base colour camera rays see (0 for lit materials).
    pub unlit_color: Vec3,
}

/// Twin of `get_material`: material `i` at a point whose texture slots have the values
/// `textures` (roughness in G, metallic in B of the metallic-roughness texture);
/// `base_color` is `get_base_color` there.
pub fn get_material(
    texels: &SurfaceTexels,
    material_index: u32,
    textures: &MaterialTextures,
    base_color: Vec4,
) -> MaterialSample {
    let factors = uint_bits_to_float(get_material_texel(
        texels,
        material_index,
        MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE,
    ));
    let metallic_roughness = textures.slots[MATERIAL_TEXTURE_METALLIC_ROUGHNESS as usize];
    let metallic = uint_bits_to_float(get_material_texel(
        texels,
        material_index,
        MATERIAL_TEXEL_EMISSIVE_METALLIC,
    ))
    .w * metallic_roughness.z;
    let specular_color = uint_bits_to_float(get_material_texel(
        texels,
        material_index,
        MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF,
    ))
    .truncate();
    let mut material = get_base_material(
        base_color.truncate(),
        metallic,
        factors.x * metallic_roughness.y,
        factors.y,
        specular_color,
        factors.z,
    );
    if texels.scene_has_layers {
        let texture = |slot: u32| textures.slots[slot as usize];
        material.specular *= texture(MATERIAL_TEXTURE_SPECULAR).w;
        material.specular_color *= texture(MATERIAL_TEXTURE_SPECULAR_COLOR).truncate();
        let layers = uint_bits_to_float(get_material_texel(
            texels,
            material_index,
            MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT,
        ));
        material.transmission = layers.x * texture(MATERIAL_TEXTURE_TRANSMISSION).x;
        material.thickness = layers.y * texture(MATERIAL_TEXTURE_THICKNESS).y;
        material.attenuation = uint_bits_to_float(get_material_texel(
            texels,
            material_index,
            MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE,
        ))
        .truncate();
        material.clearcoat = layers.z * texture(MATERIAL_TEXTURE_CLEARCOAT).x;
        material.clearcoat_roughness = layers.w * texture(MATERIAL_TEXTURE_CLEARCOAT_ROUGHNESS).y;
        let sheen = uint_bits_to_float(get_material_texel(
            texels,
            material_index,
            MATERIAL_TEXEL_SHEEN,
        ));
        material.sheen_color = sheen.truncate() * texture(MATERIAL_TEXTURE_SHEEN_COLOR).truncate();
        material.sheen_roughness = sheen.w * texture(MATERIAL_TEXTURE_SHEEN_ROUGHNESS).w;
    }
    material
}

/// Twin of `get_surface`: normals, the material after textures and the emission at a hit.
/// \param triangle The hit triangle as `ray_mesh_intersection` returned it (not oriented)
pub fn get_surface(
    texels: &SurfaceTexels,
    triangle_index: u32,
    triangle: &Triangle,
    position: Vec3,
    ray_direction: Vec3,
) -> Surface {
    let material_index = get_material_index(texels, triangle_index);
    let barycentrics = get_barycentrics(position, triangle);
    let tex_coord = get_tex_coord(texels, triangle_index, barycentrics);
    let tex_coord_1 = get_tex_coord_1(texels, triangle_index, barycentrics);
    let front = triangle.normal.dot(ray_direction) <= 0.0;
    let view = -ray_direction;
    let geometric_normal = if front {
        triangle.normal
    } else {
        -triangle.normal
    };
    let textures = sample_material_textures(texels, material_index, tex_coord, tex_coord_1);
    let shading_normal = get_front_shading_normal(
        texels,
        triangle_index,
        material_index,
        barycentrics,
        &textures,
        triangle.normal,
    );
    let shading_normal = if front {
        shading_normal
    } else {
        -shading_normal
    };
    let shading_normal = if shading_normal.dot(view) > 0.0 {
        shading_normal
    } else {
        geometric_normal
    };
    let base_color = get_surface_base_color(
        texels,
        triangle_index,
        material_index,
        barycentrics,
        textures.slots[MATERIAL_TEXTURE_BASE_COLOR as usize],
    );
    let mut material = get_material(texels, material_index, &textures, base_color);
    let double_sided = is_double_sided(texels, triangle_index);
    let emission = if front || double_sided {
        get_material_emission(
            texels,
            material_index,
            textures.slots[MATERIAL_TEXTURE_EMISSIVE as usize],
        )
    } else {
        Vec3::ZERO
    };
    let eta = if front {
        material.ior
    } else {
        1.0 / material.ior
    };
    let mut clearcoat_normal = geometric_normal;
    let mut unlit_color = Vec3::ZERO;
    if texels.scene_has_layers {
        if material.clearcoat > 0.0 {
            let normal = get_front_clearcoat_normal(
                texels,
                triangle_index,
                material_index,
                barycentrics,
                &textures,
                triangle.normal,
            );
            let normal = if front { normal } else { -normal };
            if normal.dot(view) > 0.0 {
                clearcoat_normal = normal;
            }
        }
        if is_unlit_material(texels, material_index) {
            unlit_color = base_color.truncate();
            material.base_color = Vec3::ZERO;
            material.metallic = 0.0;
            material.specular = 0.0;
            material.transmission = 0.0;
            material.clearcoat = 0.0;
            material.sheen_color = Vec3::ZERO;
        }
    }
    Surface {
        geometric_normal,
        shading_normal,
        material,
        emission,
        clearcoat_normal,
        eta,
        back_face: !front,
        unlit_color,
    }
}

/// Twin of `has_layers`: the material has transmission or a clear coat (and the scene
/// `SCENE_HAS_LAYERS`, which `get_material` already applied).
pub fn has_layers(surface: &Surface) -> bool {
    is_layered(&surface.material)
}

/// Twin of `is_transmissive`.
pub fn is_transmissive(surface: &Surface) -> bool {
    surface.material.transmission > 0.0
}

/// Twin of `get_camera_emission`: emission plus an unlit material's colour.
pub fn get_camera_emission(surface: &Surface) -> Vec3 {
    surface.emission + surface.unlit_color
}

/// Twin of `get_volume_transmittance`: absorption inside a refracting volume (rays that hit
/// its back), 1 elsewhere.
pub fn get_volume_transmittance(surface: &Surface, distance: f32) -> Vec3 {
    if is_transmissive(surface) && surface.back_face && is_refracting(&surface.material) {
        return get_absorption(&surface.material, distance);
    }
    Vec3::ONE
}

/// Twin of `get_bsdf`: f(view, light) max(0, n_s . light), and 0 for light
/// from below the geometric surface.
pub fn get_bsdf(surface: &Surface, view: Vec3, light: Vec3) -> Vec3 {
    if has_layers(surface) {
        return get_layered_bsdf(
            &surface.material,
            surface.eta,
            surface.geometric_normal,
            surface.shading_normal,
            surface.clearcoat_normal,
            view,
            light,
        );
    }
    if surface.geometric_normal.dot(light) <= 0.0 {
        return Vec3::ZERO;
    }
    get_brdf(&surface.material, surface.shading_normal, view, light)
        * surface.shading_normal.dot(light).max(0.0)
}

/// Twin of `get_bsdf_density` (glTF).
pub fn get_bsdf_density(surface: &Surface, view: Vec3, light: Vec3) -> f32 {
    if has_layers(surface) {
        return get_layered_density(
            &surface.material,
            surface.eta,
            surface.shading_normal,
            surface.clearcoat_normal,
            view,
            light,
        );
    }
    get_brdf_density(&surface.material, surface.shading_normal, view, light)
}

/// Twin of `has_only_delta_lobes` (glTF; no `SCENE_HAS_SPECULAR`, as `has_delta_lobe`): a
/// smooth full metal without layers, whose `get_bsdf` is 0 for every direction.
pub fn has_only_delta_lobes(surface: &Surface) -> bool {
    let material = &surface.material;
    get_ggx_alpha(material.roughness) == 0.0 && material.metallic == 1.0 && !has_layers(surface)
}

/// Twin of `has_delta_lobe` (glTF; the twin has no `SCENE_HAS_SPECULAR`: its materials are
/// as the scene gives them): a specular lobe or a transmission of roughness 0, or a smooth
/// clear coat.
pub fn has_delta_lobe(surface: &Surface) -> bool {
    let material = &surface.material;
    if get_ggx_alpha(material.roughness) == 0.0
        && (material.metallic > 0.0 || material.specular > 0.0 || is_transmissive(surface))
    {
        return true;
    }
    has_layers(surface)
        && material.clearcoat > 0.0
        && get_ggx_alpha(material.clearcoat_roughness) == 0.0
}

/// Twin of `sample_bsdf` (glTF): a direction, its density, weight, lobes and eta; a delta
/// pick is marked `BSDF_LOBE_DELTA`, density 0, weight its own f / p.
pub fn sample_bsdf(
    surface: &Surface,
    view: Vec3,
    random_numbers: Vec2,
    lobe_random: f32,
) -> BsdfSample {
    let mut lobes = BSDF_LOBE_REFLECT;
    let mut eta = 1.0;
    let (direction, delta_weight) = if has_layers(surface) {
        let (direction, delta_weight) = sample_layered_bsdf(
            random_numbers,
            lobe_random,
            &surface.material,
            surface.eta,
            surface.shading_normal,
            surface.clearcoat_normal,
            view,
        );
        if surface.geometric_normal.dot(direction) < 0.0 {
            lobes = BSDF_LOBE_TRANSMIT;
            if is_refracting(&surface.material) {
                eta = surface.eta;
            }
        }
        (direction, delta_weight)
    } else {
        let direction = sample_brdf(
            random_numbers,
            &surface.material,
            surface.shading_normal,
            view,
        );
        let delta = random_numbers[0]
            < get_brdf_mirror_probability(&surface.material, surface.shading_normal, view);
        let delta_weight =
            delta.then(|| get_brdf_mirror_weight(&surface.material, surface.shading_normal, view));
        (direction, delta_weight)
    };
    let mut density = get_bsdf_density(surface, view, direction);
    let mut weight = if density > 0.0 {
        get_bsdf(surface, view, direction) / density
    } else {
        Vec3::ZERO
    };
    if let Some(delta_weight) = delta_weight {
        let sides_agree = (surface.geometric_normal.dot(direction) > 0.0)
            == (surface.shading_normal.dot(direction) > 0.0);
        lobes |= BSDF_LOBE_DELTA;
        density = 0.0;
        weight = if sides_agree {
            delta_weight
        } else {
            Vec3::ZERO
        };
    }
    BsdfSample {
        direction,
        density,
        weight,
        lobes,
        eta,
    }
}
