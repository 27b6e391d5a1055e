//! A texture sampler, destroyed on drop.

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use super::error::{CallContext, VkError, VkResult};
use super::image::STORAGE_IMAGE_FORMAT;

/// A `VkSampler` with bilinear filtering, no mipmaps and clamp-to-edge addressing on
/// normalized coordinates (OpenGL's `GL_LINEAR` with `GL_CLAMP_TO_EDGE`).
pub struct Sampler {
    context: Arc<Context>,
    /// The sampler handle.
    pub handle: vk::Sampler,
}

impl Sampler {
    /// Creates a linear, clamp-to-edge sampler, after checking that the device filters
    /// `rgba32f` images linearly (an optional feature of that format in Vulkan).
    pub fn linear_clamp(context: &Arc<Context>) -> VkResult<Sampler> {
        // SAFETY: a live physical device of this instance.
        let properties = unsafe {
            context.instance.get_physical_device_format_properties(
                context.physical_device,
                STORAGE_IMAGE_FORMAT,
            )
        };
        if !properties
            .optimal_tiling_features
            .contains(vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR)
        {
            return Err(VkError::Unsupported(format!(
                "{} cannot filter rgba32f images linearly",
                context.info.name
            )));
        }
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .min_lod(0.0)
            .max_lod(0.0);
        // SAFETY: a valid create info on a live device.
        let handle =
            unsafe { context.device.create_sampler(&info, None) }.during("creating a sampler")?;
        Ok(Sampler {
            context: context.clone(),
            handle,
        })
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: users wait for the work that uses the sampler before dropping it.
        unsafe { self.context.device.destroy_sampler(self.handle, None) };
    }
}
