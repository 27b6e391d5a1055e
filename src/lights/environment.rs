//! Light from infinitely far away: an equirectangular environment map (`--environment`) or
//! a constant colour (`--background`); the alias table that importance-samples the map is
//! `super::alias_table`, what the user asks for `super::environment_source`.
//!
//! Convention: world +Y is up; a unit direction d = (x, y, z) looks up
//! u = 0.5 + atan2(x, -z) / (2 pi), v = acos(y) / pi, with (u, v) = (0, 0) the image's
//! top-left corner, so the image's centre is the direction -Z. The map is piecewise constant
//! (each texel's radiance over its patch of the sphere, no filtering), which is what the
//! sampler's density describes exactly. `rotation_degrees` turns the map about +Y,
//! right-handed: with 90, what was seen looking down -Z is seen looking down -X.

use std::path::Path;

use glam::Vec3;

use crate::files::{io_message, printable, read_at_most, MAX_FILE_BYTES};
use crate::image_io::error::ImageError;
use crate::image_io::exr_input::plain_cause;

/// The environment's radiance (linear RGB) per texel, rows top-down.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// Width in texels (u), at least 1.
    pub width: u32,
    /// Height in texels (v), at least 1.
    pub height: u32,
    /// `width * height` radiances, finite and non-negative.
    pub texels: Vec<Vec3>,
}

/// What a ray that leaves the scene sees.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// The map, or `None` for a constant colour.
    pub map: Option<EnvironmentMap>,
    /// The constant colour (without a map), linear RGB radiance.
    pub background: Vec3,
    /// Factor on the map's radiance (`--environment-strength`).
    pub strength: f32,
    /// Turn about +Y in degrees (`--environment-rotation`).
    pub rotation_degrees: f32,
}

/// Largest map vkpath reads: 16384 x 8192 texels (32 bytes each on the GPU: 4 GiB).
pub const MAX_ENVIRONMENT_TEXELS: u64 = 16384 * 8192;

impl Environment {
    /// A constant environment of radiance `background`.
    pub fn constant(background: Vec3) -> Environment {
        Environment {
            map: None,
            background,
            strength: 1.0,
            rotation_degrees: 0.0,
        }
    }

    /// Whether any light comes from it.
    pub fn emits_light(&self) -> bool {
        match &self.map {
            Some(map) => self.strength > 0.0 && map.texels.iter().any(|t| t.max_element() > 0.0),
            None => self.background.max_element() > 0.0,
        }
    }
}

/// Why an environment map could not be read (`load_environment_map`), in one line that
/// names the file once (`shown`: its path as printed).
#[derive(Debug, thiserror::Error)]
pub enum EnvironmentMapError {
    /// The file could not be read or decoded.
    #[error("cannot read environment map '{shown}': {cause}")]
    Unreadable {
        /// The file's path as printed.
        shown: String,
        /// The cause in plain words.
        cause: String,
    },
    /// Neither a .hdr nor an .exr file: the path as printed.
    #[error("environment map '{0}' must be a .hdr (Radiance) or .exr (OpenEXR) file")]
    Format(String),
    /// No texels, or more than vkpath reads.
    #[error(
        "environment map '{shown}' has {width}x{height} texels; vkpath reads 1 to {} texels",
        MAX_ENVIRONMENT_TEXELS
    )]
    Size {
        /// The file's path as printed.
        shown: String,
        /// Texels per row.
        width: u32,
        /// Rows.
        height: u32,
    },
    /// A texel of negative or non-finite radiance.
    #[error("environment map '{shown}' has a negative or non-finite texel at ({x}, {y})")]
    Texel {
        /// The file's path as printed.
        shown: String,
        /// Its column.
        x: usize,
        /// Its row, from the top.
        y: usize,
    },
}

