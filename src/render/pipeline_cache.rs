//! vkpath's pipeline cache on disk: one file per device and driver in the user's cache
//! directory (`$VKPATH_CACHE_DIR`, else `$XDG_CACHE_HOME/vkpath`, else `~/.cache/vkpath`),
//! so that a kernel the driver compiled once is not compiled again by the next process.
//!
//! A file is vkpath's header, then the driver's data: the magic `VKPATHPC`, the format
//! version, the device's vendor and device ids, its driver version, its pipeline cache UUID,
//! the vkpath version that wrote it, the data's length and their SHA-256. A file another
//! vkpath version or driver wrote is replaced silently (that is expected after an upgrade);
//! one that is corrupt (truncated, bad magic, wrong checksum) or another device's is ignored
//! with a warning. Files are written atomically (a temporary file renamed over the old one),
//! so two processes saving at once leave one whole file.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::vk::{PipelineCacheKey, PipelineCacheStore};

/// Environment variable that puts the cache somewhere else (a directory, created if missing).
pub const CACHE_DIR_VARIABLE: &str = "VKPATH_CACHE_DIR";

/// First bytes of every cache file.
const MAGIC: &[u8; 8] = b"VKPATHPC";
/// Version of the file layout below.
const FORMAT_VERSION: u32 = 1;
/// The vkpath version that writes (and accepts) cache files.
const VKPATH_VERSION: &str = env!("CARGO_PKG_VERSION");
/// Largest file read: pipeline caches of a few kernels are megabytes, not gigabytes.
const MAX_FILE_BYTES: u64 = 1 << 30;

/// The cache directory the environment names: `$VKPATH_CACHE_DIR`, `$XDG_CACHE_HOME/vkpath`
/// or `$HOME/.cache/vkpath` (the XDG base directory convention); `None` without any of them.
pub fn default_cache_dir() -> Option<PathBuf> {
    let non_empty = |name: &str| std::env::var_os(name).filter(|value| !value.is_empty());
    if let Some(dir) = non_empty(CACHE_DIR_VARIABLE) {
        return Some(PathBuf::from(dir));
    }
    if let Some(dir) = non_empty("XDG_CACHE_HOME") {
        return Some(PathBuf::from(dir).join("vkpath"));
    }
    non_empty("HOME").map(|home| PathBuf::from(home).join(".cache").join("vkpath"))
}

/// Why a cache file's contents cannot be used.
#[derive(Debug, PartialEq, Eq)]
enum Unusable {
    /// Written by another vkpath version or for another driver version: replaced without a
    /// warning.
    Stale(String),
    /// Damaged or not a vkpath cache file, or another device's: ignored with a warning.
    Corrupt(String),
}

/// The file's name for `key`: vendor, device and pipeline cache UUID (the driver version
/// and vkpath version are checked inside, so that an upgrade replaces the file instead of
/// adding one).
fn file_name(key: &PipelineCacheKey) -> String {
    format!(
        "pipelines-{:04x}-{:04x}-{}.bin",
        key.vendor_id,
        key.device_id,
        key.uuid_hex()
    )
}

/// vkpath's header for `data` of `key`'s device.
fn encode(key: &PipelineCacheKey, data: &[u8]) -> Vec<u8> {
    let mut file = Vec::with_capacity(data.len() + 128);
    file.extend_from_slice(MAGIC);
    for word in [
        FORMAT_VERSION,
        key.vendor_id,
        key.device_id,
        key.driver_version,
    ] {
        file.extend_from_slice(&word.to_le_bytes());
    }
    file.extend_from_slice(&key.pipeline_cache_uuid);
    file.extend_from_slice(&(VKPATH_VERSION.len() as u32).to_le_bytes());
    file.extend_from_slice(VKPATH_VERSION.as_bytes());
    file.extend_from_slice(&(data.len() as u64).to_le_bytes());
    file.extend_from_slice(&Sha256::digest(data));
    file.extend_from_slice(data);
    file
}

/// Reads a file's fields in order, failing on a file that ends early.
struct Reader<'a> {
    bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take(&mut self, count: usize) -> Result<&'a [u8], Unusable> {
        if self.bytes.len() < count {
            return Err(Unusable::Corrupt("the file ends early".into()));
        }
        let (taken, rest) = self.bytes.split_at(count);
        self.bytes = rest;
        Ok(taken)
    }

    fn u32(&mut self) -> Result<u32, Unusable> {
        let bytes = self.take(4)?;
        Ok(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
    }
}

