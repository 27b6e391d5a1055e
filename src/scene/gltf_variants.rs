//! `KHR_materials_variants`: a glTF file's named material variants (a shoe in "Beach",
//! "Midnight" and "Street" colours). Each primitive maps some variants to other materials
//! than its own; a render takes one variant (`LoadOptions::variant`, `render --variant`), or
//! without one the primitives' own materials, as the extension's specification says.

use std::path::Path;

use gltf::Document;
use serde_json::Value;

use super::error::SceneError;
use super::gltf_loader::malformed;
use super::printable;

/// The extension's name.
pub const EXTENSION: &str = "KHR_materials_variants";

/// The names of the file's material variants, in the file's order (none without the
/// extension; an unnamed one is called by its index, `#i`).
pub fn variant_names(document: &Document) -> Vec<String> {
    document
        .extension_value(EXTENSION)
        .and_then(|extension| extension.get("variants"))
        .and_then(Value::as_array)
        .map(|variants| {
            variants
                .iter()
                .enumerate()
                .map(|(index, variant)| {
                    variant
                        .get("name")
                        .and_then(Value::as_str)
                        .map_or_else(|| format!("#{index}"), printable)
                })
                .collect()
        })
        .unwrap_or_default()
}

/// The index of the variant called `name` in the file at `path`, or an error that lists the
/// file's variants.
pub fn variant_index(path: &Path, document: &Document, name: &str) -> Result<usize, SceneError> {
    let names = variant_names(document);
    names
        .iter()
        .position(|known| known == name)
        .ok_or_else(|| SceneError::UnknownVariant {
            path: path.to_owned(),
            name: printable(name),
            known: names,
        })
}

/// The index of the material that `primitive` takes in variant `variant` (`None`: the
/// primitive's own, which is also what it takes in a variant none of its mappings names);
/// `None` for glTF's default material. A mapping to a material the file lacks is an error
/// that names the primitive by `context` ("mesh 'm' primitive 0").
pub fn primitive_material(
    path: &Path,
    document: &Document,
    (primitive, context): (&gltf::Primitive, &str),
    variant: Option<usize>,
) -> Result<Option<usize>, SceneError> {
    let own = primitive.material().index();
    let Some(variant) = variant else {
        return Ok(own);
    };
    let mappings = primitive
        .extension_value(EXTENSION)
        .and_then(|extension| extension.get("mappings"))
        .and_then(Value::as_array);
    let names_variant = |mapping: &&Value| {
        mapping
            .get("variants")
            .and_then(Value::as_array)
            .is_some_and(|variants| variants.iter().any(|v| v.as_u64() == Some(variant as u64)))
    };
    let Some(mapping) = mappings.and_then(|m| m.iter().find(names_variant)) else {
        return Ok(own);
    };
    match mapping.get("material").and_then(Value::as_u64) {
        Some(index) if (index as usize) < document.materials().len() => Ok(Some(index as usize)),
        _ => Err(malformed(
            path,
            format!(
                "{context}: its {EXTENSION} mapping for variant {variant} names no material of the file"
            ),
        )),
    }
}
