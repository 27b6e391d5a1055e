//! glTF materials as vkpath renders them: the factors and texture slots of the material
//! parameter table (`super::material_params`: the metallic-roughness model and the
//! KHR_materials_* extensions it names), with KHR_texture_transform, and the textures they
//! use, decoded once each. Each is read where its row says glTF writes it.
//!
//! A texture that cannot be used (a missing or unreadable image, a format other than PNG,
//! JPEG or WebP, an image larger than `MAX_TEXTURE_SIZE` per side, a texture coordinate set
//! other than 0 and 1) gives a warning and the material falls back to its factor for that slot: one broken
//! texture should not stop a whole asset from rendering.

use std::collections::HashMap;
use std::io::Read as _;
use std::path::Path;

use glam::Vec3;

use super::files::{resolve_reference, LoadOptions, MAX_SCENE_FILE_BYTES};
use super::gltf_spec_gloss;
use super::material_factors::MaterialFactors;
use super::material_params::{
    GltfSource, MaterialParam, MaterialTexture, ParamKind, MATERIAL_PARAMS, MATERIAL_TEXTURES,
};
use super::materials::{PbrMaterial, TextureBinding};
use super::texture_source::TextureSourceError;
use super::textures::{decode_texture, Texture, TextureTransform, WrapMode};
use crate::contract::{
    ALPHA_MODE_BLEND, ALPHA_MODE_MASK, ALPHA_MODE_OPAQUE, MATERIAL_TEXTURE_EMISSIVE,
    MATERIAL_TEXTURE_NORMAL,
};

/// Converts materials and loads their textures, each once.
pub(crate) struct MaterialReader<'a> {
    path: &'a Path,
    document: &'a gltf::Document,
    buffers: &'a [gltf::buffer::Data],
    options: &'a LoadOptions,
    /// What it converted so far.
    pub converted: ConvertedMaterials,
}

/// What a `MaterialReader` converted: kept by a file read once (`GltfFile`) for its next
/// pose, whose reader then converts nothing again (every pose meets the same materials in
/// the same order: the hierarchy and its meshes do not move with time).
#[derive(Clone, Debug, Default)]
pub(crate) struct ConvertedMaterials {
    /// glTF material index (None: the default material) -> index in `materials`.
    material_indices: HashMap<Option<usize>, u32>,
    /// glTF texture index -> index in `textures`, or None when it could not be loaded.
    texture_indices: HashMap<usize, Option<u32>>,
    /// (index in `textures` of a specular-glossiness texture, glossinessFactor's bits) ->
    /// index in `textures` of the roughness derived from it.
    glossiness_textures: HashMap<(u32, u32), u32>,
    /// The converted materials.
    pub materials: Vec<PbrMaterial>,
    /// The decoded textures.
    pub textures: Vec<Texture>,
    /// What the user should know (textures that could not be used, ignored features).
    pub warnings: Vec<String>,
}

