//! The files of a sequence (`vkpath render --frames`), as a render farm expects them:
//! every frame's outputs checked before the first sample, `--skip-existing` trusting only
//! a finished image of this very render, and the `.partial` files that a stopped render
//! left beside a frame removed once that frame is finished.

use std::ops::Range;
use std::path::{Path, PathBuf};

use anyhow::Context as _;

use super::frames::{FrameArgs, FrameTime};
use super::output::partial_path;
use crate::image_io::exr_input::read_exr_channels;
use crate::image_io::output::{check_writable, ImageFormat};
use crate::render::metadata::RenderMetadata;
use crate::render::state_exr::read_image_metadata;

/// Checks, before the first sample, that every frame of `frames` can write each of
/// `outputs` (names with a run of `#`): the name itself was checked (`check_writable`: a
/// known format, an existing folder that takes a new file), so what is left is the files
/// that exist already under a frame's name. The folder is listed once (not one look-up per
/// frame), and each entry that is a frame's output of the range is checked as an output
/// is: a directory, a device, a FIFO, a socket or a read-only file is refused in one line
/// that names its frame.
pub fn check_frame_outputs(outputs: &[PathBuf], frames: &Range<u32>) -> anyhow::Result<()> {
    for output in outputs {
        let Some(pattern) = FramePattern::of(output) else {
            continue;
        };
        let folder = match output.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let entries = std::fs::read_dir(&folder)
            .with_context(|| format!("cannot list the folder '{}'", folder.display()))?;
        let mut taken: Vec<(u32, PathBuf)> = entries
            .filter_map(Result::ok)
            .filter_map(|entry| {
                let name = entry.file_name();
                let frame = pattern.frame_of(name.to_str()?, frames)?;
                Some((frame, output.with_file_name(name)))
            })
            .collect();
        taken.sort();
        for (frame, path) in taken {
            check_writable(&path).with_context(|| format!("frame {frame}'s output"))?;
        }
    }
    Ok(())
}

/// A file name with a run of `#`, split where `frame_path` puts the frame number.
struct FramePattern {
    /// What comes before the run.
    prefix: String,
    /// What comes after it.
    suffix: String,
    /// The run's length: the number's width, zero-padded.
    width: usize,
}

impl FramePattern {
    /// The pattern of `path`'s file name; none without a `#`.
    fn of(path: &Path) -> Option<FramePattern> {
        let name = path.file_name()?.to_str()?;
        let end = name.rfind('#')? + 1;
        let start = name[..end].trim_end_matches('#').len();
        Some(FramePattern {
            prefix: name[..start].to_string(),
            suffix: name[end..].to_string(),
            width: end - start,
        })
    }

    /// The frame of `frames` whose output is named `name`, if one is.
    fn frame_of(&self, name: &str, frames: &Range<u32>) -> Option<u32> {
        let digits = name
            .strip_prefix(&self.prefix)?
            .strip_suffix(&self.suffix)?;
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        let frame: u32 = digits.parse().ok()?;
        let width = self.width;
        (frames.contains(&frame) && format!("{frame:0width$}") == digits).then_some(frame)
    }
}

/// Why an existing output is not a finished image of the render asked for, in the words
/// that follow its name.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum NotFinished {
    /// It does not read as an image (empty, truncated, not EXR or PNG inside).
    #[error("is unreadable ({0})")]
    Unreadable(String),
    /// It has no vkpath metadata.
    #[error("has no vkpath metadata (not written by vkpath render)")]
    NoMetadata,
    /// Its metadata records no outcome (a checkpoint's or a shard's).
    #[error("records no finished render (a checkpoint or a shard)")]
    NoOutcome,
    /// Its render stopped before its end: why (`signal`, `time-limit`, `failed`).
    #[error("is partial (its render stopped: {0})")]
    Stopped(String),
    /// It holds other samples than those asked for, or fewer.
    #[error("is partial (it holds samples {}..{} of {}..{})", .held.start, .held.end, .asked.start, .asked.end)]
    Samples {
        /// The samples it holds.
        held: Range<u32>,
        /// The samples asked for.
        asked: Range<u32>,
    },
    /// A setting or image field differs: its name, the file's value and the asked one.
    #[error("is another render ({0} {1}, asked {2})")]
    Other(String, String, String),
}

/// Whether `output` is a finished image of the render whose metadata `asked` gives (lazily:
/// it hashes the scene): an image that reads whole, whose metadata says `stop=done`, holding
/// the asked samples or more of the same sequence (a 16-spp frame serves a request for 8),
/// with the same settings, scene digest and image fields (frame, time, post-processing).
pub fn finished_image(
    output: &Path,
    asked: &mut dyn FnMut() -> RenderMetadata,
    samples: &Range<u32>,
) -> Result<(), NotFinished> {
    // The reader's words without its "cannot read 'NAME': ", which the line says already.
    let unreadable = |error: String| {
        let prefix = format!("cannot read '{}': ", output.display());
        NotFinished::Unreadable(error.strip_prefix(&prefix).unwrap_or(&error).to_string())
    };
    read_whole_image(output).map_err(unreadable)?;
    let held = read_image_metadata(output)
        .map_err(|e| unreadable(e.to_string()))?
        .ok_or(NotFinished::NoMetadata)?;
    let outcome = held.outcome.as_ref().ok_or(NotFinished::NoOutcome)?;
    if outcome.stop != "done" {
        return Err(NotFinished::Stopped(outcome.stop.clone()));
    }
    if held.samples.start != samples.start || held.samples.end < samples.end {
        return Err(NotFinished::Samples {
            held: held.samples.clone(),
            asked: samples.clone(),
        });
    }
    match held.first_difference_from(&asked()) {
        Some((name, value, wanted)) => Err(NotFinished::Other(name, value, wanted)),
        None => Ok(()),
    }
}

