//! `vkpath devices`: lists the Vulkan devices.

/// Arguments of `vkpath devices`.
#[derive(Debug, Clone, clap::Args)]
pub struct DevicesArgs {
    /// Print a JSON array (index, name, type, API version, UUID, vendor ID, PCI address,
    /// ray queries) instead of one line per device.
    #[arg(long)]
    pub json: bool,
}

/// Prints one line per device, or a JSON array.
pub fn run(args: &DevicesArgs) -> anyhow::Result<()> {
    let devices = crate::vk::list_devices()?;
    if args.json {
        let list: Vec<serde_json::Value> = devices
            .iter()
            .map(|device| {
                serde_json::json!({
                    "index": device.index,
                    "name": device.name,
                    // As `render --json` names it (issue 58: "Cpu" here, "cpu" there).
                    "type": device.kind.report_name(),
                    "api_version": device.api_version,
                    "compute": device.compute_queue_family.is_some(),
                    "uuid": crate::vk::format_uuid(&device.uuid),
                    "vendor_id": device.vendor_id,
                    "pci_bus": device.pci_bus.map(|p| format!(
                        "{:04x}:{:02x}:{:02x}.{:x}",
                        p.domain, p.bus, p.device, p.function
                    )),
                    "ray_queries": device.ray_queries,
                    "description": device.to_string(),
                })
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&list)?);
    } else {
        for device in devices {
            println!("{device}");
        }
    }
    Ok(())
}
