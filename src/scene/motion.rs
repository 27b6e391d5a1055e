//! Motion blur's scene: the shutter (`--shutter S` frame intervals, opened at its
//! `--shutter-position` around the frame's time) and the scene posed at `--motion-steps` keys
//! evenly spread across it (`SceneMotion`). Each key is a whole pose of the animation (camera,
//! node transforms, skins and morph targets alike, as `GltfFile::pose` evaluates them), so
//! one mechanism blurs them all: the kernels interpolate each triangle's vertices and the
//! camera linearly between the two keys around a sample's time (Embree's and Cycles' linear
//! motion blur; `glsl/scene.glsl`). Pure data, no device: `render/gpu_motion.rs` packs it.

use glam::Vec3;
use thiserror::Error;

use crate::camera::Camera;
use crate::contract;
use crate::scene::Scene;

/// The default of `--motion-steps`: two keys, the shutter's ends (exact for linear motion).
pub const DEFAULT_MOTION_STEPS: u32 = 2;

/// The most keys a shutter may take (`--motion-steps`).
pub const MAX_MOTION_STEPS: u32 = contract::MAX_MOTION_STEPS;

/// The longest shutter, in frame intervals (`--shutter`); above one frame a warning.
pub const MAX_SHUTTER_FRAMES: f64 = 2.0;

/// Where the shutter interval lies around the frame's time (Blender's Shutter Position).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum ShutterPosition {
    /// The shutter opens at the frame's time.
    Start,
    /// The shutter is centred on the frame's time.
    #[default]
    Center,
    /// The shutter closes at the frame's time.
    End,
}

impl ShutterPosition {
    /// The name the command line and the metadata use: `start`, `center` or `end`.
    pub fn name(self) -> &'static str {
        match self {
            ShutterPosition::Start => "start",
            ShutterPosition::Center => "center",
            ShutterPosition::End => "end",
        }
    }

    /// The share of the shutter interval that lies before the frame's time.
    fn share_before(self) -> f64 {
        match self {
            ShutterPosition::Start => 0.0,
            ShutterPosition::Center => 0.5,
            ShutterPosition::End => 1.0,
        }
    }
}

/// An open shutter: how long, where around the frame's time, and at how many keys the scene
/// is posed across it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shutter {
    /// How long the shutter is open, in frame intervals (1 / fps each), in (0, 2].
    pub frames: f64,
    /// Where the interval lies around the frame's time.
    pub position: ShutterPosition,
    /// How many keys, evenly spread from the shutter's opening to its closing (2 to
    /// `MAX_MOTION_STEPS`).
    pub steps: u32,
}

/// Why a shutter or its keys cannot be used.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum MotionError {
    /// `--motion-steps` out of its range.
    #[error("--motion-steps {0}: give 2 to {MAX_MOTION_STEPS} keys across the shutter")]
    Steps(u32),
    /// `--shutter` out of its range.
    #[error(
        "--shutter {0}: give a shutter above 0 and at most {MAX_SHUTTER_FRAMES} frame intervals"
    )]
    Length(f64),
    /// The keys' scenes do not have the same triangles (one degenerate at some key).
    #[error("motion blur: the scene has {found} triangles at {time} s and {expected} at the shutter's opening (a triangle of zero area at one key?); its keys cannot be paired")]
    TriangleCount {
        /// The key's time in seconds.
        time: f64,
        /// Its triangle count.
        found: usize,
        /// The first key's.
        expected: usize,
    },
}

impl Shutter {
    /// A shutter, checked: `frames` in (0, `MAX_SHUTTER_FRAMES`], `steps` in 2 ..=
    /// `MAX_MOTION_STEPS`.
    pub fn new(frames: f64, position: ShutterPosition, steps: u32) -> Result<Shutter, MotionError> {
        if !(frames > 0.0 && frames <= MAX_SHUTTER_FRAMES) {
            return Err(MotionError::Length(frames));
        }
        if !(2..=MAX_MOTION_STEPS).contains(&steps) {
            return Err(MotionError::Steps(steps));
        }
        Ok(Shutter {
            frames,
            position,
            steps,
        })
    }

