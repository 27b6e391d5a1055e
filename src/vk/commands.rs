//! Recording and submitting command buffers on the compute queue, one batch at a time. The
//! rest of vkpath records work only through `Recorder`, whose methods are safe: every
//! resource they take is borrowed for the recording, and `CommandRunner::run` waits for the
//! submission before the borrows end.

use std::sync::Arc;

use ash::vk;

use super::buffer::Buffer;
use super::context::Context;
use super::error::{CallContext, VkError, VkResult};
use super::image::StorageImage;
use super::pipeline::{ComputePipeline, DescriptorSet};

/// How long a submitted batch may run before we give up waiting (seconds). Generous: a
/// frame on lavapipe with a large scene can take long, but a hang must not wait forever.
const SUBMIT_TIMEOUT_SECONDS: u64 = 600;
/// How long dropping a runner waits for work that timed out before it leaks the pool and
/// fence instead (destroying them while the device may still use them is not allowed, and
/// waiting for a hung device has no end).
const DROP_WAIT_SECONDS: u64 = 10;

/// Fault injection for tests: `VKPATH_INJECT_FAULT=KIND:N` makes submission N (from 1, over
/// the whole process) fail as KIND would: `device-lost`, `out-of-memory` or `fence-timeout`.
/// A lost device stays lost, as a real one does: every later submission (a read-back
/// included) fails too; the other two fail once.
const FAULT_VARIABLE: &str = "VKPATH_INJECT_FAULT";
/// Submissions so far (for fault injection).
static SUBMISSIONS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// The injected fault for this submission, if any.
fn injected_fault(device: &str) -> Option<VkError> {
    let spec = std::env::var(FAULT_VARIABLE).ok()?;
    let (kind, at) = spec.split_once(':')?;
    let at: u64 = at.parse().ok()?;
    let count = SUBMISSIONS.load(std::sync::atomic::Ordering::SeqCst);
    let lost_for_good = kind == "device-lost" && count > at;
    if count != at && !lost_for_good {
        return None;
    }
    let device = device.to_string();
    match kind {
        "device-lost" => Some(VkError::DeviceLost(device)),
        "out-of-memory" => Some(VkError::Allocation {
            what: "memory for a frame (injected fault)".into(),
            device,
            error: gpu_allocator::AllocationError::OutOfMemory,
        }),
        "fence-timeout" => Some(VkError::Timeout {
            device,
            seconds: SUBMIT_TIMEOUT_SECONDS,
        }),
        _ => None,
    }
}

/// A command pool with one reusable command buffer and a fence. `Send` but not `Sync`:
/// Vulkan requires a command pool to be externally synchronized, so one thread at a time
/// records into it (`run` takes `&self`, and the `Cell` keeps the type from being shared):
///
/// ```compile_fail
/// fn shared<T: Sync>() {}
/// shared::<vkpath::vk::CommandRunner>();
/// ```
///
/// ```
/// fn movable<T: Send>() {}
/// movable::<vkpath::vk::CommandRunner>();
/// movable::<vkpath::Renderer>();
/// ```
pub struct CommandRunner {
    context: Arc<Context>,
    pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
    /// Whether a submission did not finish in time (dropping then waits only so long).
    timed_out: std::cell::Cell<bool>,
}

