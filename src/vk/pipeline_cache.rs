//! A `VkPipelineCache` that outlives the process. A context given a `PipelineCacheStore`
//! builds every pipeline through one cache, starts it from what the store loads for its
//! device and hands it back to the store whenever a build changed it. Where the data live
//! (a file, in the application) is the store's business; this layer only knows which device
//! and driver the data belong to (`PipelineCacheKey`) and checks Vulkan's own header.

use std::collections::hash_map::DefaultHasher;
use std::fmt;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};

use ash::vk;

/// What pipeline cache data belong to: a device (vendor and device ids), its driver's
/// version and the driver's pipeline cache UUID (which drivers change whenever their
/// compiled pipelines would differ).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PipelineCacheKey {
    /// `VkPhysicalDeviceProperties::vendorID` (e.g. 0x10de for NVIDIA).
    pub vendor_id: u32,
    /// `VkPhysicalDeviceProperties::deviceID`.
    pub device_id: u32,
    /// `VkPhysicalDeviceProperties::driverVersion` (encoded as the vendor chooses).
    pub driver_version: u32,
    /// `VkPhysicalDeviceProperties::pipelineCacheUUID`.
    pub pipeline_cache_uuid: [u8; vk::UUID_SIZE],
}

/// Bytes of `VkPipelineCacheHeaderVersionOne`: header length, header version, vendor id,
/// device id (four little-endian u32 on every platform vkpath runs on: the host's byte
/// order) and the pipeline cache UUID.
pub const VULKAN_CACHE_HEADER_BYTES: usize = 16 + vk::UUID_SIZE;

impl PipelineCacheKey {
    /// The key of a device with these properties.
    pub fn of(properties: &vk::PhysicalDeviceProperties) -> PipelineCacheKey {
        PipelineCacheKey {
            vendor_id: properties.vendor_id,
            device_id: properties.device_id,
            driver_version: properties.driver_version,
            pipeline_cache_uuid: properties.pipeline_cache_uuid,
        }
    }

    /// The UUID as 32 lower-case hex digits (for file names).
    pub fn uuid_hex(&self) -> String {
        self.pipeline_cache_uuid
            .iter()
            .map(|byte| format!("{byte:02x}"))
            .collect()
    }

    /// Checks the header that Vulkan puts at the start of pipeline cache data
    /// (`VkPipelineCacheHeaderVersionOne`, in the host's byte order) against this device:
    /// `Err` says why data are not this device's (too short, another header version, another
    /// vendor, device or cache UUID).
    pub fn check_header(&self, data: &[u8]) -> Result<(), CacheHeaderError> {
        if data.len() < VULKAN_CACHE_HEADER_BYTES {
            return Err(CacheHeaderError::Short(data.len()));
        }
        let word = |i: usize| {
            let bytes = [
                data[4 * i],
                data[4 * i + 1],
                data[4 * i + 2],
                data[4 * i + 3],
            ];
            u32::from_ne_bytes(bytes)
        };
        let (length, version) = (word(0), word(1));
        if (length as usize) < VULKAN_CACHE_HEADER_BYTES
            || version != vk::PipelineCacheHeaderVersion::ONE.as_raw() as u32
        {
            return Err(CacheHeaderError::Unknown { length, version });
        }
        let (vendor, device) = (word(2), word(3));
        if (vendor, device) != (self.vendor_id, self.device_id) {
            return Err(CacheHeaderError::OtherDevice {
                made_for: (vendor, device),
                this: (self.vendor_id, self.device_id),
            });
        }
        if data[16..VULKAN_CACHE_HEADER_BYTES] != self.pipeline_cache_uuid {
            return Err(CacheHeaderError::OtherDriver);
        }
        Ok(())
    }
}

/// Why pipeline cache data are not this device's (`PipelineCacheKey::check_header`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CacheHeaderError {
    /// Fewer bytes than Vulkan's header.
    #[error(
        "{0} bytes, shorter than Vulkan's {header}-byte cache header",
        header = VULKAN_CACHE_HEADER_BYTES
    )]
    Short(usize),
    /// A header of another length or version than `VkPipelineCacheHeaderVersionOne`.
    #[error("an unknown Vulkan cache header (length {length}, version {version})")]
    Unknown {
        /// The header's length word.
        length: u32,
        /// The header's version word.
        version: u32,
    },
    /// Another vendor or device: (vendor, device) ids.
    #[error(
        "made for device {:04x}:{:04x}, not this {:04x}:{:04x}",
        made_for.0, made_for.1, this.0, this.1
    )]
    OtherDevice {
        /// The data's (vendor, device) ids.
        made_for: (u32, u32),
        /// This device's.
        this: (u32, u32),
    },
    /// Another driver (another pipeline cache UUID).
    #[error("made by another driver (its pipeline cache UUID differs)")]
    OtherDriver,
}

/// Where a context's pipeline cache lives between processes, and whom it tells that a build
/// is slow. Implementations report their own problems (a file that cannot be read or
/// written is a warning, never an error: the cache only saves time).
pub trait PipelineCacheStore: Send + Sync + fmt::Debug {
    /// The data saved for `key`'s device, if any. Data whose Vulkan header does not match
    /// (`PipelineCacheKey::check_header`) are ignored by the context.
    fn load(&self, key: &PipelineCacheKey) -> Option<Vec<u8>>;
    /// Saves the cache's data (all of it, not a difference) for `key`'s device.
    fn save(&self, key: &PipelineCacheKey, data: &[u8]);
    /// Called once per pipeline, from another thread, when building it has taken longer
    /// than `SLOW_BUILD_NOTICE_AFTER` in a process that found no cache data for its device
    /// (`load` gave none: the first run on a device builds its kernels). A warm cache does
    /// not call it, even where the driver keeps nothing in it (lavapipe 22.3 saves a bare
    /// header and compiles every run): "first run" would be untrue there.
    fn building_slowly(&self) {}
}

