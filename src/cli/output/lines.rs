//! The lines on stderr at the end of a render: the files written and the summary line, how
//! it stopped (a signal, a failure, the time limit, nothing taken) and what it kept, and the
//! validation layer's verdict.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::bail;

use super::report::{GuideSummary, RunCounts, WrittenFiles};
use super::{Finished, RenderRequest};
use crate::cli::signals;
use crate::cli::summary::{summary_line, Summary};
use crate::render::StopReason;
use crate::vk::{Context, DeviceInfo};
use crate::RenderedImage;

/// The lines on stderr after a render: resumed from where, the files written, the summary
/// line and the guide's.
pub(super) fn print_summary(
    request: &RenderRequest,
    contexts: &[Arc<Context>],
    finished: &Finished,
    files: &WrittenFiles,
    counts: &RunCounts,
) {
    let total = request.job.samples.len() as u32;
    let done = finished.metadata.samples.len() as u32;
    if let Some(resumed) = &request.job.resume {
        eprintln!(
            "vkpath: resumed from '{}' at {} of {total} spp; this run took {} more",
            resumed.display(),
            finished.resumed_samples,
            done - finished.resumed_samples
        );
    }
    for output in files.outputs {
        eprintln!("vkpath: wrote {}", output.display());
    }
    if let Some(checkpoint) = files.checkpoint {
        eprintln!("vkpath: wrote {} (checkpoint)", checkpoint.display());
    }
    if let Some(preview) = files.preview {
        eprintln!("vkpath: wrote {} (preview)", preview.display());
    }
    let devices: Vec<(DeviceInfo, u32)> = contexts
        .iter()
        .zip(&finished.devices)
        .map(|(context, report)| (context.info.clone(), report.spp))
        .collect();
    let area = request.settings.area();
    let counter = request
        .position
        .as_ref()
        .map(|p| format!("{}: ", p.counter()))
        .unwrap_or_default();
    eprintln!(
        "{counter}{}",
        summary_line(&Summary {
            devices: &devices,
            width: area.width(),
            height: area.height(),
            spp: done,
            spp_mean: request.settings.noise_threshold.map(|_| counts.spp_mean),
            new_samples: counts.new_samples,
            setup_seconds: counts.setup_seconds,
            seconds: finished.render_seconds,
            traversal: finished.scene_memory.map(|memory| memory.traversal),
        })
    );
    if let Some(guide) = &finished.guide {
        eprintln!("{}", GuideSummary::new(guide).line());
    }
}

/// What `finish` does after the report: fails as the render did, exits as a signal asks,
/// says that the time limit was reached, and fails when the validation layer complained.
pub(super) fn end_after_report(
    request: &RenderRequest,
    outputs: &[PathBuf],
    contexts: &[Arc<Context>],
    finished: &Finished,
    checkpoint: Option<&PathBuf>,
) -> anyhow::Result<()> {
    let total = request.job.samples.len() as u32;
    let done = finished.metadata.samples.len() as u32;
    if let Some(error) = &finished.failure {
        bail!(
            "rendering stopped after {done} of {total} spp: {error}; {}",
            what_a_failure_kept(request, outputs, checkpoint)
        );
    }
    match finished.stop {
        StopReason::Cancelled => {
            let (name, status) = signals::received().unwrap_or(("a signal", 130));
            let mut saved: Vec<String> = outputs
                .iter()
                .chain(checkpoint)
                .map(|p| format!("'{}'", p.display()))
                .collect();
            let last = saved.pop().unwrap_or_default();
            let saved = match saved.is_empty() {
                true => last,
                false => format!("{} and {last}", saved.join(", ")),
            };
            let kept = left_as_they_were(request, outputs);
            let frames_left = signals::frames_left();
            eprintln!(
                "vkpath: stopped by {name} after {done} of {total} spp; saved to {saved}{kept}{frames_left}"
            );
            std::process::exit(status);
        }
        StopReason::TimeLimit if !request.reporting.quiet && !request.reporting.json => {
            eprintln!("vkpath: time limit reached after {done} of {total} spp");
        }
        _ => {}
    }
    for context in contexts {
        fail_on_validation_messages(context)?;
    }
    Ok(())
}

