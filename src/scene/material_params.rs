//! The material's parameter table (as Falcor's `StandardMaterialParamLayout`): one row per
//! parameter (`MATERIAL_PARAMS`) with its name (Python's key and `MaterialFactors`' field),
//! its type, where glTF writes it, its default, its factor in `MaterialFactors` and its
//! words on the GPU (the `MATERIAL_TEXEL_*` of `glsl/shared.h`); one row per texture slot
//! (`MATERIAL_TEXTURES`) with glTF's name, its `MATERIAL_TEXTURE_*` and colour space.
//!
//! Made from it: the GPU words (`crate::render::gpu_materials::GpuMaterial`), the
//! default factors (`MaterialFactors::default`), Python's `MATERIAL_KEYS` and the reading of
//! its dicts, and the export's list of textures. Held to it by tests: the layout of
//! `glsl/shared.h` (every texel and slot named here, with its number), its readers
//! (`glsl/materials.glsl` and its twin `crate::cpu::gltf_surface` read every texel; the twin
//! gives back every parameter's value).

use glam::{Vec3, Vec4};

use super::material_factors::MaterialFactors;
use super::materials::{AlphaMode, PbrMaterial, TextureBinding};
use crate::contract::{
    ALPHA_MODE_BLEND, ALPHA_MODE_MASK, ALPHA_MODE_OPAQUE, MATERIAL_FLAG_UNLIT,
    MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK, MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE,
    MATERIAL_TEXEL_BASE_COLOR, MATERIAL_TEXEL_EMISSIVE_METALLIC, MATERIAL_TEXEL_FLAGS,
    MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE, MATERIAL_TEXEL_SHEEN,
    MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF, MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT,
    MATERIAL_TEXTURE_BASE_COLOR, MATERIAL_TEXTURE_CLEARCOAT, MATERIAL_TEXTURE_CLEARCOAT_NORMAL,
    MATERIAL_TEXTURE_CLEARCOAT_ROUGHNESS, MATERIAL_TEXTURE_EMISSIVE,
    MATERIAL_TEXTURE_METALLIC_ROUGHNESS, MATERIAL_TEXTURE_NORMAL, MATERIAL_TEXTURE_SHEEN_COLOR,
    MATERIAL_TEXTURE_SHEEN_ROUGHNESS, MATERIAL_TEXTURE_SPECULAR, MATERIAL_TEXTURE_SPECULAR_COLOR,
    MATERIAL_TEXTURE_THICKNESS, MATERIAL_TEXTURE_TRANSMISSION,
};

/// How a parameter is written, in glTF and in Python's dicts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamKind {
    /// A number.
    Number,
    /// A number at least 0, a multiplier (Python refuses one below 0).
    NonNegative,
    /// Linear RGB, three numbers (a colour factor: Python refuses a component below 0).
    Rgb,
    /// Linear RGB and alpha, four numbers (Python takes three too, alpha 1).
    Rgba,
    /// True or false (an extension's presence, for KHR_materials_unlit).
    Bool,
    /// glTF's `alphaMode`: `ALPHA_MODE_*` (Python's "opaque", "mask", "blend").
    AlphaMode,
    /// glTF's `alphaCutoff`, which only `ALPHA_MODE_MASK` reads.
    AlphaCutoff,
    /// Made from other parameters or from the textures; no file writes it as such.
    Derived,
}

/// Where glTF writes a parameter: under the material's object (or its `extension`'s object
/// in `extensions`), at `path`.
#[derive(Clone, Copy, Debug)]
pub struct GltfSource {
    /// The extension whose object holds it (None: the core material).
    pub extension: Option<&'static str>,
    /// The keys from that object down to the value.
    pub path: &'static [&'static str],
    /// An extension the material must also have for this one to count (KHR_materials_volume
    /// counts only with KHR_materials_transmission).
    pub requires: Option<&'static str>,
}

/// A parameter's factor in `MaterialFactors`, as four floats (unused ones 0; `ALPHA_MODE_*`
/// and booleans as 0.0, 1.0, 2.0).
#[derive(Clone, Copy, Debug)]
pub struct FactorAccess {
    /// Reads it.
    pub get: fn(&MaterialFactors) -> [f32; 4],
    /// Writes it.
    pub set: fn(&mut MaterialFactors, [f32; 4]),
}