impl CommandRunner {
    /// Creates the pool, command buffer and fence on the context's compute queue family.
    pub fn new(context: &Arc<Context>) -> VkResult<CommandRunner> {
        let device = &context.device;
        let mut runner = CommandRunner {
            context: context.clone(),
            pool: vk::CommandPool::null(),
            command_buffer: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            timed_out: std::cell::Cell::new(false),
        };
        // SAFETY: valid create infos; on error, Drop destroys what exists.
        unsafe {
            runner.pool = device
                .create_command_pool(
                    &vk::CommandPoolCreateInfo::default()
                        .queue_family_index(context.queue_family_index)
                        .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER),
                    None,
                )
                .during("creating a command pool")?;
            runner.command_buffer = device
                .allocate_command_buffers(
                    &vk::CommandBufferAllocateInfo::default()
                        .command_pool(runner.pool)
                        .level(vk::CommandBufferLevel::PRIMARY)
                        .command_buffer_count(1),
                )
                .during("allocating a command buffer")?[0];
            runner.fence = device
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .during("creating a fence")?;
        }
        Ok(runner)
    }

    /// Records commands with `record`, submits them and waits until they have finished.
    pub fn run(&self, record: impl FnOnce(&mut Recorder)) -> VkResult<()> {
        let device = &self.context.device;
        let command_buffer = self.command_buffer;
        // SAFETY: the previous submission has finished (we always wait), so the buffer and
        // fence can be reset and reused.
        unsafe {
            device
                .reset_command_buffer(command_buffer, vk::CommandBufferResetFlags::empty())
                .during("resetting a command buffer")?;
            device
                .begin_command_buffer(
                    command_buffer,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
                .during("beginning a command buffer")?;
            record(&mut Recorder {
                device,
                command_buffer,
            });
            device
                .end_command_buffer(command_buffer)
                .during("recording commands")?;
            let command_buffers = [command_buffer];
            let submit = [vk::SubmitInfo::default().command_buffers(&command_buffers)];
            device
                .reset_fences(&[self.fence])
                .during("resetting a fence")?;
            let name = &self.context.info.name;
            let lost = |result| match result {
                vk::Result::ERROR_DEVICE_LOST => VkError::DeviceLost(name.clone()),
                result => VkError::Call {
                    what: "submitting commands",
                    result,
                },
            };
            self.context.submit(&submit, self.fence).map_err(lost)?;
            let waited =
                device.wait_for_fences(&[self.fence], true, SUBMIT_TIMEOUT_SECONDS * 1_000_000_000);
            SUBMISSIONS.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            if let Some(fault) = injected_fault(name) {
                return Err(fault);
            }
            match waited {
                Ok(()) => Ok(()),
                Err(vk::Result::TIMEOUT) => {
                    self.timed_out.set(true);
                    Err(VkError::Timeout {
                        device: name.clone(),
                        seconds: SUBMIT_TIMEOUT_SECONDS,
                    })
                }
                Err(result) => Err(lost(result)),
            }
        }
    }
}

impl Drop for CommandRunner {
    fn drop(&mut self) {
        // SAFETY: run() waits for its submission, so nothing is pending, unless it timed
        // out: then wait a bounded while, and leak the pool and fence if the device still
        // has not finished (destroying them in use is not allowed; a hung device never
        // finishes).
        unsafe {
            let device = &self.context.device;
            if self.timed_out.get() {
                let done =
                    device.wait_for_fences(&[self.fence], true, DROP_WAIT_SECONDS * 1_000_000_000);
                if done.is_err() {
                    return;
                }
            }
            device.destroy_fence(self.fence, None);
            device.destroy_command_pool(self.pool, None);
        }
    }
}

/// Records commands into the command buffer of one `CommandRunner::run`.
pub struct Recorder<'a> {
    device: &'a ash::Device,
    command_buffer: vk::CommandBuffer,
}

