//! A glTF file read once (`GltfFile`): its bytes checked, parsed and validated, its
//! buffers and animations read, then posed at any time. A sequence of frames
//! (`render --frames`, Python's `render_frames`) opens the file once and poses it per
//! frame; `load_gltf_with` opens and poses once, so both take one code path and a frame's
//! scene is the one a load at its time gives, bit for bit.
//!
//! Its materials and textures are converted (images decoded) by the first pose and kept for
//! the next: every pose meets the same materials in the same order.

use std::io::Read as _;
use std::path::{Path, PathBuf};

use gltf::json::validation::Validate;
use gltf::{Document, Gltf};

use super::animation::{Animation, AnimationPick};
use super::files::{read_bounded, resolve_reference, LoadOptions, MAX_SCENE_FILE_BYTES};
use super::gltf_animation::{pose_at, read_animations};
use super::gltf_extensions::is_supported_extension;
use super::gltf_loader::{label, malformed, posed_scene};
use super::gltf_materials::{webp_source, ConvertedMaterials};
use super::gltf_variants;
use super::{Scene, SceneError};

mod node_less;
mod sequence;
pub use sequence::MAX_FRAMING_POSES;

/// Whether `path` names a glTF file by its extension (`.gltf` or `.glb`, in any case), as
/// `Scene::load` chooses its loader.
pub fn is_gltf_path(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// A glTF 2.0 file (JSON or binary) read once, to be posed at any time.
pub struct GltfFile {
    /// Where it was read from (named in errors; textures are found next to it).
    path: PathBuf,
    /// How it reads the files it refers to (its time and animations are each pose's).
    options: LoadOptions,
    document: Document,
    /// Every buffer's bytes.
    buffers: Vec<gltf::buffer::Data>,
    /// Every animation of the file, checked.
    animations: Vec<Animation>,
    /// The materials and textures the last pose converted, for the next (`None` before the
    /// first pose, and after one that failed).
    converted: Option<ConvertedMaterials>,
    /// What reading the file found to warn about (skipped channels, unusable rotation
    /// keys): each pose's scene says it.
    warnings: Vec<String>,
}

impl GltfFile {
    /// Reads, checks and parses the file, resolving external buffers relative to its folder
    /// (others only with `options.allow_external_paths`), and reads its animations. Fails as
    /// `load_gltf_with` would before it poses.
    pub fn open(path: &Path, options: &LoadOptions) -> Result<GltfFile, SceneError> {
        let bytes = read_bounded(path, MAX_SCENE_FILE_BYTES)?;
        let gltf_error = |error| SceneError::Gltf {
            path: path.to_owned(),
            error,
        };
        check_format(path, &bytes)?;
        check_glb_header(path, &bytes)?;
        let (Gltf { document, blob }, skipped) = node_less::parse(&bytes).map_err(gltf_error)?;
        check_required_extensions(path, &document)?;
        validate(path, &document)?;
        if let Some(name) = &options.variant {
            gltf_variants::variant_index(path, &document, name)?;
        }
        let buffers = load_buffers(path, &document, blob, options)?;
        let (animations, animation_warnings) = read_animations(path, &document, &buffers)?;
        Ok(GltfFile {
            path: path.to_owned(),
            options: options.clone(),
            document,
            buffers,
            animations,
            converted: None,
            warnings: skipped.into_iter().chain(animation_warnings).collect(),
        })
    }

    /// Whether the file has any animation (without one, every time poses the same scene).
    pub fn has_animations(&self) -> bool {
        !self.animations.is_empty()
    }

    /// The names of the file's material variants (`KHR_materials_variants`; `#index` for one
    /// without a name), in file order.
    pub fn variant_names(&self) -> Vec<String> {
        gltf_variants::variant_names(&self.document)
    }

    /// The names of the file's animations (`#index` for one without a name), in file
    /// order.
    pub fn animation_names(&self) -> Vec<String> {
        self.animations.iter().map(|a| a.name.clone()).collect()
    }

    /// The scene with the animations `pick` chooses at `time` seconds: what
    /// `load_gltf_with` gives with that time and pick, bit for bit, warnings included
    /// (textures the first pose could not use are said again by each).
    pub fn pose(&mut self, time: f32, pick: &AnimationPick) -> Result<Scene, SceneError> {
        let pose = pose_at(&self.path, &self.document, &self.animations, pick, time)?;
        let (scene, converted) = posed_scene(
            &self.path,
            &self.document,
            &self.buffers,
            &self.options,
            pose,
            self.converted.take().unwrap_or_default(),
        )?;
        self.converted = Some(converted);
        let mut scene = scene;
        scene.warnings.extend(self.warnings.iter().cloned());
        Ok(scene)
    }
}

/// Refuses a file that is neither a GLB (magic `glTF`) nor JSON (`{` after whitespace),
/// saying what it seems to be.
fn check_format(path: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    let text = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let first = text.iter().position(|b| !b.is_ascii_whitespace());
    if bytes.starts_with(b"glTF") || first.is_some_and(|i| text[i] == b'{') {
        return Ok(());
    }
    let start = &text[first.unwrap_or(0)..];
    let what = if start.is_empty() {
        "it is empty".to_string()
    } else if start.starts_with(b"<") {
        "it looks like HTML or XML (a web page saved instead of the file?)".to_string()
    } else if start.starts_with(b"\x89PNG") {
        "it is a PNG image".to_string()
    } else if start.starts_with(&[0xff, 0xd8, 0xff]) {
        "it is a JPEG image".to_string()
    } else if start.starts_with(b"PK\x03\x04") {
        "it is a ZIP archive (unpack it first)".to_string()
    } else {
        let head: Vec<String> = start.iter().take(8).map(|b| format!("{b:02x}")).collect();
        format!("it starts with the bytes {}", head.join(" "))
    };
    Err(SceneError::NotGltf {
        path: path.to_owned(),
        what,
    })
}

/// Checks a GLB header against the file before anything is read from it: the declared total
/// length (the `gltf` crate computes `length - 12` unchecked) and each chunk's length must
/// fit in the file, so that a header claiming gigabytes is refused at once.
fn check_glb_header(path: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let word = |at: usize| -> Option<u64> {
        bytes
            .get(at..at + 4)
            .map(|w| u64::from(u32::from_le_bytes([w[0], w[1], w[2], w[3]])))
    };
    let Some(length) = word(8) else {
        return Err(malformed(path, "GLB header is cut off".into()));
    };
    if length < 12 {
        return Err(malformed(
            path,
            format!("GLB header declares {length} bytes, fewer than the header's own 12"),
        ));
    }
    if length > bytes.len() as u64 {
        return Err(malformed(
            path,
            format!(
                "GLB header declares {length} bytes, but the file has {}",
                bytes.len()
            ),
        ));
    }
    let mut at = 12u64;
    while at + 8 <= length {
        let chunk = word(at as usize).unwrap_or(0);
        if at + 8 + chunk > length {
            return Err(malformed(
                path,
                format!(
                    "GLB chunk at byte {at} declares {chunk} bytes, beyond the {length} the file declares"
                ),
            ));
        }
        at += 8 + chunk;
    }
    Ok(())
}

/// Refuses a file whose `extensionsRequired` lists extensions vkpath does not implement,
/// naming them (a file that needs Draco compression is not "malformed").
fn check_required_extensions(path: &Path, document: &Document) -> Result<(), SceneError> {
    let unsupported: Vec<String> = document
        .extensions_required()
        .filter(|e| !is_supported_extension(e))
        .map(super::printable)
        .collect();
    if unsupported.is_empty() {
        Ok(())
    } else {
        Err(SceneError::RequiredExtension {
            path: path.to_owned(),
            extensions: unsupported,
        })
    }
}

/// Every buffer's bytes: the GLB's binary chunk, a base64 data URI, or a file relative to
/// the glTF's folder (others only with `allow_external_paths`), of which at most its
/// `byteLength` bytes are read; fewer than `byteLength` is an error.
fn load_buffers(
    path: &Path,
    document: &Document,
    mut blob: Option<Vec<u8>>,
    options: &LoadOptions,
) -> Result<Vec<gltf::buffer::Data>, SceneError> {
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let name = label(buffer.name(), buffer.index());
        let length = buffer.length() as u64;
        if length > MAX_SCENE_FILE_BYTES {
            return Err(SceneError::TooLarge {
                path: path.to_owned(),
                bytes: length,
                limit: MAX_SCENE_FILE_BYTES,
            });
        }
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                malformed(
                    path,
                    format!("buffer '{name}' refers to a GLB binary chunk that is missing"),
                )
            })?,
            gltf::buffer::Source::Uri(uri) => read_uri(path, &name, uri, length, options)?,
        };
        if (data.len() as u64) < length {
            return Err(malformed(
                path,
                format!(
                    "buffer '{name}' has {} bytes, fewer than its byteLength {length}",
                    data.len()
                ),
            ));
        }
        // As the gltf crate does: the reader expects 4-byte alignment.
        while data.len() % 4 != 0 {
            data.push(0);
        }
        buffers.push(gltf::buffer::Data(data));
    }
    Ok(buffers)
}