/// Where a parameter lies in a material's GPU words: `count` components of the factor texel
/// `texel` (`MATERIAL_TEXEL_*`, glsl/shared.h) from `component` on.
#[derive(Clone, Copy, Debug)]
pub struct GpuWords {
    /// The texel, `MATERIAL_TEXEL_*`.
    pub texel: u32,
    /// Its name in glsl/shared.h (`glsl/materials.glsl` and its twin read it by it).
    pub texel_name: &'static str,
    /// The first component (0: x).
    pub component: u32,
    /// How many components, from `component` on.
    pub count: u32,
    /// Its words from the sanitized material (the first `count` are written).
    pub pack: fn(&PbrMaterial) -> [u32; 4],
}

/// One row of the material's parameter table.
#[derive(Clone, Copy, Debug)]
pub struct MaterialParam {
    /// Its name: Python's key and `MaterialFactors`' field (snake case of glTF's name).
    pub name: &'static str,
    /// Its type.
    pub kind: ParamKind,
    /// Where glTF writes it (None: derived).
    pub gltf: Option<GltfSource>,
    /// glTF's default, as four floats.
    pub default: [f32; 4],
    /// Its factor in `MaterialFactors` (None: not a factor a caller gives; the texture
    /// info's scales and what is derived).
    pub factor: Option<FactorAccess>,
    /// Its words on the GPU (None: the GPU takes it folded into another, or per triangle).
    pub gpu: Option<GpuWords>,
}

/// One texture slot: glTF's name, the slot's `MATERIAL_TEXTURE_*`, its colour space and
/// the `PbrMaterial` field that binds it.
#[derive(Clone, Copy, Debug)]
pub struct MaterialTexture {
    /// glTF's name (`baseColorTexture`).
    pub name: &'static str,
    /// Where glTF writes its texture info (as `GltfSource`).
    pub gltf: GltfSource,
    /// The slot, `MATERIAL_TEXTURE_*`.
    pub slot: u32,
    /// Its name in glsl/shared.h.
    pub slot_name: &'static str,
    /// Whether its texels are sRGB (colours) rather than linear data.
    pub srgb: bool,
    /// Reads the binding.
    pub get: fn(&PbrMaterial) -> Option<TextureBinding>,
    /// Writes the binding.
    pub set: fn(&mut PbrMaterial, Option<TextureBinding>),
}

/// A `MATERIAL_TEXEL_*` or `MATERIAL_TEXTURE_*` constant with its name.
macro_rules! named {
    ($name:ident) => {
        ($name, stringify!($name))
    };
}

const fn core(path: &'static [&'static str]) -> Option<GltfSource> {
    Some(GltfSource {
        extension: None,
        path,
        requires: None,
    })
}

const fn extension(name: &'static str, path: &'static [&'static str]) -> Option<GltfSource> {
    Some(GltfSource {
        extension: Some(name),
        path,
        requires: None,
    })
}

/// KHR_materials_volume's, which counts only with KHR_materials_transmission.
const fn volume(path: &'static [&'static str]) -> Option<GltfSource> {
    Some(GltfSource {
        extension: Some("KHR_materials_volume"),
        path,
        requires: Some("KHR_materials_transmission"),
    })
}

/// KHR_materials_volume_scatter's, which counts only with KHR_materials_volume (whose own
/// values count only with KHR_materials_transmission).
const fn volume_scatter(path: &'static [&'static str]) -> Option<GltfSource> {
    Some(GltfSource {
        extension: Some("KHR_materials_volume_scatter"),
        path,
        requires: Some("KHR_materials_volume"),
    })
}

const fn factor(
    get: fn(&MaterialFactors) -> [f32; 4],
    set: fn(&mut MaterialFactors, [f32; 4]),
) -> Option<FactorAccess> {
    Some(FactorAccess { get, set })
}

