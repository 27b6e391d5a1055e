//! `vkpath render`'s depth-of-field options: a thin lens (`crate::camera::Lens`) in front of
//! whichever camera the render uses, given by its aperture (a radius, or an f-number with a
//! sensor width as Blender takes it), its focus (a distance, or the pixel to focus on) and the
//! aperture's shape.

use glam::UVec2;

use crate::camera::Camera;
use crate::cli::frames::UsageError;
use crate::cli::parse_pixel;
use crate::cli::value_error::ValueError;
use crate::lens_request::{Aperture, Focus, FocusError, LensRequest, DEFAULT_SENSOR_WIDTH_MM};
use crate::scene::Scene;

/// Depth of field: a thin lens in front of the camera.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct LensArgs {
    /// Depth of field: the radius of the lens's aperture in world units (glTF's are metres);
    /// 0 is a pinhole, the default. The focus is --focus-distance, --focus-at, or else what
    /// the image's centre sees.
    #[arg(long, value_name = "R", value_parser = parse_non_negative, conflicts_with = "f_stop", allow_hyphen_values = true)]
    pub aperture_radius: Option<f32>,
    /// Depth of field by f-number N: an aperture radius of focal length / (2 N), the focal
    /// length taken from the field of view and --sensor-width (as Blender does; world units
    /// taken as metres).
    #[arg(long, value_name = "N", value_parser = parse_positive, allow_hyphen_values = true)]
    pub f_stop: Option<f32>,
    /// Width of the sensor in millimetres, for --f-stop: it spans the image's longer side
    /// (Blender's automatic sensor fit).
    #[arg(long, value_name = "MM", value_parser = parse_positive, default_value_t = DEFAULT_SENSOR_WIDTH_MM, allow_hyphen_values = true)]
    pub sensor_width: f32,
    /// Distance from the camera to the plane in focus, along the view axis, world units.
    #[arg(long, value_name = "D", value_parser = parse_positive, conflicts_with = "focus_at", allow_hyphen_values = true)]
    pub focus_distance: Option<f32>,
    /// Autofocus: focus on what the camera ray through pixel X,Y (column, row from the top)
    /// hits.
    #[arg(long, value_name = "X,Y", value_parser = parse_pixel)]
    pub focus_at: Option<UVec2>,
    /// Aperture blades: 0 for a round aperture (the default), or 3 or more for a regular
    /// polygon (polygonal bokeh).
    #[arg(long, value_name = "N", value_parser = parse_blades, default_value_t = 0, allow_hyphen_values = true)]
    pub aperture_blades: u32,
    /// Rotation of a polygonal aperture in degrees (0: a corner points up).
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_hyphen_values = true
    )]
    pub aperture_rotation: f32,
}

impl LensArgs {
    /// Whether depth of field was asked for (a positive aperture radius or an f-number).
    pub fn has_aperture(&self) -> bool {
        self.f_stop.is_some() || self.aperture_radius.is_some_and(|radius| radius > 0.0)
    }

    /// The options given that have no effect without an aperture, by name.
    pub fn unused_without_aperture(&self) -> Vec<&'static str> {
        if self.has_aperture() {
            return Vec::new();
        }
        let mut unused = Vec::new();
        if self.focus_distance.is_some() {
            unused.push("--focus-distance");
        }
        if self.focus_at.is_some() {
            unused.push("--focus-at");
        }
        if self.aperture_blades != 0 {
            unused.push("--aperture-blades");
        }
        if self.aperture_rotation != 0.0 {
            unused.push("--aperture-rotation");
        }
        unused
    }

    /// `camera` with the lens these options describe for a `width` x `height` image of
    /// `scene` (unchanged without an aperture), resolved by `LensRequest::resolve`: the focus
    /// is found on the CPU for --focus-at or, without a focus option, the image's centre; a
    /// pixel outside the image, or one whose ray hits nothing, is a usage error. Returns the
    /// camera and, where autofocus chose it, the focus distance.
    pub fn apply(
        &self,
        mut camera: Camera,
        scene: &Scene,
        width: u32,
        height: u32,
    ) -> Result<(Camera, Option<f32>), UsageError> {
        let Some(request) = self.request() else {
            return Ok((camera, None));
        };
        let (lens, autofocus) = request
            .resolve(&camera, &scene.triangles, width, height)
            .map_err(|error| self.focus_error(error))?;
        camera.lens = lens;
        Ok((camera, autofocus))
    }

    /// The lens these options ask for (`None` without an aperture).
    fn request(&self) -> Option<LensRequest> {
        if !self.has_aperture() {
            return None;
        }
        let aperture = match (self.aperture_radius, self.f_stop) {
            (_, Some(f_stop)) => Aperture::FStop {
                f_stop,
                sensor_width_mm: self.sensor_width,
            },
            (radius, None) => Aperture::Radius(radius.unwrap_or(0.0)),
        };
        let focus = match (self.focus_distance, self.focus_at) {
            (Some(distance), _) => Focus::Distance(distance),
            (None, Some(pixel)) => Focus::Pixel(pixel),
            (None, None) => Focus::ImageCentre,
        };
        Some(LensRequest {
            aperture,
            focus,
            blades: self.aperture_blades,
            rotation_degrees: self.aperture_rotation,
        })
    }

    /// The command line's words for autofocus's `error`.
    fn focus_error(&self, error: FocusError) -> UsageError {
        let option = if self.focus_at.is_some() {
            "--focus-at"
        } else {
            "depth of field without --focus-distance or --focus-at focuses on the image's centre, and"
        };
        UsageError(match error {
            FocusError::OutsideImage {
                pixel,
                width,
                height,
            } => format!(
                "--focus-at {},{} is outside the {width}x{height} image",
                pixel.x, pixel.y
            ),
            FocusError::NothingHit { pixel } => format!(
                "{option} the camera ray through pixel {},{} hits nothing to focus on: give --focus-distance",
                pixel.x, pixel.y
            ),
        })
    }
}

