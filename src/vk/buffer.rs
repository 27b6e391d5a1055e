//! A buffer with its memory, freed on drop.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::commands::CommandRunner;
use super::context::Context;
use super::error::{CallContext, VkError, VkResult};

/// A `VkBuffer` and its memory.
pub struct Buffer {
    context: Arc<Context>,
    /// The buffer handle.
    pub handle: vk::Buffer,
    allocation: Option<Allocation>,
    /// Size in bytes.
    pub size: u64,
}

impl Buffer {
    /// Creates a buffer of `size` bytes (at least 1) in memory at `location`.
    pub fn new(
        context: &Arc<Context>,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> VkResult<Buffer> {
        let size = size.max(1);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let device = &context.device;
        // SAFETY: a valid create info on a live device.
        let handle = unsafe { device.create_buffer(&info, None) }.during("creating a buffer")?;
        let requirements = unsafe { device.get_buffer_memory_requirements(handle) };
        let allocation = context.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(allocation) => allocation,
            Err(source) => {
                unsafe { device.destroy_buffer(handle, None) };
                return Err(VkError::Allocation {
                    what: format!("buffer '{name}' ({size} bytes)"),
                    device: context.info.name.clone(),
                    error: source,
                });
            }
        };
        // SAFETY: the allocation satisfies the buffer's requirements and is not bound yet.
        if let Err(result) =
            unsafe { device.bind_buffer_memory(handle, allocation.memory(), allocation.offset()) }
        {
            let _ = context.allocator().free(allocation);
            unsafe { device.destroy_buffer(handle, None) };
            return Err(VkError::Call {
                what: "binding buffer memory",
                result,
            });
        }
        Ok(Buffer {
            context: context.clone(),
            handle,
            allocation: Some(allocation),
            size,
        })
    }

    /// A host-visible buffer holding `data`.
    pub fn with_data<T: bytemuck::Pod>(
        context: &Arc<Context>,
        name: &str,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> VkResult<Buffer> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mut buffer = Buffer::new(
            context,
            name,
            bytes.len() as u64,
            usage,
            MemoryLocation::CpuToGpu,
        )?;
        buffer.write(bytes);
        Ok(buffer)
    }

    /// The mapped bytes of a host-visible buffer.
    fn mapped(&self) -> &[u8] {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .expect("only host-visible buffers are mapped")
    }

    /// Copies `bytes` to the start of a host-visible buffer.
    pub fn write(&mut self, bytes: &[u8]) {
        let mapped = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .expect("only host-visible buffers are written");
        mapped[..bytes.len()].copy_from_slice(bytes);
    }

    /// The contents of a host-visible buffer as `T`s (copied, so any alignment works).
    pub fn read<T: bytemuck::Pod>(&self) -> Vec<T> {
        let bytes = &self.mapped()[..self.size as usize];
        bytemuck::pod_collect_to_vec(bytes)
    }
}

