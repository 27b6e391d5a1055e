//! The thin lens a user asks for, before the image it serves is known: the aperture by its
//! radius or by an f-number (with a sensor width, as Blender takes it), the focus by a
//! distance or by a pixel to focus on (autofocus), and the aperture's shape. `vkpath render`'s
//! lens options (`cli/lens.rs`) and Python's `Camera(...)` / `render(focus_at=)` both resolve
//! theirs here, for one image size, into the `Lens` the kernels take.

use glam::{UVec2, Vec2};
use thiserror::Error;

use crate::camera::{Camera, ImagePlane, Lens};
use crate::contract::SAMPLER_PCG;
use crate::cpu::get_camera_ray;
use crate::cpu::integrator::ray_mesh_intersection;
use crate::cpu::sobol::PathSample;
use crate::scene::Triangle;

/// The sensor width that an f-number is taken with when none is given, millimetres: a full
/// frame's (Blender's default).
pub const DEFAULT_SENSOR_WIDTH_MM: f32 = 36.0;

/// How large the aperture is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Aperture {
    /// Its radius, world units (0: a pinhole).
    Radius(f32),
    /// An f-number N: a radius of focal length / (2 N), the focal length that of a sensor of
    /// `sensor_width_mm` across the image's longer side at the camera's field of view (world
    /// units taken as metres).
    FStop {
        /// The f-number, above 0.
        f_stop: f32,
        /// The sensor's width, millimetres, above 0.
        sensor_width_mm: f32,
    },
}

/// Where the lens focuses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Focus {
    /// At this distance from the pinhole along the view axis, world units.
    Distance(f32),
    /// On what the pinhole's ray through the centre of this pixel (column, row from the top)
    /// hits.
    Pixel(UVec2),
    /// On what the pinhole's ray through the image's centre hits.
    ImageCentre,
}

/// A thin lens as a user asks for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensRequest {
    /// The aperture's size.
    pub aperture: Aperture,
    /// The plane in focus.
    pub focus: Focus,
    /// Aperture blades: 0 for a disc, else 3 or more (a regular polygon).
    pub blades: u32,
    /// Rotation of a polygonal aperture about the view axis, degrees (0: a corner points up).
    pub rotation_degrees: f32,
}

/// Why a lens's autofocus found no distance.
#[derive(Debug, Error, PartialEq)]
pub enum FocusError {
    /// The pixel to focus on is not in the image.
    #[error("pixel {},{} is outside the {width}x{height} image", pixel.x, pixel.y)]
    OutsideImage {
        /// The pixel asked for.
        pixel: UVec2,
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
    },
    /// The pixel's camera ray hits no triangle.
    #[error("the camera ray through pixel {},{} hits nothing to focus on", pixel.x, pixel.y)]
    NothingHit {
        /// The pixel focused on.
        pixel: UVec2,
    },
}

impl LensRequest {
    /// The lens for a `width` x `height` image of `triangles` seen by `camera` (whose own lens
    /// is ignored), and the focus distance where autofocus found it. An aperture of radius 0
    /// is the pinhole, focused nowhere.
    pub fn resolve(
        &self,
        camera: &Camera,
        triangles: &[Triangle],
        width: u32,
        height: u32,
    ) -> Result<(Lens, Option<f32>), FocusError> {
        let plane = camera.image_plane(width as f32 / height as f32);
        let aperture_radius = match self.aperture {
            Aperture::Radius(radius) => radius,
            Aperture::FStop {
                f_stop,
                sensor_width_mm,
            } => f_stop_aperture_radius(&plane, f_stop, sensor_width_mm),
        };
        if aperture_radius == 0.0 {
            return Ok((Lens::PINHOLE, None));
        }
        let pixel = match self.focus {
            Focus::Distance(distance) => return Ok((self.lens(aperture_radius, distance), None)),
            Focus::Pixel(pixel) => pixel,
            Focus::ImageCentre => UVec2::new(width / 2, height / 2),
        };
        let distance = focus_distance_at(camera, triangles, pixel, width, height)?;
        Ok((self.lens(aperture_radius, distance), Some(distance)))
    }

    /// The lens where it needs no image: an aperture given by its radius and a focus by its
    /// distance (`None` for an f-number or autofocus, which `resolve` decides per image).
    pub fn lens_without_image(&self) -> Option<Lens> {
        match (self.aperture, self.focus) {
            (Aperture::Radius(radius), Focus::Distance(distance)) => {
                Some(self.lens(radius, distance))
            }
            _ => None,
        }
    }

    /// This request's lens with its aperture and focus resolved.
    fn lens(&self, aperture_radius: f32, focus_distance: f32) -> Lens {
        Lens {
            aperture_radius,
            focus_distance,
            blades: self.blades,
            rotation: self.rotation_degrees.to_radians(),
        }
    }
}

