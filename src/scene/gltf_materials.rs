//! glTF materials as vkpath renders them: the metallic-roughness factors with
//! KHR_materials_emissive_strength, KHR_materials_specular, KHR_materials_ior,
//! KHR_materials_transmission, KHR_materials_volume, KHR_materials_clearcoat,
//! KHR_materials_unlit and KHR_texture_transform, and the textures they use, decoded once
//! each.
//!
//! A texture that cannot be used (a missing or unreadable image, a format other than PNG
//! or JPEG, an image larger than `MAX_TEXTURE_SIZE` per side, a second texture coordinate
//! set) gives a warning and the material falls back to its factor for that slot: one broken
//! texture should not stop a whole asset from rendering.

use std::collections::HashMap;
use std::io::Read as _;
use std::path::Path;

use glam::{Vec3, Vec4};

use super::files::{resolve_reference, LoadOptions, MAX_SCENE_FILE_BYTES};
use super::material_factors::MaterialFactors;
use super::materials::{AlphaMode, Clearcoat, PbrMaterial, Sheen, TextureBinding, Transmission};
use super::texture_source::TextureSourceError;
use super::textures::{decode_texture, Texture, TextureTransform, WrapMode};

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

    /// The material: its factors (`material_factors`, the conversion `Scene::from_arrays`
    /// shares) with its textures. Textures are bound in a fixed order (specular, specular
    /// colour, transmission, thickness, clear coat, sheen, base colour, metallic-roughness,
    /// emissive, normal), which numbers them.
    fn convert(&mut self, material: &gltf::Material) -> PbrMaterial {
        let name = material_label(material);
        let mut converted = material_factors(material).material();
        let pbr = material.pbr_metallic_roughness();
        if let Some(specular) = material.specular() {
            converted.specular_texture = specular
                .specular_texture()
                .and_then(|info| self.binding(&name, "specularTexture", &info));
            converted.specular_color_texture = specular
                .specular_color_texture()
                .and_then(|info| self.binding(&name, "specularColorTexture", &info));
        }
        self.transmission_textures(&name, material, &mut converted.transmission);
        self.clearcoat_textures(&name, material, &mut converted.clearcoat);
        self.sheen_textures(&name, material, &mut converted.sheen);
        converted.base_color_texture = pbr
            .base_color_texture()
            .and_then(|info| self.binding(&name, "baseColorTexture", &info));
        converted.metallic_roughness_texture = pbr
            .metallic_roughness_texture()
            .and_then(|info| self.binding(&name, "metallicRoughnessTexture", &info));
        converted.emissive_texture = material
            .emissive_texture()
            .and_then(|info| self.binding(&name, "emissiveTexture", &info));
        if let Some(normal) = material.normal_texture() {
            converted.normal_texture = self.normal_binding(&name, &normal);
            converted.normal_scale = normal.scale();
        }
        converted.sanitized()
    }

    /// KHR_materials_transmission's and KHR_materials_volume's textures.
    fn transmission_textures(
        &mut self,
        name: &str,
        material: &gltf::Material,
        out_transmission: &mut Transmission,
    ) {
        let Some(transmission) = material.transmission() else {
            return;
        };
        out_transmission.texture = transmission
            .transmission_texture()
            .and_then(|info| self.binding(name, "transmissionTexture", &info));
        if let Some(volume) = material.volume() {
            out_transmission.thickness_texture = volume
                .thickness_texture()
                .and_then(|info| self.binding(name, "thicknessTexture", &info));
        }
    }

    /// KHR_materials_clearcoat's textures and normal scale, read from the JSON (gltf 1.4 has
    /// no accessors for it).
    fn clearcoat_textures(
        &mut self,
        name: &str,
        material: &gltf::Material,
        out_clearcoat: &mut Clearcoat,
    ) {
        let Some(json) = material.extension_value("KHR_materials_clearcoat") else {
            return;
        };
        out_clearcoat.texture =
            self.json_binding(name, "clearcoatTexture", json.get("clearcoatTexture"));
        out_clearcoat.roughness_texture = self.json_binding(
            name,
            "clearcoatRoughnessTexture",
            json.get("clearcoatRoughnessTexture"),
        );
        let normal = json.get("clearcoatNormalTexture");
        out_clearcoat.normal_texture = self.json_binding(name, "clearcoatNormalTexture", normal);
        out_clearcoat.normal_scale = normal
            .and_then(|n| n.get("scale"))
            .and_then(serde_json::Value::as_f64)
            .map_or(1.0, |v| v as f32);
    }

    /// KHR_materials_sheen's textures, read from the JSON.
    fn sheen_textures(&mut self, name: &str, material: &gltf::Material, out_sheen: &mut Sheen) {
        let Some(json) = material.extension_value("KHR_materials_sheen") else {
            return;
        };
        out_sheen.color_texture =
            self.json_binding(name, "sheenColorTexture", json.get("sheenColorTexture"));
        out_sheen.roughness_texture = self.json_binding(
            name,
            "sheenRoughnessTexture",
            json.get("sheenRoughnessTexture"),
        );
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

    /// The binding of a texture slot, with its KHR_texture_transform.
    fn binding(
        &mut self,
        material: &str,
        slot: &str,
        info: &gltf::texture::Info,
    ) -> Option<TextureBinding> {
        let transform = info.texture_transform();
        let tex_coord = transform
            .as_ref()
            .and_then(|t| t.tex_coord())
            .unwrap_or(info.tex_coord());
        let transform = transform.map_or_else(TextureTransform::identity, |t| {
            TextureTransform::from_gltf(t.offset(), t.rotation(), t.scale())
        });
        self.bind(material, slot, &info.texture(), tex_coord, transform)
    }

    /// The normal texture's binding; gltf 1.4 exposes no KHR_texture_transform on it, so
    /// the extension is read from the JSON.
    fn normal_binding(
        &mut self,
        material: &str,
        normal: &gltf::material::NormalTexture,
    ) -> Option<TextureBinding> {
        let (transform_matrix, transform_tex_coord) =
            json_texture_transform(normal.extension_value("KHR_texture_transform"));
        let tex_coord = transform_tex_coord.unwrap_or(normal.tex_coord());
        self.bind(
            material,
            "normalTexture",
            &normal.texture(),
            tex_coord,
            transform_matrix,
        )
    }

    fn bind(
        &mut self,
        material: &str,
        slot: &str,
        texture: &gltf::Texture,
        tex_coord: u32,
        transform: TextureTransform,
    ) -> Option<TextureBinding> {
        if tex_coord != 0 {
            self.converted.warnings.push(format!(
                "material '{material}': {slot} uses TEXCOORD_{tex_coord}; only TEXCOORD_0 is read, so the texture is ignored"
            ));
            return None;
        }
        let index = self.texture_index(texture)?;
        Some(TextureBinding {
            texture: index,
            transform,
        })
    }

    /// Decodes a texture on first use; None (with a warning) when it cannot be used.
    fn texture_index(&mut self, texture: &gltf::Texture) -> Option<u32> {
        if let Some(&index) = self.converted.texture_indices.get(&texture.index()) {
            return index;
        }
        let index = match self.load_texture(texture) {
            Ok(loaded) => {
                self.converted.textures.push(loaded);
                Some(self.converted.textures.len() as u32 - 1)
            }
            Err(reason) => {
                let name = texture
                    .name()
                    .map_or_else(|| format!("#{}", texture.index()), super::printable);
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

    fn load_texture(&self, texture: &gltf::Texture) -> Result<Texture, TextureSourceError> {
        let image = texture.source();
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

/// A glTF material's constant factors, glTF's defaults where the file says nothing (the
/// volume's only with transmission, as before: a volume without transmission is ignored).
fn material_factors(material: &gltf::Material) -> MaterialFactors {
    let pbr = material.pbr_metallic_roughness();
    let mut factors = MaterialFactors {
        base_color: Vec4::from(pbr.base_color_factor()),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        emission: Vec3::from(material.emissive_factor()),
        emissive_strength: material.emissive_strength().unwrap_or(1.0),
        ior: material.ior().unwrap_or(1.5),
        alpha_mode: match material.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: material.alpha_cutoff().unwrap_or(0.5),
            },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        double_sided: material.double_sided(),
        unlit: material.unlit(),
        ..MaterialFactors::default()
    };
    if let Some(specular) = material.specular() {
        factors.specular = specular.specular_factor();
        factors.specular_color = Vec3::from(specular.specular_color_factor());
    }
    if let Some(transmission) = material.transmission() {
        factors.transmission = transmission.transmission_factor();
        if let Some(volume) = material.volume() {
            factors.thickness = volume.thickness_factor();
            factors.attenuation_color = Vec3::from(volume.attenuation_color());
            factors.attenuation_distance = volume.attenuation_distance();
        }
    }
    // KHR_materials_clearcoat and KHR_materials_sheen from the JSON (gltf 1.4 has no
    // accessors for them).
    let number = |json: &serde_json::Value, key: &str| {
        json.get(key)
            .and_then(serde_json::Value::as_f64)
            .map_or(0.0, |v| v as f32)
    };
    if let Some(json) = material.extension_value("KHR_materials_clearcoat") {
        factors.clearcoat = number(json, "clearcoatFactor");
        factors.clearcoat_roughness = number(json, "clearcoatRoughnessFactor");
    }
    if let Some(json) = material.extension_value("KHR_materials_sheen") {
        factors.sheen_color = json
            .get("sheenColorFactor")
            .and_then(serde_json::Value::as_array)
            .map_or(Vec3::ZERO, |values| {
                let component = |i: usize| {
                    values
                        .get(i)
                        .and_then(serde_json::Value::as_f64)
                        .map_or(0.0, |v| v as f32)
                };
                Vec3::new(component(0), component(1), component(2))
            });
        factors.sheen_roughness = number(json, "sheenRoughnessFactor");
    }
    factors
}

fn material_label(material: &gltf::Material) -> String {
    match (material.name(), material.index()) {
        (Some(name), _) => super::printable(name),
        (None, Some(index)) => format!("#{index}"),
        (None, None) => "default".to_owned(),
    }
}