/// How long a pipeline build may take before the store's `building_slowly` is called.
pub const SLOW_BUILD_NOTICE_AFTER: std::time::Duration = std::time::Duration::from_secs(1);

/// A context's pipeline cache and the store it came from.
pub(crate) struct PersistentPipelineCache {
    pub(crate) store: Arc<dyn PipelineCacheStore>,
    pub(crate) key: PipelineCacheKey,
    pub(crate) handle: vk::PipelineCache,
    /// Hash of the data last loaded or saved, so that unchanged data are not written again.
    saved: Mutex<u64>,
    /// Whether the store had no usable data for this device when the cache was created
    /// (the first run on it, or its data were another driver's).
    pub(crate) cold: bool,
}

fn hash_of(data: &[u8]) -> u64 {
    let mut hasher = DefaultHasher::new();
    data.hash(&mut hasher);
    hasher.finish()
}

impl PersistentPipelineCache {
    /// Creates the cache on `device` from what `store` loads for `key` (an empty cache when
    /// it has nothing, the data are another device's, or the driver refuses them).
    pub(crate) fn create(
        device: &ash::Device,
        store: Arc<dyn PipelineCacheStore>,
        key: PipelineCacheKey,
    ) -> Result<PersistentPipelineCache, vk::Result> {
        let initial = store
            .load(&key)
            .filter(|data| key.check_header(data).is_ok())
            .unwrap_or_default();
        let create = |data: &[u8]| {
            let info = vk::PipelineCacheCreateInfo::default().initial_data(data);
            // SAFETY: a valid create info on a live device; `data` outlives the call.
            unsafe { device.create_pipeline_cache(&info, None) }
        };
        // A driver may refuse data it cannot use; start empty then.
        let handle = match create(&initial) {
            Ok(handle) => handle,
            Err(_) if !initial.is_empty() => create(&[])?,
            Err(result) => return Err(result),
        };
        Ok(PersistentPipelineCache {
            store,
            key,
            handle,
            saved: Mutex::new(hash_of(&initial)),
            cold: initial.is_empty(),
        })
    }

    /// Hands the cache's data to the store if they changed since they were last loaded or
    /// saved. A failure to read them back is ignored: the cache only saves time.
    pub(crate) fn save_if_changed(&self, device: &ash::Device) {
        // SAFETY: the cache belongs to `device`; Vulkan synchronises access to it.
        let Ok(data) = (unsafe { device.get_pipeline_cache_data(self.handle) }) else {
            return;
        };
        let hash = hash_of(&data);
        let mut saved = self.saved.lock().unwrap_or_else(|p| p.into_inner());
        if *saved != hash {
            self.store.save(&self.key, &data);
            *saved = hash;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> PipelineCacheKey {
        PipelineCacheKey {
            vendor_id: 0x10de,
            device_id: 0x2335,
            driver_version: 7,
            pipeline_cache_uuid: [3; 16],
        }
    }

    fn header(vendor: u32, device: u32, uuid: [u8; 16]) -> Vec<u8> {
        let mut data = Vec::new();
        for word in [32u32, 1, vendor, device] {
            data.extend_from_slice(&word.to_ne_bytes());
        }
        data.extend_from_slice(&uuid);
        data
    }

    #[test]
    fn headers_of_other_devices_and_drivers_are_refused() {
        let key = key();
        assert_eq!(key.check_header(&header(0x10de, 0x2335, [3; 16])), Ok(()));
        let mut with_payload = header(0x10de, 0x2335, [3; 16]);
        with_payload.extend_from_slice(&[9; 100]);
        assert_eq!(key.check_header(&with_payload), Ok(()));
        let other_device = key.check_header(&header(0x10de, 0x2330, [3; 16]));
        assert!(other_device.unwrap_err().to_string().contains("10de:2330"));
        let other_vendor = key.check_header(&header(0x1002, 0x2335, [3; 16]));
        assert!(other_vendor.is_err());
        let other_driver = key.check_header(&header(0x10de, 0x2335, [4; 16]));
        assert!(other_driver.unwrap_err().to_string().contains("UUID"));
        assert!(key
            .check_header(&header(0x10de, 0x2335, [3; 16])[..31])
            .is_err());
        let mut version_two = header(0x10de, 0x2335, [3; 16]);
        version_two[4] = 2;
        assert!(key
            .check_header(&version_two)
            .unwrap_err()
            .to_string()
            .contains("unknown"));
        assert_eq!(
            key.check_header(&[]).unwrap_err().to_string(),
            format!("0 bytes, shorter than Vulkan's {VULKAN_CACHE_HEADER_BYTES}-byte cache header")
        );
        assert_eq!(
            key.check_header(&header(0x1002, 0x2335, [3; 16]))
                .unwrap_err()
                .to_string(),
            "made for device 1002:2335, not this 10de:2335"
        );
    }

    #[test]
    fn uuids_are_written_as_hex() {
        let mut key = key();
        key.pipeline_cache_uuid[0] = 0xab;
        assert_eq!(key.uuid_hex(), format!("ab{}", "03".repeat(15)));
    }
}
