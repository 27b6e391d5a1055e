//! The environment map's file as `Scene::with_environment` sees it: checked before the map
//! is read, so that a missing file or a directory is reported as the environment map it
//! was meant to be (not as "cannot read scene"), and the loader's messages said plainly:
//! the file named once, a truncated file called truncated.
//!
//! (The loader, `crate::lights::environment`, words its own messages; this is where they
//! are put right until that file is free to change: see `plain_environment_message`.)

use std::path::Path;

use super::{printable, SceneError};
use crate::image_io::exr_input::plain_cause;

/// The start of every message about an environment map's file.
fn prefix(path: &Path) -> String {
    format!(
        "cannot read environment map '{}'",
        printable(&path.display().to_string())
    )
}

/// Checks that the environment map `path` exists and is a regular file; the error names
/// the map and the cause ("No such file or directory", "it is a directory, not a file").
pub fn check_environment_file(path: &Path) -> Result<(), SceneError> {
    let fail = |why: String| SceneError::Environment(format!("{}: {why}", prefix(path)));
    let metadata =
        std::fs::metadata(path).map_err(|error| fail(super::error::io_message(&error)))?;
    if metadata.is_dir() {
        return Err(fail("it is a directory, not a file".into()));
    }
    if !metadata.is_file() {
        return Err(fail("it is not a regular file".into()));
    }
    Ok(())
}

/// The environment loader's error `message` about `path`, said plainly: when the image
/// reader's own "cannot read 'PATH': " follows the loader's "cannot read environment map
/// 'PATH': ", the path is named once; "failed to fill whole buffer" (a file that ends too
/// early) becomes "the file is truncated".
pub fn plain_environment_message(path: &Path, message: &str) -> String {
    let head = format!("{}: ", prefix(path));
    let repeated = format!("cannot read '{}': ", path.display());
    let message = match message.strip_prefix(&head) {
        Some(rest) => format!("{head}{}", rest.strip_prefix(&repeated).unwrap_or(rest)),
        None => message.to_string(),
    };
    plain_cause(&message)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_files_and_directories_are_named_as_the_environment_map() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("nope.hdr");
        let message = check_environment_file(&missing).unwrap_err().to_string();
        assert_eq!(
            message,
            format!(
                "cannot read environment map '{}': No such file or directory",
                missing.display()
            )
        );
        let message = check_environment_file(dir.path()).unwrap_err().to_string();
        assert!(
            message.ends_with("it is a directory, not a file"),
            "{message}"
        );
        let file = dir.path().join("sky.hdr");
        std::fs::write(&file, b"#?RADIANCE\n").unwrap();
        assert!(check_environment_file(&file).is_ok());
    }

    #[test]
    fn the_path_is_named_once_and_truncation_is_said_plainly() {
        let path = Path::new("maps/sky.exr");
        assert_eq!(
            plain_environment_message(
                path,
                "cannot read environment map 'maps/sky.exr': cannot read 'maps/sky.exr': it is a PNG image, not an OpenEXR file"
            ),
            "cannot read environment map 'maps/sky.exr': it is a PNG image, not an OpenEXR file"
        );
        assert_eq!(
            plain_environment_message(
                Path::new("t.hdr"),
                "cannot read environment map 't.hdr': failed to fill whole buffer"
            ),
            "cannot read environment map 't.hdr': the file is truncated (it ends before its image data does)"
        );
        // Other messages pass unchanged.
        let other = "environment map 'x.png' must be a .hdr (Radiance) or .exr (OpenEXR) file";
        assert_eq!(plain_environment_message(Path::new("x.png"), other), other);
    }
}