/// The bytes a buffer URI names, at most `length` of them.
fn read_uri(
    path: &Path,
    name: &str,
    uri: &str,
    length: u64,
    options: &LoadOptions,
) -> Result<Vec<u8>, SceneError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, encoded) = rest.split_once(";base64,").ok_or_else(|| {
            malformed(
                path,
                format!("buffer '{name}' has a data URI that is not base64"),
            )
        })?;
        return base64::decode(encoded)
            .map_err(|e| malformed(path, format!("buffer '{name}': bad base64 data: {e}")));
    }
    let file_name = if let Some(rest) = uri
        .strip_prefix("file://")
        .or_else(|| uri.strip_prefix("file:"))
    {
        rest
    } else if uri.split_once(':').is_some_and(|(scheme, _)| {
        scheme.len() > 1
            && scheme
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
    }) {
        return Err(malformed(
            path,
            format!("buffer '{name}' is at '{uri}'; vkpath reads local files only"),
        ));
    } else {
        uri
    };
    let decoded = urlencoding::decode(file_name).map_err(|_| {
        malformed(
            path,
            format!("buffer '{name}': its URI is not valid UTF-8 when decoded"),
        )
    })?;
    let file = resolve_reference(path, &decoded, options)?;
    let missing = |error| SceneError::MissingBuffer {
        path: path.to_owned(),
        buffer: format!("'{name}'"),
        file: super::printable(&file.display().to_string()),
        error,
    };
    let metadata = std::fs::metadata(&file).map_err(missing)?;
    if !metadata.is_file() {
        return Err(missing(std::io::Error::other("it is not a regular file")));
    }
    let mut bytes = Vec::new();
    std::io::Read::take(std::fs::File::open(&file).map_err(missing)?, length)
        .read_to_end(&mut bytes)
        .map_err(missing)?;
    Ok(bytes)
}

