//! Whether a device offers ray queries in compute shaders (`VK_KHR_ray_query` with
//! `VK_KHR_acceleration_structure`), what it lacks where it does not, and the extensions and
//! features `Context::new` enables where it does. Devices without them (Mesa 22.3's
//! lavapipe, NVIDIA's drivers, which offer ray-tracing pipelines only) get a device
//! exactly as before.

use std::ffi::{c_char, CStr};

use ash::vk;

/// The device extensions that ray queries in compute kernels need.
const EXTENSIONS: [&CStr; 3] = [
    ash::khr::acceleration_structure::NAME,
    ash::khr::ray_query::NAME,
    // Required by VK_KHR_acceleration_structure (host builds, which vkpath does not use).
    ash::khr::deferred_host_operations::NAME,
];

/// Environment variable that lowers the triangles one bottom-level structure may hold below
/// the device's own limit (never raises it): for tests of scenes beyond the limit, and for
/// users who want large scenes on the BVH.
pub const PRIMITIVE_LIMIT_VARIABLE: &str = "VKPATH_RAY_QUERY_MAX_PRIMITIVES";

/// What the device's acceleration structures allow
/// (`VkPhysicalDeviceAccelerationStructurePropertiesKHR`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RayQueryLimits {
    /// Most geometries in one bottom-level structure.
    pub max_geometry_count: u64,
    /// Most instances in one top-level structure.
    pub max_instance_count: u64,
    /// Most primitives (triangles) in one bottom-level structure.
    pub max_primitive_count: u64,
    /// Alignment of a build's scratch memory's device address, in bytes.
    pub scratch_alignment: u64,
}

/// Whether the device's compute kernels can trace rays with ray queries.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RayQuerySupport {
    /// They can: the extensions and features were enabled on the device.
    Available(RayQueryLimits),
    /// They cannot: what the device lacks, in words (`"VK_KHR_ray_query"`,
    /// `"the rayQuery feature"`, ...).
    Missing(String),
}

impl RayQuerySupport {
    /// The limits where ray queries are available.
    pub fn limits(&self) -> Option<&RayQueryLimits> {
        match self {
            RayQuerySupport::Available(limits) => Some(limits),
            RayQuerySupport::Missing(_) => None,
        }
    }

    /// Whether ray queries are available.
    pub fn is_available(&self) -> bool {
        self.limits().is_some()
    }
}

/// What `physical_device` offers of ray queries: `Available` when it has every extension of
/// `EXTENSIONS` and the `accelerationStructure`, `rayQuery` and `bufferDeviceAddress`
/// features (it must be a Vulkan 1.2 device), else what it lacks.
pub fn probe(instance: &ash::Instance, physical_device: vk::PhysicalDevice) -> RayQuerySupport {
    // SAFETY: physical_device belongs to the live instance.
    let properties = unsafe { instance.get_physical_device_properties(physical_device) };
    let version = properties.api_version;
    if vk::api_version_major(version) == 1 && vk::api_version_minor(version) < 2 {
        return RayQuerySupport::Missing("Vulkan 1.2".into());
    }
    let offered = unsafe { instance.enumerate_device_extension_properties(physical_device) }
        .unwrap_or_default();
    let missing: Vec<String> = EXTENSIONS
        .iter()
        .filter(|name| {
            !offered
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(**name))
        })
        .map(|name| name.to_string_lossy().into_owned())
        .collect();
    if !missing.is_empty() {
        return RayQuerySupport::Missing(missing.join(" and "));
    }
    let mut acceleration = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut ray_query = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut address = vk::PhysicalDeviceBufferDeviceAddressFeatures::default();
    let mut features = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut acceleration)
        .push_next(&mut ray_query)
        .push_next(&mut address);
    // SAFETY: a chain of structures of extensions the device offers, alive for the call.
    unsafe { instance.get_physical_device_features2(physical_device, &mut features) };
    let lacking: Vec<&str> = [
        (acceleration.acceleration_structure, "accelerationStructure"),
        (ray_query.ray_query, "rayQuery"),
        (address.buffer_device_address, "bufferDeviceAddress"),
    ]
    .into_iter()
    .filter(|(offered, _)| *offered == vk::FALSE)
    .map(|(_, name)| name)
    .collect();
    if !lacking.is_empty() {
        return RayQuerySupport::Missing(format!("the {} feature", lacking.join(" and ")));
    }
    let mut limits = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
    let mut properties = vk::PhysicalDeviceProperties2::default().push_next(&mut limits);
    // SAFETY: as above.
    unsafe { instance.get_physical_device_properties2(physical_device, &mut properties) };
    let lowered = std::env::var(PRIMITIVE_LIMIT_VARIABLE)
        .ok()
        .and_then(|value| value.trim().parse::<u64>().ok());
    RayQuerySupport::Available(RayQueryLimits {
        max_geometry_count: limits.max_geometry_count,
        max_instance_count: limits.max_instance_count,
        max_primitive_count: lowered.map_or(limits.max_primitive_count, |lowered| {
            lowered.min(limits.max_primitive_count)
        }),
        scratch_alignment: u64::from(
            limits
                .min_acceleration_structure_scratch_offset_alignment
                .max(1),
        ),
    })
}

/// The features that `Context::new` chains into its `VkDeviceCreateInfo` where ray queries
/// are available, with the extensions' names.
pub(crate) struct RayQueryFeatures {
    pub(crate) acceleration: vk::PhysicalDeviceAccelerationStructureFeaturesKHR<'static>,
    pub(crate) ray_query: vk::PhysicalDeviceRayQueryFeaturesKHR<'static>,
    pub(crate) address: vk::PhysicalDeviceBufferDeviceAddressFeatures<'static>,
}

impl RayQueryFeatures {
    /// The features to enable.
    pub(crate) fn enabled() -> RayQueryFeatures {
        RayQueryFeatures {
            acceleration: vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default()
                .acceleration_structure(true),
            ray_query: vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true),
            address: vk::PhysicalDeviceBufferDeviceAddressFeatures::default()
                .buffer_device_address(true),
        }
    }

    /// The extensions to enable, as pointers for `enabled_extension_names`.
    pub(crate) fn extension_names() -> Vec<*const c_char> {
        EXTENSIONS.iter().map(|name| name.as_ptr()).collect()
    }
}
