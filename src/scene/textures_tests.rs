//! Tests of `crate::scene::textures`: decoding (tiny PNGs and JPEGs made here with the
//! `image` crate's encoders), its errors, and KHR_texture_transform.

use super::*;
use image::{DynamicImage, GrayImage, ImageBuffer, Luma, LumaA, Rgb, RgbImage, Rgba, RgbaImage};

/// `image` encoded as `format` in memory.
fn encode(image: &DynamicImage, format: ImageFormat) -> Vec<u8> {
    let mut bytes = Cursor::new(Vec::new());
    image.write_to(&mut bytes, format).expect("encodes");
    bytes.into_inner()
}

fn png(image: impl Into<DynamicImage>) -> Vec<u8> {
    encode(&image.into(), ImageFormat::Png)
}

#[test]
fn rgba_png_keeps_its_texels_top_down() {
    let image = RgbaImage::from_fn(3, 2, |x, y| {
        Rgba([x as u8 * 10, y as u8 * 100, 7, 200 + x as u8])
    });
    let decoded = decode_texture(&png(image), Some("image/png")).expect("decodes");
    assert_eq!((decoded.width, decoded.height), (3, 2));
    assert_eq!(decoded.texels.len(), 6);
    // Row 1 (the second from the top), column 2.
    assert_eq!(decoded.texels[3 + 2], [20, 100, 7, 202]);
    assert_eq!(decoded.texels[0], [0, 0, 7, 200]);
}

#[test]
fn grey_and_rgb_images_become_opaque_rgba() {
    let grey = GrayImage::from_fn(2, 1, |x, _| Luma([40 + x as u8]));
    let decoded = decode_texture(&png(grey), None).expect("decodes");
    assert_eq!(decoded.texels, vec![[40, 40, 40, 255], [41, 41, 41, 255]]);
    let grey_alpha: ImageBuffer<LumaA<u8>, Vec<u8>> = ImageBuffer::from_pixel(1, 1, LumaA([9, 30]));
    let decoded =
        decode_texture(&png(DynamicImage::ImageLumaA8(grey_alpha)), None).expect("decodes");
    assert_eq!(decoded.texels, vec![[9, 9, 9, 30]]);
    let rgb = RgbImage::from_pixel(1, 1, Rgb([1, 2, 3]));
    let decoded = decode_texture(&png(rgb), None).expect("decodes");
    assert_eq!(decoded.texels, vec![[1, 2, 3, 255]]);
}

#[test]
fn sixteen_bit_channels_round_to_eight_bits() {
    // 0x4DFF / 257 = 77.69: rounding gives 78 where dropping the low byte would give 77;
    // 65535 -> 255, 0 -> 0, 128 / 257 = 0.498 -> 0.
    let image: ImageBuffer<Rgba<u16>, Vec<u16>> =
        ImageBuffer::from_pixel(1, 1, Rgba([0x4DFF, 65535, 0, 128]));
    let decoded = decode_texture(&png(DynamicImage::ImageRgba16(image)), None).expect("decodes");
    assert_eq!(decoded.texels, vec![[78, 255, 0, 0]]);
    let grey: ImageBuffer<Luma<u16>, Vec<u16>> = ImageBuffer::from_pixel(1, 1, Luma([0x4DFF]));
    let decoded = decode_texture(&png(DynamicImage::ImageLuma16(grey)), None).expect("decodes");
    assert_eq!(decoded.texels, vec![[78, 78, 78, 255]]);
}

#[test]
fn jpeg_decodes_close_to_its_source() {
    // A flat colour survives JPEG at quality 100 within a few levels.
    let image = RgbImage::from_pixel(8, 8, Rgb([200, 100, 50]));
    let mut bytes = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 100)
        .encode_image(&image)
        .expect("encodes");
    let decoded = decode_texture(&bytes, Some("image/jpeg")).expect("decodes");
    assert_eq!((decoded.width, decoded.height), (8, 8));
    for texel in &decoded.texels {
        for (channel, expected) in texel.iter().zip([200u8, 100, 50, 255]) {
            assert!(channel.abs_diff(expected) <= 3, "{texel:?}");
        }
    }
}

#[test]
fn the_bytes_decide_the_format_over_the_mime_type() {
    let bytes = png(RgbImage::from_pixel(1, 1, Rgb([5, 6, 7])));
    let decoded = decode_texture(&bytes, Some("image/jpeg")).expect("decodes as PNG");
    assert_eq!(decoded.texels, vec![[5, 6, 7, 255]]);
}

#[test]
fn webp_is_decoded_and_a_corrupt_one_is_one_line() {
    // tests/data/four_colours.webp: `cwebp -lossless -exact` (libwebp 1.2.4) of a 2 x 2 PNG
    // of red, green / blue, white
    let bytes = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/four_colours.webp"
    ))
    .unwrap();
    let decoded = decode_texture(&bytes, None).expect("a lossless WebP");
    assert_eq!((decoded.width, decoded.height), (2, 2));
    assert_eq!(
        decoded.texels,
        [
            [255, 0, 0, 255],
            [0, 255, 0, 255],
            [0, 0, 255, 255],
            [255, 255, 255, 255]
        ]
    );
    let error = decode_texture(&bytes[..30], Some("image/webp")).unwrap_err();
    assert!(
        matches!(error, TextureError::Corrupt { format: "WebP", .. }),
        "{error}"
    );
    assert_eq!(error.to_string().lines().count(), 1, "{error}");
}