/// The driver's data in a cache file, if it is a whole file of this vkpath version for
/// `key`'s device and driver.
fn decode<'a>(key: &PipelineCacheKey, file: &'a [u8]) -> Result<&'a [u8], Unusable> {
    let mut reader = Reader { bytes: file };
    if reader.take(MAGIC.len())? != MAGIC {
        return Err(Unusable::Corrupt("not a vkpath pipeline cache file".into()));
    }
    // An older layout is an upgrade's leftover; anything else is damage (or a newer vkpath's
    // file, which this one cannot read either).
    let format = reader.u32()?;
    if format < FORMAT_VERSION {
        return Err(Unusable::Stale(format!("file format {format}")));
    }
    if format != FORMAT_VERSION {
        return Err(Unusable::Corrupt(format!(
            "file format {format}, not {FORMAT_VERSION}: damaged, or written by a newer vkpath"
        )));
    }
    let (vendor, device, driver) = (reader.u32()?, reader.u32()?, reader.u32()?);
    let uuid = reader.take(key.pipeline_cache_uuid.len())?;
    if (vendor, device) != (key.vendor_id, key.device_id) || uuid != key.pipeline_cache_uuid {
        return Err(Unusable::Corrupt(format!(
            "it belongs to device {vendor:04x}:{device:04x} with another driver, not this one"
        )));
    }
    let version_length = reader.u32()? as usize;
    if version_length > 64 {
        return Err(Unusable::Corrupt(format!(
            "a {version_length}-byte version string"
        )));
    }
    let version = reader.take(version_length)?;
    if version != VKPATH_VERSION.as_bytes() {
        return Err(Unusable::Stale(format!(
            "written by vkpath {}",
            String::from_utf8_lossy(version)
        )));
    }
    if driver != key.driver_version {
        return Err(Unusable::Stale(format!("driver version {driver}")));
    }
    let length_bytes = reader.take(8)?;
    let mut length = [0u8; 8];
    length.copy_from_slice(length_bytes);
    let length = u64::from_le_bytes(length);
    let checksum = reader.take(32)?;
    if reader.bytes.len() as u64 != length {
        return Err(Unusable::Corrupt(format!(
            "it should hold {length} bytes of cache data, it holds {}",
            reader.bytes.len()
        )));
    }
    if Sha256::digest(reader.bytes).as_slice() != checksum {
        return Err(Unusable::Corrupt("its checksum does not match".into()));
    }
    key.check_header(reader.bytes)
        .map_err(|error| Unusable::Corrupt(error.to_string()))?;
    Ok(reader.bytes)
}

/// A `PipelineCacheStore` in a directory: one file per device and driver.
pub struct PipelineCacheDir {
    dir: PathBuf,
    warn: Box<dyn Fn(&str) + Send + Sync>,
    slow: Box<dyn Fn() + Send + Sync>,
}

impl std::fmt::Debug for PipelineCacheDir {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PipelineCacheDir")
            .field("dir", &self.dir)
            .finish_non_exhaustive()
    }
}

impl PipelineCacheDir {
    /// A store in `dir` (created when first written) that reports problems through `warn`
    /// (one line each, e.g. to stderr) and calls `slow` when a build takes more than a
    /// second (`vk::pipeline_cache::SLOW_BUILD_NOTICE_AFTER`).
    pub fn new(
        dir: PathBuf,
        warn: impl Fn(&str) + Send + Sync + 'static,
        slow: impl Fn() + Send + Sync + 'static,
    ) -> PipelineCacheDir {
        PipelineCacheDir {
            dir,
            warn: Box::new(warn),
            slow: Box::new(slow),
        }
    }

    /// The file that holds `key`'s device's cache.
    pub fn path(&self, key: &PipelineCacheKey) -> PathBuf {
        self.dir.join(file_name(key))
    }

    /// Writes `bytes` to `path` atomically: into a temporary file beside it, then renamed.
    fn write_atomically(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
        fs::create_dir_all(&self.dir)?;
        let mut file = tempfile::NamedTempFile::new_in(&self.dir)?;
        file.write_all(bytes)?;
        file.as_file().sync_all()?;
        file.persist(path).map_err(|error| error.error)?;
        Ok(())
    }
}

impl PipelineCacheStore for PipelineCacheDir {
    fn load(&self, key: &PipelineCacheKey) -> Option<Vec<u8>> {
        let path = self.path(key);
        let read = fs::metadata(&path).and_then(|metadata| {
            if metadata.len() > MAX_FILE_BYTES {
                return Err(std::io::Error::other(format!(
                    "{} bytes is larger than a pipeline cache should be",
                    metadata.len()
                )));
            }
            fs::read(&path)
        });
        let bytes = match read {
            Ok(bytes) => bytes,
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => return None,
            Err(error) => {
                (self.warn)(&format!(
                    "ignoring the pipeline cache '{}': {error}",
                    path.display()
                ));
                return None;
            }
        };
        match decode(key, &bytes) {
            Ok(data) => Some(data.to_vec()),
            Err(Unusable::Stale(_)) => None,
            Err(Unusable::Corrupt(why)) => {
                (self.warn)(&format!(
                    "ignoring the pipeline cache '{}' ({why}); it will be rebuilt",
                    path.display()
                ));
                None
            }
        }
    }