impl<'a> MaterialReader<'a> {
    /// A reader for the glTF file at `path` with its loaded `buffers`, which takes up where
    /// an earlier reader of the same file left off (`converted`; `Default` for none).
    pub fn new(
        path: &'a Path,
        document: &'a gltf::Document,
        buffers: &'a [gltf::buffer::Data],
        options: &'a LoadOptions,
        converted: ConvertedMaterials,
    ) -> MaterialReader<'a> {
        MaterialReader {
            path,
            document,
            buffers,
            options,
            converted,
        }
    }

    /// The index of `material` among the converted materials, converting it on first use.
    pub fn material_index(&mut self, material: &gltf::Material) -> u32 {
        if let Some(&index) = self.converted.material_indices.get(&material.index()) {
            return index;
        }
        let converted = self.convert(material);
        let index = self.converted.materials.len() as u32;
        self.converted.materials.push(converted);
        self.converted
            .material_indices
            .insert(material.index(), index);
        index
    }

    /// The material: its factors and textures, each read where its row of the parameter
    /// table (`MATERIAL_PARAMS`, `MATERIAL_TEXTURES`) says glTF writes it, then converted as
    /// `Scene::from_arrays` converts (`MaterialFactors::material`). Textures are bound in a
    /// fixed order, which numbers them: the extensions' slots (specular, specular colour,
    /// transmission, thickness, clear coat, sheen) in the table's order, then the core's
    /// (base colour, metallic-roughness, emissive), the normal texture last.
    fn convert(&mut self, material: &gltf::Material) -> PbrMaterial {
        let name = material_label(material);
        let mut json = material_json(self.document, material);
        // KHR_materials_pbrSpecularGlossiness, rewritten as metallic-roughness
        let glossiness_texture = gltf_spec_gloss::to_metal_rough(&mut json);
        let mut converted = material_factors(&json).material();
        let mut order: Vec<&MaterialTexture> = MATERIAL_TEXTURES.iter().collect();
        order.sort_by_key(|t| {
            (
                t.gltf.extension.is_none(),
                t.slot == MATERIAL_TEXTURE_NORMAL,
            )
        });
        for texture in order {
            if let Some(info) = gltf_value(&json, &texture.gltf) {
                let binding = self.json_binding(&name, texture.name, Some(info));
                // An emissive factor is the texture's scale, mostly white: alone it would
                // make the whole surface glow (the Khronos MultiUVTest's cube). Without its
                // texture the material emits nothing.
                if binding.is_none()
                    && texture.slot == MATERIAL_TEXTURE_EMISSIVE
                    && converted.emission != Vec3::ZERO
                {
                    converted.emission = Vec3::ZERO;
                    self.converted.warnings.push(format!(
                        "material '{name}': its emissiveTexture cannot be used, so it emits nothing (its emissiveFactor alone would light the whole surface)"
                    ));
                }
                (texture.set)(&mut converted, binding);
            }
        }
        if let Some((info, glossiness)) = glossiness_texture {
            converted.metallic_roughness_texture =
                self.glossiness_binding(&name, &info, glossiness);
        }
        // The texture infos' scales (glTF's default 1).
        let scale = |name: &str| {
            let param = MATERIAL_PARAMS.iter().find(|p| p.name == name);
            param
                .and_then(|p| parameter_value(&json, p))
                .map_or(1.0, |value| value[0])
        };
        converted.normal_scale = scale("normal_scale");
        converted.clearcoat.normal_scale = scale("clearcoat_normal_scale");
        converted.sanitized()
    }

    /// The metallic-roughness binding of a `specularGlossinessTexture` reference: the
    /// texture's roughness made from its glossiness (`roughness_from_glossiness`), derived
    /// once per texture and factor, on the reference's set and transform.
    fn glossiness_binding(
        &mut self,
        material: &str,
        info: &serde_json::Value,
        glossiness: f32,
    ) -> Option<TextureBinding> {
        let binding = self.json_binding(material, "specularGlossinessTexture", Some(info))?;
        let key = (binding.texture, glossiness.to_bits());
        let derived = match self.converted.glossiness_textures.get(&key) {
            Some(&derived) => derived,
            None => {
                let source = &self.converted.textures[binding.texture as usize];
                let rough = gltf_spec_gloss::roughness_from_glossiness(source, glossiness);
                self.converted.textures.push(rough);
                let derived = self.converted.textures.len() as u32 - 1;
                self.converted.glossiness_textures.insert(key, derived);
                derived
            }
        };
        Some(TextureBinding {
            texture: derived,
            ..binding
        })
    }

    /// The binding of a texture reference written in an extension's JSON (`{"index": i,
    /// "texCoord": k, "extensions": {"KHR_texture_transform": ...}}`); a warning and None
    /// where it names no texture of the file.
    fn json_binding(
        &mut self,
        material: &str,
        slot: &str,
        info: Option<&serde_json::Value>,
    ) -> Option<TextureBinding> {
        let info = info?;
        let texture = info
            .get("index")
            .and_then(serde_json::Value::as_u64)
            .and_then(|index| self.document.textures().nth(index as usize));
        let Some(texture) = texture else {
            self.converted.warnings.push(format!(
                "material '{material}': {slot} names no texture of the file, so it is ignored"
            ));
            return None;
        };
        let transform = info
            .get("extensions")
            .and_then(|e| e.get("KHR_texture_transform"));
        let (transform_matrix, transform_tex_coord) = json_texture_transform(transform);
        let tex_coord = transform_tex_coord
            .or_else(|| {
                info.get("texCoord")
                    .and_then(serde_json::Value::as_u64)
                    .map(|v| v as u32)
            })
            .unwrap_or(0);
        self.bind(material, slot, &texture, tex_coord, transform_matrix)
    }

    fn bind(
        &mut self,
        material: &str,
        slot: &str,
        texture: &gltf::Texture,
        tex_coord: u32,
        transform: TextureTransform,
    ) -> Option<TextureBinding> {
        if tex_coord > 1 {
            self.converted.warnings.push(format!(
                "material '{material}': {slot} uses TEXCOORD_{tex_coord}; only TEXCOORD_0 and TEXCOORD_1 are read, so the texture is ignored"
            ));
            return None;
        }
        let index = self.texture_index(texture)?;
        Some(TextureBinding {
            texture: index,
            transform,
            tex_coord,
        })
    }

    /// Decodes a texture on first use; None (with a warning) when it cannot be used. Its
    /// image is `EXT_texture_webp`'s (or `KHR_texture_webp`'s) `source` where it has one,
    /// else its own `source`, which is also the fallback where the WebP image cannot be
    /// used (with a warning naming it).
    fn texture_index(&mut self, texture: &gltf::Texture) -> Option<u32> {
        if let Some(&index) = self.converted.texture_indices.get(&texture.index()) {
            return index;
        }
        let name = texture
            .name()
            .map_or_else(|| format!("#{}", texture.index()), super::printable);
        let (webp, fallback) = texture_images(self.document, texture.index());
        let mut loaded = Err(TextureSourceError::NoImage);
        for image in [webp, fallback].into_iter().flatten() {
            if let Err(reason) = &loaded {
                if !matches!(reason, TextureSourceError::NoImage) {
                    self.converted.warnings.push(format!(
                        "texture '{name}': its WebP image cannot be used ({reason}), so its fallback image '{}' is used",
                        image_label(&image)
                    ));
                }
                loaded = self.load_texture(texture, &image).map_err(|reason| {
                    TextureSourceError::Image {
                        image: image_label(&image),
                        reason: Box::new(reason),
                    }
                });
            }
        }
        let index = match loaded {
            Ok(loaded) => {
                self.converted.textures.push(loaded);
                Some(self.converted.textures.len() as u32 - 1)
            }
            Err(reason) => {
                self.converted.warnings.push(format!(
                    "texture '{name}' is ignored (the material uses its factor instead): {reason}"
                ));
                None
            }
        };
        self.converted
            .texture_indices
            .insert(texture.index(), index);
        index
    }

    fn load_texture(
        &self,
        texture: &gltf::Texture,
        image: &gltf::Image,
    ) -> Result<Texture, TextureSourceError> {
        let (bytes, mime_type) = match image.source() {
            gltf::image::Source::View { view, mime_type } => {
                let buffer = self
                    .buffers
                    .get(view.buffer().index())
                    .ok_or(TextureSourceError::MissingBuffer)?;
                let end = view
                    .offset()
                    .checked_add(view.length())
                    .filter(|&end| end <= buffer.len())
                    .ok_or(TextureSourceError::ViewOutsideBuffer)?;
                (buffer[view.offset()..end].to_vec(), Some(mime_type))
            }
            gltf::image::Source::Uri { uri, mime_type } => (self.read_image_uri(uri)?, mime_type),
        };
        let decoded = decode_texture(&bytes, mime_type).map_err(TextureSourceError::Decode)?;
        let sampler = texture.sampler();
        let nearest = sampler.mag_filter() == Some(gltf::texture::MagFilter::Nearest);
        Ok(Texture::new(
            decoded,
            WrapMode::from_gltf(sampler.wrap_s()),
            WrapMode::from_gltf(sampler.wrap_t()),
            nearest,
        ))
    }

    /// An image's bytes from a data URI or a file next to the glTF (bounded as buffers are).
    fn read_image_uri(&self, uri: &str) -> Result<Vec<u8>, TextureSourceError> {
        if let Some(rest) = uri.strip_prefix("data:") {
            let (_, encoded) = rest
                .split_once(";base64,")
                .ok_or(TextureSourceError::NotBase64)?;
            return base64::decode(encoded).map_err(TextureSourceError::BadBase64);
        }
        if uri
            .split_once(':')
            .is_some_and(|(scheme, _)| scheme.len() > 1)
            && !uri.starts_with("file:")
        {
            return Err(TextureSourceError::Remote {
                uri: super::printable(uri),
            });
        }
        let file_name = uri
            .strip_prefix("file://")
            .or_else(|| uri.strip_prefix("file:"))
            .unwrap_or(uri);
        let decoded = urlencoding::decode(file_name).map_err(|_| TextureSourceError::UriNotUtf8)?;
        let file = resolve_reference(self.path, &decoded, self.options)
            .map_err(TextureSourceError::Reference)?;
        let shown = super::printable(&file.display().to_string());
        let unreadable = |error| TextureSourceError::Unreadable {
            file: shown.clone(),
            error,
        };
        let metadata = std::fs::metadata(&file).map_err(unreadable)?;
        if !metadata.is_file() {
            return Err(TextureSourceError::NotAFile {
                file: shown.clone(),
            });
        }
        let mut bytes = Vec::new();
        std::fs::File::open(&file)
            .and_then(|f| f.take(MAX_SCENE_FILE_BYTES).read_to_end(&mut bytes))
            .map_err(unreadable)?;
        Ok(bytes)
    }
}

