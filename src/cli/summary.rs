//! The one-line summary printed at the end of a render, the progress bar, and what the
//! pipeline cache tells the user (its warnings, and that the first run builds kernels).

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar on stderr that only appears once a render has run for a second, with an
/// estimate of the time left (`eta`): the sooner of the time limit and the samples still to
/// take at the rate measured since the first batch (set-up and the first batch, in which a
/// driver may compile the kernels, do not count towards the rate). With a noise threshold,
/// converged pixels stop early, so the samples' estimate is an upper bound (`eta ≤ …`), and
/// the bar shows the share of pixels converged so far (`37% converged`).
pub struct RenderProgress {
    bar: ProgressBar,
    started: Instant,
    visible: bool,
    total: u32,
    adaptive: bool,
    /// The first batch's end and its samples per pixel: where the rate is measured from.
    first_batch: Option<(Instant, u32)>,
    /// Where the frame stands in its sequence, for the frame counter and the estimate of
    /// the whole sequence's time left.
    sequence: Option<SequencePosition>,
}

/// Where a frame stands in a sequence of several (`render --frames`): the frame counter
/// of the progress bar and the summary, the sequence's time left, and what a stop leaves.
#[derive(Clone, Debug, PartialEq)]
pub struct SequencePosition {
    /// The frame number.
    pub frame: u32,
    /// The sequence's frames (`--frames START..END`).
    pub frames: std::ops::Range<u32>,
    /// What one frame took (set-up included) in the frames rendered before it, excluding
    /// the first, which opened the device (the first's alone when it is the only one);
    /// `None` before any.
    pub seconds_per_frame: Option<f64>,
}

impl SequencePosition {
    /// "frame 7 (3/10)": the frame and its place among the sequence's frames.
    pub fn counter(&self) -> String {
        format!(
            "frame {} ({}/{})",
            self.frame,
            self.frame - self.frames.start + 1,
            self.frames.len()
        )
    }

    /// The frames after this one.
    pub fn frames_after(&self) -> u32 {
        self.frames.end - self.frame - 1
    }

    /// The sequence's time left: this frame's `frame_left` and, for each frame after it,
    /// what a frame took so far (`seconds_per_frame`, else this frame's `frame_elapsed`
    /// plus what it has left); none while this frame's estimate is unknown.
    pub fn time_left(
        &self,
        frame_elapsed: Duration,
        frame_left: Option<Duration>,
    ) -> Option<Duration> {
        let frame_left = frame_left?;
        let per_frame = self
            .seconds_per_frame
            .unwrap_or_else(|| (frame_elapsed + frame_left).as_secs_f64());
        Some(
            frame_left
                + Duration::from_secs_f64(per_frame.max(0.0) * f64::from(self.frames_after())),
        )
    }
}

