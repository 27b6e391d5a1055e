//! A frame's camera as machine-learning datasets take it (issue 56): the intrinsics matrix K
//! in pixels and the camera-to-world matrix, in OpenCV's and OpenGL's conventions, with the
//! fields of view and an equivalent sensor. `render --json` reports it as `camera_data`,
//! `--camera-data` writes it beside each output (`NAME.json`), Python returns it as
//! `result.camera`.
//!
//! Conventions (stated once, here and in the README):
//! - OpenCV: camera x right, y down, z forward (into the scene); image coordinates (u, v) in
//!   pixels, u to the right, v down, the centre of the top-left pixel at (0, 0). A camera
//!   point (x, y, z) is seen at u = fx x / z + cx, v = fy y / z + cy.
//! - OpenGL (and Blender, glTF): camera x right, y up, z backward (the camera looks down -z).
//!   The same camera-to-world matrix with its y and z columns negated.
//!
//! The renderer's pinhole sees everything in front of it: `near` is 0 and `far` is `None`
//! (infinite); a projection matrix for a rasteriser picks its own.

use glam::{DVec3, Vec3};

use crate::camera::Camera;

/// Width of the sensor that `CameraData::focal_length_mm` refers to: a 36 mm full frame,
/// Blender's default (its sensor fit `horizontal`).
pub const SENSOR_WIDTH_MM: f64 = 36.0;

/// One frame's camera, for an image of `width` x `height` pixels.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CameraData {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The intrinsics matrix K (rows), pixels, OpenCV convention:
    /// [[fx, 0, cx], [0, fy, cy], [0, 0, 1]].
    pub k: [[f64; 3]; 3],
    /// Camera to world (rows, the last [0, 0, 0, 1]), OpenCV axes: x right, y down, z forward.
    pub camera_to_world_opencv: [[f64; 4]; 4],
    /// Camera to world (rows), OpenGL axes: x right, y up, z backward.
    pub camera_to_world_opengl: [[f64; 4]; 4],
    /// The near clipping distance: 0 (a path tracer clips nothing).
    pub near: f64,
    /// The far clipping distance: `None`, infinite.
    pub far: Option<f64>,
    /// Full horizontal field of view, degrees.
    pub fov_x_degrees: f64,
    /// Full vertical field of view, degrees.
    pub fov_y_degrees: f64,
    /// The sensor's width that `focal_length_mm` refers to (`SENSOR_WIDTH_MM`).
    pub sensor_width_mm: f64,
    /// The sensor's height at this aspect ratio.
    pub sensor_height_mm: f64,
    /// The focal length on that sensor: sensor width * fx / width.
    pub focal_length_mm: f64,
    /// The thin lens's aperture radius, world units (0: a pinhole).
    pub aperture_radius: f64,
    /// The distance in focus, world units (meaningful with an aperture).
    pub focus_distance: f64,
}

impl CameraData {
    /// The data of `camera` for an image of `width` x `height` pixels (the full image, also
    /// for a region: K's pixels are the full image's).
    pub fn of(camera: &Camera, width: u32, height: u32) -> CameraData {
        let plane = camera.image_plane(width as f32 / height as f32);
        let to_middle = (camera.image_plane_middle - camera.position).as_dvec3();
        let distance = to_middle.length();
        let forward = to_middle / distance;
        let right = plane.right.as_dvec3();
        let up = plane.up.as_dvec3();
        let (w, h) = (f64::from(width), f64::from(height));
        // The image plane at `distance` is |right| wide over `width` pixels
        let fx = w * distance / right.length();
        let fy = h * distance / up.length();
        let k = [
            [fx, 0.0, 0.5 * w - 0.5],
            [0.0, fy, 0.5 * h - 0.5],
            [0.0, 0.0, 1.0],
        ];
        let x = right.normalize();
        let y_down = -up.normalize();
        let position = camera.position.as_dvec3();
        let matrix = |x: DVec3, y: DVec3, z: DVec3| {
            [
                [x.x, y.x, z.x, position.x],
                [x.y, y.y, z.y, position.y],
                [x.z, y.z, z.z, position.z],
                [0.0, 0.0, 0.0, 1.0],
            ]
        };
        let fov = |size: f64, f: f64| (2.0 * (0.5 * size / f).atan()).to_degrees();
        CameraData {
            width,
            height,
            k,
            camera_to_world_opencv: matrix(x, y_down, forward),
            camera_to_world_opengl: matrix(x, -y_down, -forward),
            near: 0.0,
            far: None,
            fov_x_degrees: fov(w, fx),
            fov_y_degrees: fov(h, fy),
            sensor_width_mm: SENSOR_WIDTH_MM,
            sensor_height_mm: SENSOR_WIDTH_MM * h / w,
            focal_length_mm: SENSOR_WIDTH_MM * fx / w,
            aperture_radius: f64::from(camera.lens.aperture_radius),
            focus_distance: f64::from(camera.lens.focus_distance),
        }
    }

    /// Where the world point `point` is seen, in OpenCV's pixel coordinates (u, v), through
    /// K and the inverse of `camera_to_world_opencv`; `None` behind the camera.
    pub fn project(&self, point: Vec3) -> Option<[f64; 2]> {
        let m = &self.camera_to_world_opencv;
        let offset = point.as_dvec3() - DVec3::new(m[0][3], m[1][3], m[2][3]);
        // The rotation's inverse is its transpose: the camera point is (column . offset)
        let axis = |c: usize| DVec3::new(m[0][c], m[1][c], m[2][c]).dot(offset);
        let (x, y, z) = (axis(0), axis(1), axis(2));
        if z <= 0.0 {
            return None;
        }
        let k = &self.k;
        Some([k[0][0] * x / z + k[0][2], k[1][1] * y / z + k[1][2]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn k_projects_a_point_where_the_camera_ray_through_it_leaves_the_image_plane() {
        let camera = Camera::look_at(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.0, 0.5, -1.0),
            Vec3::Y,
            0.9,
        );
        let (width, height) = (64, 48);
        let data = CameraData::of(&camera, width, height);
        // The point at image coordinates (s, t) from the left-bottom corner (in [0, 1]),
        // pushed 7 units along its ray: pixel (s W - 0.5, (1 - t) H - 0.5) in OpenCV's terms.
        let plane = camera.image_plane(width as f32 / height as f32);
        for (s, t) in [(0.5, 0.5), (0.1, 0.9), (0.75, 0.2)] {
            let through = plane.left_bottom + s * plane.right + t * plane.up;
            let point = camera.position + 7.0 * (through - camera.position);
            let [u, v] = data.project(point).unwrap();
            let want = [f64::from(s) * 64.0 - 0.5, (1.0 - f64::from(t)) * 48.0 - 0.5];
            assert!((u - want[0]).abs() < 1e-3, "{u} != {}", want[0]);
            assert!((v - want[1]).abs() < 1e-3, "{v} != {}", want[1]);
        }
        assert!((data.fov_y_degrees - 0.9f64.to_degrees()).abs() < 1e-4);
        // OpenGL looks down its -z: the view direction
        let m = data.camera_to_world_opengl;
        let back = DVec3::new(m[0][2], m[1][2], m[2][2]);
        let view = (Vec3::new(0.0, 0.5, -1.0) - camera.position)
            .as_dvec3()
            .normalize();
        assert!((back + view).length() < 1e-6);
        assert!(data
            .project(camera.position - Vec3::new(0.0, 0.5, -4.0))
            .is_none());
    }
}
