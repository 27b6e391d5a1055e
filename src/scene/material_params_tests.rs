//! The parameter table against the places that must agree with it: the layout of
//! `glsl/shared.h`, the GLSL readers and their twins, `MaterialFactors`' defaults.

use std::collections::BTreeMap;

use glam::{Vec3, Vec4};

use super::*;
use crate::contract::{MATERIAL_FACTOR_TEXEL_COUNT, MATERIAL_TEXTURE_SLOT_COUNT};
use crate::cpu::gltf_surface::{self as twin, SurfaceTexels};
use crate::render::gpu_materials::{material_texel_words, GpuMaterial};
use crate::render::gpu_textures::TextureAtlas;
use crate::scene::materials::SceneMaterials;
use crate::scene::textures::{DecodedImage, Texture, TextureTransform, WrapMode};

/// The text of a file of the crate.
fn source(path: &str) -> String {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The `#define NAME <integer>` lines of glsl/shared.h whose name starts with `prefix`.
fn shared_defines(prefix: &str) -> BTreeMap<String, u32> {
    source("glsl/shared.h")
        .lines()
        .filter_map(|line| {
            let words: Vec<&str> = line.split_whitespace().collect();
            match words.as_slice() {
                ["#define", name, value] if name.starts_with(prefix) => {
                    Some(((*name).to_owned(), value.parse().ok()?))
                }
                _ => None,
            }
        })
        .collect()
}

#[test]
fn every_factor_word_is_one_parameters_or_unused() {
    let mut owner: BTreeMap<(u32, u32), &str> = BTreeMap::new();
    for param in MATERIAL_PARAMS {
        let Some(gpu) = &param.gpu else { continue };
        assert!(
            gpu.count >= 1 && gpu.component + gpu.count <= 4,
            "{}",
            param.name
        );
        assert!(gpu.texel < MATERIAL_FACTOR_TEXEL_COUNT, "{}", param.name);
        for component in gpu.component..gpu.component + gpu.count {
            if let Some(other) = owner.insert((gpu.texel, component), param.name) {
                panic!(
                    "{} and {other} share texel {} component {component}",
                    param.name, gpu.texel
                );
            }
        }
    }
    for &word in UNUSED_MATERIAL_WORDS {
        assert!(owner.insert(word, "unused").is_none(), "{word:?}");
    }
    // Every word of every factor texel is someone's: no gap, no overlap.
    assert_eq!(owner.len(), 4 * MATERIAL_FACTOR_TEXEL_COUNT as usize);
    let names: Vec<&str> = MATERIAL_PARAMS.iter().map(|p| p.name).collect();
    for (i, name) in names.iter().enumerate() {
        assert!(!names[..i].contains(name), "{name} twice");
    }
}

#[test]
fn the_table_and_glsl_shared_h_name_the_same_layout() {
    let texels = shared_defines("MATERIAL_TEXEL_");
    let mut named: BTreeMap<String, u32> = BTreeMap::new();
    for gpu in MATERIAL_PARAMS.iter().filter_map(|p| p.gpu.as_ref()) {
        assert_eq!(
            texels.get(gpu.texel_name),
            Some(&gpu.texel),
            "glsl/shared.h's {}",
            gpu.texel_name
        );
        named.insert(gpu.texel_name.to_owned(), gpu.texel);
    }
    let declared: BTreeMap<String, u32> = texels
        .into_iter()
        .filter(|(name, _)| name != "MATERIAL_TEXEL_COUNT")
        .collect();
    assert_eq!(
        named, declared,
        "every MATERIAL_TEXEL_* of glsl/shared.h is some parameter's"
    );
    let slots: BTreeMap<String, u32> = shared_defines("MATERIAL_TEXTURE_")
        .into_iter()
        .filter(|(name, _)| name != "MATERIAL_TEXTURE_SLOT_COUNT")
        .collect();
    let table: BTreeMap<String, u32> = MATERIAL_TEXTURES
        .iter()
        .map(|t| (t.slot_name.to_owned(), t.slot))
        .collect();
    assert_eq!(table, slots, "every MATERIAL_TEXTURE_* is one row");
    assert_eq!(
        MATERIAL_TEXTURES.len(),
        MATERIAL_TEXTURE_SLOT_COUNT as usize
    );
    let mut numbers: Vec<u32> = table.values().copied().collect();
    numbers.sort_unstable();
    assert_eq!(
        numbers,
        (0..MATERIAL_TEXTURE_SLOT_COUNT).collect::<Vec<_>>()
    );
}

#[test]
fn the_glsl_readers_and_their_twins_read_every_texel() {
    // glsl/materials.glsl unpacks the words (glsl/gltf_surface.glsl picks the base colour's
    // and emission's slots); src/cpu/gltf_surface.rs is their twin.
    let glsl = source("glsl/materials.glsl") + &source("glsl/gltf_surface.glsl");
    let rust = source("src/cpu/gltf_surface.rs");
    let texels = MATERIAL_PARAMS
        .iter()
        .filter_map(|p| p.gpu.as_ref())
        .map(|gpu| gpu.texel_name);
    let slots = MATERIAL_TEXTURES.iter().map(|t| t.slot_name);
    for name in texels.chain(slots) {
        assert!(glsl.contains(name), "glsl/materials.glsl reads no {name}");
        assert!(
            rust.contains(name),
            "src/cpu/gltf_surface.rs reads no {name}"
        );
    }
}

#[test]
fn default_factors_are_the_tables_defaults() {
    let factors = MaterialFactors::default();
    for param in MATERIAL_PARAMS {
        if let Some(factor) = &param.factor {
            assert_eq!((factor.get)(&factors), param.default, "{}", param.name);
        }
    }
    assert_eq!(factors.alpha_mode, AlphaMode::Opaque);
    assert_eq!(factors.attenuation_distance, f32::INFINITY);
    // Each factor's set and get agree, on a value other than its default.
    for param in MATERIAL_PARAMS {
        let Some(factor) = &param.factor else {
            continue;
        };
        let mut changed = MaterialFactors {
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            ..factors
        };
        let value = match param.kind {
            ParamKind::Bool | ParamKind::AlphaMode => [1.0, 0.0, 0.0, 0.0],
            ParamKind::Number | ParamKind::NonNegative | ParamKind::AlphaCutoff => {
                [0.25, 0.0, 0.0, 0.0]
            }
            ParamKind::Rgb => [0.25, 0.5, 0.75, 0.0],
            ParamKind::Rgba => [0.25, 0.5, 0.75, 0.125],
            ParamKind::Derived => panic!("{}: a factor is not derived", param.name),
        };
        (factor.set)(&mut changed, value);
        assert_eq!((factor.get)(&changed), value, "{}", param.name);
    }
    assert_eq!(
        material_keys().len(),
        MATERIAL_PARAMS
            .iter()
            .filter(|p| p.factor.is_some())
            .count()
    );
}

/// A material with a distinct value in every parameter and a texture in every slot, packed.
fn distinct_material() -> (PbrMaterial, Vec<u32>, u32) {
    let mut factors = MaterialFactors::default();
    for (i, param) in MATERIAL_PARAMS.iter().enumerate() {
        let Some(factor) = &param.factor else {
            continue;
        };
        let x = 0.01 * (i as f32 + 1.0);
        let value = match param.kind {
            ParamKind::Bool => [1.0, 0.0, 0.0, 0.0],
            ParamKind::AlphaMode => [ALPHA_MODE_MASK as f32, 0.0, 0.0, 0.0],
            _ => [x, x + 0.001, x + 0.002, x + 0.003],
        };
        (factor.set)(&mut factors, value);
    }
    // Lit, so that the emission stays; the unlit flag's word then set apart.
    let mut material = MaterialFactors {
        unlit: false,
        ..factors
    }
    .material();
    material.unlit = true;
    material.normal_scale = 0.7;
    material.clearcoat.normal_scale = 0.8;
    let image = DecodedImage {
        width: 1,
        height: 1,
        texels: vec![[255; 4]],
    };
    let textures = vec![Texture::new(
        image,
        WrapMode::Repeat,
        WrapMode::Repeat,
        true,
    )];
    for slot in MATERIAL_TEXTURES {
        let binding = TextureBinding::new(0, TextureTransform::identity());
        (slot.set)(&mut material, Some(binding));
    }
    let atlas = TextureAtlas::new(&textures, 1 << 20).unwrap();
    let scene = SceneMaterials {
        materials: vec![material],
        textures,
        triangles: vec![],
        ..Default::default()
    };
    let packed = GpuMaterial::new(&material, &scene, &atlas);
    let mask = packed.texture_mask();
    (material, material_texel_words(&[packed]), mask)
}

#[test]
fn the_twins_read_back_every_parameter() {
    // Every parameter the GPU takes, packed by the table and read by the CPU twins of
    // glsl/materials.glsl's readers (the GPU readers are held to the twins by
    // tests/surface_twins.rs): each comes back where the table says it lies.
    let (material, words, mask) = distinct_material();
    let texels = SurfaceTexels {
        triangles: &[],
        shading: &[],
        materials: &words,
        texture_texels: &[],
        scene_texture_slots: 0,
        scene_has_layers: true,
        scene_vertex_attributes: 0,
    };
    let textures = twin::MaterialTextures {
        slots: [Vec4::ONE; MATERIAL_TEXTURE_SLOT_COUNT as usize],
    };
    let base_color = twin::get_base_color(&texels, 0, Vec4::ONE);
    let sample = twin::get_material(&texels, 0, &textures, base_color);
    let with_textures = SurfaceTexels {
        scene_texture_slots: u32::MAX,
        ..texels
    };
    let read: Vec<(&str, Vec<f32>)> = MATERIAL_PARAMS
        .iter()
        .filter(|param| param.gpu.is_some())
        .map(|param| {
            let value: Vec<f32> = match param.name {
                "base_color" => base_color.to_array().to_vec(),
                "metallic" => vec![sample.metallic],
                "roughness" => vec![sample.roughness],
                "emission" => twin::get_material_emission(&texels, 0, Vec4::ONE)
                    .to_array()
                    .to_vec(),
                "specular" => vec![sample.specular],
                "specular_color" => sample.specular_color.to_array().to_vec(),
                "ior" => vec![sample.ior],
                "transmission" => vec![sample.transmission],
                "thickness" => vec![sample.thickness],
                "clearcoat" => vec![sample.clearcoat],
                "clearcoat_roughness" => vec![sample.clearcoat_roughness],
                "sheen_color" => sample.sheen_color.to_array().to_vec(),
                "sheen_roughness" => vec![sample.sheen_roughness],
                "alpha_mode" => vec![twin::get_material_alpha_mode(&texels, 0) as f32],
                "alpha_cutoff" => vec![twin::get_material_alpha_cutoff(&texels, 0)],
                "unlit" => vec![f32::from(u8::from(twin::is_unlit_material(&texels, 0)))],
                "normal_scale" => vec![twin::get_material_normal_scale(&texels, 0)],
                "clearcoat_normal_scale" => {
                    vec![twin::get_material_clearcoat_normal_scale(&texels, 0)]
                }
                "attenuation_coefficient" => sample.attenuation.to_array().to_vec(),
                "scattering_coefficient" => twin::get_material_volume_scattering(&texels, 0)
                    .truncate()
                    .to_array()
                    .to_vec(),
                "scatter_anisotropy" => vec![twin::get_material_volume_scattering(&texels, 0).w],
                "texture_mask" => {
                    let present = MATERIAL_TEXTURES
                        .iter()
                        .filter(|t| twin::has_material_texture(&with_textures, 0, t.slot))
                        .fold(0, |bits, t| bits | 1 << t.slot);
                    vec![present as f32]
                }
                other => panic!("no twin reads {other}: add its reader here"),
            };
            (param.name, value)
        })
        .collect();
    for (name, value) in read {
        let param = MATERIAL_PARAMS.iter().find(|p| p.name == name).unwrap();
        let gpu = param.gpu.as_ref().unwrap();
        let packed = (gpu.pack)(&material);
        let expected: Vec<f32> = packed[..gpu.count as usize]
            .iter()
            .map(|&word| match param.kind {
                ParamKind::AlphaMode | ParamKind::Bool => word as f32,
                ParamKind::Derived if name == "texture_mask" => word as f32,
                _ => f32::from_bits(word),
            })
            .collect();
        assert_eq!(value, expected, "{name}");
    }
    assert_eq!(mask, (1 << MATERIAL_TEXTURE_SLOT_COUNT) - 1);
    // The values were distinct (a reader of the wrong word would have found another's).
    assert_eq!(sample.clearcoat, material.clearcoat.factor);
    assert_ne!(sample.clearcoat, sample.clearcoat_roughness);
    assert_eq!(sample.sheen_color, material.sheen.color);
    assert!(material.sheen.color.min_element() > 0.0 && material.unlit);
    assert_ne!(material.emission, Vec3::ZERO);
}