/// The WebP extensions' names: `EXT_texture_webp` and its Khronos successor, whose texture
/// object holds the WebP image's index as `source`.
const WEBP_EXTENSIONS: [&str; 2] = ["EXT_texture_webp", "KHR_texture_webp"];

/// Texture `index`'s images: its WebP extension's `source` (None without one) and its own
/// `source` (None where the file leaves it out, which it may where it requires the
/// extension); each None too where it names no image of the file.
fn texture_images<'a>(
    document: &'a gltf::Document,
    index: usize,
) -> (Option<gltf::Image<'a>>, Option<gltf::Image<'a>>) {
    let Some(json) = document.as_json().textures.get(index) else {
        return (None, None);
    };
    let image = |index: usize| document.images().nth(index);
    let webp = webp_source(json).and_then(image);
    // gltf-json's stand-in for a missing source is u32::MAX, which names no image.
    (webp, image(json.source.value()))
}

/// The image index a texture's WebP extension names, where it has one.
pub(super) fn webp_source(texture: &gltf::json::Texture) -> Option<usize> {
    let others = &texture.extensions.as_ref()?.others;
    WEBP_EXTENSIONS
        .iter()
        .find_map(|name| others.get(*name)?.get("source")?.as_u64())
        .and_then(|source| usize::try_from(source).ok())
}

