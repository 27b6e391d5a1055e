//! The Vulkan instance, the chosen device with one compute queue, and the memory allocator.
//! Everything else in `vk` holds an `Arc<Context>`, so the context is destroyed last.
//!
//! Threads: a `Context` is `Send + Sync` and may be shared by any number of threads (an
//! `Arc<Context>`). What Vulkan requires to be externally synchronized is locked inside it:
//! submissions to its one queue (`Context::submit`) and the allocator. Objects that record
//! commands (`CommandRunner`, hence `Renderer`) are `Send` but not `Sync`: move one to a
//! thread, or give each thread its own; sharing one between threads does not compile.

use std::ffi::{c_char, CStr};
use std::fmt;
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::device_choice::{choose_devices, format_uuid, DeviceEnvironment, PciBusInfo};
use super::error::{CallContext, VkError, VkResult};
use super::pipeline_cache::{PersistentPipelineCache, PipelineCacheKey, PipelineCacheStore};
use super::ray_query_support::{self, RayQueryFeatures, RayQuerySupport};
use super::validation::{messenger_create_info, ValidationMessages};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to create a context.
#[derive(Clone, Debug, Default)]
pub struct ContextOptions {
    /// Enable `VK_LAYER_KHRONOS_validation` and count its messages.
    pub validate: bool,
    /// Which device: an index of `vkpath devices`, a `GPU-` UUID (or a unique prefix), or a
    /// case-insensitive part of its name. `None` reads `VKPATH_DEVICE`, then
    /// `CUDA_VISIBLE_DEVICES` (on machines with NVIDIA devices), else picks a discrete GPU, else
    /// an integrated or virtual one, else the CPU device (`device_choice::choose_devices`).
    pub device: Option<String>,
    /// Why `device` was chosen, when the caller chose it (several devices): replaces the
    /// reason `Context::new` would give (`Context::chosen_because`).
    pub chosen_because: Option<String>,
    /// Fail unless the chosen device is a GPU (not a CPU implementation such as lavapipe).
    pub require_gpu: bool,
    /// Build pipelines through a pipeline cache that this store keeps between processes
    /// (`None`: no pipeline cache).
    pub pipeline_cache: Option<Arc<dyn PipelineCacheStore>>,
}

/// The kind of a physical device, as Vulkan reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeviceKind {
    /// A discrete GPU.
    DiscreteGpu,
    /// A GPU integrated with the CPU.
    IntegratedGpu,
    /// A virtualized GPU.
    VirtualGpu,
    /// A CPU implementation (e.g. Mesa's lavapipe / llvmpipe).
    Cpu,
    /// Anything else.
    Other,
}

impl DeviceKind {
    fn from_vk(kind: vk::PhysicalDeviceType) -> DeviceKind {
        match kind {
            vk::PhysicalDeviceType::DISCRETE_GPU => DeviceKind::DiscreteGpu,
            vk::PhysicalDeviceType::INTEGRATED_GPU => DeviceKind::IntegratedGpu,
            vk::PhysicalDeviceType::VIRTUAL_GPU => DeviceKind::VirtualGpu,
            vk::PhysicalDeviceType::CPU => DeviceKind::Cpu,
            _ => DeviceKind::Other,
        }
    }

    /// Whether this is a GPU of any kind.
    pub fn is_gpu(self) -> bool {
        matches!(
            self,
            DeviceKind::DiscreteGpu | DeviceKind::IntegratedGpu | DeviceKind::VirtualGpu
        )
    }

    /// How JSON reports name it (`render --json`'s and `devices --json`'s `type`):
    /// `discrete-gpu`, `integrated-gpu`, `virtual-gpu`, `cpu` or `other`.
    pub fn report_name(self) -> &'static str {
        match self {
            DeviceKind::DiscreteGpu => "discrete-gpu",
            DeviceKind::IntegratedGpu => "integrated-gpu",
            DeviceKind::VirtualGpu => "virtual-gpu",
            DeviceKind::Cpu => "cpu",
            DeviceKind::Other => "other",
        }
    }

    /// Preference when no device is named: lower is better.
    pub(crate) fn rank(self) -> u32 {
        match self {
            DeviceKind::DiscreteGpu => 0,
            DeviceKind::IntegratedGpu => 1,
            DeviceKind::VirtualGpu => 2,
            DeviceKind::Other => 3,
            DeviceKind::Cpu => 4,
        }
    }
}

