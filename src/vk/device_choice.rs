//! Which device(s) to render on: a pure function of the devices (as `describe_devices`
//! gathers them), the `--device` value and the environment (`VKPATH_DEVICE`,
//! `CUDA_VISIBLE_DEVICES`, `CUDA_DEVICE_ORDER`), so that every rule is unit-tested without a
//! GPU. The Vulkan side only gathers the facts.
//!
//! Precedence: `--device`, then `VKPATH_DEVICE`, then `CUDA_VISIBLE_DEVICES` (only where the
//! machine has NVIDIA devices: it is CUDA's variable, and Slurm, Ray and Dask hand a task its
//! GPU through it), then the best-ranked device. `NVIDIA_VISIBLE_DEVICES` is never read: inside a
//! container the runtime has already applied it.

use super::context::DeviceInfo;
use super::error::VkError;

/// PCI's vendor ID of NVIDIA.
pub const NVIDIA_VENDOR_ID: u32 = 0x10de;

/// Where a device sits on the PCI bus (`VK_EXT_pci_bus_info`), the order CUDA follows under
/// `CUDA_DEVICE_ORDER=PCI_BUS_ID`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct PciBusInfo {
    /// PCI domain.
    pub domain: u32,
    /// Bus number.
    pub bus: u32,
    /// Device number.
    pub device: u32,
    /// Function number.
    pub function: u32,
}

/// Formats a device UUID as NVIDIA does (`GPU-xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx`, lower
/// case), the form `nvidia-smi -L` and `CUDA_VISIBLE_DEVICES` use.
pub fn format_uuid(uuid: &[u8; 16]) -> String {
    let hex: String = uuid.iter().map(|b| format!("{b:02x}")).collect();
    format!(
        "GPU-{}-{}-{}-{}-{}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

/// The environment variables that choose a device, read once (`from_process`) so that the
/// choice itself stays a pure function.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DeviceEnvironment {
    /// `VKPATH_DEVICE`: what `--device` takes, used when `--device` is not given.
    pub vkpath_device: Option<String>,
    /// `CUDA_VISIBLE_DEVICES`: CUDA indices or `GPU-` UUIDs, comma-separated.
    pub cuda_visible_devices: Option<String>,
    /// `CUDA_DEVICE_ORDER`: `PCI_BUS_ID` makes CUDA's indices reproducible.
    pub cuda_device_order: Option<String>,
}

impl DeviceEnvironment {
    /// Reads the variables of this process.
    pub fn from_process() -> DeviceEnvironment {
        let read = |name| std::env::var(name).ok();
        DeviceEnvironment {
            vkpath_device: read("VKPATH_DEVICE").filter(|v| !v.trim().is_empty()),
            cuda_visible_devices: read("CUDA_VISIBLE_DEVICES"),
            cuda_device_order: read("CUDA_DEVICE_ORDER"),
        }
    }
}

/// What `choose_devices` decided.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeviceChoice {
    /// Indices into the device list (as `vkpath devices` lists them), in the order to use;
    /// one unless the selector was `all` or a comma-separated list.
    pub indices: Vec<usize>,
    /// Whether the selector asked for several devices (`all`, `A,B`), even if one was found.
    pub several: bool,
    /// Why, in words, for the device line and `--json` (e.g. `VKPATH_DEVICE=GPU-1a2b`).
    pub reason: String,
}

/// Picks the device(s): `device` is `--device`'s value, `environment` the variables,
/// `require_gpu` whether `--require-gpu` was given (only to word the error of a task that
/// `CUDA_VISIBLE_DEVICES` gives no GPU). Devices without a compute queue are never taken.
pub fn choose_devices(
    devices: &[DeviceInfo],
    device: Option<&str>,
    environment: &DeviceEnvironment,
    require_gpu: bool,
) -> Result<DeviceChoice, VkError> {
    let choice = choose_unchecked(devices, device, environment, require_gpu)?;
    if choice.indices.iter().any(|&i| {
        devices
            .get(i)
            .is_none_or(|d| d.compute_queue_family.is_none())
    }) {
        return Err(VkError::NoComputeDevice(list(devices)));
    }
    Ok(choice)
}

