//! Recording and submitting command buffers on the compute queue, one batch at a time.

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use super::error::{CallContext, VkError, VkResult};

/// How long a submitted batch may run before we give up waiting (seconds). Generous: a
/// frame on lavapipe with a large scene can take long, but a hang must not wait forever.
const SUBMIT_TIMEOUT_SECONDS: u64 = 600;

/// A command pool with one reusable command buffer and a fence.
pub struct CommandRunner {
    context: Arc<Context>,
    pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
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
    pub fn run(&self, record: impl FnOnce(&ash::Device, vk::CommandBuffer)) -> VkResult<()> {
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
            record(device, command_buffer);
            device
                .end_command_buffer(command_buffer)
                .during("recording commands")?;
            let command_buffers = [command_buffer];
            let submit = [vk::SubmitInfo::default().command_buffers(&command_buffers)];
            device
                .reset_fences(&[self.fence])
                .during("resetting a fence")?;
            device
                .queue_submit(self.context.queue, &submit, self.fence)
                .during("submitting commands")?;
            match device.wait_for_fences(
                &[self.fence],
                true,
                SUBMIT_TIMEOUT_SECONDS * 1_000_000_000,
            ) {
                Ok(()) => Ok(()),
                Err(vk::Result::TIMEOUT) => Err(VkError::Timeout(SUBMIT_TIMEOUT_SECONDS)),
                Err(result) => Err(VkError::Call {
                    what: "waiting for the device",
                    result,
                }),
            }
        }
    }
}

impl Drop for CommandRunner {
    fn drop(&mut self) {
        // SAFETY: run() waits for its submission, so nothing is pending (unless it timed
        // out, in which case we wait for the device before destroying anything).
        unsafe {
            let device = &self.context.device;
            let _ = device.device_wait_idle();
            device.destroy_fence(self.fence, None);
            device.destroy_command_pool(self.pool, None);
        }
    }
}

/// A barrier that makes all earlier compute-shader and transfer writes visible to later
/// compute shaders and transfers (the only synchronisation a batch of frames needs).
pub fn full_compute_barrier(device: &ash::Device, command_buffer: vk::CommandBuffer) {
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

/// A barrier that makes writes of `stage` (with `access`) visible to the host, before it
/// reads a buffer back after the submission's fence.
pub fn host_read_barrier(
    device: &ash::Device,
    command_buffer: vk::CommandBuffer,
    stage: vk::PipelineStageFlags,
    access: vk::AccessFlags,
) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(access)
        .dst_access_mask(vk::AccessFlags::HOST_READ);
    // SAFETY: recording into a command buffer in the recording state.
    unsafe {
        device.cmd_pipeline_barrier(
            command_buffer,
            stage,
            vk::PipelineStageFlags::HOST,
            vk::DependencyFlags::empty(),
            &[barrier],
            &[],
            &[],
        );
    }
}
