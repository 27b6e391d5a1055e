//! Motion vectors (`--aov motion`, issue 56): for each pixel's first hit (the ground truth's
//! ray through the pixel centre, `crate::render::ground_truth`), where that surface point is
//! seen in the next frame's image and in the previous frame's, in pixels: Kubric's forward
//! and backward flow, Cycles' vector pass (with its signs and its y made ours, below).
//!
//! How: the ID pass gives the hit triangle and the hit's barycentrics. The same barycentric
//! point on the same triangle of the scene posed one frame later (`FrameNeighbours`: the
//! glTF file posed at t + 1 / fps with `GltfFile::pose`, the camera at that time) is where
//! the surface point went, exactly, whatever moved it: the camera, node transforms, skins or
//! morph targets. Projected with that time's camera (`CameraData::project`, OpenCV's pixel
//! coordinates) it gives the pixel it is seen at; the flow is that minus where it is seen
//! now (the current camera's projection of the current point, which is the pixel's centre
//! up to rounding).
//!
//! Conventions (as `crate::camera_data`'s): pixels, x to the right, y down (rows top-down),
//! the full image's pixels (a region's flow is the full render's). `motion_forward` =
//! (u, v) in the next frame - (u, v) in this one, so that pixel + forward flow is where the
//! point lands next frame; `motion_backward` = (u, v) in the previous frame - (u, v) in this
//! one. The third channel is 1 where the flow is defined (the ray hit something and the
//! point is in front of the other frame's camera), else 0 with a flow of 0. Occlusion in
//! the other frame is not tested: a point hidden there still has its flow.
//!
//! A still render (no animation, or nothing moves) has no neighbours: its flow is 0 (with
//! 1 in the third channel where the ray hit), and the command line says so in one note.

use glam::Vec3;
use thiserror::Error;

use crate::camera::Camera;
use crate::camera_data::CameraData;
use crate::render::ground_truth::FirstHits;
use crate::scene::Scene;

/// The EXR layer of the forward flow.
pub const FORWARD_LAYER: &str = "motion_forward";

/// The EXR layer of the backward flow.
pub const BACKWARD_LAYER: &str = "motion_backward";

/// The scene at one neighbouring frame's time: every triangle's vertices (world space, in
/// the order of `Scene::triangles`) and the camera.
#[derive(Clone, Debug, PartialEq)]
pub struct NeighbourPose {
    /// The time in seconds.
    pub time: f64,
    /// Each triangle's v_0, v_1, v_2 at that time.
    pub triangles: Vec<[Vec3; 3]>,
    /// The camera at that time.
    pub camera: Camera,
}

/// A frame's scene one frame interval before and after it (at t - 1 / fps and t + 1 / fps),
/// what motion vectors compare the frame with.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameNeighbours {
    /// At t - 1 / fps: the backward flow's.
    pub previous: NeighbourPose,
    /// At t + 1 / fps: the forward flow's.
    pub next: NeighbourPose,
}

/// Why a frame's neighbours cannot give its motion vectors.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum MotionVectorError {
    /// A neighbour's scene does not have the frame's triangles (one degenerate at one time).
    #[error("--aov motion: the scene has {found} triangles at {time} s and {expected} at the frame's time (a triangle of zero area at one of them?); the frames' triangles cannot be paired")]
    TriangleCount {
        /// The neighbour's time in seconds.
        time: f64,
        /// Its triangle count.
        found: usize,
        /// The frame's.
        expected: usize,
    },
}

impl NeighbourPose {
    /// `scene` (posed at `time`) seen by `camera`.
    pub fn new(time: f64, scene: &Scene, camera: Camera) -> NeighbourPose {
        NeighbourPose {
            time,
            triangles: scene.triangles.iter().map(|t| t.positions).collect(),
            camera,
        }
    }
}

impl FrameNeighbours {
    /// The neighbours of a frame whose scene has `triangles` triangles; an error where a
    /// neighbour's count differs (its triangles cannot be paired with the frame's).
    pub fn new(
        triangles: usize,
        previous: NeighbourPose,
        next: NeighbourPose,
    ) -> Result<FrameNeighbours, MotionVectorError> {
        for pose in [&previous, &next] {
            if pose.triangles.len() != triangles {
                return Err(MotionVectorError::TriangleCount {
                    time: pose.time,
                    found: pose.triangles.len(),
                    expected: triangles,
                });
            }
        }
        Ok(FrameNeighbours { previous, next })
    }

    /// Whether nothing moves between the neighbours and the frame (`scene` seen by
    /// `camera`): every triangle and the camera the same, bit for bit.
    pub fn is_still(&self, scene: &Scene, camera: &Camera) -> bool {
        [&self.previous, &self.next].iter().all(|pose| {
            pose.camera == *camera
                && pose
                    .triangles
                    .iter()
                    .zip(&scene.triangles)
                    .all(|(a, b)| *a == b.positions)
        })
    }
}