    /// The keys' times in seconds, from the shutter's opening to its closing, for a frame at
    /// `time` seconds played at `fps` frames per second: key k at open + k / (steps - 1) of
    /// the interval, which is `frames / fps` seconds long.
    pub fn key_times(&self, time: f64, fps: f64) -> Vec<f64> {
        let length = self.frames / fps;
        let open = time - self.position.share_before() * length;
        let last = f64::from(self.steps - 1);
        (0..self.steps)
            .map(|k| open + length * f64::from(k) / last)
            .collect()
    }
}

/// A triangle at one key: its vertices and unit normal, world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeyTriangle {
    /// v_0, v_1, v_2.
    pub positions: [Vec3; 3],
    /// The unit normal (the side the vertices are counter-clockwise from).
    pub normal: Vec3,
}

/// The scene at the shutter's keys: every triangle's vertices and the camera at each key,
/// the triangles in the order of `Scene::triangles`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneMotion {
    /// The shutter the keys were posed for.
    pub shutter: Shutter,
    /// `triangles[k][i]`: triangle i at key k.
    pub triangles: Vec<Vec<KeyTriangle>>,
    /// The camera at each key.
    pub cameras: Vec<Camera>,
}

impl SceneMotion {
    /// The motion of the keys' `poses` (each key's scene and camera, in key order, at
    /// `times`); an error where two keys' scenes have different triangle counts.
    pub fn new(
        shutter: Shutter,
        poses: Vec<(Scene, Camera)>,
        times: &[f64],
    ) -> Result<SceneMotion, MotionError> {
        let expected = poses.first().map_or(0, |(scene, _)| scene.triangles.len());
        let mut triangles = Vec::with_capacity(poses.len());
        let mut cameras = Vec::with_capacity(poses.len());
        for ((scene, camera), &time) in poses.into_iter().zip(times) {
            if scene.triangles.len() != expected {
                return Err(MotionError::TriangleCount {
                    time,
                    found: scene.triangles.len(),
                    expected,
                });
            }
            triangles.push(
                scene
                    .triangles
                    .iter()
                    .map(|t| KeyTriangle {
                        positions: t.positions,
                        normal: t.normal,
                    })
                    .collect(),
            );
            cameras.push(camera);
        }
        Ok(SceneMotion {
            shutter,
            triangles,
            cameras,
        })
    }

    /// How many keys (`SPEC_MOTION_STEPS`).
    pub fn steps(&self) -> u32 {
        self.triangles.len() as u32
    }

    /// Whether nothing moves: every key's triangles and camera are the first key's, bit for
    /// bit (a shutter on a still scene then renders the still image).
    pub fn is_still(&self) -> bool {
        let (Some(first_triangles), Some(first_camera)) =
            (self.triangles.first(), self.cameras.first())
        else {
            return true;
        };
        self.triangles
            .iter()
            .zip(&self.cameras)
            .all(|(triangles, camera)| triangles == first_triangles && camera == first_camera)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_spread_evenly_across_the_shutter_where_its_position_says() {
        let centred = Shutter::new(0.5, ShutterPosition::Center, 3).unwrap();
        assert_eq!(centred.key_times(1.0, 4.0), vec![0.9375, 1.0, 1.0625]);
        let start = Shutter::new(1.0, ShutterPosition::Start, 2).unwrap();
        assert_eq!(start.key_times(1.0, 4.0), vec![1.0, 1.25]);
        let end = Shutter::new(1.0, ShutterPosition::End, 2).unwrap();
        assert_eq!(end.key_times(1.0, 4.0), vec![0.75, 1.0]);
    }

    #[test]
    fn bad_shutters_are_refused() {
        for frames in [0.0, -0.5, 2.5, f64::NAN] {
            assert!(Shutter::new(frames, ShutterPosition::Center, 2).is_err());
        }
        for steps in [0, 1, 65] {
            assert_eq!(
                Shutter::new(1.0, ShutterPosition::Center, steps),
                Err(MotionError::Steps(steps))
            );
        }
        assert!(Shutter::new(2.0, ShutterPosition::End, 64).is_ok());
    }
}
