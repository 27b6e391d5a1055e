//! Writing images: OpenEXR with linear radiance as 32-bit floats (optionally with the
//! per-pixel second moment and sample count), or PNG, sRGB-encoded after exposure and clamp.
//! Files are written to a temporary name in the same directory and renamed into place, so a
//! failed write never leaves a partial file behind.

use std::path::{Path, PathBuf};

use exr::prelude::{AnyChannel, AnyChannels, FlatSamples, Image, WritableImage};

use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;

/// The file formats vkpath writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// OpenEXR: linear radiance, 32-bit float per channel.
    Exr,
    /// PNG: 8-bit sRGB after exposure and clamping.
    Png,
}

/// Names of the extra EXR channels written with `--moments`.
pub const SECOND_MOMENT_CHANNELS: [&str; 3] =
    ["second_moment.R", "second_moment.G", "second_moment.B"];
/// Name of the EXR channel holding each pixel's sample count (with `--moments`).
pub const SAMPLE_COUNT_CHANNEL: &str = "sample_count.Y";

/// How to turn radiance into an image file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SaveOptions {
    /// PNG only: radiance is multiplied by 2^exposure before clamping to [0, 1].
    pub exposure: f32,
    /// EXR only: also store the second moment and sample count of each pixel.
    pub moments: bool,
}

impl Default for SaveOptions {
    fn default() -> Self {
        SaveOptions {
            exposure: 0.0,
            moments: false,
        }
    }
}

impl ImageFormat {
    /// The format for a path's extension (`.exr` or `.png`, any case).
    pub fn from_path(path: &Path) -> Result<ImageFormat> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("exr") => Ok(ImageFormat::Exr),
            Some("png") => Ok(ImageFormat::Png),
            _ => Err(Error::Image(format!(
                "cannot write '{}': unsupported image format (use .exr or .png)",
                path.display()
            ))),
        }
    }
}

/// Checks, before rendering, that an image can be written to `path`: a known extension and
/// a directory that exists and accepts a new file. Returns the format.
pub fn check_writable(path: &Path) -> Result<ImageFormat> {
    let format = ImageFormat::from_path(path)?;
    if path.is_dir() {
        return Err(Error::Image(format!(
            "cannot write '{}': it is a directory",
            path.display()
        )));
    }
    let probe = temporary_path(path);
    std::fs::write(&probe, b"")
        .and_then(|()| std::fs::remove_file(&probe))
        .map_err(|e| Error::Image(format!("cannot write '{}': {e}", path.display())))?;
    Ok(format)
}

/// A hidden sibling of `path` to write into before renaming.
fn temporary_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.vkpath-{}.tmp", std::process::id()))
}

/// Writes `image` to `path` in the format its extension names.
pub fn save_image(path: &Path, image: &RenderedImage, options: &SaveOptions) -> Result<()> {
    let format = ImageFormat::from_path(path)?;
    let temporary = temporary_path(path);
    let written = match format {
        ImageFormat::Exr => write_exr(&temporary, image, options.moments),
        ImageFormat::Png => write_png(&temporary, image, options.exposure),
    }
    .and_then(|()| {
        std::fs::rename(&temporary, path).map_err(|e| format!("renaming into place: {e}"))
    });
    written.map_err(|message| {
        let _ = std::fs::remove_file(&temporary);
        Error::Image(format!("cannot write '{}': {message}", path.display()))
    })
}

fn write_exr(path: &Path, image: &RenderedImage, moments: bool) -> std::result::Result<(), String> {
    let channel = |name: &str, values: Vec<f32>| AnyChannel::new(name, FlatSamples::F32(values));
    let mean = |c: usize| image.mean.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let mut channels = vec![
        channel("R", mean(0)),
        channel("G", mean(1)),
        channel("B", mean(2)),
        channel("A", mean(3)),
    ];
    if moments {
        for (c, name) in SECOND_MOMENT_CHANNELS.iter().enumerate() {
            channels.push(channel(
                name,
                image.second_moment.iter().map(|p| p[c]).collect(),
            ));
        }
        channels.push(channel(SAMPLE_COUNT_CHANNEL, image.sample_count.clone()));
    }
    let size = (image.width as usize, image.height as usize);
    Image::from_channels(size, AnyChannels::sort(channels.into()))
        .write()
        .to_file(path)
        .map_err(|e| e.to_string())
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
pub fn linear_to_srgb(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// 8-bit sRGB of a linear radiance value: times 2^exposure, clamped to [0, 1] (NaN to 0),
/// encoded, rounded.
pub fn to_srgb8(radiance: f32, exposure: f32) -> u8 {
    let scaled = radiance * exposure.exp2();
    let clamped = if scaled.is_nan() {
        0.0
    } else {
        scaled.clamp(0.0, 1.0)
    };
    (linear_to_srgb(clamped) * 255.0).round() as u8
}

fn write_png(path: &Path, image: &RenderedImage, exposure: f32) -> std::result::Result<(), String> {
    let bytes: Vec<u8> = image
        .mean
        .iter()
        .flat_map(|p| {
            [
                to_srgb8(p[0], exposure),
                to_srgb8(p[1], exposure),
                to_srgb8(p[2], exposure),
            ]
        })
        .collect();
    image::save_buffer_with_format(
        path,
        &bytes,
        image.width,
        image.height,
        image::ColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_encoding_matches_reference_points() {
        assert_eq!(to_srgb8(0.0, 0.0), 0);
        assert_eq!(to_srgb8(1.0, 0.0), 255);
        assert_eq!(to_srgb8(7.0, 0.0), 255);
        assert_eq!(to_srgb8(f32::NAN, 0.0), 0);
        // Linear 0.5 is sRGB 0.735 -> 188; exposure -1 halves the radiance first.
        assert_eq!(to_srgb8(0.5, 0.0), 188);
        assert_eq!(to_srgb8(1.0, -1.0), 188);
    }

    #[test]
    fn unsupported_extensions_and_missing_directories_are_rejected() {
        assert!(check_writable(Path::new("out.jpg")).is_err());
        let message = check_writable(Path::new("/nonexistent-dir/out.exr"))
            .unwrap_err()
            .to_string();
        assert!(message.contains("/nonexistent-dir/out.exr"), "{message}");
    }
}