/// The forward and backward flow (`FORWARD_LAYER`, `BACKWARD_LAYER`) of each pixel's first
/// hit `hits` of `scene` seen by `camera` in an image of `width` x `height` pixels (the full
/// image's, also for a region's hits), rows top-down: (du, dv, defined) per pixel, as the
/// module says; all 0 where nothing was hit. Without `neighbours` (a still render) the flow
/// is 0.
pub fn motion_pixels(
    scene: &Scene,
    camera: &Camera,
    hits: &FirstHits,
    neighbours: Option<&FrameNeighbours>,
    (width, height): (u32, u32),
) -> [Vec<[f32; 3]>; 2] {
    let now = CameraData::of(camera, width, height);
    let flow = |other: Option<&NeighbourPose>| -> Vec<[f32; 3]> {
        let then = other.map(|pose| CameraData::of(&pose.camera, width, height));
        hits.hits
            .iter()
            .map(|hit| {
                let Some(hit) = hit else {
                    return [0.0; 3];
                };
                let index = hit.triangle as usize;
                let (Some(here), Some(there)) = (
                    scene.triangles.get(index).map(|t| t.positions),
                    match other {
                        Some(pose) => pose.triangles.get(index).copied(),
                        None => scene.triangles.get(index).map(|t| t.positions),
                    },
                ) else {
                    return [0.0; 3];
                };
                let seen_now = now.project(interpolate(here, hit.barycentrics));
                let seen_then = then
                    .as_ref()
                    .unwrap_or(&now)
                    .project(interpolate(there, hit.barycentrics));
                match (seen_now, seen_then) {
                    (Some([u0, v0]), Some([u1, v1])) => [(u1 - u0) as f32, (v1 - v0) as f32, 1.0],
                    _ => [0.0; 3],
                }
            })
            .collect()
    };
    [
        flow(neighbours.map(|n| &n.next)),
        flow(neighbours.map(|n| &n.previous)),
    ]
}

/// b_0 a + b_1 b + b_2 c.
fn interpolate([a, b, c]: [Vec3; 3], w: Vec3) -> Vec3 {
    w.x * a + w.y * b + w.z * c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::ground_truth::FirstHit;
    use crate::scene::Triangle;

    /// One triangle in the plane z = 0 seen from (0, 0, 4), 16 x 16 pixels over [-2, 2]^2
    /// (tan(fov / 2) = 1/2), as tests/ground_truth_cli.rs's camera.
    fn still() -> (Scene, Camera) {
        let positions = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let scene = Scene {
            triangles: vec![Triangle::new(positions, Vec3::ONE, Vec3::ZERO, false).unwrap()],
            ..Scene::default()
        };
        let camera = Camera::look_at(
            Vec3::new(0.0, 0.0, 4.0),
            Vec3::ZERO,
            Vec3::Y,
            2.0 * 0.5f32.atan(),
        );
        (scene, camera)
    }

    #[test]
    fn a_point_moved_right_flows_right_and_a_still_one_not_at_all() {
        let (scene, camera) = still();
        // The triangle's centroid, and a miss
        let hits = FirstHits {
            width: 2,
            height: 1,
            hits: vec![
                Some(FirstHit {
                    triangle: 0,
                    barycentrics: Vec3::splat(1.0 / 3.0),
                }),
                None,
            ],
        };
        let shifted = |dx: f32| {
            let mut triangles: Vec<[Vec3; 3]> = vec![scene.triangles[0].positions];
            for v in &mut triangles[0] {
                v.x += dx;
            }
            NeighbourPose {
                time: 0.0,
                triangles,
                camera,
            }
        };
        // 0.25 world units in the plane z = 0 is one pixel
        let neighbours = FrameNeighbours::new(1, shifted(-0.5), shifted(0.25)).unwrap();
        assert!(!neighbours.is_still(&scene, &camera));
        let [forward, backward] =
            motion_pixels(&scene, &camera, &hits, Some(&neighbours), (16, 16));
        assert!((forward[0][0] - 1.0).abs() < 1e-4 && forward[0][1].abs() < 1e-4);
        assert!((backward[0][0] + 2.0).abs() < 1e-4, "{backward:?}");
        assert_eq!(forward[0][2], 1.0);
        assert_eq!(forward[1], [0.0; 3]);
        // Still: exactly 0, defined where hit
        let [forward, _] = motion_pixels(&scene, &camera, &hits, None, (16, 16));
        assert_eq!(forward, vec![[0.0, 0.0, 1.0], [0.0; 3]]);
        // Behind the next camera: undefined
        let mut behind = shifted(0.0);
        behind.camera.position.z = -1.0;
        behind.camera.image_plane_middle.z = -2.0;
        let neighbours = FrameNeighbours::new(1, shifted(0.0), behind).unwrap();
        let [forward, backward] =
            motion_pixels(&scene, &camera, &hits, Some(&neighbours), (16, 16));
        assert_eq!(forward[0], [0.0; 3]);
        assert_eq!(backward[0], [0.0, 0.0, 1.0]);
    }

    #[test]
    fn neighbours_with_other_triangles_are_refused() {
        let (_, camera) = still();
        let pose = |n: usize| NeighbourPose {
            time: 0.5,
            triangles: vec![[Vec3::ZERO; 3]; n],
            camera,
        };
        assert_eq!(
            FrameNeighbours::new(2, pose(2), pose(1)),
            Err(MotionVectorError::TriangleCount {
                time: 0.5,
                found: 1,
                expected: 2
            })
        );
    }
}
