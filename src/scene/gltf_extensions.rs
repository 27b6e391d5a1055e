//! Which glTF extensions vkpath implements, and one warning for each extension a file uses
//! that it does not (so nothing a file asks for is ignored in silence).

use super::material_params::{MATERIAL_PARAMS, MATERIAL_TEXTURES};

/// The glTF extensions whose meaning vkpath implements beyond the material's: those are the
/// ones the material parameter table reads (`super::material_params`).
const OTHER_SUPPORTED_EXTENSIONS: [&str; 8] = [
    "KHR_texture_transform",
    "KHR_mesh_quantization",
    "KHR_lights_punctual",
    "KHR_materials_variants",
    "EXT_texture_webp",
    "KHR_texture_webp",
    // Converted to the metallic-roughness model (`super::gltf_spec_gloss`).
    "KHR_materials_pbrSpecularGlossiness",
    // Each instance flattened as a node's copy of its mesh (`super::gltf_instancing`).
    "EXT_mesh_gpu_instancing",
];

/// Whether vkpath implements the meaning of glTF extension `name` (a file that requires
/// others is refused with their names): the material parameter table's extensions and
/// `OTHER_SUPPORTED_EXTENSIONS`.
pub fn is_supported_extension(name: &str) -> bool {
    OTHER_SUPPORTED_EXTENSIONS.contains(&name)
        || MATERIAL_PARAMS
            .iter()
            .filter_map(|param| param.gltf)
            .chain(MATERIAL_TEXTURES.iter().map(|texture| texture.gltf))
            .any(|source| source.extension == Some(name))
}

/// Every glTF extension vkpath implements (`is_supported_extension`'s), each once.
#[cfg(test)]
pub fn supported_extensions() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = OTHER_SUPPORTED_EXTENSIONS
        .into_iter()
        .chain(
            MATERIAL_PARAMS
                .iter()
                .filter_map(|param| param.gltf?.extension),
        )
        .chain(
            MATERIAL_TEXTURES
                .iter()
                .filter_map(|texture| texture.gltf.extension),
        )
        .collect();
    names.sort_unstable();
    names.dedup();
    names
}

/// What a render loses when vkpath ignores a known extension: (extension, what is lost).
/// Extensions not listed here get a generic sentence.
const WHAT_IS_LOST: &[(&str, &str)] = &[
    (
        "KHR_materials_iridescence",
        "surfaces render without thin-film colours",
    ),
    (
        "KHR_materials_anisotropy",
        "anisotropic highlights render isotropic",
    ),
    (
        "KHR_materials_dispersion",
        "refraction renders without dispersion",
    ),
    (
        "KHR_materials_diffuse_transmission",
        "no light passes diffusely through thin surfaces",
    ),
    (
        "KHR_texture_basisu",
        "KTX2/Basis textures are not read; their factors stay",
    ),
    (
        "KHR_draco_mesh_compression",
        "Draco-compressed meshes are not decoded",
    ),
    (
        "EXT_meshopt_compression",
        "meshopt-compressed buffers are not decoded",
    ),
    (
        "KHR_animation_pointer",
        "its channels (animated material factors, lights, cameras) are skipped; node animations play",
    ),
    ("KHR_xmp_json_ld", "metadata only; nothing is lost"),
];

/// One warning line for each extension in `extensions_used` that vkpath does not implement,
/// naming it and what the render loses ("KHR_materials_iridescence: ignored, surfaces
/// render without thin-film colours"), each extension once, in the file's order.
pub fn unsupported_extension_warnings<'a>(
    extensions_used: impl IntoIterator<Item = &'a str>,
) -> Vec<String> {
    let mut seen: Vec<&str> = Vec::new();
    let mut warnings = Vec::new();
    for extension in extensions_used {
        if is_supported_extension(extension) || seen.contains(&extension) {
            continue;
        }
        seen.push(extension);
        let lost = WHAT_IS_LOST
            .iter()
            .find(|(name, _)| *name == extension)
            .map(|(_, lost)| (*lost).to_string())
            .unwrap_or_else(|| "vkpath does not implement it; what it adds is lost".to_string());
        warnings.push(format!(
            "glTF extension {}: ignored, {lost}",
            super::printable(extension)
        ));
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_unsupported_extension_warns_once_and_supported_ones_do_not() {
        let warnings = unsupported_extension_warnings([
            "KHR_materials_iridescence",
            "KHR_materials_ior",
            "KHR_materials_iridescence",
            "VENDOR_something",
        ]);
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert_eq!(
            warnings[0],
            "glTF extension KHR_materials_iridescence: ignored, surfaces render without thin-film colours"
        );
        assert!(warnings[1].starts_with("glTF extension VENDOR_something: ignored, "));
    }

    #[test]
    fn the_table_names_no_supported_extension() {
        for (name, _) in WHAT_IS_LOST {
            assert!(!is_supported_extension(name), "{name}");
        }
    }

    #[test]
    fn the_supported_extensions_are_the_material_tables_and_eight_more() {
        // The eleven vkpath implemented before the material table named them, variants,
        // KHR_materials_volume_scatter, WebP textures, specular-glossiness (converted) and
        // GPU instancing.
        let supported = [
            "KHR_materials_emissive_strength",
            "KHR_materials_specular",
            "KHR_materials_ior",
            "KHR_materials_transmission",
            "KHR_materials_volume",
            "KHR_materials_volume_scatter",
            "KHR_materials_clearcoat",
            "KHR_materials_sheen",
            "KHR_materials_unlit",
            "KHR_texture_transform",
            "KHR_mesh_quantization",
            "KHR_lights_punctual",
            "KHR_materials_variants",
            "EXT_texture_webp",
            "KHR_texture_webp",
            "KHR_materials_pbrSpecularGlossiness",
            "EXT_mesh_gpu_instancing",
        ];
        for name in supported {
            assert!(is_supported_extension(name), "{name}");
        }
        assert_eq!(supported_extensions().len(), supported.len());
        assert!(supported_extensions()
            .iter()
            .all(|name| is_supported_extension(name)));
        for name in ["KHR_materials_iridescence", "KHR_materials", "", "VENDOR_x"] {
            assert!(!is_supported_extension(name), "{name}");
        }
    }
}