/// Ends the command, writing nothing, when a render stopped before this run's first sample:
/// a failure or a time limit as an error, a signal as the signal asks.
pub(super) fn refuse_when_nothing_was_taken(finished: &Finished) -> anyhow::Result<()> {
    let new_samples = finished.metadata.samples.len() as u32 - finished.resumed_samples;
    if finished.stop == StopReason::Done || new_samples > 0 {
        return Ok(());
    }
    if let (true, None, StopReason::Cancelled) =
        (finished.tile_by_tile, &finished.failure, finished.stop)
    {
        let (name, status) = signals::received().unwrap_or(("a signal", 130));
        eprintln!(
            "vkpath: stopped by {name} before the last tile: a render finishing its tiles one \
             at a time has no sample of those it did not reach, so nothing was written \
             (--checkpoint keeps what a stopped render took){}",
            signals::frames_left()
        );
        std::process::exit(status);
    }
    match (&finished.failure, finished.stop) {
        (Some(error), _) => {
            bail!("rendering failed before its first sample, so nothing was written: {error}")
        }
        (None, StopReason::Cancelled) => signals::exit_with_nothing_written(),
        _ => bail!(
            "the render stopped ({}) before its first sample: nothing was written",
            finished.stop.name()
        ),
    }
}

/// Warns once when pixels are NaN or infinite.
pub(super) fn warn_about_non_finite_pixels(image: &RenderedImage) {
    let non_finite = image
        .mean
        .iter()
        .filter(|p| !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()))
        .count();
    if non_finite > 0 {
        eprintln!(
            "vkpath: warning: {non_finite} pixels are not finite (NaN or infinite); the scene's values overflow 32-bit floats"
        );
    }
}

/// What the line of a render that failed after some samples says it kept, and how to go
/// on: the partial images (the outputs left as they were) and, with a checkpoint, the
/// `--resume` that continues from it; without one, that the next render starts over.
fn what_a_failure_kept(
    request: &RenderRequest,
    outputs: &[PathBuf],
    checkpoint: Option<&PathBuf>,
) -> String {
    let images = format!(
        "the samples taken are in {}{}",
        quoted_paths(outputs),
        left_as_they_were(request, outputs)
    );
    match checkpoint {
        Some(checkpoint) => format!(
            "{images}; add --resume '{}' to go on from its last checkpoint",
            checkpoint.display()
        ),
        None => format!(
            "{images}; without --checkpoint a render cannot resume, so a new one starts over"
        ),
    }
}

/// Paths as the lines name them: `'a.png', 'b.exr'`.
fn quoted_paths(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| format!("'{}'", p.display())).collect();
    names.join(", ")
}

/// What a line adds where a stopped render wrote beside its outputs (`written`, their
/// `.partial` siblings): ` ('out.png' left as it was)` for the outputs that exist, `'out.exr'
/// not written` for those that do not; nothing where it wrote the outputs.
fn left_as_they_were(request: &RenderRequest, written: &[PathBuf]) -> String {
    if written == request.outputs {
        return String::new();
    }
    let (kept, absent): (Vec<PathBuf>, Vec<PathBuf>) =
        request.outputs.iter().cloned().partition(|o| o.exists());
    let mut parts = Vec::new();
    if !kept.is_empty() {
        parts.push(format!("{} left as it was", quoted_paths(&kept)));
    }
    if !absent.is_empty() {
        parts.push(format!("{} not written", quoted_paths(&absent)));
    }
    format!(" ({})", parts.join("; "))
}

/// Fails, after a command has done its work, when the validation layer (`--validate`)
/// reported any error or warning; they were logged as they came.
pub fn fail_on_validation_messages(context: &Context) -> anyhow::Result<()> {
    if let Some(messages) = context.validation_messages() {
        if messages.total() > 0 {
            bail!(
                "the validation layer reported {} errors and {} warnings (see the log above)",
                messages.errors(),
                messages.warnings()
            );
        }
    }
    Ok(())
}
