//! KHR_materials_pbrSpecularGlossiness (archived, superseded by KHR_materials_specular)
//! converted to the metallic-roughness model as glTF-Transform's `metalRough()` does it:
//! the material's JSON is rewritten into the core model plus KHR_materials_ior and
//! KHR_materials_specular, which the material parameter table then reads as any file's.
//!
//! The conversion (in its words: "precise and reliable", no metalness heuristic):
//! - `baseColorFactor` = `diffuseFactor`, `baseColorTexture` = `diffuseTexture`;
//! - `metallicFactor` 0 (a dielectric), KHR_materials_ior's `ior` 1000, so that the
//!   dielectric's F0 is ((ior - 1) / (ior + 1))^2 = 0.996;
//! - KHR_materials_specular's `specularFactor` 1 and `specularColorFactor` = the
//!   extension's `specularFactor` (F0 = min(0.996 specular, 1)); its
//!   `specularColorTexture` = `specularGlossinessTexture` (sRGB RGB);
//! - `roughnessFactor` = 1 - `glossinessFactor` without a texture; with
//!   `specularGlossinessTexture`, `roughnessFactor` 1 and a metallic-roughness texture
//!   whose G is 255 - round(A glossinessFactor) per texel (`roughness_from_glossiness`).

use serde_json::{json, Value};

use super::textures::Texture;

/// The extension's name.
pub const SPEC_GLOSS: &str = "KHR_materials_pbrSpecularGlossiness";

/// Rewrites a material's JSON that has KHR_materials_pbrSpecularGlossiness into the
/// metallic-roughness model (module doc), removing the extension; returns its
/// `specularGlossinessTexture` info and `glossinessFactor` where it has that texture (the
/// caller binds the derived roughness texture). A material without the extension is left
/// as it is.
pub fn to_metal_rough(material: &mut Value) -> Option<(Value, f32)> {
    let spec_gloss = material
        .get_mut("extensions")?
        .as_object_mut()?
        .remove(SPEC_GLOSS)?;
    let number = |key: &str, default: f64| {
        spec_gloss
            .get(key)
            .and_then(Value::as_f64)
            .unwrap_or(default)
    };
    let glossiness = number("glossinessFactor", 1.0);
    let diffuse = spec_gloss
        .get("diffuseFactor")
        .cloned()
        .unwrap_or_else(|| json!([1.0, 1.0, 1.0, 1.0]));
    let specular_color = spec_gloss
        .get("specularFactor")
        .cloned()
        .unwrap_or_else(|| json!([1.0, 1.0, 1.0]));
    let texture = spec_gloss.get("specularGlossinessTexture").cloned();
    let mut pbr = json!({
        "baseColorFactor": diffuse,
        "metallicFactor": 0.0,
        "roughnessFactor": if texture.is_some() { 1.0 } else { 1.0 - glossiness },
    });
    if let Some(diffuse_texture) = spec_gloss.get("diffuseTexture") {
        pbr["baseColorTexture"] = diffuse_texture.clone();
    }
    let mut specular = json!({"specularFactor": 1.0, "specularColorFactor": specular_color});
    if let Some(texture) = &texture {
        specular["specularColorTexture"] = texture.clone();
    }
    material["pbrMetallicRoughness"] = pbr;
    let extensions = &mut material["extensions"];
    extensions["KHR_materials_ior"] = json!({"ior": 1000.0});
    extensions["KHR_materials_specular"] = specular;
    texture.map(|info| (info, glossiness as f32))
}

/// The metallic-roughness texture of a specular-glossiness texture: per texel G (roughness)
/// = 255 - round(A `glossiness`), R and B (metallic, whose factor is 0) 0, A 255; the
/// same size, wrap modes and filter.
pub fn roughness_from_glossiness(texture: &Texture, glossiness: f32) -> Texture {
    let texels = texture
        .texels
        .iter()
        .map(|&[_, _, _, a]| {
            let gloss = (f32::from(a) * glossiness).round().clamp(0.0, 255.0) as u8;
            [0, 255 - gloss, 0, 255]
        })
        .collect();
    Texture {
        texels,
        ..texture.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::textures::{DecodedImage, WrapMode};

    #[test]
    fn factors_become_metallic_roughness_with_ior_and_specular() {
        let mut material = json!({
            "name": "gold",
            "extensions": {SPEC_GLOSS: {
                "diffuseFactor": [0.1, 0.2, 0.3, 0.5],
                "specularFactor": [1.0, 0.766, 0.336],
                "glossinessFactor": 0.9
            }}
        });
        assert_eq!(to_metal_rough(&mut material), None);
        let expected = json!({
            "name": "gold",
            "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.3, 0.5],
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0 - 0.9},
            "extensions": {
                "KHR_materials_ior": {"ior": 1000.0},
                "KHR_materials_specular": {"specularFactor": 1.0,
                                           "specularColorFactor": [1.0, 0.766, 0.336]}
            }
        });
        assert_eq!(material, expected);
        // The extension's defaults: white diffuse and specular, glossiness 1
        let mut bare = json!({"extensions": {SPEC_GLOSS: {}}});
        to_metal_rough(&mut bare);
        assert_eq!(bare["pbrMetallicRoughness"]["roughnessFactor"], 0.0);
        assert_eq!(
            bare["extensions"]["KHR_materials_specular"]["specularColorFactor"],
            json!([1.0, 1.0, 1.0])
        );
        // Without the extension nothing changes
        let mut plain = json!({"pbrMetallicRoughness": {"metallicFactor": 0.5}});
        let before = plain.clone();
        assert_eq!(to_metal_rough(&mut plain), None);
        assert_eq!(plain, before);
    }

    #[test]
    fn textures_move_and_glossiness_becomes_a_roughness_texture() {
        let diffuse = json!({"index": 0, "texCoord": 1});
        let spec_gloss = json!({"index": 1});
        let mut material = json!({"extensions": {SPEC_GLOSS: {
            "diffuseTexture": diffuse, "specularGlossinessTexture": spec_gloss,
            "glossinessFactor": 0.5
        }}});
        assert_eq!(
            to_metal_rough(&mut material),
            Some((spec_gloss.clone(), 0.5))
        );
        assert_eq!(
            material["pbrMetallicRoughness"]["baseColorTexture"],
            diffuse
        );
        // Roughness comes from the texture: its factor is 1
        assert_eq!(material["pbrMetallicRoughness"]["roughnessFactor"], 1.0);
        assert_eq!(
            material["extensions"]["KHR_materials_specular"]["specularColorTexture"],
            spec_gloss
        );
        let texture = Texture::new(
            DecodedImage {
                width: 3,
                height: 1,
                texels: vec![[10, 20, 30, 0], [40, 50, 60, 255], [70, 80, 90, 101]],
            },
            WrapMode::ClampToEdge,
            WrapMode::Repeat,
            true,
        );
        let rough = roughness_from_glossiness(&texture, 0.5);
        // 255 - round(A * 0.5): 255, 255 - 128 (127.5 rounds up), 255 - 51 (50.5 rounds up)
        assert_eq!(
            rough.texels,
            [[0, 255, 0, 255], [0, 127, 0, 255], [0, 204, 0, 255]]
        );
        assert_eq!(
            (rough.width, rough.wrap_s, rough.wrap_t, rough.nearest),
            (3, WrapMode::ClampToEdge, WrapMode::Repeat, true)
        );
    }
}