/// `choose_devices` before checking that each device has a compute queue.
fn choose_unchecked(
    devices: &[DeviceInfo],
    device: Option<&str>,
    environment: &DeviceEnvironment,
    require_gpu: bool,
) -> Result<DeviceChoice, VkError> {
    let has_nvidia = devices.iter().any(|d| d.vendor_id == NVIDIA_VENDOR_ID);
    let cuda = environment.cuda_visible_devices.as_deref();
    // The CUDA variable restricts what `all` and the default see, on NVIDIA machines only;
    // read only there, so that a list vkpath cannot map does not stop a `--device 1`.
    let visible = || match cuda {
        Some(value) if has_nvidia => cuda_visible(devices, value, environment).map(Some),
        _ => Ok(None),
    };
    let cuda_note = match cuda {
        Some(value) if !has_nvidia && !hides_all(value) => {
            format!("; CUDA_VISIBLE_DEVICES={value} ignored: no NVIDIA device")
        }
        Some(value) if has_nvidia => format!("; CUDA_VISIBLE_DEVICES={value} not applied"),
        _ => String::new(),
    };
    let named = match device {
        Some(selector) => Some((selector, format!("--device {selector}"))),
        None => environment
            .vkpath_device
            .as_deref()
            .map(|selector| (selector, format!("VKPATH_DEVICE={selector}"))),
    };
    if let Some((selector, source)) = named {
        let selector = selector.trim();
        if selector.eq_ignore_ascii_case("all") {
            let (indices, reason) = match visible()? {
                Some(listed) => (
                    listed,
                    format!(
                        "{source}: the devices of CUDA_VISIBLE_DEVICES={}",
                        cuda.unwrap_or_default()
                    ),
                ),
                None => (
                    devices
                        .iter()
                        .filter(|d| d.compute_queue_family.is_some())
                        .map(|d| d.index)
                        .collect(),
                    format!("{source}{cuda_note}"),
                ),
            };
            if indices.is_empty() {
                return Err(VkError::NoComputeDevice(list(devices)));
            }
            return Ok(DeviceChoice {
                indices,
                several: true,
                reason,
            });
        }
        let several = selector.contains(',');
        // A wrong VKPATH_DEVICE is named as such: the command line shows no --device.
        let indices = selector
            .split(',')
            .map(|part| find_one(devices, part.trim()))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|error| match device {
                Some(_) => error,
                None => VkError::Choice(format!("{source}: {error}")),
            })?;
        return Ok(DeviceChoice {
            indices,
            several,
            reason: format!("{source}{cuda_note}"),
        });
    }
    if let (Some(listed), Some(value)) = (visible()?, cuda) {
        if listed.is_empty() {
            return no_gpu_for_this_task(devices, value, require_gpu);
        }
        return Ok(DeviceChoice {
            indices: vec![listed[0]],
            several: false,
            reason: format!("CUDA_VISIBLE_DEVICES={value}"),
        });
    }
    let best = devices
        .iter()
        .filter(|d| d.compute_queue_family.is_some())
        .min_by_key(|d| (d.kind.rank(), d.index))
        .ok_or_else(|| VkError::NoComputeDevice(list(devices)))?;
    Ok(DeviceChoice {
        indices: vec![best.index],
        several: false,
        reason: format!(
            "default (first of: discrete GPU, integrated GPU, virtual GPU, CPU device){cuda_note}"
        ),
    })
}

/// Whether a `CUDA_VISIBLE_DEVICES` value gives no device at all (empty, or `-1` first).
fn hides_all(value: &str) -> bool {
    let first = value.split(',').next().unwrap_or("").trim();
    first.is_empty() || first == "-1"
}

/// `CUDA_VISIBLE_DEVICES=""` or `-1` on an NVIDIA machine: the task was given no GPU, so
/// only a CPU device may be used.
fn no_gpu_for_this_task(
    devices: &[DeviceInfo],
    value: &str,
    require_gpu: bool,
) -> Result<DeviceChoice, VkError> {
    if require_gpu {
        return Err(VkError::Choice(format!(
            "a GPU was required (--require-gpu), but CUDA_VISIBLE_DEVICES='{value}' gives this task no GPU"
        )));
    }
    let cpu = devices
        .iter()
        .find(|d| !d.kind.is_gpu() && d.compute_queue_family.is_some())
        .ok_or_else(|| {
            VkError::Choice(format!(
                "CUDA_VISIBLE_DEVICES='{value}' gives this task no GPU and there is no CPU device (install mesa-vulkan-drivers for lavapipe)"
            ))
        })?;
    Ok(DeviceChoice {
        indices: vec![cpu.index],
        several: false,
        reason: format!("CUDA_VISIBLE_DEVICES='{value}' gives this task no GPU"),
    })
}

/// The devices `CUDA_VISIBLE_DEVICES` lists, in its order, as indices of `devices`. As CUDA
/// does, the list ends at an empty entry or `-1`; every entry before must name a device.
fn cuda_visible(
    devices: &[DeviceInfo],
    value: &str,
    environment: &DeviceEnvironment,
) -> Result<Vec<usize>, VkError> {
    let nvidia: Vec<&DeviceInfo> = devices
        .iter()
        .filter(|d| d.vendor_id == NVIDIA_VENDOR_ID)
        .collect();
    let mut listed = Vec::new();
    for entry in value.split(',').map(str::trim) {
        if entry.is_empty() || entry == "-1" {
            break;
        }
        let index = if entry.len() >= 4 && entry[..4].eq_ignore_ascii_case("GPU-") {
            nvidia
                .iter()
                .find(|d| format_uuid(&d.uuid).eq_ignore_ascii_case(entry))
                .map(|d| d.index)
                .ok_or_else(|| VkError::DeviceNotFound {
                    selector: format!("CUDA_VISIBLE_DEVICES entry {entry}"),
                    available: list(devices),
                })?
        } else if entry.len() >= 4 && entry[..4].eq_ignore_ascii_case("MIG-") {
            return Err(VkError::Choice(format!(
                "CUDA_VISIBLE_DEVICES={value} names a MIG instance ({entry}), which Vulkan cannot use; give the task a whole GPU"
            )));
        } else {
            let cuda_index: usize = entry.parse().map_err(|_| {
                VkError::Choice(format!(
                    "CUDA_VISIBLE_DEVICES={value}: '{entry}' is neither a CUDA index nor a GPU- UUID"
                ))
            })?;
            cuda_index_to_device(&nvidia, cuda_index, value, environment)?
        };
        listed.push(index);
    }
    Ok(listed)
}

