//! The one-line summary printed at the end of a render, and the progress bar.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar on stderr that only appears once a render has run for a second.
pub struct RenderProgress {
    bar: ProgressBar,
    started: Instant,
    visible: bool,
}

impl RenderProgress {
    /// A hidden bar counting samples per pixel up to `total`.
    pub fn new(total: u32) -> RenderProgress {
        let bar =
            ProgressBar::with_draw_target(Some(u64::from(total)), ProgressDrawTarget::hidden());
        if let Ok(style) =
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} spp, eta {eta}")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        RenderProgress {
            bar,
            started: Instant::now(),
            visible: false,
        }
    }

    /// Reports the samples per pixel done so far.
    pub fn update(&mut self, samples_done: u32) {
        if !self.visible && self.started.elapsed() > Duration::from_secs(1) {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.visible = true;
        }
        self.bar.set_position(u64::from(samples_done));
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// "device NAME [KIND], WxH, N spp, S s, M M samples/s".
pub fn summary_line(
    device: &crate::vk::DeviceInfo,
    width: u32,
    height: u32,
    spp: u32,
    seconds: f64,
) -> String {
    let samples = f64::from(width) * f64::from(height) * f64::from(spp);
    format!(
        "device {} [{}], {width}x{height}, {spp} spp, {seconds:.2} s, {:.3} M samples/s",
        device.name,
        device.kind,
        samples / seconds.max(1e-9) / 1e6
    )
}
