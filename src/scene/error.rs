//! What can go wrong when loading a scene. Every message is one line that names the file, so
//! that the CLI can print it as it is.

use std::path::PathBuf;

use thiserror::Error;

/// An error while loading a scene file (or the built-in scene).
///
/// The `Display` text is the whole story, including the underlying crate's message; the
/// variants do not chain a `source()` so that printing the chain does not repeat it.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read (missing, no permission, a directory, ...).
    #[error("cannot read scene '{}': {}", path.display(), io_message(error))]
    Read {
        /// The scene file as given.
        path: PathBuf,
        /// Why it could not be read.
        error: std::io::Error,
    },
    /// The path is not a regular file (a directory, a named pipe, a device).
    #[error("cannot read scene '{}': it is {kind}, not a file", path.display())]
    NotAFile {
        /// The path as given.
        path: PathBuf,
        /// What it is instead, in words.
        kind: &'static str,
    },
    /// The file is larger than vkpath reads.
    #[error(
        "cannot read '{}': it has {bytes} bytes, more than the {limit} vkpath reads from one file",
        path.display()
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size (or the size it claims).
        bytes: u64,
        /// The bound.
        limit: u64,
    },
    /// A `.gltf`/`.glb` file that is neither JSON glTF nor GLB.
    #[error("'{}' is neither a JSON glTF file nor a GLB file: {what}", path.display())]
    NotGltf {
        /// The file.
        path: PathBuf,
        /// What it seems to be instead.
        what: String,
    },
    /// The glTF file requires extensions vkpath does not implement.
    #[error(
        "glTF '{}' requires the extension{} {}, which vkpath does not support",
        path.display(),
        if extensions.len() == 1 { "" } else { "s" },
        extensions.join(", ")
    )]
    RequiredExtension {
        /// The file.
        path: PathBuf,
        /// The unsupported extensions it lists in `extensionsRequired`.
        extensions: Vec<String>,
    },
    /// A material variant (`KHR_materials_variants`) that the file does not have was asked for.
    #[error(
        "glTF '{}' has no material variant '{name}' ({})",
        path.display(),
        if known.is_empty() { "it has no variants".to_owned() } else { format!("its variants: {}", known.join(", ")) }
    )]
    UnknownVariant {
        /// The file.
        path: PathBuf,
        /// The variant asked for.
        name: String,
        /// The file's variants.
        known: Vec<String>,
    },
    /// A file that the scene refers to (a buffer) is missing or unreadable.
    #[error(
        "glTF '{}': cannot read its buffer {buffer} '{file}': {}",
        path.display(),
        io_message(error)
    )]
    MissingBuffer {
        /// The scene file.
        path: PathBuf,
        /// The buffer's index or name.
        buffer: String,
        /// The file it looked for (printable).
        file: String,
        /// Why it could not be read.
        error: std::io::Error,
    },
    /// The scene refers to a file outside its folder.
    #[error(
        "glTF '{}' refers to '{reference}', outside its folder; pass --allow-external-paths to allow that",
        path.display()
    )]
    ExternalPath {
        /// The scene file.
        path: PathBuf,
        /// The reference as written (decoded).
        reference: String,
    },
    /// A material emits more than 32-bit floats can carry through a render.
    #[error(
        "scene '{}': mesh '{mesh}' emits {emission}, beyond the {limit:e} that 32-bit floats carry through a render",
        path.display()
    )]
    EmissionTooLarge {
        /// The scene file.
        path: PathBuf,
        /// The mesh or object.
        mesh: String,
        /// The largest emission component.
        emission: f32,
        /// The bound.
        limit: f32,
    },
    /// The file's extension names no format we can load.
    #[error(
        "cannot load scene '{}': unsupported file extension{} (expected .gltf, .glb or .obj)",
        path.display(),
        extension.as_ref().map(|e| format!(" '.{e}'")).unwrap_or_default()
    )]
    UnsupportedExtension {
        /// The scene file as given.
        path: PathBuf,
        /// The extension, without its dot; `None` when the file has none.
        extension: Option<String>,
    },
    /// The `gltf` crate rejected the file (bad JSON, failed validation, missing buffer, ...).
    #[error("malformed glTF '{}': {error}", path.display())]
    Gltf {
        /// The scene file as given.
        path: PathBuf,
        /// The `gltf` crate's error.
        error: gltf::Error,
    },
    /// `--animation` names an animation that the glTF file does not have.
    #[error("'{}': {reason}", path.display())]
    Animation {
        /// The scene file as given.
        path: PathBuf,
        /// What was asked and what the file has.
        reason: String,
    },
    /// The glTF file passed the `gltf` crate's checks but breaks a rule of the format that
    /// we check ourselves (accessor types and extents, index ranges, the node hierarchy).
    #[error("malformed glTF '{}': {reason}", path.display())]
    MalformedGltf {
        /// The scene file as given.
        path: PathBuf,
        /// What is wrong, naming the object (mesh, node, accessor) where possible.
        reason: String,
    },
    /// The `tobj` crate (or our check before it) rejected the OBJ file or its material
    /// library; the message gives the place as `file:line` when the line is known.
    #[error("malformed OBJ '{}{}': {error}", path.display(), line.map_or(String::new(), |line| format!(":{line}")))]
    Obj {
        /// The scene file (or material library) as given.
        path: PathBuf,
        /// The line (from 1) that the error is on, when known.
        line: Option<usize>,
        /// The `tobj` crate's error.
        error: tobj::LoadError,
    },
    /// The scene has more triangles than vkpath renders (glTF instancing can make many).
    #[error("scene '{}' has more than {limit} triangles, more than vkpath renders", path.display())]
    TooManyTriangles {
        /// The scene file.
        path: PathBuf,
        /// The bound.
        limit: usize,
    },
    /// After loading (dropping degenerate triangles, skipping points and lines) nothing is
    /// left to render.
    #[error("scene '{}' contains no triangles{details}", path.display())]
    NoTriangles {
        /// The scene file as given.
        path: PathBuf,
        /// What was dropped or skipped, in parentheses (empty when nothing was).
        details: String,
    },
    /// The scene's camera is orthographic; the workshop's camera is a pinhole.
    #[error(
        "scene '{}': camera '{camera}' is orthographic; only perspective cameras are supported",
        path.display()
    )]
    OrthographicCamera {
        /// The scene file as given.
        path: PathBuf,
        /// The camera's name, or `#index` when it has none.
        camera: String,
    },
    /// The scene's camera cannot be turned into a pinhole camera.
    #[error("scene '{}': camera '{camera}' is unusable: {reason}", path.display())]
    InvalidCamera {
        /// The scene file as given.
        path: PathBuf,
        /// The camera's name, or `#index` when it has none.
        camera: String,
        /// Why, e.g. a field of view outside (0, pi) or a degenerate node transform.
        reason: String,
    },
    /// A vertex position (after transformation to world space) is infinite or NaN.
    #[error("scene '{}': mesh '{mesh}' has a non-finite vertex position", path.display())]
    NonFinitePosition {
        /// The scene file as given.
        path: PathBuf,
        /// The mesh (glTF) or object (OBJ) name, or `#index` when it has none.
        mesh: String,
    },
    /// More triangles were asked of the generated scale-test scene than it may have.
    #[error("--generated {requested}: at most {limit} triangles")]
    TooManyGeneratedTriangles {
        /// The triangle count asked for.
        requested: usize,
        /// The most it may have (`scene::source::MAX_GENERATED_TRIANGLES`).
        limit: usize,
    },
    /// The embedded workshop scene could not be parsed (a bug in the build, not user input).
    #[error("built-in Cornell box scene is broken: {reason}")]
    Builtin {
        /// What is wrong with it.
        reason: String,
    },
    /// The environment asked for could not be loaded (`crate::lights::EnvironmentSource`):
    /// the message names the map's file.
    #[error(transparent)]
    Environment(#[from] crate::lights::environment::EnvironmentMapError),
    /// A scene from arrays (`Scene::from_arrays`) whose arrays do not fit together.
    #[error("scene from arrays: {0}")]
    Arrays(String),
}

// A file's name and an I/O error in one line: the scene's messages and the lights' share them.
pub(crate) use crate::files::io_message;
pub use crate::files::printable;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn read_error_is_one_line_without_os_error_code() {
        let error = SceneError::Read {
            path: PathBuf::from("x.gltf"),
            error: std::io::Error::from_raw_os_error(2),
        };
        assert_eq!(
            error.to_string(),
            "cannot read scene 'x.gltf': No such file or directory"
        );
    }

    #[test]
    fn unsupported_extension_names_it() {
        let error = SceneError::UnsupportedExtension {
            path: PathBuf::from("a/b.ply"),
            extension: Some("ply".into()),
        };
        assert_eq!(
            error.to_string(),
            "cannot load scene 'a/b.ply': unsupported file extension '.ply' \
             (expected .gltf, .glb or .obj)"
        );
        let error = SceneError::UnsupportedExtension {
            path: PathBuf::from("b"),
            extension: None,
        };
        assert!(error
            .to_string()
            .contains("unsupported file extension (expected"));
    }
}