impl RenderProgress {
    /// A hidden bar counting samples per pixel up to `total`; `adaptive` for a render with
    /// a noise threshold.
    pub fn new(total: u32, adaptive: bool) -> RenderProgress {
        let bar =
            ProgressBar::with_draw_target(Some(u64::from(total)), ProgressDrawTarget::hidden());
        if let Ok(style) =
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} spp, {msg}")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        RenderProgress {
            bar,
            started: Instant::now(),
            visible: false,
            total,
            adaptive,
            first_batch: None,
            sequence: None,
        }
    }

    /// The bar of a frame of a sequence: it adds the frame counter and the sequence's time
    /// left ("frame 7 (3/10), eta 2s, sequence eta 1m 05s").
    pub fn in_sequence(self, position: Option<SequencePosition>) -> RenderProgress {
        RenderProgress {
            sequence: position,
            ..self
        }
    }

    /// Reports the samples per pixel done so far, the time limit's deadline, if any, and
    /// under a noise threshold the share of pixels converged (0 to 1).
    pub fn update(
        &mut self,
        samples_done: u32,
        deadline: Option<Instant>,
        converged_share: Option<f64>,
    ) {
        let now = Instant::now();
        if !self.visible && self.started.elapsed() > Duration::from_secs(1) {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.visible = true;
        }
        let (first_time, first_done) = *self.first_batch.get_or_insert((now, samples_done));
        let samples_left = eta_of_samples(
            self.total.saturating_sub(samples_done),
            samples_done.saturating_sub(first_done),
            now.saturating_duration_since(first_time),
        );
        let limit_left = deadline.map(|d| d.saturating_duration_since(now));
        let mut message = eta_text(samples_left, limit_left, self.adaptive);
        if let Some(sequence) = &self.sequence {
            let frame_left = match (samples_left, limit_left) {
                (Some(s), Some(l)) => Some(s.min(l)),
                (s, l) => s.or(l),
            };
            let left = sequence.time_left(self.started.elapsed(), frame_left);
            message = format!(
                "{}, {message}, sequence eta {}",
                sequence.counter(),
                left.map_or("?".to_string(), short_duration)
            );
        }
        if let Some(share) = converged_share {
            message.push_str(&format!(", {}", converged_text(share)));
        }
        self.bar.set_message(message);
        self.bar.set_position(u64::from(samples_done));
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// The time the `left` samples per pixel still take at the rate of `taken` in `elapsed`;
/// none before a rate is measured.
fn eta_of_samples(left: u32, taken: u32, elapsed: Duration) -> Option<Duration> {
    if left == 0 {
        return Some(Duration::ZERO);
    }
    (taken > 0 && !elapsed.is_zero()).then(|| elapsed.mul_f64(f64::from(left) / f64::from(taken)))
}

/// The bar's estimate: the sooner of the samples' and the time limit's ("eta 12s"); "eta ≤"
/// where what decides is only a bound (the samples' with a noise threshold, `adaptive`; the
/// limit's before the samples' is known); "eta ?" while nothing is known yet.
fn eta_text(samples: Option<Duration>, limit: Option<Duration>, adaptive: bool) -> String {
    let (eta, bound) = match (samples, limit) {
        (Some(s), Some(l)) if l <= s => (l, false),
        (Some(s), _) => (s, adaptive),
        (None, Some(l)) => (l, true),
        (None, None) => return "eta ?".to_string(),
    };
    format!(
        "eta {}{}",
        if bound { "≤ " } else { "" },
        short_duration(eta)
    )
}

/// The share of converged pixels as the bar shows it: "37% converged", rounded down so that
/// "100%" means every pixel.
fn converged_text(share: f64) -> String {
    format!(
        "{}% converged",
        (share.clamp(0.0, 1.0) * 100.0).floor() as u32
    )
}

/// A duration as the bar shows it: "7s", "3m 05s", "1h 02m".
fn short_duration(duration: Duration) -> String {
    let seconds = duration.as_secs_f64().ceil() as u64;
    match seconds {
        0..=59 => format!("{seconds}s"),
        60..=3599 => format!("{}m {:02}s", seconds / 60, seconds % 60),
        _ => format!("{}h {:02}m", seconds / 3600, seconds % 3600 / 60),
    }
}

/// The pipeline cache of the user's cache directory (`render::pipeline_cache`), printing
/// its warnings and, once per process, a line when building kernels takes over a second;
/// `None` (with a warning) when no cache directory can be found. The line about building
/// kernels is printed only when `announce` is set (not with `--quiet`).
pub fn pipeline_cache_store(
    announce: bool,
) -> Option<std::sync::Arc<dyn crate::vk::PipelineCacheStore>> {
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
        move || {
            if !announce {
                return;
            }
            NOTICE.call_once(|| {
                eprintln!("vkpath: building kernels for this scene (first run on this device)…")
            })
        },
    )))
}

/// The numbers of a render's summary line.
pub struct Summary<'a> {
    /// The devices, and the samples per pixel each took in this run.
    pub devices: &'a [(crate::vk::DeviceInfo, u32)],
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel the image holds (resumed ones included); with `--noise-threshold`,
    /// the most any pixel holds (the cap).
    pub spp: u32,
    /// With `--noise-threshold`: the mean over the pixels of the samples each holds;
    /// `None` when every pixel holds `spp`.
    pub spp_mean: Option<f64>,
    /// Samples this run took, all pixels together (the rate counts these only: samples
    /// resumed from a checkpoint took no time here, and pixels that stopped early took no
    /// more).
    pub new_samples: f64,
    /// Seconds from the command's start to the first sample.
    pub setup_seconds: f64,
    /// Seconds of rendering.
    pub seconds: f64,
    /// How rays found hits (`Traversal::name`: "compressed BVH", "ray queries", ...), where
    /// known.
    pub traversal: Option<&'a str>,
}

/// "device NAME [KIND], traversal T, WxH, N spp, setup T s, render S s, M M samples/s" for
/// one device ("mean N spp, cap C" with `--noise-threshold`; the traversal that ran, where
/// known); for several, "K devices, traversal T, WxH, ... M M samples/s (NAME: N1 spp,
/// ...)".
pub fn summary_line(summary: &Summary) -> String {
    let Summary {
        devices,
        width,
        height,
        spp,
        spp_mean,
        new_samples,
        setup_seconds,
        seconds,
        traversal,
    } = *summary;
    let rate = new_samples / seconds.max(1e-9) / 1e6;
    let samples = match spp_mean {
        Some(mean) => format!("mean {} spp, cap {spp}", format_spp_mean(mean)),
        None => format!("{spp} spp"),
    };
    let traversal = traversal.map_or(String::new(), |t| format!("traversal {t}, "));
    let common = format!(
        "{traversal}{width}x{height}, {samples}, setup {setup_seconds:.2} s, render {seconds:.2} s, {rate:.3} M samples/s"
    );
    match devices {
        [(device, _)] => format!("device {} [{}], {common}", device.name, device.kind),
        _ => {
            let shares: Vec<String> = devices
                .iter()
                .map(|(device, spp)| format!("{}: {spp} spp", device.name))
                .collect();
            format!(
                "{} devices, {common} ({})",
                devices.len(),
                shares.join(", ")
            )
        }
    }
}