impl Buffer {
    /// A device-local buffer of `usage` filled with `bytes` through a staging buffer; the
    /// copy has finished when this returns.
    pub fn device_local_with_data(
        context: &Arc<Context>,
        commands: &CommandRunner,
        name: &str,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> VkResult<Buffer> {
        let staging = Buffer::with_data(
            context,
            "staging",
            bytes,
            vk::BufferUsageFlags::TRANSFER_SRC,
        )?;
        let buffer = Buffer::new(
            context,
            name,
            bytes.len() as u64,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        commands.run(|recorder| recorder.copy_buffer(&staging, &buffer, bytes.len() as u64))?;
        Ok(buffer)
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        if let Some(allocation) = self.allocation.take() {
            let _ = self.context.allocator().free(allocation);
        }
        // SAFETY: users wait for the work that uses the buffer before dropping it.
        unsafe { self.context.device.destroy_buffer(self.handle, None) };
    }
}

/// A view of a buffer as an array of texels (a uniform texel buffer), destroyed on drop.
/// Shaders read it with `texelFetch` on a `textureBuffer`/`utextureBuffer`.
pub struct TexelBufferView {
    context: Arc<Context>,
    /// The view handle.
    pub handle: vk::BufferView,
    /// The viewed buffer, kept alive as long as the view.
    _buffer: Buffer,
}

impl TexelBufferView {
    /// Views all of `buffer` as RGBA32_UINT texels (16 bytes each), after checking that the
    /// device allows that many; `what` names the data in the error.
    pub fn rgba32_uint(
        context: &Arc<Context>,
        buffer: Buffer,
        what: &str,
    ) -> VkResult<TexelBufferView> {
        TexelBufferView::within_limit(context, buffer, what, 16, vk::Format::R32G32B32A32_UINT)
    }

    /// Views all of `buffer` as R32_UINT texels (one 32-bit word each, read as the `x` of a
    /// `utextureBuffer`'s `uvec4`), after checking that the device allows that many; `what`
    /// names the data in the error. Uniform texel buffers of this format are mandatory in
    /// Vulkan.
    pub fn r32_uint(
        context: &Arc<Context>,
        buffer: Buffer,
        what: &str,
    ) -> VkResult<TexelBufferView> {
        TexelBufferView::within_limit(context, buffer, what, 4, vk::Format::R32_UINT)
    }

    /// A device-local uniform texel buffer filled with `words` through a staging buffer,
    /// viewed as R32_UINT texels; `name` labels the buffer and names the data in the error
    /// (`r32_uint`).
    pub fn upload_r32_uint(
        context: &Arc<Context>,
        commands: &CommandRunner,
        name: &str,
        words: &[u32],
    ) -> VkResult<TexelBufferView> {
        let buffer = Buffer::device_local_with_data(
            context,
            commands,
            name,
            bytemuck::cast_slice(words),
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
        )?;
        TexelBufferView::r32_uint(context, buffer, &format!("scene's {name}"))
    }

    /// Views all of `buffer` as texels of `format`, `texel_bytes` each, after checking that
    /// the device allows that many; `what` names the data in the error.
    fn within_limit(
        context: &Arc<Context>,
        buffer: Buffer,
        what: &str,
        texel_bytes: u64,
        format: vk::Format,
    ) -> VkResult<TexelBufferView> {
        let texels = buffer.size / texel_bytes;
        let limit = u64::from(context.limits.max_texel_buffer_elements);
        if texels > limit {
            return Err(VkError::TooLarge(format!(
                "the {what} need {texels} texels, more than this device's texel-buffer limit of {limit}"
            )));
        }
        TexelBufferView::new(context, buffer, format)
    }

    /// A device-local uniform texel buffer filled with `bytes` (whole 16-byte texels)
    /// through a staging buffer, viewed as RGBA32_UINT texels; `name` labels the buffer and
    /// names the data in the error (`rgba32_uint`).
    pub fn upload_rgba32_uint(
        context: &Arc<Context>,
        commands: &CommandRunner,
        name: &str,
        bytes: &[u8],
    ) -> VkResult<TexelBufferView> {
        let buffer = Buffer::device_local_with_data(
            context,
            commands,
            name,
            bytes,
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
        )?;
        TexelBufferView::rgba32_uint(context, buffer, &format!("scene's {name}"))
    }

    /// Bytes of the viewed buffer.
    pub fn byte_size(&self) -> u64 {
        self._buffer.size
    }

    /// Views all of `buffer` as RGBA8_UINT texels (4 bytes each, read as `uvec4` in 0..=255
    /// by a `utextureBuffer`), after checking that the device allows that many; `what` names
    /// the data in the error. Uniform texel buffers of this format are mandatory in Vulkan.
    pub fn rgba8_uint(
        context: &Arc<Context>,
        buffer: Buffer,
        what: &str,
    ) -> VkResult<TexelBufferView> {
        TexelBufferView::within_limit(context, buffer, what, 4, vk::Format::R8G8B8A8_UINT)
    }

    /// Views all of `buffer` (created with `UNIFORM_TEXEL_BUFFER` usage) as texels of `format`.
    pub fn new(
        context: &Arc<Context>,
        buffer: Buffer,
        format: vk::Format,
    ) -> VkResult<TexelBufferView> {
        let info = vk::BufferViewCreateInfo::default()
            .buffer(buffer.handle)
            .format(format)
            .offset(0)
            .range(vk::WHOLE_SIZE);
        // SAFETY: a live buffer with texel-buffer usage on a live device.
        let handle = unsafe { context.device.create_buffer_view(&info, None) }
            .during("creating a texel buffer view")?;
        Ok(TexelBufferView {
            context: context.clone(),
            handle,
            _buffer: buffer,
        })
    }
}

impl Drop for TexelBufferView {
    fn drop(&mut self) {
        // SAFETY: users wait for the work that uses the view before dropping it.
        unsafe { self.context.device.destroy_buffer_view(self.handle, None) };
    }
}