/// An image's name for messages: its name, or `#index`.
fn image_label(image: &gltf::Image) -> String {
    image
        .name()
        .map_or_else(|| format!("#{}", image.index()), super::printable)
}

/// A KHR_texture_transform written as JSON: its matrix (identity without one) and its
/// `texCoord` override.
fn json_texture_transform(
    transform: Option<&serde_json::Value>,
) -> (TextureTransform, Option<u32>) {
    let number = |value: Option<&serde_json::Value>, default: f32| {
        value.and_then(|v| v.as_f64()).map_or(default, |v| v as f32)
    };
    let pair = |key: &str, default: [f32; 2]| {
        transform
            .and_then(|t| t.get(key))
            .and_then(|v| v.as_array())
            .map_or(default, |a| {
                [number(a.first(), default[0]), number(a.get(1), default[1])]
            })
    };
    let matrix = match transform {
        Some(t) => TextureTransform::from_gltf(
            pair("offset", [0.0, 0.0]),
            number(t.get("rotation"), 0.0),
            pair("scale", [1.0, 1.0]),
        ),
        None => TextureTransform::identity(),
    };
    let tex_coord = transform
        .and_then(|t| t.get("texCoord"))
        .and_then(|v| v.as_u64())
        .map(|v| v as u32);
    (matrix, tex_coord)
}