/// A mean sample count as the summary prints it: whole samples from 10 up, one decimal
/// below (where a fraction of a sample is a large part of it).
pub fn format_spp_mean(mean: f64) -> String {
    if mean >= 10.0 {
        format!("{mean:.0}")
    } else {
        format!("{mean:.1}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_eta_is_the_sooner_of_the_samples_and_the_time_limit() {
        let s = Duration::from_secs;
        // 10 spp in 2 s since the first batch, 40 left: 8 s.
        assert_eq!(eta_of_samples(40, 10, s(2)), Some(s(8)));
        assert_eq!(eta_of_samples(40, 0, s(2)), None);
        assert_eq!(eta_of_samples(0, 0, s(0)), Some(s(0)));
        // The case: --time-limit 4 said "eta 60m"; the limit decides.
        assert_eq!(eta_text(Some(s(3600)), Some(s(4)), false), "eta 4s");
        assert_eq!(eta_text(Some(s(3)), Some(s(40)), false), "eta 3s");
        // A noise threshold makes the samples' estimate a bound, not the limit's.
        assert_eq!(eta_text(Some(s(200)), None, true), "eta ≤ 3m 20s");
        assert_eq!(eta_text(Some(s(200)), Some(s(100)), true), "eta 1m 40s");
        assert_eq!(eta_text(None, Some(s(100)), false), "eta ≤ 1m 40s");
        assert_eq!(eta_text(None, None, false), "eta ?");
        assert_eq!(short_duration(Duration::from_millis(7200)), "8s");
        assert_eq!(short_duration(s(3725)), "1h 02m");
    }

    #[test]
    fn a_sequence_counts_its_frames_and_estimates_the_time_left_of_all() {
        let s = Duration::from_secs;
        let mut position = SequencePosition {
            frame: 12,
            frames: 10..20,
            seconds_per_frame: None,
        };
        assert_eq!(position.counter(), "frame 12 (3/10)");
        assert_eq!(position.frames_after(), 7);
        // The first frames: this one's 4 s + 6 s left, for each of the 7 after it.
        assert_eq!(position.time_left(s(4), Some(s(6))), Some(s(76)));
        assert_eq!(position.time_left(s(4), None), None);
        position.seconds_per_frame = Some(2.0);
        assert_eq!(position.time_left(s(4), Some(s(1))), Some(s(15)));
        position.frame = 19;
        assert_eq!(position.time_left(s(4), Some(s(1))), Some(s(1)));
    }

    #[test]
    fn the_converged_share_rounds_down_so_that_100_means_every_pixel() {
        assert_eq!(converged_text(0.0), "0% converged");
        assert_eq!(converged_text(0.375), "37% converged");
        assert_eq!(converged_text(0.9999), "99% converged");
        assert_eq!(converged_text(1.0), "100% converged");
    }

    use crate::vk::{DeviceInfo, DeviceKind};

    fn device() -> DeviceInfo {
        DeviceInfo {
            index: 0,
            name: "llvmpipe".into(),
            kind: DeviceKind::Cpu,
            api_version: "1.3.0".into(),
            compute_queue_family: Some(0),
            uuid: [0; 16],
            vendor_id: 0x10005,
            pci_bus: None,
            ray_queries: false,
        }
    }

    #[test]
    fn the_rate_counts_the_samples_taken_and_an_adaptive_render_says_its_mean() {
        let devices = [(device(), 1024)];
        // 128x128 pixels that took 256 samples each on average, in 2 s: 2.097 M samples/s,
        // not the 8.389 M that 1024 spp would claim.
        let summary = Summary {
            devices: &devices,
            width: 128,
            height: 128,
            spp: 1024,
            spp_mean: Some(256.2),
            new_samples: 128.0 * 128.0 * 256.0,
            setup_seconds: 0.5,
            seconds: 2.0,
            traversal: Some("compressed BVH"),
        };
        let line = summary_line(&summary);
        assert!(
            line.contains(
                "128x128, mean 256 spp, cap 1024, setup 0.50 s, render 2.00 s, 2.097 M samples/s"
            ),
            "{line}"
        );
        let uniform = summary_line(&Summary {
            spp_mean: None,
            ..summary
        });
        assert!(uniform.contains("128x128, 1024 spp, setup"), "{uniform}");
        // The traversal that ran, named (issue 58)
        assert!(
            uniform.contains("], traversal compressed BVH, 128x128"),
            "{uniform}"
        );
        assert_eq!(format_spp_mean(3.26), "3.3");
    }
}
