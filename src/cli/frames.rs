//! `vkpath render`'s time and frames: `--time`, `--frames START..END` at `--fps`, outputs
//! whose run of `#` takes the frame number, `--animation` and `--skip-existing`.

use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::cli::value_error::ValueError;
use crate::render::metadata::parse_range;
use crate::scene::animation::AnimationPick;

/// The default of `--fps`.
pub const DEFAULT_FPS: f64 = 24.0;

/// The most frames one `--frames` range may hold: a million (11.6 hours at 24 fps, far
/// beyond any one farm task); a longer range is a typo, refused before anything renders.
pub const MAX_FRAMES: u32 = 1_000_000;

/// When the scene is rendered: one time, or a range of frames.
#[derive(Debug, Clone, clap::Args)]
pub struct FrameArgs {
    /// Render the scene at this time in seconds (a glTF file's animations evaluated then;
    /// before the first key the first key holds, after the last the last). Default 0.
    #[arg(long, value_name = "SECONDS", value_parser = parse_time, allow_hyphen_values = true,
          conflicts_with = "frames")]
    pub time: Option<f64>,
    /// Render frames START..END (END excluded, as --sample-range), frame f at time f / --fps.
    /// With more than one frame, each -o needs a run of '#' that takes the zero-padded frame
    /// number (-o out_####.png writes out_0007.png for frame 7). (`check` and `shadertoy`
    /// have a --frames of their own: a count.)
    #[arg(long, value_name = "START..END", value_parser = parse_frames)]
    pub frames: Option<Range<u32>>,
    /// Frames per second of --frames.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_FPS, value_parser = parse_fps)]
    pub fps: f64,
    /// Play only this one of a glTF file's animations (its name, or its index from 0);
    /// all of them play at once by default.
    #[arg(long, value_name = "NAME|INDEX")]
    pub animation: Option<String>,
    /// Leave alone every frame whose outputs are all finished images of this render (read
    /// whole; metadata with stop=done, the same scene digest and settings, at least the
    /// samples asked), saying so; render the others again (a line says why): for re-queued
    /// farm tasks.
    #[arg(long)]
    pub skip_existing: bool,
}

/// A usage error found after parsing (the command exits with status 2, as for clap's).
#[derive(Debug)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// One image of a sequence: its frame number (`None` for a still) and its time in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTime {
    /// The frame number, or `None` when no `--frames` was given.
    pub frame: Option<u32>,
    /// The scene time in seconds.
    pub time: f64,
}

impl FrameArgs {
    /// The images to render, in order: each frame of `--frames`, else one at `--time` (or 0).
    /// Lazily: a long range holds no list of its frames.
    pub fn frame_times(&self) -> impl Iterator<Item = FrameTime> + '_ {
        let still = self.frames.is_none().then(|| FrameTime {
            frame: None,
            time: self.time.unwrap_or(0.0),
        });
        let frames = self.frames.clone().unwrap_or(0..0);
        still.into_iter().chain(frames.map(|frame| FrameTime {
            frame: Some(frame),
            time: f64::from(frame) / self.fps,
        }))
    }

    /// The animations `--animation` picks.
    pub fn pick(&self) -> AnimationPick {
        self.animation
            .clone()
            .map_or(AnimationPick::All, AnimationPick::One)
    }

    /// Whether the images are at a time given on the command line (the JSON report then
    /// gives `frame` and `time`).
    pub fn timed(&self) -> bool {
        self.time.is_some() || self.frames.is_some()
    }

    /// Checks, before anything renders, that several frames do not write one file: each
    /// output needs a run of `#`.
    pub fn check_outputs(&self, outputs: &[PathBuf]) -> Result<(), UsageError> {
        let several = self.frames.as_ref().is_some_and(|f| f.len() > 1);
        if let Some(plain) = outputs.iter().find(|o| several && !has_frame_run(o)) {
            return Err(UsageError(format!(
                "--frames renders several frames, but -o '{}' has no run of '#' for the frame number (e.g. -o out_####.png)",
                plain.display()
            )));
        }
        Ok(())
    }
}

impl FrameTime {
    /// How messages name a frame: "frame 7", or "time 0.5 s" for a still.
    pub fn name(&self) -> String {
        match self.frame {
            Some(number) => format!("frame {number}"),
            None => format!("time {} s", self.time),
        }
    }
}

/// Whether a path's file name has a `#`.
fn has_frame_run(path: &Path) -> bool {
    path.file_name()
        .is_some_and(|name| name.to_string_lossy().contains('#'))
}