const fn words(
    (texel, texel_name): (u32, &'static str),
    component: u32,
    count: u32,
    pack: fn(&PbrMaterial) -> [u32; 4],
) -> Option<GpuWords> {
    Some(GpuWords {
        texel,
        texel_name,
        component,
        count,
        pack,
    })
}

/// A number as four floats.
fn one(x: f32) -> [f32; 4] {
    [x, 0.0, 0.0, 0.0]
}

/// A float's bits as the first word.
fn bits(x: f32) -> [u32; 4] {
    [x.to_bits(), 0, 0, 0]
}

/// A colour's bits.
fn rgb_bits(c: Vec3) -> [u32; 4] {
    c.extend(0.0).to_array().map(f32::to_bits)
}

/// An RGB value of four floats.
fn rgb(v: [f32; 4]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

/// `ALPHA_MODE_*` of a mode.
pub fn alpha_mode_code(mode: AlphaMode) -> u32 {
    match mode {
        AlphaMode::Opaque => ALPHA_MODE_OPAQUE,
        AlphaMode::Mask { .. } => ALPHA_MODE_MASK,
        AlphaMode::Blend => ALPHA_MODE_BLEND,
    }
}

/// The mode of `ALPHA_MODE_*` `code`, with `cutoff` for a mask (opaque for an unknown code).
pub fn alpha_mode_of(code: u32, cutoff: f32) -> AlphaMode {
    match code {
        ALPHA_MODE_MASK => AlphaMode::Mask { cutoff },
        ALPHA_MODE_BLEND => AlphaMode::Blend,
        _ => AlphaMode::Opaque,
    }
}

/// The alpha cutoff of a mode (0 unless a mask: the GPU word of opaque and blended
/// materials).
fn cutoff_of(mode: AlphaMode) -> f32 {
    match mode {
        AlphaMode::Mask { cutoff } => cutoff,
        _ => 0.0,
    }
}

/// The material's texture slots that hold a texture: bit (1 << `MATERIAL_TEXTURE_*`) each.
pub fn texture_mask(material: &PbrMaterial) -> u32 {
    MATERIAL_TEXTURES
        .iter()
        .filter(|texture| (texture.get)(material).is_some())
        .fold(0, |mask, texture| mask | 1 << texture.slot)
}

/// The first texture slot (glTF's name, in `MATERIAL_TEXTURES`' order) of the material that
/// reads `TEXCOORD_1`; None where every slot reads `TEXCOORD_0` or holds no texture.
pub fn first_slot_on_tex_coord_1(material: &PbrMaterial) -> Option<&'static str> {
    MATERIAL_TEXTURES
        .iter()
        .find(|texture| (texture.get)(material).is_some_and(|b| b.tex_coord == 1))
        .map(|texture| texture.name)
}

/// The material's parameters, one row each: the factors a caller gives (`MaterialFactors`,
/// Python's keys, in this order), then the words the GPU takes beyond them. A new factor is
/// a row here, a field of `MaterialFactors` and of `PbrMaterial`, and its reader in
/// `glsl/materials.glsl` (with its twin).
pub const MATERIAL_PARAMS: &[MaterialParam] = &[
    MaterialParam {
        name: "base_color",
        kind: ParamKind::Rgba,
        gltf: core(&["pbrMetallicRoughness", "baseColorFactor"]),
        default: [1.0; 4],
        factor: factor(
            |f| f.base_color.to_array(),
            |f, v| f.base_color = Vec4::from(v),
        ),
        gpu: words(named!(MATERIAL_TEXEL_BASE_COLOR), 0, 4, |m| {
            m.base_color.to_array().map(f32::to_bits)
        }),
    },
    MaterialParam {
        name: "metallic",
        kind: ParamKind::Number,
        gltf: core(&["pbrMetallicRoughness", "metallicFactor"]),
        default: [1.0, 0.0, 0.0, 0.0],
        factor: factor(|f| one(f.metallic), |f, v| f.metallic = v[0]),
        gpu: words(named!(MATERIAL_TEXEL_EMISSIVE_METALLIC), 3, 1, |m| {
            bits(m.metallic)
        }),
    },
    MaterialParam {
        name: "roughness",
        kind: ParamKind::Number,
        gltf: core(&["pbrMetallicRoughness", "roughnessFactor"]),
        default: [1.0, 0.0, 0.0, 0.0],
        factor: factor(|f| one(f.roughness), |f, v| f.roughness = v[0]),
        gpu: words(
            named!(MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE),
            0,
            1,
            |m| bits(m.roughness),
        ),
    },
    MaterialParam {
        name: "emission",
        kind: ParamKind::Rgb,
        gltf: core(&["emissiveFactor"]),
        default: [0.0; 4],
        factor: factor(
            |f| f.emission.extend(0.0).to_array(),
            |f, v| f.emission = rgb(v),
        ),
        // Times emissive_strength (0 for unlit materials): `MaterialFactors::material`.
        gpu: words(named!(MATERIAL_TEXEL_EMISSIVE_METALLIC), 0, 3, |m| {
            rgb_bits(m.emission)
        }),
    },
    MaterialParam {
        name: "emissive_strength",
        kind: ParamKind::NonNegative,
        gltf: extension("KHR_materials_emissive_strength", &["emissiveStrength"]),
        default: [1.0, 0.0, 0.0, 0.0],
        factor: factor(
            |f| one(f.emissive_strength),
            |f, v| f.emissive_strength = v[0],
        ),
        gpu: None,
    },
    MaterialParam {
        name: "specular",
        kind: ParamKind::Number,
        gltf: extension("KHR_materials_specular", &["specularFactor"]),
        default: [1.0, 0.0, 0.0, 0.0],
        factor: factor(|f| one(f.specular), |f, v| f.specular = v[0]),
        gpu: words(
            named!(MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE),
            1,
            1,
            |m| bits(m.specular),
        ),
    },
    MaterialParam {
        name: "specular_color",
        kind: ParamKind::Rgb,
        gltf: extension("KHR_materials_specular", &["specularColorFactor"]),
        default: [1.0, 1.0, 1.0, 0.0],
        factor: factor(
            |f| f.specular_color.extend(0.0).to_array(),
            |f, v| f.specular_color = rgb(v),
        ),
        gpu: words(
            named!(MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF),
            0,
            3,
            |m| rgb_bits(m.specular_color),
        ),
    },
    MaterialParam {
        name: "ior",
        kind: ParamKind::Number,
        gltf: extension("KHR_materials_ior", &["ior"]),
        default: [1.5, 0.0, 0.0, 0.0],
        factor: factor(|f| one(f.ior), |f, v| f.ior = v[0]),
        gpu: words(
            named!(MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE),
            2,
            1,
            |m| bits(m.ior),
        ),
    },
    MaterialParam {
        name: "transmission",
        kind: ParamKind::Number,
        gltf: extension("KHR_materials_transmission", &["transmissionFactor"]),
        default: [0.0; 4],
        factor: factor(|f| one(f.transmission), |f, v| f.transmission = v[0]),
        gpu: words(
            named!(MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT),
            0,
            1,
            |m| bits(m.transmission.factor),
        ),
    },
    MaterialParam {
        name: "thickness",
        kind: ParamKind::Number,
        gltf: volume(&["thicknessFactor"]),
        default: [0.0; 4],
        factor: factor(|f| one(f.thickness), |f, v| f.thickness = v[0]),
        gpu: words(
            named!(MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT),
            1,
            1,
            |m| bits(m.transmission.thickness),
        ),
    },
    MaterialParam {
        name: "attenuation_color",
        kind: ParamKind::Rgb,
        gltf: volume(&["attenuationColor"]),
        default: [1.0, 1.0, 1.0, 0.0],
        factor: factor(
            |f| f.attenuation_color.extend(0.0).to_array(),
            |f, v| f.attenuation_color = rgb(v),
        ),
        // Folded into "attenuation_coefficient" with attenuation_distance.
        gpu: None,
    },
    MaterialParam {
        name: "attenuation_distance",
        kind: ParamKind::Number,
        gltf: volume(&["attenuationDistance"]),
        default: [f32::INFINITY, 0.0, 0.0, 0.0],
        factor: factor(
            |f| one(f.attenuation_distance),
            |f, v| f.attenuation_distance = v[0],
        ),
        gpu: None,
    },
    MaterialParam {
        // Folded with attenuation_color and attenuation_distance into
        // "attenuation_coefficient" (sigma_a) and "scattering_coefficient" (sigma_s).
        name: "multiscatter_color",
        kind: ParamKind::Rgb,
        gltf: volume_scatter(&["multiscatterColor"]),
        default: [0.0; 4],
        factor: factor(
            |f| f.multiscatter_color.extend(0.0).to_array(),
            |f, v| f.multiscatter_color = rgb(v),
        ),
        gpu: None,
    },
    MaterialParam {
        name: "scatter_anisotropy",
        kind: ParamKind::Number,
        gltf: volume_scatter(&["scatterAnisotropy"]),
        default: [0.0; 4],
        factor: factor(
            |f| one(f.scatter_anisotropy),
            |f, v| f.scatter_anisotropy = v[0],
        ),
        gpu: words(named!(MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK), 2, 1, |m| {
            bits(m.transmission.anisotropy)
        }),
    },
    MaterialParam {
        name: "clearcoat",
        kind: ParamKind::Number,
        gltf: extension("KHR_materials_clearcoat", &["clearcoatFactor"]),
        default: [0.0; 4],
        factor: factor(|f| one(f.clearcoat), |f, v| f.clearcoat = v[0]),
        gpu: words(
            named!(MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT),
            2,
            1,
            |m| bits(m.clearcoat.factor),
        ),
    },
    MaterialParam {
        name: "clearcoat_roughness",
        kind: ParamKind::Number,
        gltf: extension("KHR_materials_clearcoat", &["clearcoatRoughnessFactor"]),
        default: [0.0; 4],
        factor: factor(
            |f| one(f.clearcoat_roughness),
            |f, v| f.clearcoat_roughness = v[0],
        ),
        gpu: words(
            named!(MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT),
            3,
            1,
            |m| bits(m.clearcoat.roughness),
        ),
    },
    MaterialParam {
        name: "sheen_color",
        kind: ParamKind::Rgb,
        gltf: extension("KHR_materials_sheen", &["sheenColorFactor"]),
        default: [0.0; 4],
        factor: factor(
            |f| f.sheen_color.extend(0.0).to_array(),
            |f, v| f.sheen_color = rgb(v),
        ),
        gpu: words(named!(MATERIAL_TEXEL_SHEEN), 0, 3, |m| {
            rgb_bits(m.sheen.color)
        }),
    },
    MaterialParam {
        name: "sheen_roughness",
        kind: ParamKind::Number,
        gltf: extension("KHR_materials_sheen", &["sheenRoughnessFactor"]),
        default: [0.0; 4],
        factor: factor(|f| one(f.sheen_roughness), |f, v| f.sheen_roughness = v[0]),
        gpu: words(named!(MATERIAL_TEXEL_SHEEN), 3, 1, |m| {
            bits(m.sheen.roughness)
        }),
    },
    MaterialParam {
        name: "alpha_mode",
        kind: ParamKind::AlphaMode,
        gltf: core(&["alphaMode"]),
        default: [ALPHA_MODE_OPAQUE as f32, 0.0, 0.0, 0.0],
        factor: factor(
            |f| one(alpha_mode_code(f.alpha_mode) as f32),
            |f, v| f.alpha_mode = alpha_mode_of(v[0] as u32, 0.5),
        ),
        gpu: words(named!(MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK), 0, 1, |m| {
            [alpha_mode_code(m.alpha_mode), 0, 0, 0]
        }),
    },
    MaterialParam {
        name: "alpha_cutoff",
        kind: ParamKind::AlphaCutoff,
        gltf: core(&["alphaCutoff"]),
        default: [0.5, 0.0, 0.0, 0.0],
        factor: factor(
            |f| match f.alpha_mode {
                AlphaMode::Mask { cutoff } => one(cutoff),
                _ => one(0.5),
            },
            |f, v| {
                if let AlphaMode::Mask { cutoff } = &mut f.alpha_mode {
                    *cutoff = v[0];
                }
            },
        ),
        gpu: words(
            named!(MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF),
            3,
            1,
            |m| bits(cutoff_of(m.alpha_mode)),
        ),
    },
    MaterialParam {
        name: "double_sided",
        kind: ParamKind::Bool,
        gltf: core(&["doubleSided"]),
        default: [0.0; 4],
        factor: factor(
            |f| one(f32::from(u8::from(f.double_sided))),
            |f, v| f.double_sided = v[0] != 0.0,
        ),
        // Per triangle (`TRIANGLE_FLAG_DOUBLE_SIDED`), not per material.
        gpu: None,
    },
    MaterialParam {
        name: "unlit",
        kind: ParamKind::Bool,
        gltf: extension("KHR_materials_unlit", &[]),
        default: [0.0; 4],
        factor: factor(
            |f| one(f32::from(u8::from(f.unlit))),
            |f, v| f.unlit = v[0] != 0.0,
        ),
        gpu: words(named!(MATERIAL_TEXEL_FLAGS), 0, 1, |m| {
            [if m.unlit { MATERIAL_FLAG_UNLIT } else { 0 }, 0, 0, 0]
        }),
    },
    // The words the GPU takes beyond the factors.
    MaterialParam {
        name: "normal_scale",
        kind: ParamKind::Number,
        gltf: core(&["normalTexture", "scale"]),
        default: [1.0, 0.0, 0.0, 0.0],
        factor: None,
        gpu: words(
            named!(MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE),
            3,
            1,
            |m| bits(m.normal_scale),
        ),
    },
    MaterialParam {
        name: "clearcoat_normal_scale",
        kind: ParamKind::Number,
        gltf: extension(
            "KHR_materials_clearcoat",
            &["clearcoatNormalTexture", "scale"],
        ),
        default: [1.0, 0.0, 0.0, 0.0],
        factor: None,
        gpu: words(
            named!(MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE),
            3,
            1,
            |m| bits(m.clearcoat.normal_scale),
        ),
    },
    MaterialParam {
        // -ln(attenuation_color) / attenuation_distance per channel (Beer-Lambert).
        name: "attenuation_coefficient",
        kind: ParamKind::Derived,
        gltf: None,
        default: [0.0; 4],
        factor: None,
        gpu: words(
            named!(MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE),
            0,
            3,
            |m| rgb_bits(m.transmission.attenuation),
        ),
    },
    MaterialParam {
        // sigma_t rho_ss per channel (KHR_materials_volume_scatter; 0 without it).
        name: "scattering_coefficient",
        kind: ParamKind::Derived,
        gltf: None,
        default: [0.0; 4],
        factor: None,
        gpu: words(named!(MATERIAL_TEXEL_FLAGS), 1, 3, |m| {
            rgb_bits(m.transmission.scattering)
        }),
    },
    MaterialParam {
        // Bit (1 << MATERIAL_TEXTURE_*) per slot that holds a texture.
        name: "texture_mask",
        kind: ParamKind::Derived,
        gltf: None,
        default: [0.0; 4],
        factor: None,
        gpu: words(named!(MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK), 1, 1, |m| {
            [texture_mask(m), 0, 0, 0]
        }),
    },
];

/// The words of the factor texels that no parameter takes (0): (texel, component).
pub const UNUSED_MATERIAL_WORDS: &[(u32, u32)] = &[(MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK, 3)];

/// The names of the factors a caller gives (`MaterialFactors`; Python's `MATERIAL_KEYS`), in
/// the table's order.
pub fn material_keys() -> Vec<&'static str> {
    MATERIAL_PARAMS
        .iter()
        .filter(|param| param.factor.is_some())
        .map(|param| param.name)
        .collect()
}