impl fmt::Display for DeviceKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DeviceKind::DiscreteGpu => "discrete GPU",
            DeviceKind::IntegratedGpu => "integrated GPU",
            DeviceKind::VirtualGpu => "virtual GPU",
            DeviceKind::Cpu => "CPU device (software rendering, not a GPU)",
            DeviceKind::Other => "device of unknown type",
        })
    }
}

/// What `vkpath devices` shows of a physical device.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    /// Index in Vulkan's enumeration order (what `--device N` takes).
    pub index: usize,
    /// The driver's name for the device.
    pub name: String,
    /// GPU or CPU.
    pub kind: DeviceKind,
    /// Supported Vulkan version, e.g. "1.3.230".
    pub api_version: String,
    /// Queue family index of a queue that supports compute, if any.
    pub compute_queue_family: Option<u32>,
    /// `VkPhysicalDeviceIDProperties::deviceUUID` (what CUDA and `nvidia-smi` call the GPU's
    /// UUID on NVIDIA; all zero on a Vulkan 1.0 device).
    pub uuid: [u8; 16],
    /// PCI vendor ID (0x10de: NVIDIA).
    pub vendor_id: u32,
    /// Its PCI address, where the driver has `VK_EXT_pci_bus_info`.
    pub pci_bus: Option<PciBusInfo>,
    /// Whether its kernels can trace rays with ray queries (`VK_KHR_ray_query`:
    /// `--accel hardware`).
    pub ray_queries: bool,
}

impl fmt::Display for DeviceInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {} [{}], Vulkan {}",
            self.index, self.name, self.kind, self.api_version
        )?;
        write!(f, ", {}", format_uuid(&self.uuid))?;
        if self.compute_queue_family.is_none() {
            f.write_str(", no compute queue")?;
        }
        if self.ray_queries {
            f.write_str(", ray queries")?;
        }
        Ok(())
    }
}

