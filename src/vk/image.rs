//! A 2D array storage image of rgba32f texels with its view and memory, freed on drop; or,
//! made with `StorageImage::sampled_2d` or `StorageImage::sampled_cube`, a 2D or cube-map
//! one that shaders also sample.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::context::Context;
use super::error::{CallContext, VkError, VkResult};

/// Texel format of every storage image here (matches `rgba32f` in GLSL).
pub const STORAGE_IMAGE_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// An `rgba32f` 2D array image usable as a storage image and as a copy source/destination.
pub struct StorageImage {
    context: Arc<Context>,
    /// The image handle.
    pub handle: vk::Image,
    /// A view of all its layers (`image2DArray` in GLSL; `image2D` and `sampler2D` for an
    /// image made with `sampled_2d`, `samplerCube` for one made with `sampled_cube`).
    pub view: vk::ImageView,
    allocation: Option<Allocation>,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Number of array layers.
    pub layers: u32,
}

impl StorageImage {
    /// Creates the image in device memory, in layout UNDEFINED (transition it before use).
    pub fn new(
        context: &Arc<Context>,
        name: &str,
        width: u32,
        height: u32,
        layers: u32,
    ) -> VkResult<StorageImage> {
        Self::create(
            context,
            name,
            (width, height, layers),
            vk::ImageUsageFlags::empty(),
            vk::ImageViewType::TYPE_2D_ARRAY,
        )
    }

    /// Creates a one-layer image that shaders can also sample (`sampler2D`, through a
    /// combined image sampler in GENERAL layout), with a 2D view, in layout UNDEFINED.
    pub fn sampled_2d(
        context: &Arc<Context>,
        name: &str,
        width: u32,
        height: u32,
    ) -> VkResult<StorageImage> {
        Self::create(
            context,
            name,
            (width, height, 1),
            vk::ImageUsageFlags::SAMPLED,
            vk::ImageViewType::TYPE_2D,
        )
    }

    /// Creates a cube map of six `side` x `side` layers (+X, -X, +Y, -Y, +Z, -Z, as Vulkan
    /// and OpenGL order a cube's faces) that shaders sample (`samplerCube`, through a
    /// combined image sampler in GENERAL layout), with a cube view, in layout UNDEFINED.
    pub fn sampled_cube(context: &Arc<Context>, name: &str, side: u32) -> VkResult<StorageImage> {
        Self::create(
            context,
            name,
            (side, side, 6),
            vk::ImageUsageFlags::SAMPLED,
            vk::ImageViewType::CUBE,
        )
    }

    /// The image of `new`, `sampled_2d` and `sampled_cube`, with `extra_usage` and a view
    /// of `view_type`.
    fn create(
        context: &Arc<Context>,
        name: &str,
        (width, height, layers): (u32, u32, u32),
        extra_usage: vk::ImageUsageFlags,
        view_type: vk::ImageViewType,
    ) -> VkResult<StorageImage> {
        let device = &context.device;
        let flags = if view_type == vk::ImageViewType::CUBE {
            vk::ImageCreateFlags::CUBE_COMPATIBLE
        } else {
            vk::ImageCreateFlags::empty()
        };
        let info = vk::ImageCreateInfo::default()
            .flags(flags)
            .image_type(vk::ImageType::TYPE_2D)
            .format(STORAGE_IMAGE_FORMAT)
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(layers)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(
                vk::ImageUsageFlags::STORAGE
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::TRANSFER_DST
                    | extra_usage,
            )
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: a valid create info on a live device.
        let handle = unsafe { device.create_image(&info, None) }.during("creating an image")?;
        let requirements = unsafe { device.get_image_memory_requirements(handle) };
        let allocation = context.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(allocation) => allocation,
            Err(source) => {
                unsafe { device.destroy_image(handle, None) };
                return Err(VkError::Allocation {
                    what: format!("image '{name}' ({width}x{height}x{layers})"),
                    device: context.info.name.clone(),
                    error: source,
                });
            }
        };
        let view = unsafe {
            device
                .bind_image_memory(handle, allocation.memory(), allocation.offset())
                .and_then(|()| {
                    device.create_image_view(
                        &vk::ImageViewCreateInfo::default()
                            .image(handle)
                            .view_type(view_type)
                            .format(STORAGE_IMAGE_FORMAT)
                            .subresource_range(Self::all_layers(layers)),
                        None,
                    )
                })
        };
        match view {
            Ok(view) => Ok(StorageImage {
                context: context.clone(),
                handle,
                view,
                allocation: Some(allocation),
                width,
                height,
                layers,
            }),
            Err(result) => {
                let _ = context.allocator().free(allocation);
                unsafe { device.destroy_image(handle, None) };
                Err(VkError::Call {
                    what: "binding image memory / creating its view",
                    result,
                })
            }
        }
    }

    /// The subresource range of all layers of the one mip level.
    pub fn all_layers(layers: u32) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange::default()
            .aspect_mask(vk::ImageAspectFlags::COLOR)
            .level_count(1)
            .layer_count(layers)
    }

    /// Size in bytes of all layers, tightly packed.
    pub fn byte_size(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height) * u64::from(self.layers) * 16
    }
}

impl Drop for StorageImage {
    fn drop(&mut self) {
        // SAFETY: users wait for the work that uses the image before dropping it.
        unsafe {
            self.context.device.destroy_image_view(self.view, None);
            self.context.device.destroy_image(self.handle, None);
        }
        if let Some(allocation) = self.allocation.take() {
            let _ = self.context.allocator().free(allocation);
        }
    }
}
