//! The one-line summary printed at the end of a render, the progress bar, and what the
//! pipeline cache tells the user (its warnings, and that the first run builds kernels).

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

/// The pipeline cache of the user's cache directory (`render::pipeline_cache`), printing
/// its warnings and, once per process, a line when building kernels takes over a second;
/// `None` (with a warning) when no cache directory can be found.
pub fn pipeline_cache_store() -> Option<std::sync::Arc<dyn crate::vk::PipelineCacheStore>> {
    use crate::render::pipeline_cache::{default_cache_dir, PipelineCacheDir, CACHE_DIR_VARIABLE};
    static NOTICE: std::sync::Once = std::sync::Once::new();
    let Some(dir) = default_cache_dir() else {
        eprintln!(
            "vkpath: warning: no pipeline cache: set {CACHE_DIR_VARIABLE}, XDG_CACHE_HOME or HOME"
        );
        return None;
    };
    Some(std::sync::Arc::new(PipelineCacheDir::new(
        dir,
        |warning| eprintln!("vkpath: warning: {warning}"),
        || {
            NOTICE.call_once(|| {
                eprintln!("vkpath: building kernels for this scene (first run on this device)…")
            })
        },
    )))
}

/// "device NAME [KIND], WxH, N spp, setup T s, render S s, M M samples/s": `setup_seconds` to
/// build the renderer (kernels, BVH, uploads), `seconds` to render.
pub fn summary_line(
    device: &crate::vk::DeviceInfo,
    width: u32,
    height: u32,
    spp: u32,
    setup_seconds: f64,
    seconds: f64,
) -> String {
    let samples = f64::from(width) * f64::from(height) * f64::from(spp);
    format!(
        "device {} [{}], {width}x{height}, {spp} spp, setup {setup_seconds:.2} s, render {seconds:.2} s, {:.3} M samples/s",
        device.name,
        device.kind,
        samples / seconds.max(1e-9) / 1e6
    )
}
