//! Reading scene files and the files they refer to, safely: only regular files (a named
//! pipe or a device such as /dev/zero would block or never end), never more than a bound,
//! and, for files a scene names, only inside the scene's folder unless allowed otherwise.

use std::io::Read;
use std::path::{Component, Path, PathBuf};

use super::SceneError;

/// The most bytes vkpath reads from one scene file or one file that a scene refers to
/// (1 GiB): more than any scene it renders needs (10^6 triangles take 96 MB on the GPU),
/// and a bound that a hostile or broken file cannot push memory past.
pub const MAX_SCENE_FILE_BYTES: u64 = crate::files::MAX_FILE_BYTES;

/// How scene files may be read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadOptions {
    /// Whether a glTF file may refer to files outside its own folder (absolute paths,
    /// `../`, `file:` URIs). Off by default: a scene from elsewhere must not read
    /// `/etc/passwd` or a device.
    pub allow_external_paths: bool,
    /// The time in seconds at which a glTF file's animations are evaluated (0 by default:
    /// their first keys, or the rest pose where nothing is animated).
    pub time: f32,
    /// Which of a glTF file's animations play (all by default).
    pub animation: super::animation::AnimationPick,
    /// The glTF file's material variant (`KHR_materials_variants`) by name; `None`: the
    /// primitives' own materials.
    pub variant: Option<String>,
}

/// Reads a whole regular file of at most `limit` bytes.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, SceneError> {
    let read_error = |error| SceneError::Read {
        path: path.to_owned(),
        error,
    };
    let metadata = std::fs::metadata(path).map_err(read_error)?;
    if !metadata.is_file() {
        return Err(SceneError::NotAFile {
            path: path.to_owned(),
            kind: file_kind(&metadata),
        });
    }
    if metadata.len() > limit {
        return Err(SceneError::TooLarge {
            path: path.to_owned(),
            bytes: metadata.len(),
            limit,
        });
    }
    let file = std::fs::File::open(path).map_err(read_error)?;
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    // The size can change while reading; never read more than the bound all the same.
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    if bytes.len() as u64 > limit {
        return Err(SceneError::TooLarge {
            path: path.to_owned(),
            bytes: bytes.len() as u64,
            limit,
        });
    }
    Ok(bytes)
}

/// What kind of file system object a non-regular file is, in words.
/// The error of a path that exists but is no regular file (a directory given as a scene):
/// said before its extension is judged, since a folder has no format.
pub(super) fn existing_non_file(path: &Path) -> Option<SceneError> {
    let metadata = std::fs::metadata(path).ok()?;
    (!metadata.is_file()).then(|| SceneError::NotAFile {
        path: path.to_owned(),
        kind: file_kind(&metadata),
    })
}

fn file_kind(metadata: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let kind = metadata.file_type();
    if kind.is_dir() {
        "a directory"
    } else if kind.is_fifo() {
        "a named pipe"
    } else if kind.is_char_device() || kind.is_block_device() {
        "a device"
    } else if kind.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

/// The file that a scene at `scene` names with the (already percent-decoded) relative or
/// absolute path `name`: relative to the scene's folder, and refused when it lies outside
/// that folder unless `options` allow it.
pub fn resolve_reference(
    scene: &Path,
    name: &str,
    options: &LoadOptions,
) -> Result<PathBuf, SceneError> {
    let folder = scene.parent().unwrap_or(Path::new(""));
    let reference = Path::new(name);
    let escapes = reference.is_absolute() || {
        // Walk the components: `..` below the folder leaves it.
        let mut depth = 0i32;
        reference.components().any(|component| {
            match component {
                Component::ParentDir => depth -= 1,
                Component::Normal(_) => depth += 1,
                _ => {}
            }
            depth < 0
        })
    };
    let outside = || SceneError::ExternalPath {
        path: scene.to_owned(),
        reference: super::printable(name),
    };
    if escapes && !options.allow_external_paths {
        return Err(outside());
    }
    let file = folder.join(reference);
    // A symbolic link inside the folder may point outside it: what it resolves to counts.
    if !options.allow_external_paths {
        if let (Ok(real_file), Ok(real_folder)) = (
            file.canonicalize(),
            if folder.as_os_str().is_empty() {
                Path::new(".")
            } else {
                folder
            }
            .canonicalize(),
        ) {
            if !real_file.starts_with(&real_folder) {
                return Err(outside());
            }
        }
    }
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_bounded_regular_files_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.bin");
        std::fs::write(&file, [1u8; 100]).unwrap();
        assert_eq!(read_bounded(&file, 100).unwrap().len(), 100);
        assert!(matches!(
            read_bounded(&file, 99),
            Err(SceneError::TooLarge { bytes: 100, .. })
        ));
        assert!(matches!(
            read_bounded(dir.path(), 99),
            Err(SceneError::NotAFile {
                kind: "a directory",
                ..
            })
        ));
        let message = read_bounded(Path::new("/dev/zero"), 10)
            .unwrap_err()
            .to_string();
        assert!(message.contains("a device"), "{message}");
    }

    #[test]
    fn references_stay_in_the_scene_folder() {
        let scene = Path::new("/scenes/box/scene.gltf");
        let options = LoadOptions::default();
        assert_eq!(
            resolve_reference(scene, "data/buffer.bin", &options).unwrap(),
            Path::new("/scenes/box/data/buffer.bin")
        );
        assert!(resolve_reference(scene, "a/../b.bin", &options).is_ok());
        for outside in ["../../etc/passwd", "/etc/passwd", "a/../../b.bin"] {
            let error = resolve_reference(scene, outside, &options)
                .unwrap_err()
                .to_string();
            assert!(
                error.contains("--allow-external-paths"),
                "{outside}: {error}"
            );
        }
        // A link inside the folder to a file outside it is outside too.
        let dir = tempfile::tempdir().unwrap();
        let inner = dir.path().join("scene");
        std::fs::create_dir(&inner).unwrap();
        std::fs::write(dir.path().join("secret.bin"), b"x").unwrap();
        std::os::unix::fs::symlink("../secret.bin", inner.join("link.bin")).unwrap();
        assert!(resolve_reference(&inner.join("a.gltf"), "link.bin", &options).is_err());
        let allowed = LoadOptions {
            allow_external_paths: true,
            ..LoadOptions::default()
        };
        assert_eq!(
            resolve_reference(scene, "/etc/passwd", &allowed).unwrap(),
            Path::new("/etc/passwd")
        );
    }
}
