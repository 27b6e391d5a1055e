//! The workshop's pinhole camera (Part 1): a camera position and an image plane given by its
//! left-bottom corner and its right and up edge vectors. Every camera vkpath knows (the
//! workshop's, glTF's perspective cameras, look-at cameras for OBJ) is expressed this way.

use glam::Vec3;
use thiserror::Error;

/// The vertical field of view of a look-at camera when none is given, in degrees.
pub const DEFAULT_VERTICAL_FOV_DEGREES: f32 = 45.0;

/// Why a look-at camera cannot be made. The messages name the `vkpath render` options that
/// give a look-at camera's parameters.
#[derive(Clone, Copy, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum CameraError {
    /// The vertical field of view is not in (0, 180) degrees (or is NaN).
    #[error("--fov {0} is outside (0, 180) degrees")]
    FieldOfView(f32),
    /// The camera position equals the target, or the view direction is parallel to up.
    #[error(
        "--camera-position, --look-at and --up do not define a view (the view direction is zero or parallel to --up)"
    )]
    NoViewDirection,
}

/// A thin lens in front of the pinhole (depth of field): rays leave from a point of the
/// aperture and pass through the point of the focus plane that the pinhole's ray meets, as in
/// Mitsuba's `thinlens` and pbrt's perspective camera. `Lens::PINHOLE` (radius 0) is the
/// workshop's pinhole, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lens {
    /// Radius of the aperture, world units (0: a pinhole). A polygonal aperture's corners
    /// lie on this circle.
    pub aperture_radius: f32,
    /// Distance from the pinhole to the plane in focus, along the view axis, world units.
    pub focus_distance: f32,
    /// Number of aperture blades: 0 for a disc, else 3 or more (a regular polygon).
    pub blades: u32,
    /// Rotation of a polygonal aperture about the view axis, radians (0: a corner points up).
    pub rotation: f32,
}

impl Lens {
    /// No lens: the pinhole camera.
    pub const PINHOLE: Lens = Lens {
        aperture_radius: 0.0,
        focus_distance: 1.0,
        blades: 0,
        rotation: 0.0,
    };

    /// Whether this is the pinhole (no depth of field).
    pub fn is_pinhole(&self) -> bool {
        self.aperture_radius == 0.0
    }
}

impl Default for Lens {
    fn default() -> Lens {
        Lens::PINHOLE
    }
}

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
    /// The lens in front of the pinhole (`Lens::PINHOLE`: none).
    pub lens: Lens,
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
    /// The camera's lens (`Lens::PINHOLE`: none).
    pub lens: Lens,
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
            lens: Lens::PINHOLE,
        }
    }

    /// `look_at` for parameters given by a user: refuses a vertical field of view outside
    /// (0, 180) degrees, a `target` equal to `position` and an `up_hint` (numerically)
    /// parallel to the view direction, rather than producing NaNs. `vertical_fov_degrees` is
    /// the full vertical opening angle in degrees.
    pub fn look_at_checked(
        position: Vec3,
        target: Vec3,
        up_hint: Vec3,
        vertical_fov_degrees: f32,
    ) -> Result<Camera, CameraError> {
        // Written so that NaN fails too.
        if !(vertical_fov_degrees > 0.0 && vertical_fov_degrees < 180.0) {
            return Err(CameraError::FieldOfView(vertical_fov_degrees));
        }
        let forward = target - position;
        // |forward x up| = |forward| |up| sin(angle): parallel when the sine is below 1e-6.
        if forward.length() == 0.0
            || forward.cross(up_hint).length() < 1e-6 * forward.length() * up_hint.length()
        {
            return Err(CameraError::NoViewDirection);
        }
        Ok(Camera::look_at(
            position,
            target,
            up_hint,
            vertical_fov_degrees.to_radians(),
        ))
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
            lens: self.lens,
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

    #[test]
    fn look_at_checked_matches_look_at() {
        let (position, target) = (Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO);
        let checked = Camera::look_at_checked(position, target, Vec3::Y, 45.0).unwrap();
        let unchecked = Camera::look_at(position, target, Vec3::Y, 45f32.to_radians());
        assert_eq!(checked, unchecked);
    }

    #[test]
    fn look_at_checked_refuses_fields_of_view_outside_0_to_180_degrees() {
        for fov in [0.0, -10.0, 180.0, 200.0, f32::NAN] {
            let error = Camera::look_at_checked(Vec3::Z, Vec3::ZERO, Vec3::Y, fov).unwrap_err();
            assert!(matches!(error, CameraError::FieldOfView(_)), "{fov}");
            assert!(error.to_string().starts_with("--fov "), "{error}");
            assert!(error.to_string().ends_with(" is outside (0, 180) degrees"));
        }
    }

    #[test]
    fn look_at_checked_refuses_a_zero_view_direction() {
        let point = Vec3::new(1.0, 2.0, 3.0);
        let error = Camera::look_at_checked(point, point, Vec3::Y, 45.0).unwrap_err();
        assert_eq!(error, CameraError::NoViewDirection);
        assert!(
            error.to_string().contains("do not define a view"),
            "{error}"
        );
    }

    #[test]
    fn look_at_checked_refuses_up_parallel_to_the_view_direction() {
        for up in [Vec3::Y, -2.0 * Vec3::Y] {
            let error = Camera::look_at_checked(Vec3::ZERO, Vec3::Y, up, 45.0).unwrap_err();
            assert_eq!(error, CameraError::NoViewDirection, "up {up}");
        }
        // Nearly parallel but not numerically so is a valid (if tilted) view.
        assert!(
            Camera::look_at_checked(Vec3::ZERO, Vec3::Y, Vec3::new(1e-3, 1.0, 0.0), 45.0).is_ok()
        );
    }
}