/// The aperture radius of f-number `f_stop` for the image plane `plane`: focal length /
/// (2 N), the focal length that of a sensor `sensor_width_mm` wide across the image's longer
/// side (Blender's automatic sensor fit), in metres: focal length / sensor width = the
/// pinhole's distance from the image plane / the plane's longer side.
pub fn f_stop_aperture_radius(plane: &ImagePlane, f_stop: f32, sensor_width_mm: f32) -> f32 {
    let axis = plane.right.cross(plane.up).normalize();
    let middle = plane.left_bottom + 0.5 * (plane.right + plane.up);
    let distance = (middle - plane.camera_position).dot(axis).abs();
    let side = plane.right.length().max(plane.up.length());
    let focal_length_mm = sensor_width_mm * distance / side;
    focal_length_mm / (2.0 * f_stop) / 1000.0
}

/// Autofocus: the distance along the view axis of what the pinhole's ray through the centre
/// of `pixel` (column, row from the top) of a `width` x `height` image hits, found on the CPU
/// by the workshop's ray-mesh intersection.
pub fn focus_distance_at(
    camera: &Camera,
    triangles: &[Triangle],
    pixel: UVec2,
    width: u32,
    height: u32,
) -> Result<f32, FocusError> {
    if pixel.x >= width || pixel.y >= height {
        return Err(FocusError::OutsideImage {
            pixel,
            width,
            height,
        });
    }
    let mut plane = camera.image_plane(width as f32 / height as f32);
    plane.lens = Lens::PINHOLE;
    let tex_coord = Vec2::new(
        (pixel.x as f32 + 0.5) / width as f32,
        1.0 - (pixel.y as f32 + 0.5) / height as f32,
    );
    // A pinhole's ray draws no numbers: any sample will do.
    let sample = PathSample::new(SAMPLER_PCG, UVec2::ZERO, 0, 0);
    let (origin, direction) = get_camera_ray(&plane, UVec2::ZERO, &sample, false, tex_coord);
    let hit = ray_mesh_intersection(triangles, origin, direction)
        .ok_or(FocusError::NothingHit { pixel })?;
    let axis = plane.right.cross(plane.up).normalize();
    Ok(hit.t * direction.dot(axis).abs())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A camera at the origin looking down -z with a 90 degree vertical field of view, and a
    /// large square facing it at z = -4.
    fn camera_and_wall() -> (Camera, Vec<Triangle>) {
        let camera = Camera::look_at(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90f32.to_radians());
        let corners = [
            Vec3::new(-10.0, -10.0, -4.0),
            Vec3::new(10.0, -10.0, -4.0),
            Vec3::new(10.0, 10.0, -4.0),
            Vec3::new(-10.0, 10.0, -4.0),
        ];
        let triangle = |a: usize, b: usize, c: usize| {
            Triangle::new(
                [corners[a], corners[b], corners[c]],
                Vec3::ONE,
                Vec3::ZERO,
                false,
            )
            .unwrap()
        };
        (camera, vec![triangle(0, 1, 2), triangle(0, 2, 3)])
    }

    #[test]
    fn autofocus_finds_the_wall_along_the_view_axis() {
        let (camera, wall) = camera_and_wall();
        let request = LensRequest {
            aperture: Aperture::Radius(0.1),
            focus: Focus::Pixel(UVec2::new(3, 12)),
            blades: 6,
            rotation_degrees: 90.0,
        };
        // Every point of the wall is 4 units along the view axis, wherever the pixel is.
        let (lens, found) = request.resolve(&camera, &wall, 16, 16).unwrap();
        assert!((lens.focus_distance - 4.0).abs() < 1e-5, "{lens:?}");
        assert_eq!(found, Some(lens.focus_distance));
        assert_eq!((lens.aperture_radius, lens.blades), (0.1, 6));
        assert!((lens.rotation - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        let outside = LensRequest {
            focus: Focus::Pixel(UVec2::new(16, 0)),
            ..request
        };
        assert!(matches!(
            outside.resolve(&camera, &wall, 16, 16),
            Err(FocusError::OutsideImage { .. })
        ));
        assert_eq!(
            request.resolve(&camera, &[], 16, 16),
            Err(FocusError::NothingHit {
                pixel: UVec2::new(3, 12)
            })
        );
    }

    #[test]
    fn an_f_number_gives_blenders_aperture_and_radius_0_is_the_pinhole() {
        let (camera, wall) = camera_and_wall();
        // A 36 mm sensor across a square image at 90 degrees: focal length 18 mm; f/2 gives
        // a 9 mm aperture diameter, a radius of 4.5 mm.
        let request = LensRequest {
            aperture: Aperture::FStop {
                f_stop: 2.0,
                sensor_width_mm: 36.0,
            },
            focus: Focus::Distance(2.0),
            blades: 0,
            rotation_degrees: 0.0,
        };
        let (lens, found) = request.resolve(&camera, &wall, 32, 32).unwrap();
        assert!((lens.aperture_radius - 0.0045).abs() < 1e-7, "{lens:?}");
        assert_eq!((lens.focus_distance, found), (2.0, None));
        let pinhole = LensRequest {
            aperture: Aperture::Radius(0.0),
            focus: Focus::ImageCentre,
            ..request
        };
        assert_eq!(
            pinhole.resolve(&camera, &[], 32, 32),
            Ok((Lens::PINHOLE, None))
        );
    }
}