/// A Vulkan instance and logical device with one compute queue and an allocator.
pub struct Context {
    /// Keeps the loader loaded as long as the instance lives.
    _entry: ash::Entry,
    /// The instance.
    pub instance: ash::Instance,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Validation message counts (boxed: the messenger's callback points at it).
    validation: Option<Box<ValidationMessages>>,
    /// The chosen physical device.
    pub physical_device: vk::PhysicalDevice,
    /// What the chosen device is.
    pub info: DeviceInfo,
    /// Why it was chosen, in words (`--device 1`, `CUDA_VISIBLE_DEVICES=GPU-...`, `default:
    /// ...`), for the device line and `--json`.
    pub chosen_because: String,
    /// Its limits (workgroup counts, push constant size, ...).
    pub limits: vk::PhysicalDeviceLimits,
    /// Whether its kernels can trace rays with ray queries (enabled on the device where
    /// they can), with the acceleration structures' limits.
    pub ray_queries: RayQuerySupport,
    /// The logical device.
    pub device: ash::Device,
    /// The compute queue, locked: Vulkan requires every submission to a queue to be
    /// externally synchronized (`submit`).
    queue: Mutex<vk::Queue>,
    /// Its family index.
    pub queue_family_index: u32,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    /// The pipeline cache, when `ContextOptions::pipeline_cache` gave a store.
    pipeline_cache: Option<PersistentPipelineCache>,
}

/// Environment variable naming the Vulkan loader library to use instead of the system's
/// `libvulkan.so.1` (e.g. a loader unpacked next to the binary).
pub const LOADER_PATH_VARIABLE: &str = "VKPATH_VULKAN_LOADER";

fn load_entry() -> VkResult<ash::Entry> {
    // SAFETY: loading a Vulkan loader library; nothing else runs its initialisation.
    let loaded = match std::env::var_os(LOADER_PATH_VARIABLE) {
        Some(path) => unsafe { ash::Entry::load_from(&path) },
        None => unsafe { ash::Entry::load() },
    };
    loaded.map_err(|e| VkError::LoaderMissing(e.to_string()))
}

fn has_validation_layer(entry: &ash::Entry) -> VkResult<bool> {
    // SAFETY: a plain query with no pointers of ours.
    let layers =
        unsafe { entry.enumerate_instance_layer_properties() }.during("listing instance layers")?;
    Ok(layers
        .iter()
        .any(|layer| layer.layer_name_as_c_str() == Ok(VALIDATION_LAYER)))
}

fn create_instance(
    entry: &ash::Entry,
    validation: Option<&ValidationMessages>,
) -> VkResult<ash::Instance> {
    let app_info = vk::ApplicationInfo::default()
        .application_name(c"vkpath")
        .engine_name(c"vkpath")
        .api_version(vk::API_VERSION_1_2);
    let mut layers: Vec<*const c_char> = Vec::new();
    let mut extensions: Vec<*const c_char> = Vec::new();
    if validation.is_some() {
        layers.push(VALIDATION_LAYER.as_ptr());
        extensions.push(ash::ext::debug_utils::NAME.as_ptr());
    }
    let mut create_info = vk::InstanceCreateInfo::default()
        .application_info(&app_info)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    // Also report what happens during vkCreateInstance / vkDestroyInstance.
    let mut messenger_info = validation.map(messenger_create_info);
    if let Some(info) = messenger_info.as_mut() {
        create_info = create_info.push_next(info);
    }
    // SAFETY: every pointer in create_info outlives the call.
    match unsafe { entry.create_instance(&create_info, None) } {
        Ok(instance) => Ok(instance),
        Err(vk::Result::ERROR_INCOMPATIBLE_DRIVER) => Err(VkError::NoDriver(
            "vkCreateInstance: no compatible driver (VK_ERROR_INCOMPATIBLE_DRIVER)".into(),
        )),
        Err(vk::Result::ERROR_LAYER_NOT_PRESENT) => Err(VkError::ValidationLayerMissing),
        Err(result) => Err(VkError::Call {
            what: "creating the Vulkan instance",
            result,
        }),
    }
}

fn describe_devices(instance: &ash::Instance) -> VkResult<Vec<(vk::PhysicalDevice, DeviceInfo)>> {
    // SAFETY: queries on a live instance.
    let devices = match unsafe { instance.enumerate_physical_devices() } {
        Ok(devices) => devices,
        Err(vk::Result::ERROR_INITIALIZATION_FAILED) => Vec::new(),
        Err(result) => {
            return Err(VkError::Call {
                what: "listing Vulkan devices",
                result,
            })
        }
    };
    Ok(devices
        .into_iter()
        .enumerate()
        .map(|(index, physical_device)| {
            // SAFETY: physical_device came from this instance.
            let properties = unsafe { instance.get_physical_device_properties(physical_device) };
            let families =
                unsafe { instance.get_physical_device_queue_family_properties(physical_device) };
            let compute_queue_family = families
                .iter()
                .position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
                .map(|i| i as u32);
            let v = properties.api_version;
            let (uuid, pci_bus) = identity(instance, physical_device, v);
            let info = DeviceInfo {
                index,
                name: properties
                    .device_name_as_c_str()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_else(|_| "(unnamed)".into()),
                kind: DeviceKind::from_vk(properties.device_type),
                api_version: format!(
                    "{}.{}.{}",
                    vk::api_version_major(v),
                    vk::api_version_minor(v),
                    vk::api_version_patch(v)
                ),
                compute_queue_family,
                uuid,
                vendor_id: properties.vendor_id,
                pci_bus,
                ray_queries: ray_query_support::probe(instance, physical_device).is_available(),
            };
            (physical_device, info)
        })
        .collect())
}

/// The device's UUID (`VkPhysicalDeviceIDProperties`, Vulkan 1.1) and, where the driver has
/// `VK_EXT_pci_bus_info`, its PCI address; zeros and `None` on a Vulkan 1.0 device.
fn identity(
    instance: &ash::Instance,
    physical_device: vk::PhysicalDevice,
    api_version: u32,
) -> ([u8; 16], Option<PciBusInfo>) {
    if vk::api_version_minor(api_version) == 0 && vk::api_version_major(api_version) == 1 {
        return ([0; 16], None);
    }
    // SAFETY: physical_device came from this instance.
    let has_pci_bus_info =
        unsafe { instance.enumerate_device_extension_properties(physical_device) }
            .unwrap_or_default()
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(ash::ext::pci_bus_info::NAME));
    let mut id = vk::PhysicalDeviceIDProperties::default();
    let mut pci = vk::PhysicalDevicePCIBusInfoPropertiesEXT::default();
    let mut properties = vk::PhysicalDeviceProperties2::default().push_next(&mut id);
    if has_pci_bus_info {
        properties = properties.push_next(&mut pci);
    }
    // SAFETY: the chain holds structures the device supports (Vulkan 1.1, the extension
    // only where listed), all alive for the call.
    unsafe { instance.get_physical_device_properties2(physical_device, &mut properties) };
    let pci_bus = has_pci_bus_info.then_some(PciBusInfo {
        domain: pci.pci_domain,
        bus: pci.pci_bus,
        device: pci.pci_device,
        function: pci.pci_function,
    });
    (id.device_uuid, pci_bus)
}

