//! The share of converged pixels under `--noise-threshold`, for the progress bar: the path
//! tracer counts each pixel once, in the dispatch whose samples made it converged
//! (`BINDING_CONVERGED_PIXELS`), into a one-word host-visible buffer that the host zeroes
//! before a batch and adds up after it. A resumed render starts from the converged pixels
//! of the state it resumes (`converged_pixel_count`, with the kernel's twins).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use ash::vk;

use crate::contract::{LAYER_COMPENSATION, LAYER_SUM, LAYER_SUM_OF_SQUARES};
use crate::error::Result;
use crate::render::accumulation::Accumulation;
use crate::render::adaptive::{is_noise_check_due, is_pixel_converged, NoiseThreshold};
use crate::vk::{Buffer, Context};

/// The device's per-batch count and the render's running total.
pub struct ConvergedPixels {
    /// The kernel's counter (`BINDING_CONVERGED_PIXELS`), one `u32`, host-visible.
    pub buffer: Buffer,
    /// Pixels converged so far; shared with whoever reports progress (`handle`).
    total: Arc<AtomicU64>,
}

impl ConvergedPixels {
    /// A counter at 0.
    pub fn new(context: &Arc<Context>) -> Result<ConvergedPixels> {
        Ok(ConvergedPixels {
            buffer: Buffer::with_data(
                context,
                "converged pixels",
                &[0u32],
                vk::BufferUsageFlags::STORAGE_BUFFER,
            )?,
            total: Arc::new(AtomicU64::new(0)),
        })
    }

    /// The running total, to read while the render goes on (e.g. after each batch).
    pub fn handle(&self) -> Arc<AtomicU64> {
        self.total.clone()
    }

    /// Zeroes the device's count before a batch's submissions.
    pub fn begin_batch(&mut self) {
        self.buffer.write(bytemuck::bytes_of(&0u32));
    }

    /// Adds the device's count after a batch (its submissions waited for, each ending with
    /// a barrier that makes the count visible to the host).
    pub fn end_batch(&mut self) {
        let counted = self.buffer.read::<u32>().first().copied().unwrap_or(0);
        self.total.fetch_add(u64::from(counted), Ordering::SeqCst);
    }

    /// Sets the total (0 for a cleared state; a resumed state's count).
    pub fn set(&self, total: u64) {
        self.total.store(total, Ordering::SeqCst);
    }
}

/// The pixels of `state` that the kernel would judge converged before its next sample
/// (`is_noise_check_due` and `is_pixel_converged`, the kernel's twins), as it counts them.
pub fn converged_pixel_count(state: &Accumulation, noise: &NoiseThreshold) -> u64 {
    let pixels = state.width as usize * state.height as usize;
    let layer = |index: u32, pixel: usize| state.texels[index as usize * pixels + pixel];
    (0..pixels)
        .filter(|&pixel| {
            let sum = layer(LAYER_SUM, pixel);
            let compensation = layer(LAYER_COMPENSATION, pixel);
            let squares = layer(LAYER_SUM_OF_SQUARES, pixel);
            let estimate: [f32; 3] = std::array::from_fn(|c| sum[c] - compensation[c]);
            is_noise_check_due(sum[3], noise.min_spp)
                && is_pixel_converged(
                    estimate,
                    sum[3],
                    [squares[0], squares[1], squares[2]],
                    noise.threshold,
                )
        })
        .count() as u64
}
