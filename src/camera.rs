//! The workshop's pinhole camera (Part 1): a camera position and an image plane given by its
//! left-bottom corner and its right and up edge vectors. Every camera vkpath knows (the
//! workshop's, glTF's perspective cameras, look-at cameras for OBJ) is expressed this way.

use glam::Vec3;

/// A pinhole camera, independent of the image's aspect ratio (world space, metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The pinhole.
    pub position: Vec3,
    /// The centre of the image plane.
    pub image_plane_middle: Vec3,
    /// The image plane's full-height edge vector, pointing up in the image.
    pub up: Vec3,
    /// The image plane's full-width edge vector for an aspect ratio (width / height) of 1,
    /// pointing right in the image.
    pub right_per_unit_aspect: Vec3,
}

/// The image plane of a camera for one aspect ratio: what `get_primary_ray_direction` takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImagePlane {
    /// The pinhole, world space.
    pub camera_position: Vec3,
    /// The image plane's left-bottom corner, world space.
    pub left_bottom: Vec3,
    /// Full-width edge vector, world space.
    pub right: Vec3,
    /// Full-height edge vector, world space.
    pub up: Vec3,
}

impl Camera {
    /// A camera at `position` looking at `target`, with `up_hint` giving the image's up
    /// direction (it need not be orthogonal to the view direction, only not parallel) and
    /// `vertical_fov` the full vertical opening angle in radians, in (0, pi).
    pub fn look_at(position: Vec3, target: Vec3, up_hint: Vec3, vertical_fov: f32) -> Camera {
        let forward = (target - position).normalize();
        let right_direction = forward.cross(up_hint).normalize();
        let up_direction = right_direction.cross(forward);
        // The image plane lies at distance 1 from the pinhole.
        let height = 2.0 * (0.5 * vertical_fov).tan();
        Camera {
            position,
            image_plane_middle: position + forward,
            up: height * up_direction,
            right_per_unit_aspect: height * right_direction,
        }
    }

    /// The image plane for an image of `aspect` = width / height:
    /// left_bottom = middle - right / 2 - up / 2, right = aspect * right_per_unit_aspect.
    pub fn image_plane(&self, aspect: f32) -> ImagePlane {
        let right = aspect * self.right_per_unit_aspect;
        ImagePlane {
            camera_position: self.position,
            left_bottom: self.image_plane_middle - 0.5 * right - 0.5 * self.up,
            right,
            up: self.up,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_centre_ray_points_at_target() {
        let camera = Camera::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y, 1.0);
        let plane = camera.image_plane(2.0);
        let centre = plane.left_bottom + 0.5 * plane.right + 0.5 * plane.up;
        let direction = (centre - plane.camera_position).normalize();
        let expected = (Vec3::ZERO - camera.position).normalize();
        assert!(direction.abs_diff_eq(expected, 1e-6));
        // Vertical opening angle: the top and bottom edge rays are 1 radian apart.
        let bottom = (plane.left_bottom + 0.5 * plane.right - plane.camera_position).normalize();
        let top = (bottom * 0.0 + plane.left_bottom + 0.5 * plane.right + plane.up
            - plane.camera_position)
            .normalize();
        assert!((bottom.angle_between(top) - 1.0).abs() < 1e-5);
        // Width is aspect times height.
        assert!((plane.right.length() - 2.0 * plane.up.length()).abs() < 1e-5);
    }
}
