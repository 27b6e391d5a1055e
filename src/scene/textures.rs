//! Textures of glTF materials on the CPU side: decoding PNG, JPEG and WebP images to RGBA8
//! (`decode_texture`), the sampler's wrap modes and filter (`Texture`), and
//! KHR_texture_transform (`TextureTransform`). Nothing here knows the GPU: the packing for
//! the shaders is `crate::render::gpu_textures`, the lookups are `glsl/textures.glsl` and
//! their Rust twins `crate::cpu::textures`.

use std::io::Cursor;

use image::{ImageFormat, ImageReader, Limits};
use thiserror::Error;

/// Most texels along either side of a texture; larger images are refused before their
/// texels are allocated.
pub const MAX_TEXTURE_SIZE: u32 = 16384;

/// Most bytes the image decoder may allocate for one texture (1 GiB): the RGBA8 texels of a
/// `MAX_TEXTURE_SIZE`² texture (exactly 1 GiB) fit, a header that claims more is refused.
pub const MAX_TEXTURE_DECODE_BYTES: u64 = 1 << 30;

/// The KTX2 file identifier (`«KTX 20»\r\n\x1A\n`), which the `image` crate does not know.
const KTX2_IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// What can go wrong with a texture. Every message is one line.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum TextureError {
    /// The image is in a format vkpath does not decode (KTX2, AVIF, an unknown one).
    #[error("texture format {format} is not supported: vkpath reads PNG, JPEG and WebP textures only (KTX2 and others are not supported)")]
    UnsupportedFormat {
        /// The format in words, as recognised from the bytes or the MIME type.
        format: String,
    },
    /// The bytes claim to be PNG, JPEG or WebP but cannot be decoded.
    #[error("corrupt {format} texture: {message}")]
    Corrupt {
        /// "PNG", "JPEG" or "WebP".
        format: &'static str,
        /// The decoder's message, on one line.
        message: String,
    },
    /// The image is larger than `MAX_TEXTURE_SIZE` along a side or than
    /// `MAX_TEXTURE_DECODE_BYTES` decoded.
    #[error("texture of {width}x{height} texels is too large: vkpath reads at most {max}x{max} texels and {bytes} bytes decoded", max = MAX_TEXTURE_SIZE, bytes = MAX_TEXTURE_DECODE_BYTES)]
    TooLarge {
        /// Width the image claims, in texels.
        width: u32,
        /// Height the image claims, in texels.
        height: u32,
    },
    /// The textures together need more texels than the GPU's texel buffer holds.
    #[error("the textures need {texels} texels in all, more than the {limit} of this device's texel buffer")]
    AtlasTooLarge {
        /// Texels of all textures together.
        texels: u64,
        /// The most texels the device's (or vkpath's u32) texel indices can address.
        limit: u64,
    },
}

/// An image decoded to 8-bit RGBA, rows top-down as stored in the file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DecodedImage {
    /// Width in texels, at least 1.
    pub width: u32,
    /// Height in texels, at least 1.
    pub height: u32,
    /// `width * height` texels, row by row from the top; the rgb as stored in the file
    /// (sRGB or linear is the material's business), alpha linear.
    pub texels: Vec<[u8; 4]>,
}

/// How texture coordinates outside [0, 1] map to texels (a glTF sampler's `wrapS`/`wrapT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum WrapMode {
    /// The texture tiles the plane (glTF's default).
    #[default]
    Repeat,
    /// Coordinates outside read the edge texels.
    ClampToEdge,
    /// Tiles alternate with their mirror image.
    MirroredRepeat,
}

impl WrapMode {
    /// The wrap mode of a glTF sampler.
    pub fn from_gltf(mode: gltf::texture::WrappingMode) -> WrapMode {
        match mode {
            gltf::texture::WrappingMode::Repeat => WrapMode::Repeat,
            gltf::texture::WrappingMode::ClampToEdge => WrapMode::ClampToEdge,
            gltf::texture::WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
        }
    }
}

/// A texture as a material uses it: RGBA8 texels and how to sample them.
///
/// Texture coordinates follow glTF: (0, 0) is the image's top-left corner, u grows to the
/// right and v downwards, (1, 1) is the bottom-right corner; texel (x, y) covers
/// [x, x + 1] / width × [y, y + 1] / height.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Texture {
    /// Width in texels, at least 1.
    pub width: u32,
    /// Height in texels, at least 1.
    pub height: u32,
    /// `width * height` texels, row by row from the top.
    pub texels: Vec<[u8; 4]>,
    /// Wrap mode along u.
    pub wrap_s: WrapMode,
    /// Wrap mode along v.
    pub wrap_t: WrapMode,
    /// Nearest-texel lookup instead of bilinear filtering (glTF `magFilter` NEAREST).
    pub nearest: bool,
}

impl Texture {
    /// A texture with the texels of `image`, sampled with the given wrap modes and filter.
    pub fn new(image: DecodedImage, wrap_s: WrapMode, wrap_t: WrapMode, nearest: bool) -> Texture {
        Texture {
            width: image.width,
            height: image.height,
            texels: image.texels,
            wrap_s,
            wrap_t,
            nearest,
        }
    }
}

