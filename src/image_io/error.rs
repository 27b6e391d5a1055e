//! What can go wrong reading or writing an image: the one error type of `crate::image_io`,
//! which `crate::Error` wraps.

use std::fmt::Display;
use std::path::{Path, PathBuf};

/// An image that could not be read or written: the path and the cause, in one line.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImageError {
    /// Reading the file at `path` failed.
    #[error("cannot read '{}': {message}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// Writing the file at `path` failed, or the path cannot take an image.
    #[error("cannot write '{}': {message}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

impl ImageError {
    /// Reading `path` failed because of `message`.
    pub fn read(path: &Path, message: impl Display) -> ImageError {
        ImageError::Read {
            path: path.to_path_buf(),
            message: message.to_string(),
        }
    }

    /// Writing `path` failed because of `message`.
    pub fn write(path: &Path, message: impl Display) -> ImageError {
        ImageError::Write {
            path: path.to_path_buf(),
            message: message.to_string(),
        }
    }
}

/// Result with `ImageError`.
pub type ImageResult<T> = std::result::Result<T, ImageError>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_path_and_the_cause_in_one_line() {
        let error = ImageError::write(Path::new("out/a.png"), "disk full");
        assert_eq!(error.to_string(), "cannot write 'out/a.png': disk full");
        let error = ImageError::read(Path::new("b.exr"), "not an EXR");
        assert_eq!(error.to_string(), "cannot read 'b.exr': not an EXR");
    }
}