impl Recorder<'_> {
    /// The command buffer being recorded, for commands of extensions that this file does not
    /// wrap (`crate::vk::acceleration_structure`'s builds).
    pub(crate) fn command_buffer(&self) -> vk::CommandBuffer {
        self.command_buffer
    }

    /// Binds `pipeline` for compute dispatches, with `set` as its set 0.
    pub fn bind(&mut self, pipeline: &ComputePipeline, set: &DescriptorSet) {
        // SAFETY: the command buffer is recording; run() waits for the submission while the
        // pipeline and set are borrowed by the caller.
        unsafe {
            self.device.cmd_bind_pipeline(
                self.command_buffer,
                vk::PipelineBindPoint::COMPUTE,
                pipeline.pipeline,
            );
            self.device.cmd_bind_descriptor_sets(
                self.command_buffer,
                vk::PipelineBindPoint::COMPUTE,
                pipeline.layout,
                0,
                &[set.set],
                &[],
            );
        }
    }

    /// Sets the push constants of `pipeline` (its whole range) to `constants`.
    pub fn push_constants<T: bytemuck::Pod>(&mut self, pipeline: &ComputePipeline, constants: &T) {
        // SAFETY: the command buffer is recording; the pipeline layout is alive.
        unsafe {
            self.device.cmd_push_constants(
                self.command_buffer,
                pipeline.layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::bytes_of(constants),
            );
        }
    }

    /// Dispatches the bound `pipeline` over `invocations` (x, y, z): as many workgroups of
    /// its size (read from its SPIR-V) as cover them.
    pub fn dispatch(&mut self, pipeline: &ComputePipeline, invocations: [u32; 3]) {
        let size = pipeline.workgroup_size();
        let groups: Vec<u32> = (0..3)
            .map(|i| invocations[i].div_ceil(size[i].max(1)))
            .collect();
        // SAFETY: the command buffer is recording with a compute pipeline bound.
        unsafe {
            self.device
                .cmd_dispatch(self.command_buffer, groups[0], groups[1], groups[2]);
        }
    }

    /// Makes all earlier compute-shader and transfer writes visible to later compute
    /// shaders and transfers (the only synchronisation a batch of frames needs).
    pub fn compute_barrier(&mut self) {
        full_compute_barrier(self.device, self.command_buffer);
    }

    /// Makes all earlier compute-shader and transfer writes visible to the host, which reads
    /// buffers back after the submission's fence.
    pub fn host_read_barrier(&mut self) {
        let barrier = vk::MemoryBarrier::default()
            .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
            .dst_access_mask(vk::AccessFlags::HOST_READ);
        // SAFETY: recording into a command buffer in the recording state.
        unsafe {
            self.device.cmd_pipeline_barrier(
                self.command_buffer,
                vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::HOST,
                vk::DependencyFlags::empty(),
                &[barrier],
                &[],
                &[],
            );
        }
    }

    /// Copies the first `size` bytes of `from` to `to`, then a compute barrier.
    pub fn copy_buffer(&mut self, from: &Buffer, to: &Buffer, size: u64) {
        // SAFETY: both buffers are alive and at least `size` bytes (Buffer sizes are >= 1).
        unsafe {
            self.device.cmd_copy_buffer(
                self.command_buffer,
                from.handle,
                to.handle,
                &[vk::BufferCopy {
                    src_offset: 0,
                    dst_offset: 0,
                    size: size.clamp(1, from.size.min(to.size)),
                }],
            );
        }
        self.compute_barrier();
    }

    /// Fills all of `buffer` (created with `TRANSFER_DST` usage) with the word `value`, then
    /// a compute barrier.
    pub fn fill_buffer(&mut self, buffer: &Buffer, value: u32) {
        // SAFETY: the buffer is alive; WHOLE_SIZE fills it to its last whole word.
        unsafe {
            self.device.cmd_fill_buffer(
                self.command_buffer,
                buffer.handle,
                0,
                vk::WHOLE_SIZE,
                value,
            );
        }
        self.compute_barrier();
    }

    /// Moves a new image from UNDEFINED to GENERAL and clears every layer to zero, then a
    /// compute barrier.
    pub fn clear_storage_image(&mut self, image: &StorageImage) {
        self.set_layout(
            image,
            (
                vk::ImageLayout::UNDEFINED,
                vk::AccessFlags::empty(),
                vk::PipelineStageFlags::TOP_OF_PIPE,
            ),
            (
                vk::ImageLayout::GENERAL,
                vk::AccessFlags::TRANSFER_WRITE,
                vk::PipelineStageFlags::TRANSFER,
            ),
        );
        // SAFETY: the image is alive and in GENERAL.
        unsafe {
            self.device.cmd_clear_color_image(
                self.command_buffer,
                image.handle,
                vk::ImageLayout::GENERAL,
                &vk::ClearColorValue { float32: [0.0; 4] },
                &[StorageImage::all_layers(image.layers)],
            );
        }
        self.compute_barrier();
    }

    /// Copies every layer of a storage image in GENERAL (written by compute shaders) to
    /// `buffer`, layer after layer, leaves the image in GENERAL, and makes the copy visible
    /// to the host.
    pub fn copy_image_to_buffer(&mut self, image: &StorageImage, buffer: &Buffer) {
        let general = (
            vk::ImageLayout::GENERAL,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
        );
        let source = (
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            vk::AccessFlags::TRANSFER_READ,
            vk::PipelineStageFlags::TRANSFER,
        );
        self.set_layout(image, general, source);
        let region = whole_image(image);
        // SAFETY: the image is in TRANSFER_SRC_OPTIMAL; callers size the buffer with
        // StorageImage::byte_size().
        unsafe {
            self.device.cmd_copy_image_to_buffer(
                self.command_buffer,
                image.handle,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer.handle,
                &[region],
            );
        }
        self.set_layout(image, source, general);
        self.host_read_barrier();
    }

    /// Copies `buffer` (every layer of the image, layer after layer, as
    /// `copy_image_to_buffer` writes them) into a storage image in GENERAL and leaves it in
    /// GENERAL, visible to later compute shaders.
    pub fn copy_buffer_to_image(&mut self, buffer: &Buffer, image: &StorageImage) {
        let general = (
            vk::ImageLayout::GENERAL,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
            vk::PipelineStageFlags::COMPUTE_SHADER,
        );
        let destination = (
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            vk::AccessFlags::TRANSFER_WRITE,
            vk::PipelineStageFlags::TRANSFER,
        );
        self.set_layout(image, general, destination);
        let region = whole_image(image);
        // SAFETY: the image is in TRANSFER_DST_OPTIMAL; callers size the buffer with
        // StorageImage::byte_size().
        unsafe {
            self.device.cmd_copy_buffer_to_image(
                self.command_buffer,
                buffer.handle,
                image.handle,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            );
        }
        self.set_layout(image, destination, general);
    }

    /// Records a barrier that moves all layers of `image` from one use to another.
    fn set_layout(&mut self, image: &StorageImage, from: LayoutUse, to: LayoutUse) {
        let barrier = vk::ImageMemoryBarrier::default()
            .src_access_mask(from.1)
            .dst_access_mask(to.1)
            .old_layout(from.0)
            .new_layout(to.0)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(image.handle)
            .subresource_range(StorageImage::all_layers(image.layers));
        // SAFETY: recording into a command buffer in the recording state; the image is alive.
        unsafe {
            self.device.cmd_pipeline_barrier(
                self.command_buffer,
                from.2,
                to.2,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[barrier],
            );
        }
    }
}

/// A copy region covering every layer of a storage image, tightly packed in the buffer.
fn whole_image(image: &StorageImage) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .image_subresource(
            vk::ImageSubresourceLayers::default()
                .aspect_mask(vk::ImageAspectFlags::COLOR)
                .layer_count(image.layers),
        )
        .image_extent(vk::Extent3D {
            width: image.width,
            height: image.height,
            depth: 1,
        })
}

/// A layout, the accesses to wait for or to make wait, and their pipeline stage.
type LayoutUse = (vk::ImageLayout, vk::AccessFlags, vk::PipelineStageFlags);

/// A barrier that makes all earlier compute-shader and transfer writes visible to later
/// compute shaders and transfers.
fn full_compute_barrier(device: &ash::Device, command_buffer: vk::CommandBuffer) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(
            vk::AccessFlags::SHADER_READ
                | vk::AccessFlags::SHADER_WRITE
                | vk::AccessFlags::TRANSFER_READ
                | vk::AccessFlags::TRANSFER_WRITE,
        );
    // SAFETY: recording into a command buffer in the recording state.
    unsafe {
        device.cmd_pipeline_barrier(
            command_buffer,
            vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
            vk::DependencyFlags::empty(),
            &[barrier],
            &[],
            &[],
        );
    }
}