/// The material's JSON as the file has it (gltf's typed extensions written back under
/// their names); null for glTF's default material.
fn material_json(document: &gltf::Document, material: &gltf::Material) -> serde_json::Value {
    material
        .index()
        .and_then(|index| document.as_json().materials.get(index))
        .and_then(|json| serde_json::to_value(json).ok())
        .unwrap_or(serde_json::Value::Null)
}

/// The value at `source` in a material's JSON: None where the material lacks its extension
/// (or the one it requires) or the value.
fn gltf_value<'j>(
    json: &'j serde_json::Value,
    source: &GltfSource,
) -> Option<&'j serde_json::Value> {
    let extension = |name: &str| json.get("extensions")?.get(name);
    if let Some(required) = source.requires {
        extension(required)?;
    }
    let object = match source.extension {
        Some(name) => extension(name)?,
        None => json,
    };
    source
        .path
        .iter()
        .try_fold(object, |value, key| value.get(key))
}

/// A parameter's value in a material's JSON, as four floats (`ParamKind`'s encoding); None
/// where the file does not write it, or writes something else than its type (glTF's
/// default then holds). A colour's missing component is the default's.
fn parameter_value(json: &serde_json::Value, param: &MaterialParam) -> Option<[f32; 4]> {
    let value = gltf_value(json, param.gltf.as_ref()?)?;
    let number = |v: &serde_json::Value| v.as_f64().map(|x| x as f32);
    match param.kind {
        ParamKind::Number | ParamKind::NonNegative | ParamKind::AlphaCutoff => {
            Some([number(value)?, 0.0, 0.0, 0.0])
        }
        ParamKind::Rgb | ParamKind::Rgba => {
            let components = value.as_array()?;
            let mut out = param.default;
            let count = if param.kind == ParamKind::Rgb { 3 } else { 4 };
            for (k, slot) in out.iter_mut().enumerate().take(count) {
                if let Some(x) = components.get(k).and_then(number) {
                    *slot = x;
                }
            }
            Some(out)
        }
        // An extension without fields (KHR_materials_unlit) is true by its presence.
        ParamKind::Bool => {
            let on = value.as_bool().unwrap_or(value.is_object());
            Some([f32::from(u8::from(on)), 0.0, 0.0, 0.0])
        }
        ParamKind::AlphaMode => {
            let code = match value.as_str()? {
                "MASK" => ALPHA_MODE_MASK,
                "BLEND" => ALPHA_MODE_BLEND,
                _ => ALPHA_MODE_OPAQUE,
            };
            Some([code as f32, 0.0, 0.0, 0.0])
        }
        ParamKind::Derived => None,
    }
}

/// A glTF material's constant factors, each where its row says, glTF's defaults where the
/// file says nothing (the volume's only with transmission: a volume without transmission is
/// ignored).
fn material_factors(json: &serde_json::Value) -> MaterialFactors {
    let mut factors = MaterialFactors::default();
    for param in MATERIAL_PARAMS {
        if let (Some(factor), Some(value)) = (param.factor, parameter_value(json, param)) {
            (factor.set)(&mut factors, value);
        }
    }
    factors
}