/// The `gltf` crate's validation, preceded by the one check its validation needs but does
/// not make (its POSITION hook indexes the accessor list with the unchecked index), less its
/// verdict on `extensionsRequired` (vkpath's list decides, `check_required_extensions`).
fn validate(path: &Path, document: &Document) -> Result<(), SceneError> {
    let root = document.as_json();
    for (mesh_index, mesh) in root.meshes.iter().enumerate() {
        for (primitive_index, primitive) in mesh.primitives.iter().enumerate() {
            for accessor in primitive.attributes.values() {
                if accessor.value() >= root.accessors.len() {
                    return Err(malformed(
                        path,
                        format!(
                            "mesh {mesh_index} primitive {primitive_index} refers to accessor \
                             {}, which does not exist",
                            accessor.value()
                        ),
                    ));
                }
            }
        }
    }
    // A texture whose image is a WebP extension's may leave out its own `source`
    // (EXT_texture_webp: where the file requires the extension), which the crate reports
    // as missing.
    let is_webp_only = |path: &gltf::json::Path| {
        root.textures.iter().enumerate().any(|(index, texture)| {
            webp_source(texture).is_some() && path.as_str() == format!("textures[{index}].source")
        })
    };
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        // `extensionsRequired` is `check_required_extensions`'s: the crate refuses every name
        // outside its own features, some that vkpath implements among them (clearcoat,
        // sheen, specular, volume, mesh quantization).
        if !path.as_str().starts_with("extensionsRequired") && !is_webp_only(&path) {
            errors.push((path, error))
        }
    });
    if errors.is_empty() {
        Ok(())
    } else {
        Err(SceneError::Gltf {
            path: path.to_owned(),
            error: gltf::Error::Validation(errors),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every float of the triangles as its bits: equal only bit for bit.
    fn triangle_bits(scene: &Scene) -> Vec<u32> {
        scene
            .triangles
            .iter()
            .flat_map(|t| {
                let [a, b, c] = t.positions;
                [a, b, c, t.normal, t.color, t.emission]
                    .into_iter()
                    .flat_map(|v| v.to_array())
                    .map(f32::to_bits)
                    .chain([u32::from(t.double_sided)])
            })
            .collect()
    }

    #[test]
    fn a_file_opened_once_poses_as_a_load_at_each_time() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/RiggedSimple.gltf");
        let mut file = GltfFile::open(&path, &LoadOptions::default()).unwrap();
        // Forwards and back: a pose depends on its time alone.
        for time in [0.0, 0.4, 1.3, 0.2] {
            let posed = file.pose(time, &AnimationPick::All).unwrap();
            let options = LoadOptions {
                time,
                ..LoadOptions::default()
            };
            let loaded = super::super::gltf_loader::load_gltf_with(&path, &options).unwrap();
            assert!(triangle_bits(&posed) == triangle_bits(&loaded), "{time} s");
            assert_eq!(posed.materials, loaded.materials, "{time} s");
            assert_eq!(posed.warnings, loaded.warnings, "{time} s");
            assert_eq!(posed.mesh_instances.len(), loaded.mesh_instances.len());
        }
        // The skin moves: the poses differ.
        let mut moved = |time| triangle_bits(&file.pose(time, &AnimationPick::All).unwrap());
        let (rest, bent) = (moved(0.0), moved(1.3));
        assert_ne!(rest, bent);
    }
}