/// Lists the Vulkan devices that the loader finds (for `vkpath devices`).
pub fn list_devices() -> VkResult<Vec<DeviceInfo>> {
    let entry = load_entry()?;
    let instance = create_instance(&entry, None)?;
    let devices = describe_devices(&instance);
    // SAFETY: nothing was created from the instance.
    unsafe { instance.destroy_instance(None) };
    let devices = devices?;
    if devices.is_empty() {
        return Err(VkError::NoDriver("the loader found no device".into()));
    }
    Ok(devices.into_iter().map(|(_, info)| info).collect())
}

/// Picks a device as `ContextOptions::device` and the environment say (one device: the
/// first of a list), with the reason.
fn choose_device(
    devices: &[(vk::PhysicalDevice, DeviceInfo)],
    selector: Option<&str>,
    environment: &DeviceEnvironment,
    require_gpu: bool,
) -> VkResult<(vk::PhysicalDevice, DeviceInfo, String)> {
    let infos: Vec<DeviceInfo> = devices.iter().map(|(_, info)| info.clone()).collect();
    let choice = choose_devices(&infos, selector, environment, require_gpu)?;
    let (physical_device, info) = devices
        .iter()
        .find(|(_, info)| choice.indices.first() == Some(&info.index))
        .ok_or_else(|| VkError::NoComputeDevice(String::new()))?
        .clone();
    Ok((physical_device, info, choice.reason))
}

