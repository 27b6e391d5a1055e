//! Path guiding's buffers on the device: the guide the path tracer samples
//! (`BINDING_GUIDE`, `crate::guiding::Guide::words`) and the training splats its training
//! frames add up (`BINDING_GUIDE_SPLATS`). Every build of the path tracer binds both; an
//! unguided render binds a guide of no cells and a one-word splat buffer, which its kernel
//! (specialized `GUIDING_OFF`) never reads.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::contract::GUIDE_HEADER_TEXEL_COUNT;
use crate::error::Result;
use crate::guiding::{Guide, GuideGrid, GuideSplats};
use crate::vk::{Buffer, CommandRunner, Context, TexelBufferView};

/// The guide's and the training splats' buffers.
pub struct GuideBuffers {
    /// The guide's texel buffer (replaced by `set_guide`).
    pub guide: TexelBufferView,
    /// The training splats, device-local, cleared before each training iteration.
    pub splats: Buffer,
    /// Host-visible copy of `splats`, read after each iteration (guided renders only).
    readback: Option<Buffer>,
    /// The grid the guide covers (guided renders only).
    grid: Option<GuideGrid>,
}

impl GuideBuffers {
    /// What an unguided render binds: an empty guide and a one-word splat buffer.
    pub fn unguided(context: &Arc<Context>) -> Result<GuideBuffers> {
        let header = vec![0u32; 4 * GUIDE_HEADER_TEXEL_COUNT as usize];
        Ok(GuideBuffers {
            guide: guide_view(context, &header)?,
            splats: Buffer::new(
                context,
                "guide splats (unused)",
                16,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryLocation::GpuOnly,
            )?,
            readback: None,
            grid: None,
        })
    }

    /// A guided render's, on `grid`: the guide starts with no guided cell (the first
    /// training iteration samples the BSDF alone), and a splat buffer of
    /// `GuideGrid::splat_word_count` words.
    pub fn guided(context: &Arc<Context>, grid: GuideGrid) -> Result<GuideBuffers> {
        let bytes = 4 * grid.splat_word_count() as u64;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        Ok(GuideBuffers {
            guide: guide_view(context, GuideSplats::new(grid.clone()).build().words())?,
            splats: Buffer::new(
                context,
                "guide splats",
                bytes,
                usage,
                MemoryLocation::GpuOnly,
            )?,
            readback: Some(Buffer::new(
                context,
                "guide splats readback",
                bytes,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?),
            grid: Some(grid),
        })
    }

    /// The grid of a guided render's buffers.
    pub fn grid(&self) -> Option<&GuideGrid> {
        self.grid.as_ref()
    }

    /// Puts `guide` in a new texel buffer (the caller rebinds `guide`).
    pub fn set_guide(&mut self, context: &Arc<Context>, guide: &Guide) -> Result<()> {
        self.guide = guide_view(context, guide.words())?;
        Ok(())
    }

    /// Zeroes the training splats (before an iteration's frames).
    pub fn clear_splats(&self, commands: &CommandRunner) -> Result<()> {
        commands.run(|recorder| recorder.fill_buffer(&self.splats, 0))?;
        Ok(())
    }

    /// The splats the frames since `clear_splats` added up (a guided render's only).
    pub fn read_splats(&self, commands: &CommandRunner) -> Result<Option<GuideSplats>> {
        let (Some(readback), Some(grid)) = (&self.readback, &self.grid) else {
            return Ok(None);
        };
        commands.run(|recorder| {
            recorder.copy_buffer(&self.splats, readback, self.splats.size);
            recorder.host_read_barrier();
        })?;
        let words: Vec<u32> = readback.read();
        GuideSplats::from_device_words(grid, &words).map(Some)
    }
}

/// A guide's words in an RGBA32_UINT texel buffer.
fn guide_view(context: &Arc<Context>, words: &[u32]) -> Result<TexelBufferView> {
    let buffer = Buffer::with_data(
        context,
        "guide",
        words,
        vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
    )?;
    Ok(TexelBufferView::rgba32_uint(context, buffer, "guide")?)
}