    fn save(&self, key: &PipelineCacheKey, data: &[u8]) {
        let path = self.path(key);
        if let Err(error) = self.write_atomically(&path, &encode(key, data)) {
            (self.warn)(&format!(
                "cannot save the pipeline cache '{}': {error} (use --no-cache or {CACHE_DIR_VARIABLE})",
                path.display()
            ));
        }
    }

    fn building_slowly(&self) {
        (self.slow)();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> PipelineCacheKey {
        PipelineCacheKey {
            vendor_id: 0x10005,
            device_id: 0,
            driver_version: 42,
            pipeline_cache_uuid: *b"0123456789abcdef",
        }
    }

    /// Vulkan's header for `key` followed by a payload.
    fn cache_data(key: &PipelineCacheKey) -> Vec<u8> {
        let mut data = Vec::new();
        for word in [32u32, 1, key.vendor_id, key.device_id] {
            data.extend_from_slice(&word.to_ne_bytes());
        }
        data.extend_from_slice(&key.pipeline_cache_uuid);
        data.extend_from_slice(b"compiled kernels");
        data
    }

    #[test]
    fn files_round_trip() {
        let key = key();
        let data = cache_data(&key);
        assert_eq!(decode(&key, &encode(&key, &data)), Ok(&data[..]));
    }

    #[test]
    fn damaged_files_are_corrupt() {
        let key = key();
        let file = encode(&key, &cache_data(&key));
        let corrupt = |bytes: &[u8]| matches!(decode(&key, bytes), Err(Unusable::Corrupt(_)));
        // Truncated anywhere: in the header, in the data, or with nothing at all.
        for length in [0, 7, 20, 60, file.len() - 1] {
            assert!(corrupt(&file[..length]), "truncated to {length}");
        }
        // One flipped bit in the data fails the checksum; in the magic, the magic check.
        let mut flipped = file.clone();
        *flipped.last_mut().unwrap() ^= 1;
        assert!(corrupt(&flipped));
        let mut magic = file.clone();
        magic[0] = b'X';
        assert!(corrupt(&magic));
        // A damaged format version.
        let mut format = file.clone();
        format[8] ^= 0x5a;
        assert!(corrupt(&format));
        // A byte too many.
        let mut longer = file.clone();
        longer.push(0);
        assert!(corrupt(&longer));
    }

    #[test]
    fn other_devices_are_corrupt_and_other_versions_stale() {
        let key = key();
        let data = cache_data(&key);
        let other_device = PipelineCacheKey {
            device_id: 1,
            ..key
        };
        assert!(matches!(
            decode(&other_device, &encode(&key, &data)),
            Err(Unusable::Corrupt(_))
        ));
        let newer_driver = PipelineCacheKey {
            driver_version: 43,
            ..key
        };
        assert!(matches!(
            decode(&newer_driver, &encode(&key, &data)),
            Err(Unusable::Stale(_))
        ));
        // Another vkpath version: the version string inside differs.
        let mut file = encode(&key, &data);
        let at = 8 + 16 + 16 + 4;
        file[at] = file[at].wrapping_add(1);
        assert!(matches!(decode(&key, &file), Err(Unusable::Stale(_))));
        // Data whose Vulkan header names another device, under a valid checksum.
        let foreign = cache_data(&other_device);
        assert!(matches!(
            decode(&key, &encode(&key, &foreign)),
            Err(Unusable::Corrupt(_))
        ));
    }

    #[test]
    fn the_store_saves_loads_and_warns_about_corrupt_files() {
        use std::sync::{Arc, Mutex};
        let dir = tempfile::tempdir().unwrap();
        let warnings = Arc::new(Mutex::new(Vec::<String>::new()));
        let sink = warnings.clone();
        let store = PipelineCacheDir::new(
            dir.path().join("nested"),
            move |warning| sink.lock().unwrap().push(warning.to_owned()),
            || {},
        );
        let key = key();
        assert_eq!(store.load(&key), None);
        let data = cache_data(&key);
        store.save(&key, &data);
        assert_eq!(store.load(&key), Some(data.clone()));
        assert!(warnings.lock().unwrap().is_empty());
        // No temporary file is left beside the cache.
        let entries = fs::read_dir(dir.path().join("nested")).unwrap().count();
        assert_eq!(entries, 1);
        fs::write(store.path(&key), b"VKPATHPC garbage").unwrap();
        assert_eq!(store.load(&key), None);
        let warnings = warnings.lock().unwrap();
        assert_eq!(warnings.len(), 1);
        assert!(
            warnings[0].contains("ignoring the pipeline cache"),
            "{warnings:?}"
        );
    }
}