/// A number of world units that is at least 0 and finite.
fn parse_non_negative(text: &str) -> Result<f32, ValueError> {
    match text.trim().parse::<f32>() {
        Ok(value) if value.is_finite() && value >= 0.0 => Ok(value),
        _ => Err(ValueError::NotNonNegative { text: text.into() }),
    }
}

/// A number that is above 0 and finite.
fn parse_positive(text: &str) -> Result<f32, ValueError> {
    match text.trim().parse::<f32>() {
        Ok(value) if value.is_finite() && value > 0.0 => Ok(value),
        _ => Err(ValueError::NotPositive { text: text.into() }),
    }
}

/// 0 (a round aperture) or 3 and more blades (at most 64).
fn parse_blades(text: &str) -> Result<u32, ValueError> {
    match text.trim().parse::<u32>() {
        Ok(value) if value == 0 || (3..=64).contains(&value) => Ok(value),
        _ => Err(ValueError::NotBlades { text: text.into() }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_parse_or_say_what_is_wrong() {
        assert_eq!(parse_non_negative("0").unwrap(), 0.0);
        assert!(parse_non_negative("-0.1").is_err());
        assert!(parse_non_negative("nan").is_err());
        assert!(parse_positive("0").is_err());
        assert_eq!(parse_positive("2.5").unwrap(), 2.5);
        assert_eq!(parse_blades("6").unwrap(), 6);
        assert_eq!(parse_blades("0").unwrap(), 0);
        for bad in ["1", "2", "65", "-3", "x"] {
            assert!(parse_blades(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn an_f_stop_gives_the_aperture_blender_gives() {
        // A 36 mm sensor over a square image with a 90 degree field of view: the focal length
        // is 18 mm, and at f/2 the aperture's diameter 9 mm, its radius 4.5 mm.
        let scene = Scene::builtin_cornell_box().unwrap();
        let camera = Camera::look_at(
            glam::Vec3::new(0.0, 0.0, 5.0),
            glam::Vec3::ZERO,
            glam::Vec3::Y,
            90f32.to_radians(),
        );
        let args = LensArgs {
            f_stop: Some(2.0),
            sensor_width: 36.0,
            focus_distance: Some(4.0),
            ..LensArgs::default()
        };
        let (lensed, autofocus) = args.apply(camera, &scene, 64, 64).unwrap();
        assert!((lensed.lens.aperture_radius - 0.0045).abs() < 1e-7);
        assert_eq!(lensed.lens.focus_distance, 4.0);
        assert_eq!(autofocus, None);
    }

    #[test]
    fn autofocus_finds_the_box_and_refuses_pixels_outside_or_on_nothing() {
        let scene = Scene::builtin_cornell_box().unwrap();
        let camera = scene.camera.unwrap();
        let args = LensArgs {
            aperture_radius: Some(0.1),
            ..LensArgs::default()
        };
        let (lensed, autofocus) = args.apply(camera, &scene, 32, 32).unwrap();
        // The centre sees the back wall, in front of the camera.
        let distance = autofocus.unwrap();
        assert!(distance > 0.0 && lensed.lens.focus_distance == distance);
        let outside = LensArgs {
            focus_at: Some(UVec2::new(32, 0)),
            ..args.clone()
        };
        let error = outside.apply(camera, &scene, 32, 32).unwrap_err();
        assert!(error.0.contains("outside the 32x32 image"), "{}", error.0);
        let empty = Scene {
            triangles: Vec::new(),
            ..Scene::builtin_cornell_box().unwrap()
        };
        let error = args.apply(camera, &empty, 32, 32).unwrap_err();
        assert!(error.0.contains("hits nothing"), "{}", error.0);
    }
}
