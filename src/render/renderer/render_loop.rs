//! The render loop: batches until every sample is taken or something stops it (a cancel
//! flag, a deadline, a failure), with the periodic checkpoint and preview hooks between
//! batches, then the final image.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::render::accumulation::Accumulation;
use crate::render::tiles::{Tiles, TilesEnd};

use super::{RenderControl, RenderOutcome, Renderer, StopReason};

impl Renderer {
    /// Renders until every sample is taken or `cancel` is set, one batch at a time, calling
    /// `progress` with the samples per pixel taken after each batch, and reads the image
    /// back. An error after some samples were taken ends the render without losing them
    /// (`RenderOutcome::failure`); an error before any is returned.
    pub fn render_to_end(
        &mut self,
        progress: impl FnMut(u32),
        cancel: Option<&AtomicBool>,
    ) -> Result<RenderOutcome> {
        self.render_with(
            progress,
            RenderControl {
                cancel,
                ..RenderControl::default()
            },
        )
    }

    /// `render_to_end` with every control: a cancel flag, a deadline, periodic
    /// checkpoints.
    pub fn render_with(
        &mut self,
        mut progress: impl FnMut(u32),
        mut control: RenderControl,
    ) -> Result<RenderOutcome> {
        let started = Instant::now();
        let mut last_checkpoint = Instant::now();
        let mut last_preview = Instant::now();
        let mut failure = None;
        // A guided render trains its guide first; a signal or the time limit stops that too
        // (with no sample taken).
        let cancelled = || {
            control
                .cancel
                .is_some_and(|flag| flag.load(Ordering::SeqCst))
        };
        let late = || control.deadline.is_some_and(|d| Instant::now() >= d);
        let trained = self.train_guide_until(&|| cancelled() || late())?;
        let stop = loop {
            if !trained {
                break if cancelled() {
                    StopReason::Cancelled
                } else {
                    StopReason::TimeLimit
                };
            }
            if self.is_complete() {
                break StopReason::Done;
            }
            if control
                .cancel
                .is_some_and(|flag| flag.load(Ordering::SeqCst))
            {
                break StopReason::Cancelled;
            }
            let budget = control
                .deadline
                .map(|d| d.saturating_duration_since(Instant::now()));
            if budget == Some(Duration::ZERO) {
                break StopReason::TimeLimit;
            }
            match self.render_batch_within(budget) {
                Ok(done) => progress(done),
                Err(error) if self.samples_done == 0 => return Err(error),
                Err(error) => {
                    failure = Some(error);
                    break StopReason::Failed;
                }
            }
            // Periodic hooks read the accumulation back only when one is due (and not after
            // the last batch: the caller has the final state in the outcome).
            let due = |hook: &Option<(Duration, _)>, last: Instant| {
                hook.as_ref()
                    .is_some_and(|(interval, _)| last.elapsed() >= *interval)
            };
            let checkpoint_due = due(&control.checkpoint, last_checkpoint);
            let preview_due = due(&control.preview, last_preview);
            if (checkpoint_due || preview_due) && !self.is_complete() {
                let state = match self.accumulation() {
                    Ok(state) => state,
                    Err(error) => {
                        failure = Some(error);
                        break StopReason::Failed;
                    }
                };
                if let (true, Some((_, checkpoint))) = (checkpoint_due, control.checkpoint.as_mut())
                {
                    checkpoint(&state)?;
                    last_checkpoint = Instant::now();
                }
                if let (true, Some((_, preview))) = (preview_due, control.preview.as_mut()) {
                    preview(&state)?;
                    last_preview = Instant::now();
                }
            }
        };
        let seconds = started.elapsed().as_secs_f64();
        let (image, state) = match (self.final_image(), failure) {
            (Ok(image_and_state), failure_so_far) => {
                failure = failure_so_far;
                image_and_state
            }
            (Err(error), _) if self.samples_done == 0 => return Err(error),
            // A device that failed (lost) cannot give back what it holds either; any other
            // error of the read-back (a loop limit's flagged pixels) is the render's own.
            (Err(read_back), None) if !matches!(read_back, Error::Vulkan(_)) => {
                return Err(read_back)
            }
            (Err(read_back), failure) => {
                return Err(Error::RenderLost {
                    samples: self.samples_done,
                    error: Box::new(failure.unwrap_or(read_back)),
                    kept: String::new(),
                })
            }
        };
        Ok(RenderOutcome {
            image,
            samples: self.samples_done,
            seconds,
            setup_seconds: self.setup_seconds,
            stop,
            state,
            failure,
            guide: self.guide_report.clone(),
            scene_memory: self.scene.memory,
        })
    }

    /// Renders every remaining sample and reads the image back; any error is returned.
    pub fn render_all(&mut self) -> Result<RenderedImage> {
        Ok(self.render_to_end(|_| {}, None)?.finished()?.image)
    }

    /// The image at the end of a render and, unless it went tile by tile, its state (a
    /// render going tile by tile hands its image out: it holds none after).
    fn final_image(&mut self) -> Result<(RenderedImage, Option<Accumulation>)> {
        match self.tiles.as_mut().map(Tiles::end).transpose()? {
            Some(TilesEnd::Image { image, rays }) => {
                self.rays_traced = rays;
                Ok((image, None))
            }
            Some(TilesEnd::CutPaths(flagged)) => Err(self.loop_limit_error(flagged)),
            Some(TilesEnd::WholeState) | None => {
                let state = self.accumulation()?;
                Ok((state.image(), Some(state)))
            }
        }
    }
}
