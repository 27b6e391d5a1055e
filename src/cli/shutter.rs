//! `vkpath render`'s motion blur: `--shutter`, `--shutter-position` and `--motion-steps`
//! (Blender's Shutter and Position; Cycles' motion steps), and the scene posed at the
//! shutter's keys (`SceneMotion`).

use crate::camera::Camera;
use crate::cli::value_error::ValueError;
use crate::scene::animation::AnimationPick;
use crate::scene::gltf_file::GltfFile;
use crate::scene::motion::{
    SceneMotion, Shutter, ShutterPosition, DEFAULT_MOTION_STEPS, MAX_MOTION_STEPS,
    MAX_SHUTTER_FRAMES,
};
use crate::scene::Scene;

/// Motion blur's options.
#[derive(Debug, Clone, clap::Args)]
pub struct ShutterArgs {
    /// Motion blur: open the shutter for this many frame intervals (1 / --fps each; 0 to 2,
    /// a warning above 1), around the frame's time (--frames) or --time; each sample sees the
    /// scene (camera, node transforms, skins, morph targets) at a time within it. 0: none.
    #[arg(long, value_name = "FRAMES", value_parser = parse_shutter, allow_hyphen_values = true)]
    pub shutter: Option<f64>,
    /// Where the shutter interval lies around the frame's time.
    #[arg(long, value_enum, value_name = "POSITION", default_value_t = ShutterPosition::Center)]
    pub shutter_position: ShutterPosition,
    /// How many keys, evenly spread across the shutter, the scene is posed at (2 to 64); it
    /// moves linearly between two keys: more for rotations and curved paths.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MOTION_STEPS, value_parser = parse_motion_steps)]
    pub motion_steps: u32,
}

impl ShutterArgs {
    /// The shutter asked for, if any (`--shutter 0`: none).
    pub fn shutter(&self) -> Option<Shutter> {
        let frames = self.shutter.filter(|&frames| frames > 0.0)?;
        Shutter::new(frames, self.shutter_position, self.motion_steps).ok()
    }

    /// The warnings these options call for: a shutter longer than a frame interval (frames
    /// then overlap in time, as Blender allows), and the shutter's other options without one.
    pub fn warnings(&self) -> Vec<String> {
        let mut warnings = Vec::new();
        match self.shutter {
            Some(frames) if frames > 1.0 => warnings.push(format!(
                "--shutter {frames}: the shutter stays open longer than a frame interval, so each frame's blur overlaps the next's"
            )),
            Some(frames) if frames > 0.0 => {}
            _ => {
                if self.shutter_position != ShutterPosition::Center {
                    warnings.push("--shutter-position has no effect without --shutter".into());
                }
                if self.motion_steps != DEFAULT_MOTION_STEPS {
                    warnings.push("--motion-steps has no effect without --shutter".into());
                }
            }
        }
        warnings
    }
}

/// Where a shutter lies in time: around the frame at `time` seconds, played at `fps`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeyTimes {
    /// The frame's time in seconds.
    pub time: f64,
    /// Frames per second (a frame interval is 1 / fps).
    pub fps: f64,
}

/// `file`'s animations `pick` chooses posed at `shutter`'s keys around `at`, each key with
/// the camera `camera_at` gives for its scene; `None` where nothing moves across the
/// shutter (the still image is the blurred one).
pub fn pose_keys(
    file: &mut GltfFile,
    shutter: Shutter,
    at: KeyTimes,
    pick: &AnimationPick,
    mut camera_at: impl FnMut(&Scene) -> anyhow::Result<Camera>,
) -> anyhow::Result<Option<SceneMotion>> {
    let times = shutter.key_times(at.time, at.fps);
    let mut poses = Vec::with_capacity(times.len());
    for &time in &times {
        let key = file.pose(time as f32, pick)?;
        let camera = camera_at(&key)?;
        poses.push((key, camera));
    }
    let motion = SceneMotion::new(shutter, poses, &times)?;
    Ok((!motion.is_still()).then_some(motion))
}

/// A shutter in frame intervals: finite, 0 to `MAX_SHUTTER_FRAMES`.
fn parse_shutter(text: &str) -> Result<f64, ValueError> {
    match text.trim().parse::<f64>() {
        Ok(frames) if (0.0..=MAX_SHUTTER_FRAMES).contains(&frames) => Ok(frames),
        _ => Err(ValueError::NotShutter { text: text.into() }),
    }
}

/// A number of keys, 2 to `MAX_MOTION_STEPS`.
fn parse_motion_steps(text: &str) -> Result<u32, ValueError> {
    match text.trim().parse::<u32>() {
        Ok(steps) if (2..=MAX_MOTION_STEPS).contains(&steps) => Ok(steps),
        _ => Err(ValueError::NotMotionSteps { text: text.into() }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_shutters_and_steps_are_refused() {
        for bad in ["-0.5", "2.5", "nan", "inf", "x"] {
            assert!(parse_shutter(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_shutter("0.5"), Ok(0.5));
        assert_eq!(parse_shutter("2"), Ok(2.0));
        for bad in ["0", "1", "65", "-2", "two"] {
            assert!(parse_motion_steps(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_motion_steps("64"), Ok(64));
    }

    #[test]
    fn a_long_shutter_and_lone_options_are_warned_about() {
        let args = |shutter, steps| ShutterArgs {
            shutter,
            shutter_position: ShutterPosition::Center,
            motion_steps: steps,
        };
        assert_eq!(args(Some(1.5), 2).warnings().len(), 1);
        assert!(args(Some(1.0), 4).warnings().is_empty());
        assert_eq!(args(None, 4).warnings().len(), 1);
        assert!(args(Some(0.0), 2).shutter().is_none());
        assert_eq!(args(Some(0.5), 3).shutter().map(|s| s.steps), Some(3));
    }
}