/// Reads an equirectangular map from a Radiance `.hdr` or OpenEXR `.exr` file; non-finite or
/// negative radiance is an error naming the texel.
pub fn load_environment_map(path: &Path) -> Result<EnvironmentMap, EnvironmentMapError> {
    let shown = printable(&path.display().to_string());
    // Every message about the file names it once, as the environment map it was meant to
    // be, with the cause in plain words.
    let fail = |cause: &dyn std::fmt::Display| EnvironmentMapError::Unreadable {
        shown: shown.clone(),
        cause: plain_cause(cause),
    };
    let metadata = std::fs::metadata(path).map_err(|e| fail(&io_message(&e)))?;
    if metadata.is_dir() {
        return Err(fail(&"it is a directory, not a file"));
    }
    if !metadata.is_file() {
        return Err(fail(&"it is not a regular file"));
    }
    let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
    let (width, height, texels) = match extension.as_deref() {
        Some("exr") => {
            let exr = crate::image_io::exr_input::read_exr(path).map_err(|error| match error {
                ImageError::Read { message, .. } => fail(&message),
                other => fail(&other),
            })?;
            let image = exr.image;
            let texels: Vec<Vec3> = image
                .mean
                .iter()
                .map(|p| Vec3::new(p[0], p[1], p[2]))
                .collect();
            (image.width, image.height, texels)
        }
        Some("hdr") => {
            let bytes = read_at_most(path, MAX_FILE_BYTES).map_err(|e| fail(&e))?;
            let image = image::load_from_memory_with_format(&bytes, image::ImageFormat::Hdr)
                .map_err(|e| fail(&e))?
                .into_rgb32f();
            let (width, height) = image.dimensions();
            let texels: Vec<Vec3> = image.pixels().map(|p| Vec3::from(p.0)).collect();
            (width, height, texels)
        }
        _ => return Err(EnvironmentMapError::Format(shown)),
    };
    if u64::from(width) * u64::from(height) > MAX_ENVIRONMENT_TEXELS || width == 0 || height == 0 {
        return Err(EnvironmentMapError::Size {
            shown,
            width,
            height,
        });
    }
    if let Some(index) = texels
        .iter()
        .position(|t: &Vec3| !t.is_finite() || t.min_element() < 0.0)
    {
        return Err(EnvironmentMapError::Texel {
            shown,
            x: index % width as usize,
            y: index / width as usize,
        });
    }
    Ok(EnvironmentMap {
        width,
        height,
        texels,
    })
}

/// Solid angle (sr) of the patch of the sphere that texel row `row` of a `width` x `height`
/// map covers, one texel of it: 2 pi / width (cos theta_top - cos theta_bottom), as
/// 2 sin(pi (row + 1/2) / height) sin(pi / (2 height)) without cancellation.
pub fn texel_solid_angle(row: u32, width: u32, height: u32) -> f64 {
    use std::f64::consts::PI;
    let height = f64::from(height);
    2.0 * PI / f64::from(width)
        * 2.0
        * (PI * (f64::from(row) + 0.5) / height).sin()
        * (PI / (2.0 * height)).sin()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::alias_table::AliasTable;

    #[test]
    fn unreadable_maps_are_named_once_with_the_cause_in_plain_words() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("nope.hdr");
        assert_eq!(
            load_environment_map(&missing).unwrap_err().to_string(),
            format!(
                "cannot read environment map '{}': No such file or directory",
                missing.display()
            )
        );
        let message = load_environment_map(dir.path()).unwrap_err().to_string();
        assert!(
            message.ends_with("it is a directory, not a file"),
            "{message}"
        );
        // A PNG named .exr: the path once, what the file is.
        let not_exr = dir.path().join("sky.exr");
        std::fs::write(&not_exr, b"\x89PNG\r\n\x1a\n0000").unwrap();
        let message = load_environment_map(&not_exr).unwrap_err().to_string();
        assert_eq!(message.matches("sky.exr").count(), 1, "{message}");
        assert!(message.contains("not an OpenEXR file"), "{message}");
        // A Radiance header whose pixels are missing: truncated, in those words.
        let truncated = dir.path().join("t.hdr");
        std::fs::write(
            &truncated,
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n",
        )
        .unwrap();
        let message = load_environment_map(&truncated).unwrap_err().to_string();
        assert!(
            message.starts_with("cannot read environment map '")
                && message.ends_with("the file is truncated (it ends before its image data does)"),
            "{message}"
        );
    }

    #[test]
    fn a_black_map_samples_uniformly_and_does_not_emit() {
        let map = EnvironmentMap {
            width: 2,
            height: 1,
            texels: vec![Vec3::ZERO; 2],
        };
        assert_eq!(AliasTable::new(&map).probabilities, vec![0.5, 0.5]);
        let environment = Environment {
            map: Some(map),
            ..Environment::constant(Vec3::ONE)
        };
        assert!(!environment.emits_light());
        assert!(Environment::constant(Vec3::splat(0.1)).emits_light());
    }
}
