//! `vkpath devices`: lists the Vulkan devices.

/// Prints one line per device.
pub fn run() -> anyhow::Result<()> {
    for device in crate::vk::list_devices()? {
        println!("{device}");
    }
    Ok(())
}
