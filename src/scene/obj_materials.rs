//! MTL materials as vkpath renders them: the workshop's Lambertian material (`Kd` albedo,
//! `Ke` emission) with `map_Kd` as its base colour texture, read like the MTL libraries
//! (a regular file inside the OBJ's folder, bounded) and decoded once per file.
//!
//! A `map_Kd` that cannot be used (missing, outside the folder, not PNG or JPEG, too large)
//! is a warning and the material keeps its `Kd`; other maps (`map_Ks`, `bump`, ...) are
//! ignored with a warning. `map_Kd`'s `-s` and `-o` options become a texture transform and
//! `-clamp on` clamps to the edge; its other options are ignored with a warning.

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;

use super::files::{read_bounded, resolve_reference, LoadOptions, MAX_SCENE_FILE_BYTES};
use super::materials::{PbrMaterial, TextureBinding};
use super::obj_loader::DEFAULT_ALBEDO;
use super::texture_source::TextureSourceError;
use super::textures::{decode_texture, Texture, TextureTransform, WrapMode};
use super::{Material, SceneError};

/// An OBJ scene's materials: one per MTL material in tobj's order, then the default
/// material (index `materials.len() - 1`) for faces without one.
pub(crate) struct ObjMaterials {
    /// The materials as the shading data refers to them.
    pub materials: Vec<PbrMaterial>,
    /// The same materials as the workshop's triangles carry them (`Kd`, `Ke`).
    pub workshop: Vec<Material>,
    /// The decoded `map_Kd` textures.
    pub textures: Vec<Texture>,
    /// What the user should know (maps ignored, textures that could not be used).
    pub warnings: Vec<String>,
}

impl ObjMaterials {
    /// Converts tobj's materials of the OBJ file at `obj_path`, loading their `map_Kd`
    /// textures (each file once).
    pub fn new(obj_path: &Path, materials: &[tobj::Material]) -> ObjMaterials {
        let mut converted = ObjMaterials {
            materials: Vec::with_capacity(materials.len() + 1),
            workshop: Vec::with_capacity(materials.len() + 1),
            textures: Vec::new(),
            warnings: Vec::new(),
        };
        // (file name, clamped) -> texture index, or None when it could not be used.
        let mut texture_indices: HashMap<(String, bool), Option<u32>> = HashMap::new();
        for material in materials {
            if let Some(warning) = ignored_maps_warning(material) {
                converted.warnings.push(warning);
            }
            let workshop = convert_material(material);
            let mut pbr = PbrMaterial::lambertian(workshop.color, workshop.emission, false);
            if let Some(statement) = &material.diffuse_texture {
                pbr.base_color_texture =
                    converted.bind(obj_path, material, statement, &mut texture_indices);
            }
            converted.materials.push(pbr);
            converted.workshop.push(workshop);
        }
        let default = Material::sanitized(Vec3::splat(DEFAULT_ALBEDO), Vec3::ZERO, false);
        converted.materials.push(PbrMaterial::lambertian(
            default.color,
            default.emission,
            false,
        ));
        converted.workshop.push(default);
        converted
    }

    /// The binding of a `map_Kd` statement (options and file name); None (with a warning)
    /// when its texture cannot be used.
    fn bind(
        &mut self,
        obj_path: &Path,
        material: &tobj::Material,
        statement: &str,
        texture_indices: &mut HashMap<(String, bool), Option<u32>>,
    ) -> Option<TextureBinding> {
        let name = super::printable(&material.name);
        let map = parse_texture_statement(statement);
        if !map.ignored_options.is_empty() {
            self.warnings.push(format!(
                "material '{name}': map_Kd options {} are ignored",
                map.ignored_options.join(", ")
            ));
        }
        let key = (map.file.clone(), map.clamp);
        let texture = match texture_indices.get(&key) {
            Some(&index) => index,
            None => {
                let index = match load_texture(obj_path, &map.file) {
                    Ok(image) => {
                        let wrap = if map.clamp {
                            WrapMode::ClampToEdge
                        } else {
                            WrapMode::Repeat
                        };
                        self.textures.push(Texture::new(image, wrap, wrap, false));
                        Some(self.textures.len() as u32 - 1)
                    }
                    Err(reason) => {
                        self.warnings.push(format!(
                            "material '{name}': map_Kd '{}' is ignored (the material uses its Kd \
                             instead): {reason}",
                            super::printable(&map.file)
                        ));
                        None
                    }
                };
                texture_indices.insert(key, index);
                index
            }
        }?;
        Some(TextureBinding::new(texture, map.transform))
    }
}

