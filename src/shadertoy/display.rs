//! Writing a pass's image as ShaderToy shows it: a PNG of the values the shader wrote,
//! clamped to [0, 1] and stored as they are (the canvas is 8-bit and the browser takes its
//! values as sRGB-encoded, so no transfer function is applied), alpha ignored; or an EXR of
//! the floats themselves (RGBA).

use std::path::Path;

use crate::error::Result;
use crate::image_io::data::RenderedImage;
use crate::image_io::output::{
    save_image, write_atomically, write_rgb8_png, ImageFormat, SaveOptions,
};

/// The 8-bit value ShaderToy's canvas shows for a shader's output `value`: clamped to
/// [0, 1] (NaN as 0), times 255, rounded.
pub fn display_byte(value: f32) -> u8 {
    let clamped = if value.is_nan() {
        0.0
    } else {
        value.clamp(0.0, 1.0)
    };
    (clamped * 255.0).round() as u8
}

/// Writes `image` to `path`: PNG as ShaderToy displays it, EXR as the floats (RGBA).
pub fn save_pass_image(path: &Path, image: &RenderedImage) -> Result<()> {
    match ImageFormat::from_path(path)? {
        ImageFormat::Exr => Ok(save_image(path, image, &SaveOptions::default())?),
        ImageFormat::Png => {
            let bytes: Vec<u8> = image
                .mean
                .iter()
                .flat_map(|p| [display_byte(p[0]), display_byte(p[1]), display_byte(p[2])])
                .collect();
            Ok(write_atomically(path, |temporary| {
                write_rgb8_png(temporary, image.width, image.height, &bytes)
            })?)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_clamped_not_encoded() {
        assert_eq!(display_byte(0.5), 128);
        assert_eq!(display_byte(-1.0), 0);
        assert_eq!(display_byte(3.0), 255);
        assert_eq!(display_byte(f32::NAN), 0);
        assert_eq!(display_byte(0.25), 64);
    }
}