/// Reads the image at `path` whole (every pixel decoded), to tell an empty or truncated
/// file from an image; the error in words.
fn read_whole_image(path: &Path) -> Result<(), String> {
    match ImageFormat::from_path(path).map_err(|e| e.to_string())? {
        ImageFormat::Exr => read_exr_channels(path)
            .map(|_| ())
            .map_err(|e| e.to_string()),
        ImageFormat::Png => image::ImageReader::open(path)
            .map_err(|e| e.to_string())?
            .with_guessed_format()
            .map_err(|e| e.to_string())?
            .decode()
            .map(|_| ())
            .map_err(|e| e.to_string()),
    }
}

impl FrameArgs {
    /// Whether `--skip-existing` skips `frame`, whose outputs are `outputs`: each of them is
    /// a finished image of this render (`finished_image`, against the metadata `asked`
    /// gives, holding `samples` or more). An output that exists but is not one is rendered
    /// again, as a line says (unless `quiet`); missing ones are rendered without a word.
    /// A skipped frame says so on stderr (unless `quiet`), removes the stale `.partial`
    /// files beside its outputs and, with `json`, prints its object (`stop: skipped`) so
    /// that a script reads one object per frame.
    pub fn skip(
        &self,
        frame: FrameTime,
        outputs: &[PathBuf],
        asked: impl Fn() -> RenderMetadata,
        samples: &Range<u32>,
        json: bool,
        quiet: bool,
    ) -> bool {
        if !self.skip_existing || !outputs.iter().all(|o| o.exists()) {
            return false;
        }
        // The scene is hashed once, and only for a file that passed the other checks.
        let metadata = std::cell::OnceCell::new();
        let mut asked_metadata = || metadata.get_or_init(&asked).clone();
        for output in outputs {
            if let Err(why) = finished_image(output, &mut asked_metadata, samples) {
                if !quiet {
                    eprintln!(
                        "vkpath render: {}: '{}' {why}: rendering it again",
                        frame.name(),
                        output.display(),
                    );
                }
                return false;
            }
        }
        if json {
            let skipped = serde_json::json!({
                "schema_version": super::output::RENDER_REPORT_SCHEMA_VERSION,
                "outputs": outputs.iter().map(|o| o.display().to_string()).collect::<Vec<_>>(),
                "frame": frame.frame,
                "time": frame.time,
                "stop": "skipped",
            });
            println!("{skipped}");
        }
        if !quiet {
            let names: Vec<String> = outputs
                .iter()
                .map(|o| format!("'{}'", o.display()))
                .collect();
            eprintln!(
                "vkpath render: {}: {} already finished, skipped (--skip-existing)",
                frame.name(),
                names.join(", ")
            );
        }
        remove_stale_partials(outputs, frame, !quiet);
        true
    }
}

/// Removes the `.partial` files (`out_0007.partial.png`) that a render stopped by Ctrl-C or
/// a failure left beside `outputs`, now that `frame` is finished there; one that holds more
/// samples than its finished output, or is no vkpath image, is left alone. Says so when
/// `talk`.
pub fn remove_stale_partials(outputs: &[PathBuf], frame: FrameTime, talk: bool) {
    for output in outputs {
        let partial = partial_path(output);
        if !partial.is_file() {
            continue;
        }
        let samples = |path: &Path| read_image_metadata(path).ok().flatten().map(|m| m.samples);
        let (Some(stale), Some(finished)) = (samples(&partial), samples(output)) else {
            continue;
        };
        if stale.len() > finished.len() {
            continue;
        }
        match std::fs::remove_file(&partial) {
            Ok(()) if talk => eprintln!(
                "vkpath: removed '{}', left by a stopped render of {} (now finished in '{}')",
                partial.display(),
                frame.name(),
                output.display()
            ),
            Ok(()) => {}
            Err(error) => eprintln!(
                "vkpath: warning: cannot remove the stale '{}': {error}",
                partial.display()
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_pattern_finds_the_frames_of_the_range_only() {
        let pattern = FramePattern::of(Path::new("out/c_###.exr")).unwrap();
        let frames = 5..120;
        assert_eq!(pattern.frame_of("c_007.exr", &frames), Some(7));
        assert_eq!(pattern.frame_of("c_119.exr", &frames), Some(119));
        assert_eq!(pattern.frame_of("c_120.exr", &frames), None);
        assert_eq!(pattern.frame_of("c_004.exr", &frames), None);
        // Not how the frame's name is written: unpadded, other digits, other names.
        assert_eq!(pattern.frame_of("c_7.exr", &frames), None);
        assert_eq!(pattern.frame_of("c_0007.exr", &frames), None);
        assert_eq!(pattern.frame_of("c_007.png", &frames), None);
        assert_eq!(pattern.frame_of("c_0x7.exr", &frames), None);
        assert_eq!(pattern.frame_of("c_.exr", &frames), None);
        // A number wider than the run takes the digits it needs, as frame_path writes it.
        assert_eq!(pattern.frame_of("c_1000.exr", &(0..2000)), Some(1000));
        assert!(FramePattern::of(Path::new("plain.exr")).is_none());
    }
}