/// `Kd` as albedo (default [`DEFAULT_ALBEDO`]), `Ke` as emission (default 0).
fn convert_material(material: &tobj::Material) -> Material {
    // `as f32` because tobj's float type is f64 under its `use_f64` feature.
    #[allow(clippy::unnecessary_cast)]
    let to_vec3 = |c: [_; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
    let color = material
        .diffuse
        .map(to_vec3)
        .unwrap_or(Vec3::splat(DEFAULT_ALBEDO));
    let emission = material.emissive.map(to_vec3).unwrap_or(Vec3::ZERO);
    Material::sanitized(color, emission, false)
}

/// A texture file next to the OBJ, decoded; the reason in words when it cannot be used.
fn load_texture(
    obj_path: &Path,
    file_name: &str,
) -> Result<super::textures::DecodedImage, TextureSourceError> {
    let file = resolve_reference(obj_path, file_name, &LoadOptions::default()).map_err(
        |error| match error {
            SceneError::ExternalPath { .. } => TextureSourceError::OutsideObjFolder,
            other => TextureSourceError::Reference(other),
        },
    )?;
    let bytes = read_bounded(&file, MAX_SCENE_FILE_BYTES).map_err(|error| match error {
        SceneError::Read { error, .. } => TextureSourceError::Unreadable {
            file: super::printable(&file.display().to_string()),
            error,
        },
        other => TextureSourceError::Reference(other),
    })?;
    decode_texture(&bytes, None).map_err(TextureSourceError::Decode)
}

/// A `map_Kd` statement after the keyword: its options and its file name.
#[derive(Debug, PartialEq)]
struct TextureStatement {
    /// The file name (may contain spaces; `\` read as `/`, as Windows exporters write it).
    file: String,
    /// `-s` and `-o` as a transform of glTF-convention texture coordinates.
    transform: TextureTransform,
    /// `-clamp on`.
    clamp: bool,
    /// The options given that vkpath ignores (`-bm`, `-t`, ...).
    ignored_options: Vec<String>,
}

/// Splits a texture statement into its options and file name. Options are the MTL
/// format's (`-o`, `-s`, `-t` with one to three numbers, `-mm` with two, the others with
/// one); the file name is the rest of the line from the first word that is none of them.
fn parse_texture_statement(statement: &str) -> TextureStatement {
    let mut rest = statement.trim();
    let next_word = |rest: &mut &str| -> Option<String> {
        let (word, tail) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
        (!word.is_empty()).then(|| {
            let word = word.to_owned();
            *rest = tail.trim_start();
            word
        })
    };
    let number = |word: &str| word.parse::<f32>().ok().filter(|x| x.is_finite());
    let (mut scale, mut offset, mut clamp) = ([1.0f32; 3], [0.0f32; 3], false);
    let mut ignored_options = Vec::new();
    loop {
        let option = rest.split_whitespace().next().unwrap_or("");
        let arguments = match option {
            "-o" | "-s" | "-t" => 3,
            "-mm" => 2,
            "-blendu" | "-blendv" | "-bm" | "-boost" | "-cc" | "-clamp" | "-imfchan"
            | "-texres" | "-type" => 1,
            _ => break,
        };
        next_word(&mut rest);
        let mut values = Vec::new();
        while values.len() < arguments {
            let word = rest.split_whitespace().next().unwrap_or("");
            // Numeric options take as many numbers as follow (up to three); the others
            // take exactly their count of words.
            if matches!(option, "-o" | "-s" | "-t" | "-mm") && number(word).is_none() {
                break;
            }
            match next_word(&mut rest) {
                Some(word) => values.push(word),
                None => break,
            }
        }
        match option {
            "-s" => values
                .iter()
                .zip(&mut scale)
                .for_each(|(v, s)| *s = number(v).unwrap_or(1.0)),
            "-o" => values
                .iter()
                .zip(&mut offset)
                .for_each(|(v, o)| *o = number(v).unwrap_or(0.0)),
            "-clamp" => clamp = values.first().is_some_and(|v| v == "on"),
            _ => ignored_options.push(option.to_owned()),
        }
    }
    // MTL applies uv' = s uv + o with v up the image; in glTF's v-down coordinates
    // (v_gltf = 1 - v) that is v'_gltf = s_v v_gltf + (1 - s_v - o_v).
    let transform = TextureTransform::from_gltf(
        [offset[0], 1.0 - scale[1] - offset[1]],
        0.0,
        [scale[0], scale[1]],
    );
    TextureStatement {
        file: rest.replace('\\', "/"),
        transform,
        clamp,
        ignored_options,
    }
}

/// A warning naming the material and the texture maps it has that vkpath ignores (every
/// one but `map_Kd`), if it has any.
fn ignored_maps_warning(material: &tobj::Material) -> Option<String> {
    let known = [
        ("map_Ka", &material.ambient_texture),
        ("map_Ks", &material.specular_texture),
        ("map_Bump", &material.normal_texture),
        ("map_Ns", &material.shininess_texture),
        ("map_d", &material.dissolve_texture),
    ];
    let mut maps: Vec<String> = known
        .iter()
        .filter(|(_, texture)| texture.is_some())
        .map(|(keyword, _)| keyword.to_string())
        .collect();
    // Maps tobj does not know (map_Ke, map_Pr, bump, ...) land among the unknown parameters.
    let mut unknown: Vec<String> = material
        .unknown_param
        .keys()
        .filter(|key| key.starts_with("map_") || ["disp", "decal", "refl"].contains(&key.as_str()))
        .map(|key| super::printable(key))
        .collect();
    unknown.sort();
    maps.extend(unknown);
    if maps.is_empty() {
        return None;
    }
    Some(format!(
        "material '{}' has texture maps ({}), which are ignored (vkpath reads map_Kd only); \
         using its constant colours",
        super::printable(&material.name),
        maps.join(", ")
    ))
}

/// An MTL text that tobj can parse without panicking: a colour statement (`Ka`, `Kd`,
/// `Ks`, `Ke`, `Tf`) with fewer than three numbers gets its missing components from the
/// first (the MTL format lets `Kd r` stand for `Kd r r r`), and one with none is dropped
/// (tobj 4 unwraps three numbers; an empty line keeps its place, so that line numbers stay
/// the file's). Lines lose their indentation: tobj cuts a map's file name from the line at
/// the keyword's length, so `\tmap_Kd a.png` would name `d a.png`.
pub(crate) fn sanitize_mtl(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    let mut sanitized = String::with_capacity(text.len());
    for line in text.lines().map(str::trim_start) {
        let mut words = line.split_whitespace();
        let keyword = words.next().unwrap_or("");
        if ["Ka", "Kd", "Ks", "Ke", "Tf"].contains(&keyword) {
            let numbers: Vec<&str> = words.collect();
            match numbers.as_slice() {
                [] => {}
                [r] => sanitized.push_str(&format!("{keyword} {r} {r} {r}")),
                [r, g] => sanitized.push_str(&format!("{keyword} {r} {g} {g}")),
                _ => sanitized.push_str(line),
            }
        } else {
            sanitized.push_str(line);
        }
        sanitized.push('\n');
    }
    sanitized
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_options_are_split_from_the_file_name() {
        let plain = parse_texture_statement("textures\\old brick.png");
        assert_eq!(plain.file, "textures/old brick.png");
        assert_eq!(plain.transform, TextureTransform::identity());
        assert!(!plain.clamp && plain.ignored_options.is_empty());

        let map = parse_texture_statement("-s 2 4 1 -o 0.5 -bm 0.3 -clamp on -t 1 brick.png");
        assert_eq!(map.file, "brick.png");
        assert!(map.clamp);
        assert_eq!(map.ignored_options, vec!["-bm".to_owned(), "-t".to_owned()]);
        // u' = 2 u + 0.5; v'_obj = 4 v_obj, so v'_gltf = 1 - 4 (1 - v_gltf) = 4 v_gltf - 3.
        assert_eq!(
            map.transform,
            TextureTransform::from_gltf([0.5, -3.0], 0.0, [2.0, 4.0])
        );
    }
}