/// `path` with the last run of `#` in its file name replaced by `frame`, zero-padded to
/// the run's length (Blender's rule); unchanged without a `#` or a frame.
pub fn frame_path(path: &Path, frame: Option<u32>) -> PathBuf {
    let (Some(frame), Some(name)) = (frame, path.file_name().and_then(|n| n.to_str())) else {
        return path.to_owned();
    };
    let Some(end) = name.rfind('#').map(|i| i + 1) else {
        return path.to_owned();
    };
    let start = name[..end].trim_end_matches('#').len();
    let width = end - start;
    let name = format!("{}{frame:0width$}{}", &name[..start], &name[end..]);
    path.with_file_name(name)
}

/// A time in seconds: finite and not negative.
fn parse_time(text: &str) -> Result<f64, ValueError> {
    match text.trim().parse::<f64>() {
        Ok(time) if time.is_finite() && time >= 0.0 => Ok(time),
        _ => Err(ValueError::NotTime { text: text.into() }),
    }
}

/// Frames per second: finite and above 0.
fn parse_fps(text: &str) -> Result<f64, ValueError> {
    match text.trim().parse::<f64>() {
        Ok(fps) if fps.is_finite() && fps > 0.0 => Ok(fps),
        _ => Err(ValueError::NotFrameRate { text: text.into() }),
    }
}

/// START..END with START < END, at most `MAX_FRAMES` frames.
fn parse_frames(text: &str) -> Result<Range<u32>, ValueError> {
    let frames = parse_range(text)
        .filter(|r| !r.is_empty())
        .ok_or_else(|| ValueError::NotFrameRange { text: text.into() })?;
    if frames.len() > MAX_FRAMES as usize {
        return Err(ValueError::TooManyFrames {
            text: text.into(),
            count: u64::from(frames.end - frames.start),
        });
    }
    Ok(frames)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_of_hashes_takes_the_padded_frame() {
        let path = |p: &str, f| frame_path(Path::new(p), f);
        assert_eq!(path("out_####.png", Some(7)), PathBuf::from("out_0007.png"));
        assert_eq!(path("d#/f_#.exr", Some(12)), PathBuf::from("d#/f_12.exr"));
        assert_eq!(path("a##b##.png", Some(3)), PathBuf::from("a##b03.png"));
        assert_eq!(path("plain.png", Some(3)), PathBuf::from("plain.png"));
        assert_eq!(path("out_##.png", None), PathBuf::from("out_##.png"));
    }

    #[test]
    fn bad_times_rates_and_ranges_are_refused() {
        assert!(parse_time("-1").is_err());
        assert!(parse_time("nan").is_err());
        assert_eq!(parse_time("0.5"), Ok(0.5));
        assert!(parse_fps("0").is_err());
        assert!(parse_fps("-24").is_err());
        assert!(parse_frames("5..2").is_err());
        assert!(parse_frames("3..3").is_err());
        assert_eq!(parse_frames("2..5"), Ok(2..5));
        assert!(parse_frames("0..4000000000").is_err());
        assert!(parse_frames("7..1000008").is_err());
        assert_eq!(parse_frames("7..1000007"), Ok(7..1_000_007));
        assert_eq!(
            parse_frames("4294967000..4294967295"),
            Ok(4_294_967_000..4_294_967_295)
        );
    }

    #[test]
    fn a_long_range_is_iterated_lazily() {
        let args = FrameArgs {
            time: None,
            frames: Some(0..MAX_FRAMES),
            fps: 24.0,
            animation: None,
            skip_existing: false,
        };
        let last = args.frame_times().last().map(|f| f.frame);
        assert_eq!(last, Some(Some(MAX_FRAMES - 1)));
        let still = FrameArgs {
            frames: None,
            time: Some(0.5),
            ..args
        };
        let times: Vec<FrameTime> = still.frame_times().collect();
        assert_eq!(
            times,
            vec![FrameTime {
                frame: None,
                time: 0.5
            }]
        );
    }

    #[test]
    fn frame_f_is_at_f_over_fps() {
        let args = FrameArgs {
            time: None,
            frames: Some(3..5),
            fps: 2.0,
            animation: None,
            skip_existing: false,
        };
        let times: Vec<f64> = args.frame_times().map(|f| f.time).collect();
        assert_eq!(times, vec![1.5, 2.0]);
        assert!(args.check_outputs(&[PathBuf::from("a.png")]).is_err());
        assert!(args.check_outputs(&[PathBuf::from("a_#.png")]).is_ok());
    }
}
