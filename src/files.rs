//! A user's files in one-line messages, and read within a bound: below the rooms that read a
//! user's files (`crate::scene`, `crate::lights`), so that no room imports another for them
//! (the lights' environment map once imported the scene's errors, which import the
//! environment's).

use std::io::Read;
use std::path::Path;

/// The most bytes vkpath reads from one file a user gives (1 GiB): more than any scene it
/// renders needs (10^6 triangles take 96 MB on the GPU), and a bound that a hostile or
/// broken file cannot push memory past (`crate::scene::files::MAX_SCENE_FILE_BYTES`).
pub const MAX_FILE_BYTES: u64 = 1 << 30;

/// Text from a file (a name, a URI), made safe for a one-line message: control characters
/// (newlines, carriage returns, ...) are written as escapes.
pub fn printable(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_default().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// An I/O error's message without the "(os error N)" suffix that `std` appends, which means
/// nothing to a user reading one line of output.
pub(crate) fn io_message(error: &std::io::Error) -> String {
    let message = error.to_string();
    match message.rfind(" (os error ") {
        Some(start) if message.ends_with(')') => message[..start].to_owned(),
        _ => message,
    }
}

/// Why `read_at_most` could not read a file, in plain words (the caller names the file).
#[derive(Debug, thiserror::Error)]
pub enum BoundedReadError {
    /// Opening or reading it failed.
    #[error("{}", io_message(.0))]
    Io(std::io::Error),
    /// It is larger than the bound.
    #[error("it has {bytes} bytes, more than the {limit} vkpath reads from one file")]
    TooLarge {
        /// Its size, or as much of it as was read.
        bytes: u64,
        /// The bound.
        limit: u64,
    },
}

/// Reads the whole file at `path` if it has at most `limit` bytes (never more than the
/// bound, even where the file grows while it is read). The caller checks first that it is
/// a regular file (a named pipe would block).
pub(crate) fn read_at_most(path: &Path, limit: u64) -> Result<Vec<u8>, BoundedReadError> {
    let file = std::fs::File::open(path).map_err(BoundedReadError::Io)?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(BoundedReadError::Io)?;
    match bytes.len() as u64 {
        read if read > limit => Err(BoundedReadError::TooLarge { bytes: read, limit }),
        _ => Ok(bytes),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_read_within_its_bound() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f");
        std::fs::write(&path, b"12345").unwrap();
        assert_eq!(read_at_most(&path, 5).unwrap(), b"12345");
        assert_eq!(
            read_at_most(&path, 4).unwrap_err().to_string(),
            "it has 5 bytes, more than the 4 vkpath reads from one file"
        );
        let missing = read_at_most(&dir.path().join("nope"), 4).unwrap_err();
        assert_eq!(missing.to_string(), "No such file or directory");
        assert_eq!(printable("a\nb"), "a\\nb");
    }
}