/// The device of CUDA index `cuda_index`: reproducible with one NVIDIA device, or with
/// `CUDA_DEVICE_ORDER=PCI_BUS_ID` and every NVIDIA device's PCI address; CUDA's default
/// order (fastest first) is CUDA's own heuristic, which vkpath does not guess.
fn cuda_index_to_device(
    nvidia: &[&DeviceInfo],
    cuda_index: usize,
    value: &str,
    environment: &DeviceEnvironment,
) -> Result<usize, VkError> {
    let out_of_range = || {
        VkError::Choice(format!(
            "CUDA_VISIBLE_DEVICES={value}: CUDA index {cuda_index} is past the {} NVIDIA device(s) Vulkan sees",
            nvidia.len()
        ))
    };
    if nvidia.len() == 1 {
        return if cuda_index == 0 {
            Ok(nvidia[0].index)
        } else {
            Err(out_of_range())
        };
    }
    let pci_order = environment
        .cuda_device_order
        .as_deref()
        .is_some_and(|o| o.trim() == "PCI_BUS_ID");
    let needs_uuids = |why: &str| {
        VkError::Choice(format!(
            "CUDA_VISIBLE_DEVICES={value} gives CUDA indices, which vkpath can only map to Vulkan devices {why}; list UUIDs instead (GPU-..., as `vkpath devices` or `nvidia-smi -L` print them)"
        ))
    };
    if !pci_order {
        return Err(needs_uuids("with CUDA_DEVICE_ORDER=PCI_BUS_ID"));
    }
    let mut by_bus: Vec<(PciBusInfo, usize)> = Vec::new();
    for device in nvidia {
        match device.pci_bus {
            Some(bus) => by_bus.push((bus, device.index)),
            None => {
                return Err(needs_uuids(
                    "through VK_EXT_pci_bus_info, which the driver lacks",
                ))
            }
        }
    }
    by_bus.sort();
    by_bus
        .get(cuda_index)
        .map(|&(_, index)| index)
        .ok_or_else(out_of_range)
}

/// One device named by `selector`: a `GPU-` UUID or a unique prefix of one, an index, or a
/// case-insensitive part of a name (the first device whose name contains it).
fn find_one(devices: &[DeviceInfo], selector: &str) -> Result<usize, VkError> {
    let not_found = || VkError::DeviceNotFound {
        selector: selector.to_string(),
        available: list(devices),
    };
    if selector.len() >= 4 && selector[..4].eq_ignore_ascii_case("GPU-") {
        let needle = selector.to_ascii_lowercase();
        let matching: Vec<&DeviceInfo> = devices
            .iter()
            .filter(|d| {
                format_uuid(&d.uuid)
                    .to_ascii_lowercase()
                    .starts_with(&needle)
            })
            .collect();
        return match matching.as_slice() {
            [one] => Ok(one.index),
            [] => Err(not_found()),
            _ => Err(VkError::Choice(format!(
                "the UUID prefix '{selector}' matches {} devices ({}); give more of it",
                matching.len(),
                matching
                    .iter()
                    .map(|d| format!("{} {}", d.index, d.name))
                    .collect::<Vec<_>>()
                    .join(", ")
            ))),
        };
    }
    if let Ok(index) = selector.parse::<usize>() {
        if let Some(device) = devices.iter().find(|d| d.index == index) {
            return Ok(device.index);
        }
    }
    // A part of a name must name one device: two lavapipes (two ICDs) are told apart by
    // index or UUID, never by whichever comes first. A whole name, given exactly, wins.
    let needle = selector.to_lowercase();
    let matching: Vec<&DeviceInfo> = devices
        .iter()
        .filter(|d| !needle.is_empty() && d.name.to_lowercase().contains(&needle))
        .collect();
    let exact: Vec<&DeviceInfo> = matching
        .iter()
        .copied()
        .filter(|d| d.name.to_lowercase() == needle)
        .collect();
    match (matching.as_slice(), exact.as_slice()) {
        ([one], _) | (_, [one]) => Ok(one.index),
        ([], _) => Err(not_found()),
        _ => Err(VkError::Choice(format!(
            "'{selector}' matches {} devices ({}); give its index or UUID (`vkpath devices` lists them)",
            matching.len(),
            matching
                .iter()
                .map(|d| format!("{} {} {}", d.index, d.name, format_uuid(&d.uuid)))
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

/// The devices, "0 NAME, 1 NAME", for error messages.
fn list(devices: &[DeviceInfo]) -> String {
    devices
        .iter()
        .map(|d| format!("{} {} {}", d.index, d.name, format_uuid(&d.uuid)))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests;
