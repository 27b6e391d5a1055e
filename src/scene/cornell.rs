//! The workshop's Cornell box (`scenes/workshop_cornell_box.json`): 30 triangles and the
//! camera hard-coded in the Path Tracing Workshop's exercises, embedded in the binary.

use glam::Vec3;
use serde::Deserialize;

use super::{Scene, SceneError, Triangle};
use crate::camera::Camera;

/// The scene file, compiled in so that vkpath renders something with no input at all.
const WORKSHOP_CORNELL_BOX_JSON: &str = include_str!("../../scenes/workshop_cornell_box.json");

/// The file's layout; other fields (descriptions) are ignored.
#[derive(Deserialize)]
struct CornellFile {
    camera: CornellCamera,
    triangles: Vec<CornellTriangle>,
}

/// The workshop's camera, already in our `Camera`'s form.
#[derive(Deserialize)]
struct CornellCamera {
    position: [f32; 3],
    middle: [f32; 3],
    up: [f32; 3],
    right_per_unit_aspect: [f32; 3],
}

/// One `triangle_t` of the workshop.
#[derive(Deserialize)]
struct CornellTriangle {
    positions: [[f32; 3]; 3],
    normal: [f32; 3],
    color: [f32; 3],
    emission: [f32; 3],
}

/// The workshop's Cornell box and camera. The normals are taken as stored rather than
/// recomputed, so that the scene matches the workshop's bit for bit; a test checks that they
/// are unit length and agree with the counter-clockwise winding.
pub fn workshop_cornell_box() -> Result<Scene, SceneError> {
    let file: CornellFile =
        serde_json::from_str(WORKSHOP_CORNELL_BOX_JSON).map_err(|error| SceneError::Builtin {
            reason: error.to_string(),
        })?;
    let triangles = file
        .triangles
        .iter()
        .map(|t| Triangle {
            positions: t.positions.map(Vec3::from),
            normal: Vec3::from(t.normal),
            color: Vec3::from(t.color),
            emission: Vec3::from(t.emission),
            double_sided: false,
        })
        .collect();
    let camera = Camera {
        position: Vec3::from(file.camera.position),
        image_plane_middle: Vec3::from(file.camera.middle),
        up: Vec3::from(file.camera.up),
        right_per_unit_aspect: Vec3::from(file.camera.right_per_unit_aspect),
        lens: crate::camera::Lens::PINHOLE,
    };
    Ok(Scene {
        triangles,
        camera: Some(camera),
        warnings: Vec::new(),
        materials: None,
        punctual_lights: Vec::new(),
        environment: None,
        cameras: vec![camera],
        mesh_instances: Vec::new(),
        motion: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn has_thirty_triangles_and_a_ceiling_light() {
        let scene = workshop_cornell_box().unwrap();
        assert_eq!(scene.triangles.len(), 30);
        assert!(scene.warnings.is_empty());
        for (index, triangle) in scene.triangles.iter().enumerate() {
            let is_light = index == 24 || index == 29;
            if is_light {
                assert_eq!(triangle.emission, Vec3::splat(3.0), "triangle {index}");
                assert_eq!(triangle.color, Vec3::ZERO, "triangle {index}");
                // The ceiling (z = 0.5488 in Blender's z-up frame) faces down into the box.
                assert_eq!(triangle.normal, Vec3::NEG_Z, "triangle {index}");
            } else {
                assert_eq!(triangle.emission, Vec3::ZERO, "triangle {index}");
            }
            assert!(!triangle.double_sided);
        }
    }

    #[test]
    fn stored_normals_are_unit_and_match_the_winding() {
        let scene = workshop_cornell_box().unwrap();
        for (index, triangle) in scene.triangles.iter().enumerate() {
            let [v0, v1, v2] = triangle.positions;
            let geometric = (v1 - v0).cross(v2 - v0).normalize();
            assert!(
                (triangle.normal.length() - 1.0).abs() < 1e-4,
                "triangle {index}: |n| = {}",
                triangle.normal.length()
            );
            // Same side as the counter-clockwise cross product, and in fact the same
            // direction up to the float32 rounding of the exported vertices.
            assert!(triangle.normal.dot(geometric) > 0.9999, "triangle {index}");
        }
    }

    #[test]
    fn camera_is_the_workshops() {
        let camera = workshop_cornell_box().unwrap().camera.unwrap();
        assert_eq!(camera.position, Vec3::new(0.278, 0.8, 0.2744));
        assert_eq!(camera.image_plane_middle, Vec3::new(0.278, 0.0, 0.2744));
        assert_eq!(camera.up, Vec3::new(0.0, 0.0, 0.56));
        assert_eq!(camera.right_per_unit_aspect, Vec3::new(-0.56, 0.0, 0.0));
        assert_eq!(Scene::builtin_cornell_box().unwrap().camera, Some(camera));
    }
}