const fn texture(
    name: &'static str,
    gltf: Option<GltfSource>,
    (slot, slot_name): (u32, &'static str),
    srgb: bool,
    get: fn(&PbrMaterial) -> Option<TextureBinding>,
    set: fn(&mut PbrMaterial, Option<TextureBinding>),
) -> MaterialTexture {
    let Some(gltf) = gltf else {
        panic!("a texture has a glTF source");
    };
    MaterialTexture {
        name,
        gltf,
        slot,
        slot_name,
        srgb,
        get,
        set,
    }
}

/// The material's texture slots, in glTF's order (the core material's, then each
/// extension's): the order `scene.json` lists the textures it leaves out in.
pub const MATERIAL_TEXTURES: &[MaterialTexture] = &[
    texture(
        "baseColorTexture",
        core(&["pbrMetallicRoughness", "baseColorTexture"]),
        named!(MATERIAL_TEXTURE_BASE_COLOR),
        true,
        |m| m.base_color_texture,
        |m, b| m.base_color_texture = b,
    ),
    texture(
        "metallicRoughnessTexture",
        core(&["pbrMetallicRoughness", "metallicRoughnessTexture"]),
        named!(MATERIAL_TEXTURE_METALLIC_ROUGHNESS),
        false,
        |m| m.metallic_roughness_texture,
        |m, b| m.metallic_roughness_texture = b,
    ),
    texture(
        "normalTexture",
        core(&["normalTexture"]),
        named!(MATERIAL_TEXTURE_NORMAL),
        false,
        |m| m.normal_texture,
        |m, b| m.normal_texture = b,
    ),
    texture(
        "emissiveTexture",
        core(&["emissiveTexture"]),
        named!(MATERIAL_TEXTURE_EMISSIVE),
        true,
        |m| m.emissive_texture,
        |m, b| m.emissive_texture = b,
    ),
    texture(
        "specularTexture",
        extension("KHR_materials_specular", &["specularTexture"]),
        named!(MATERIAL_TEXTURE_SPECULAR),
        false,
        |m| m.specular_texture,
        |m, b| m.specular_texture = b,
    ),
    texture(
        "specularColorTexture",
        extension("KHR_materials_specular", &["specularColorTexture"]),
        named!(MATERIAL_TEXTURE_SPECULAR_COLOR),
        true,
        |m| m.specular_color_texture,
        |m, b| m.specular_color_texture = b,
    ),
    texture(
        "transmissionTexture",
        extension("KHR_materials_transmission", &["transmissionTexture"]),
        named!(MATERIAL_TEXTURE_TRANSMISSION),
        false,
        |m| m.transmission.texture,
        |m, b| m.transmission.texture = b,
    ),
    texture(
        "thicknessTexture",
        volume(&["thicknessTexture"]),
        named!(MATERIAL_TEXTURE_THICKNESS),
        false,
        |m| m.transmission.thickness_texture,
        |m, b| m.transmission.thickness_texture = b,
    ),
    texture(
        "clearcoatTexture",
        extension("KHR_materials_clearcoat", &["clearcoatTexture"]),
        named!(MATERIAL_TEXTURE_CLEARCOAT),
        false,
        |m| m.clearcoat.texture,
        |m, b| m.clearcoat.texture = b,
    ),
    texture(
        "clearcoatRoughnessTexture",
        extension("KHR_materials_clearcoat", &["clearcoatRoughnessTexture"]),
        named!(MATERIAL_TEXTURE_CLEARCOAT_ROUGHNESS),
        false,
        |m| m.clearcoat.roughness_texture,
        |m, b| m.clearcoat.roughness_texture = b,
    ),
    texture(
        "clearcoatNormalTexture",
        extension("KHR_materials_clearcoat", &["clearcoatNormalTexture"]),
        named!(MATERIAL_TEXTURE_CLEARCOAT_NORMAL),
        false,
        |m| m.clearcoat.normal_texture,
        |m, b| m.clearcoat.normal_texture = b,
    ),
    texture(
        "sheenColorTexture",
        extension("KHR_materials_sheen", &["sheenColorTexture"]),
        named!(MATERIAL_TEXTURE_SHEEN_COLOR),
        true,
        |m| m.sheen.color_texture,
        |m, b| m.sheen.color_texture = b,
    ),
    texture(
        "sheenRoughnessTexture",
        extension("KHR_materials_sheen", &["sheenRoughnessTexture"]),
        named!(MATERIAL_TEXTURE_SHEEN_ROUGHNESS),
        false,
        |m| m.sheen.roughness_texture,
        |m, b| m.sheen.roughness_texture = b,
    ),
];

#[cfg(test)]
#[path = "material_params_tests.rs"]
mod tests;
