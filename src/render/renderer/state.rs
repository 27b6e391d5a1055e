//! The render's state on the host: read back (`accumulation`, `read_back`) for a
//! checkpoint, a shard or a preview, and uploaded again to resume from it.

use ash::vk;

use crate::contract;
use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::render::accumulation::Accumulation;
use crate::render::converged_pixels::converged_pixel_count;
use crate::render::tiles::area_texel_count;
use crate::vk::Buffer;

use super::loop_budget::loop_limit_advice;
use super::Renderer;

impl Renderer {
    /// Reads the raw accumulation state back (for a checkpoint or a shard), and updates
    /// `rays_traced`.
    pub fn accumulation(&mut self) -> Result<Accumulation> {
        let texels = match self.tiles.as_mut() {
            Some(tiles) => tiles
                .whole_state(&self.settings, self.area, "read back")?
                .clone(),
            None => self.read_texels()?,
        };
        let pixels = self.area.width() as usize * self.area.height() as usize;
        let squares = contract::LAYER_SUM_OF_SQUARES as usize * pixels;
        let flagged = texels[squares..squares + pixels]
            .iter()
            .filter(|texel| texel[3] != 0.0)
            .count();
        if flagged > 0 {
            return Err(self.loop_limit_error(flagged));
        }
        let state = Accumulation {
            width: self.area.width(),
            height: self.area.height(),
            texels,
            samples: self.samples_taken(),
            guide: self.guide.clone(),
        };
        self.rays_traced = state.rays_traced();
        Ok(state)
    }

    /// Copies the accumulation image back and returns the per-pixel mean, second moment and
    /// sample count. Can be called at any time (e.g. to save a partial render).
    pub fn read_back(&mut self) -> Result<RenderedImage> {
        Ok(self.accumulation()?.image())
    }

    /// Continues a render from its saved state: uploads it and goes on with the next
    /// sample, so that the result is bit for bit what an uninterrupted render gives. The
    /// state must be of this render's size and start where this render starts. A guided
    /// render samples with the state's frozen guide where it has one (the same guide the
    /// saved samples were taken with, whatever device resumes), else trains its own.
    pub fn resume(&mut self, state: &Accumulation) -> Result<()> {
        match &state.guide {
            Some(guide) => self.use_frozen_guide(guide.clone())?,
            None => self.train_guide()?,
        }
        let (width, height) = (self.area.width(), self.area.height());
        if (state.width, state.height) != (width, height)
            || state.texels.len() != area_texel_count(self.area)
        {
            return Err(Error::InvalidSettings(format!(
                "the saved state is {}x{}, the render {width}x{height}",
                state.width, state.height
            )));
        }
        if state.samples.start != self.first_sample
            || state.samples.len() as u32 > self.settings.spp
        {
            return Err(Error::InvalidSettings(format!(
                "the saved state holds samples {}..{}, the render takes {}..{}",
                state.samples.start,
                state.samples.end,
                self.first_sample,
                self.first_sample + self.settings.spp
            )));
        }
        if let Some(tiles) = self.tiles.as_mut() {
            tiles
                .whole_state(&self.settings, self.area, "resume into")?
                .copy_from_slice(&state.texels);
        } else {
            let upload = Buffer::with_data(
                &self.context,
                "saved state",
                &state.texels,
                vk::BufferUsageFlags::TRANSFER_SRC,
            )?;
            let image = &self.accumulation;
            self.commands
                .run(|recorder| recorder.copy_buffer_to_image(&upload, image))?;
        }
        self.samples_done = state.samples.len() as u32;
        if let Some(noise) = &self.settings.noise_threshold {
            self.converged_pixels
                .set(converged_pixel_count(state, noise));
        }
        Ok(())
    }

    /// The error of a render whose paths the loop limit may have cut short in `flagged`
    /// pixels.
    pub(super) fn loop_limit_error(&self, flagged: usize) -> Error {
        Error::LoopLimit(format!(
            "the loop limit (llvmpipe's {} loop iterations, after which it ends loops \
             silently, or the limit of a checked function's loops) may have cut paths short \
             in {flagged} pixels, so the image would be wrong: {}",
            contract::LLVMPIPE_LOOP_LIMIT,
            loop_limit_advice(self.traversal, true)
        ))
    }

    /// Copies the accumulation image back: every layer, texel by texel.
    fn read_texels(&mut self) -> Result<Vec<[f32; 4]>> {
        let (image, readback) = (&self.accumulation, &self.readback);
        self.commands
            .run(|recorder| recorder.copy_image_to_buffer(image, readback))?;
        Ok(self.readback.read())
    }
}