#[test]
fn ktx2_and_unknown_formats_are_refused() {
    let mut ktx2 = KTX2_IDENTIFIER.to_vec();
    ktx2.extend_from_slice(&[0; 64]);
    let error = decode_texture(&ktx2, Some("image/ktx2")).unwrap_err();
    assert_eq!(
        error,
        TextureError::UnsupportedFormat {
            format: "KTX2".into()
        }
    );

    let error = decode_texture(b"not an image", Some("image/x-made\nup")).unwrap_err();
    assert!(
        matches!(error, TextureError::UnsupportedFormat { .. }),
        "{error}"
    );
    let error = decode_texture(b"not an image", None).unwrap_err();
    assert!(error.to_string().contains("unknown"), "{error}");
    for error in [
        decode_texture(&ktx2, None).unwrap_err(),
        decode_texture(b"x", Some("image/x-made\nup")).unwrap_err(),
    ] {
        assert_eq!(error.to_string().lines().count(), 1, "{error}");
    }
}

#[test]
fn corrupt_data_is_an_error_on_one_line() {
    let bytes = png(RgbImage::from_fn(16, 16, |x, y| Rgb([x as u8, y as u8, 0])));
    let truncated = &bytes[..bytes.len() / 2];
    let error = decode_texture(truncated, None).unwrap_err();
    assert!(
        matches!(error, TextureError::Corrupt { format: "PNG", .. }),
        "{error}"
    );
    assert_eq!(error.to_string().lines().count(), 1, "{error}");

    let mut garbage = bytes[..8].to_vec(); // the PNG signature, then nothing sensible
    garbage.extend_from_slice(&[0xff; 40]);
    let error = decode_texture(&garbage, None).unwrap_err();
    assert!(
        matches!(error, TextureError::Corrupt { format: "PNG", .. }),
        "{error}"
    );

    // Unrecognisable bytes that the MIME type calls JPEG.
    let error = decode_texture(b"\0\0\0\0 not a jpeg", Some("image/jpeg")).unwrap_err();
    assert!(
        matches!(error, TextureError::Corrupt { format: "JPEG", .. }),
        "{error}"
    );
    assert_eq!(error.to_string().lines().count(), 1, "{error}");
}

#[test]
fn images_wider_or_taller_than_the_limit_are_refused_with_their_size() {
    let too_wide = png(GrayImage::new(MAX_TEXTURE_SIZE + 1, 1));
    let error = decode_texture(&too_wide, None).unwrap_err();
    assert_eq!(
        error,
        TextureError::TooLarge {
            width: MAX_TEXTURE_SIZE + 1,
            height: 1
        }
    );
    assert!(error.to_string().contains("16385x1"), "{error}");
    let too_tall = png(GrayImage::new(1, MAX_TEXTURE_SIZE + 1));
    assert!(matches!(
        decode_texture(&too_tall, None),
        Err(TextureError::TooLarge { height: 16385, .. })
    ));
    // At the limit it decodes.
    let at_limit = png(GrayImage::new(MAX_TEXTURE_SIZE, 1));
    assert_eq!(
        decode_texture(&at_limit, None).expect("decodes").width,
        MAX_TEXTURE_SIZE
    );
}

#[test]
fn wrap_modes_come_from_gltf() {
    use gltf::texture::WrappingMode;
    assert_eq!(WrapMode::from_gltf(WrappingMode::Repeat), WrapMode::Repeat);
    assert_eq!(
        WrapMode::from_gltf(WrappingMode::ClampToEdge),
        WrapMode::ClampToEdge
    );
    assert_eq!(
        WrapMode::from_gltf(WrappingMode::MirroredRepeat),
        WrapMode::MirroredRepeat
    );
}

/// `transform` applied to (u, v).
fn apply(transform: &TextureTransform, u: f32, v: f32) -> [f32; 2] {
    let [r0, r1] = transform.matrix;
    [r0[0] * u + r0[1] * v + r0[2], r1[0] * u + r1[1] * v + r1[2]]
}

fn assert_close(actual: [f32; 2], expected: [f32; 2]) {
    let error = (actual[0] - expected[0])
        .abs()
        .max((actual[1] - expected[1]).abs());
    assert!(error < 1e-6, "{actual:?} != {expected:?}");
}

#[test]
fn texture_transform_follows_the_extension_example() {
    assert_eq!(
        apply(&TextureTransform::identity(), 0.25, 0.75),
        [0.25, 0.75]
    );
    // KHR_texture_transform's example: offset (0, 1), rotation pi/2, scale 0.5 "utilizes only
    // the lower left quadrant of the source image, rotated clockwise 90 degrees".
    let transform =
        TextureTransform::from_gltf([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5]);
    assert_close(apply(&transform, 0.0, 0.0), [0.0, 1.0]); // bottom-left corner of the image
    assert_close(apply(&transform, 1.0, 0.0), [0.0, 0.5]);
    assert_close(apply(&transform, 0.0, 1.0), [0.5, 1.0]);
    assert_close(apply(&transform, 1.0, 1.0), [0.5, 0.5]);
    // Scale first, then rotation, then offset.
    let transform = TextureTransform::from_gltf([0.1, 0.2], 0.0, [2.0, 3.0]);
    assert_close(apply(&transform, 1.0, 1.0), [2.1, 3.2]);
}