/// Decodes a PNG, JPEG or WebP image (a glTF image's bytes; WebP by the `image` crate's
/// pure-Rust decoder, lossy and lossless) to RGBA8.
///
/// The format is recognised from the bytes; `mime_type` (the glTF image's `mimeType`) only
/// names the format when the bytes match none. Greyscale, grey-alpha and RGB images get
/// alpha 1 (and grey copied to rgb); 16-bit channels are rounded to the nearest 8-bit value
/// (`round(c * 255 / 65535)`, the `image` crate's conversion). The decoder is limited to
/// `MAX_TEXTURE_SIZE` texels along each side and `MAX_TEXTURE_DECODE_BYTES`, so that an
/// absurd header is refused before anything is allocated for it.
pub fn decode_texture(bytes: &[u8], mime_type: Option<&str>) -> Result<DecodedImage, TextureError> {
    let format = texture_format(bytes, mime_type)?;
    let format_name = match format {
        ImageFormat::Png => "PNG",
        ImageFormat::WebP => "WebP",
        _ => "JPEG",
    };
    let corrupt = |error: image::ImageError| TextureError::Corrupt {
        format: format_name,
        message: one_line(&error.to_string()),
    };
    let reader = |limits: Limits| {
        let mut reader = ImageReader::with_format(Cursor::new(bytes), format);
        reader.limits(limits);
        reader
    };
    // The header alone first, without limits, so that the error can name the size.
    let (width, height) = reader(Limits::default())
        .into_dimensions()
        .map_err(corrupt)?;
    let decoded_bytes = u64::from(width) * u64::from(height) * 4;
    if width > MAX_TEXTURE_SIZE
        || height > MAX_TEXTURE_SIZE
        || decoded_bytes > MAX_TEXTURE_DECODE_BYTES
    {
        return Err(TextureError::TooLarge { width, height });
    }
    if width == 0 || height == 0 {
        return Err(TextureError::Corrupt {
            format: format_name,
            message: format!("the image has {width}x{height} texels"),
        });
    }
    let image = reader(texture_limits())
        .decode()
        .map_err(|error| match error {
            image::ImageError::Limits(_) => TextureError::TooLarge { width, height },
            error => corrupt(error),
        })?;
    let rgba = image.to_rgba8();
    let (width, height) = rgba.dimensions();
    let texels = rgba
        .into_raw()
        .chunks_exact(4)
        .map(|texel| [texel[0], texel[1], texel[2], texel[3]])
        .collect();
    Ok(DecodedImage {
        width,
        height,
        texels,
    })
}

/// The decoder limits of `decode_texture`.
fn texture_limits() -> Limits {
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIZE);
    limits.max_image_height = Some(MAX_TEXTURE_SIZE);
    limits.max_alloc = Some(MAX_TEXTURE_DECODE_BYTES);
    limits
}

/// PNG, JPEG or WebP, from the bytes or else from the MIME type; any other format is an
/// error.
fn texture_format(bytes: &[u8], mime_type: Option<&str>) -> Result<ImageFormat, TextureError> {
    if bytes.starts_with(&KTX2_IDENTIFIER) {
        return Err(TextureError::UnsupportedFormat {
            format: "KTX2".into(),
        });
    }
    let format = match image::guess_format(bytes) {
        Ok(format) => format,
        Err(_) => match mime_type.map(str::to_ascii_lowercase).as_deref() {
            Some("image/png") => ImageFormat::Png,
            Some("image/jpeg") => ImageFormat::Jpeg,
            Some("image/webp") => ImageFormat::WebP,
            Some(mime) => {
                return Err(TextureError::UnsupportedFormat {
                    format: format!("'{}'", one_line(mime)),
                })
            }
            None => {
                return Err(TextureError::UnsupportedFormat {
                    format: "unknown (neither the bytes nor a MIME type name it)".into(),
                })
            }
        },
    };
    match format {
        ImageFormat::Png | ImageFormat::Jpeg | ImageFormat::WebP => Ok(format),
        other => Err(TextureError::UnsupportedFormat {
            format: format!("{other:?}"),
        }),
    }
}

/// `text` on one line (line breaks and other control characters become spaces), at most
/// 200 characters, for messages built from a decoder's text or a file's string.
fn one_line(text: &str) -> String {
    let line: String = text
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .take(200)
        .collect();
    line.trim().to_string()
}

/// A KHR_texture_transform: texture coordinates become `matrix * (u, v, 1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureTransform {
    /// The two rows of the affine map: u' = row 0 · (u, v, 1), v' = row 1 · (u, v, 1).
    pub matrix: [[f32; 3]; 2],
}

impl Default for TextureTransform {
    fn default() -> TextureTransform {
        TextureTransform::identity()
    }
}

impl TextureTransform {
    /// No transform (a texture without KHR_texture_transform).
    pub fn identity() -> TextureTransform {
        TextureTransform {
            matrix: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        }
    }

    /// The transform of KHR_texture_transform's `offset`, `rotation` (radians) and `scale`:
    /// matrix = Translation · Rotation · Scale, so that uv is scaled first, rotated, then
    /// offset.
    ///
    /// The rotation's rows are (cos, sin) and (−sin, cos): "counter-clockwise" in glTF's
    /// v-down uv space. The extension's GLSL listing writes these numbers into a
    /// column-major `mat3`, which is the transpose; the listing is known to be wrong
    /// (KhronosGroup/glTF issue 1563), and the extension's own example (offset (0, 1),
    /// rotation π/2, scale 0.5 maps uv to the lower-left quadrant), its sample model
    /// TextureTransformTest, Babylon.js and three.js all use the rows here.
    pub fn from_gltf(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> TextureTransform {
        let (sin, cos) = rotation.sin_cos();
        TextureTransform {
            matrix: [
                [cos * scale[0], sin * scale[1], offset[0]],
                [-sin * scale[0], cos * scale[1], offset[1]],
            ],
        }
    }
}

#[cfg(test)]
#[path = "textures_tests.rs"]
mod tests;