impl Context {
    /// Loads Vulkan, creates the instance (with validation if asked), picks a device and
    /// creates a logical device with one compute queue.
    pub fn new(options: &ContextOptions) -> VkResult<Arc<Context>> {
        let entry = load_entry()?;
        let validation = if options.validate {
            if !has_validation_layer(&entry)? {
                return Err(VkError::ValidationLayerMissing);
            }
            Some(Box::<ValidationMessages>::default())
        } else {
            None
        };
        let instance = create_instance(&entry, validation.as_deref())?;
        // From here on, a failure must destroy what exists: build a partial context whose
        // Drop does it.
        let messenger = match validation.as_deref() {
            Some(messages) => {
                let debug_utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
                let info = messenger_create_info(messages);
                // SAFETY: `messages` is boxed and owned by the context, which outlives it.
                match unsafe { debug_utils.create_debug_utils_messenger(&info, None) } {
                    Ok(messenger) => Some((debug_utils, messenger)),
                    Err(result) => {
                        unsafe { instance.destroy_instance(None) };
                        return Err(VkError::Call {
                            what: "creating the debug messenger",
                            result,
                        });
                    }
                }
            }
            None => None,
        };
        let destroy_instance =
            |messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>| {
                // SAFETY: no device was created from this instance.
                unsafe {
                    if let Some((debug_utils, messenger)) = messenger {
                        debug_utils.destroy_debug_utils_messenger(messenger, None);
                    }
                    instance.destroy_instance(None);
                }
            };
        let chosen = describe_devices(&instance).and_then(|devices| {
            if devices.is_empty() {
                return Err(VkError::NoDriver("the loader found no device".into()));
            }
            choose_device(
                &devices,
                options.device.as_deref(),
                &DeviceEnvironment::from_process(),
                options.require_gpu,
            )
        });
        let (physical_device, info, reason) = match chosen {
            Ok(chosen) => chosen,
            Err(error) => {
                destroy_instance(messenger);
                return Err(error);
            }
        };
        if options.require_gpu && !info.kind.is_gpu() {
            destroy_instance(messenger);
            return Err(VkError::NotAGpu {
                name: info.name,
                kind: info.kind.to_string(),
            });
        }
        let queue_family_index = info.compute_queue_family.expect("checked by choose_device");
        let priorities = [1.0f32];
        let queue_info = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family_index)
            .queue_priorities(&priorities)];
        // Ray queries where the device offers them (src/vk/ray_query_support.rs); other
        // devices are created exactly as without them.
        let ray_queries = ray_query_support::probe(&instance, physical_device);
        let mut ray_query_features = RayQueryFeatures::enabled();
        let ray_query_extensions = RayQueryFeatures::extension_names();
        let mut device_info = vk::DeviceCreateInfo::default().queue_create_infos(&queue_info);
        if ray_queries.is_available() {
            device_info = device_info
                .enabled_extension_names(&ray_query_extensions)
                .push_next(&mut ray_query_features.acceleration)
                .push_next(&mut ray_query_features.ray_query)
                .push_next(&mut ray_query_features.address);
        }
        // SAFETY: physical_device belongs to instance; the create info outlives the call.
        let device = match unsafe { instance.create_device(physical_device, &device_info, None) } {
            Ok(device) => device,
            Err(result) => {
                destroy_instance(messenger);
                return Err(VkError::Call {
                    what: "creating the logical device",
                    result,
                });
            }
        };
        // SAFETY: the queue family was requested with one queue.
        let queue = unsafe { device.get_device_queue(queue_family_index, 0) };
        let properties = unsafe { instance.get_physical_device_properties(physical_device) };
        let limits = properties.limits;
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device,
            debug_settings: Default::default(),
            buffer_device_address: ray_queries.is_available(),
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(allocator) => allocator,
            Err(source) => {
                unsafe { device.destroy_device(None) };
                destroy_instance(messenger);
                return Err(VkError::Allocation {
                    what: "the memory allocator".into(),
                    device: info.name.clone(),
                    error: source,
                });
            }
        };
        let pipeline_cache = match &options.pipeline_cache {
            Some(store) => {
                let key = PipelineCacheKey::of(&properties);
                match PersistentPipelineCache::create(&device, store.clone(), key) {
                    Ok(cache) => Some(cache),
                    Err(result) => {
                        // SAFETY: nothing else was created from the device but the allocator.
                        drop(allocator);
                        unsafe { device.destroy_device(None) };
                        destroy_instance(messenger);
                        return Err(VkError::Call {
                            what: "creating the pipeline cache",
                            result,
                        });
                    }
                }
            }
            None => None,
        };
        Ok(Arc::new(Context {
            _entry: entry,
            instance,
            messenger,
            validation,
            physical_device,
            info,
            chosen_because: options.chosen_because.clone().unwrap_or(reason),
            limits,
            ray_queries,
            device,
            queue: Mutex::new(queue),
            queue_family_index,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            pipeline_cache,
        }))
    }

    /// The validation layer's message counts, when validation is on.
    pub fn validation_messages(&self) -> Option<&ValidationMessages> {
        self.validation.as_deref()
    }

    /// The size of the device's largest device-local memory heap, in bytes (what one
    /// render's resources must fit in).
    pub fn device_memory_bytes(&self) -> u64 {
        // SAFETY: the physical device belongs to the live instance.
        let properties = unsafe {
            self.instance
                .get_physical_device_memory_properties(self.physical_device)
        };
        properties.memory_heaps[..properties.memory_heap_count as usize]
            .iter()
            .filter(|heap| heap.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|heap| heap.size)
            .max()
            .unwrap_or(0)
    }

    /// The pipeline cache to build pipelines with (null when there is none).
    pub(crate) fn pipeline_cache(&self) -> vk::PipelineCache {
        self.pipeline_cache
            .as_ref()
            .map_or(vk::PipelineCache::null(), |cache| cache.handle)
    }

    /// The store of the pipeline cache, if there is one and it started cold (no data for
    /// this device): to tell it that a build is slow (`PipelineCacheStore::building_slowly`).
    pub(crate) fn cold_pipeline_cache_store(&self) -> Option<&dyn PipelineCacheStore> {
        self.pipeline_cache
            .as_ref()
            .filter(|cache| cache.cold)
            .map(|cache| &*cache.store)
    }

    /// Saves the pipeline cache through its store if a build changed it (after each
    /// pipeline, so that an interrupted process keeps what it built).
    pub(crate) fn pipeline_built(&self) {
        if let Some(cache) = &self.pipeline_cache {
            cache.save_if_changed(&self.device);
        }
    }

    /// What identifies this device's pipeline cache data.
    pub fn pipeline_cache_key(&self) -> PipelineCacheKey {
        // SAFETY: the physical device belongs to the live instance.
        let properties = unsafe {
            self.instance
                .get_physical_device_properties(self.physical_device)
        };
        PipelineCacheKey::of(&properties)
    }

    /// Submits `submits` to the compute queue, signalling `fence`, holding the queue's lock
    /// for the call (so threads sharing the context may submit at once).
    ///
    /// # Safety
    /// As `vkQueueSubmit`: the command buffers are recorded and not pending elsewhere, and
    /// `fence` (if not null) is unsignalled and belongs to this context's device.
    pub unsafe fn submit(
        &self,
        submits: &[vk::SubmitInfo],
        fence: vk::Fence,
    ) -> ash::prelude::VkResult<()> {
        let queue = self
            .queue
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        // SAFETY: the caller's promises, and the lock serializes access to the queue.
        unsafe { self.device.queue_submit(*queue, submits, fence) }
    }

    /// Locks the memory allocator.
    pub(crate) fn allocator(&self) -> MutexGuard<'_, Allocator> {
        // A panic while holding the lock cannot leave the allocator half-updated in a way
        // that matters more than the panic itself.
        self.allocator
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: every resource holds an Arc<Context>, so all of them are gone; the
        // allocator is dropped before the device, the device before the instance.
        unsafe {
            let _ = self.device.device_wait_idle();
            if let Some(cache) = self.pipeline_cache.take() {
                self.device.destroy_pipeline_cache(cache.handle, None);
            }
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((debug_utils, messenger)) = self.messenger.take() {
                debug_utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contexts_may_be_shared_between_threads() {
        fn shared<T: Send + Sync>() {}
        shared::<Context>();
        shared::<Arc<Context>>();
    }

    #[test]
    fn cpu_devices_rank_after_gpus() {
        assert!(DeviceKind::DiscreteGpu.rank() < DeviceKind::Cpu.rank());
        assert!(DeviceKind::IntegratedGpu.rank() < DeviceKind::Cpu.rank());
        assert!(!DeviceKind::Cpu.is_gpu());
    }
}