/// A material's name for messages: its name, `#index`, or "default".
pub(super) fn material_label(material: &gltf::Material) -> String {
    match (material.name(), material.index()) {
        (Some(name), _) => super::printable(name),
        (None, Some(index)) => format!("#{index}"),
        (None, None) => "default".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::materials::AlphaMode;
    use glam::{Vec3, Vec4};

    /// The factors of the first material of a glTF document whose `materials` is `json`,
    /// read as the loader reads them (through gltf's parse and the table's paths).
    fn factors_of(materials: &str, used: &str) -> MaterialFactors {
        let text = format!(
            r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": [{used}], "materials": {materials}}}"#
        );
        let gltf = gltf::Gltf::from_slice(text.as_bytes()).unwrap();
        let material = gltf.document.materials().next().unwrap();
        material_factors(&material_json(&gltf.document, &material))
    }

    #[test]
    fn every_factor_is_read_where_gltf_writes_it() {
        // Written as the specification spells each key, not from the table.
        let factors = factors_of(
            r#"[{
                "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.3, 0.4],
                                         "metallicFactor": 0.5, "roughnessFactor": 0.6},
                "emissiveFactor": [0.7, 0.8, 0.9],
                "alphaMode": "MASK", "alphaCutoff": 0.25, "doubleSided": true,
                "extensions": {
                    "KHR_materials_emissive_strength": {"emissiveStrength": 3.0},
                    "KHR_materials_specular": {"specularFactor": 0.3,
                                               "specularColorFactor": [0.4, 0.5, 0.6]},
                    "KHR_materials_ior": {"ior": 1.7},
                    "KHR_materials_transmission": {"transmissionFactor": 0.8},
                    "KHR_materials_volume": {"thicknessFactor": 0.05,
                                             "attenuationColor": [0.9, 0.8, 0.7],
                                             "attenuationDistance": 2.5},
                    "KHR_materials_volume_scatter": {"multiscatterColor": [0.6, 0.5, 0.4],
                                                     "scatterAnisotropy": -0.3},
                    "KHR_materials_clearcoat": {"clearcoatFactor": 0.35,
                                                "clearcoatRoughnessFactor": 0.45},
                    "KHR_materials_sheen": {"sheenColorFactor": [0.15, 0.25, 0.35],
                                            "sheenRoughnessFactor": 0.55},
                    "KHR_materials_unlit": {}
                }
            }]"#,
            r#""KHR_materials_emissive_strength", "KHR_materials_specular", "KHR_materials_ior",
               "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_clearcoat",
               "KHR_materials_sheen", "KHR_materials_unlit", "KHR_materials_volume_scatter""#,
        );
        let expected = MaterialFactors {
            base_color: Vec4::new(0.1, 0.2, 0.3, 0.4),
            metallic: 0.5,
            roughness: 0.6,
            emission: Vec3::new(0.7, 0.8, 0.9),
            emissive_strength: 3.0,
            specular: 0.3,
            specular_color: Vec3::new(0.4, 0.5, 0.6),
            ior: 1.7,
            transmission: 0.8,
            thickness: 0.05,
            attenuation_color: Vec3::new(0.9, 0.8, 0.7),
            attenuation_distance: 2.5,
            multiscatter_color: Vec3::new(0.6, 0.5, 0.4),
            scatter_anisotropy: -0.3,
            clearcoat: 0.35,
            clearcoat_roughness: 0.45,
            sheen_color: Vec3::new(0.15, 0.25, 0.35),
            sheen_roughness: 0.55,
            alpha_mode: AlphaMode::Mask { cutoff: 0.25 },
            double_sided: true,
            unlit: true,
        };
        assert_eq!(factors, expected);
    }

    #[test]
    fn a_volume_without_transmission_and_a_bare_material_keep_the_defaults() {
        let volume_only = factors_of(
            r#"[{"extensions": {"KHR_materials_volume": {"thicknessFactor": 1.0,
                                                          "attenuationDistance": 1.0}}}]"#,
            r#""KHR_materials_volume""#,
        );
        assert_eq!(volume_only, MaterialFactors::default());
        let masked = factors_of(r#"[{"alphaMode": "MASK"}]"#, "");
        assert_eq!(masked.alpha_mode, AlphaMode::Mask { cutoff: 0.5 });
        assert_eq!(factors_of("[{}]", ""), MaterialFactors::default());
    }
}
