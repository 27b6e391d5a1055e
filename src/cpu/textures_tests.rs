//! Tests of the texture twins against values computed by hand.

use super::*;
use crate::contract::{TEXTURE_SLOT_TEXEL_COUNT, WRAP_CLAMP_TO_EDGE};
use crate::render::gpu_textures::GpuTextureSlot;
use crate::scene::textures::{DecodedImage, Texture, TextureTransform, WrapMode};

/// A slot for `texture` at texel 0 of the buffer.
fn slot(texture: &Texture, srgb: bool, transform: &TextureTransform) -> TextureSlot {
    let [a, b, c] = GpuTextureSlot::new(0, texture, srgb, transform)
        .to_texels()
        .map(UVec4::from_array);
    unpack_texture_slot(a, b, c)
}

fn texture(
    width: u32,
    height: u32,
    texels: Vec<[u8; 4]>,
    wrap: WrapMode,
    nearest: bool,
) -> Texture {
    Texture::new(
        DecodedImage {
            width,
            height,
            texels,
        },
        wrap,
        wrap,
        nearest,
    )
}

#[test]
fn texel_scale_reads_bytes_as_unorm() {
    assert_eq!(TEXTURE_SLOT_TEXEL_COUNT, 3);
    // 255 * TEXEL_UNORM_SCALE rounds to exactly 1 and every byte is within an ulp of b / 255.
    assert_eq!(255.0 * TEXEL_UNORM_SCALE, 1.0);
    assert_eq!(TEXEL_UNORM_SCALE, 1.0f32 / 255.0);
    for byte in 0..=255u8 {
        let scaled = f32::from(byte) * TEXEL_UNORM_SCALE;
        let exact = f64::from(byte) / 255.0;
        assert!(
            (f64::from(scaled) - exact).abs() <= f64::from(f32::EPSILON) * exact,
            "{byte}"
        );
    }
}

#[test]
fn srgb_to_linear_matches_the_standard() {
    assert_eq!(srgb_to_linear(0.0), 0.0);
    assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
    assert!((srgb_to_linear(0.5) - 0.21404114).abs() < 1e-7);
    // The linear segment: 0.04045 / 12.92 = 0.0031308.
    assert!((srgb_to_linear(0.04045) - 0.003130805).abs() < 1e-8);
    assert!((srgb_to_linear(0.02) - 0.02 / 12.92).abs() < 1e-9);
    // Continuous at the seam (the two pieces meet within 1e-7).
    assert!((srgb_to_linear(0.040451) - srgb_to_linear(0.04045)).abs() < 1e-6);
}

#[test]
fn repeat_is_a_euclidean_modulo() {
    let wrapped: Vec<i32> = (-4..5)
        .map(|i| wrap_texel_coordinate(i, 3, WRAP_REPEAT))
        .collect();
    assert_eq!(wrapped, vec![2, 0, 1, 2, 0, 1, 2, 0, 1]);
    let limit = TEXTURE_COORDINATE_LIMIT as i32;
    assert_eq!(wrap_texel_coordinate(limit, 3, WRAP_REPEAT), limit % 3);
    assert_eq!(
        wrap_texel_coordinate(-limit, 3, WRAP_REPEAT),
        (-limit).rem_euclid(3)
    );
}

#[test]
fn mirrored_repeat_alternates_tiles_and_mirrors() {
    // Size 3: ... | 2 1 0 | 0 1 2 | 2 1 0 | 0 1 2 | ...
    let wrapped: Vec<i32> = (-6..9)
        .map(|i| wrap_texel_coordinate(i, 3, WRAP_MIRRORED_REPEAT))
        .collect();
    assert_eq!(wrapped, vec![0, 1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1, 2]);
    let single: Vec<i32> = (-2..3)
        .map(|i| wrap_texel_coordinate(i, 1, WRAP_MIRRORED_REPEAT))
        .collect();
    assert_eq!(single, vec![0; 5]);
}

#[test]
fn clamp_to_edge_clamps_and_sizes_below_one_count_as_one() {
    let wrapped: Vec<i32> = (-2..5)
        .map(|i| wrap_texel_coordinate(i, 3, WRAP_CLAMP_TO_EDGE))
        .collect();
    assert_eq!(wrapped, vec![0, 0, 0, 1, 2, 2, 2]);
    for mode in [WRAP_REPEAT, WRAP_CLAMP_TO_EDGE, WRAP_MIRRORED_REPEAT, 3] {
        assert_eq!(wrap_texel_coordinate(-7, 0, mode), 0);
        assert_eq!(wrap_texel_coordinate(7, -5, mode), 0);
    }
}

#[test]
fn bilinear_midpoint_of_two_texels_is_their_mean() {
    // Two texels side by side: 0 and 200 (linear), so the midpoint u = 0.5 reads 100.
    let texels = vec![[0, 0, 0, 255], [200, 100, 50, 55]];
    let t = texture(2, 1, texels.clone(), WrapMode::ClampToEdge, false);
    let s = slot(&t, false, &TextureTransform::identity());
    let mid = sample_texture(&texels, &s, Vec2::new(0.5, 0.5));
    let expected = Vec4::new(100.0, 50.0, 25.0, 155.0) / 255.0;
    assert!((mid - expected).abs().max_element() < 1e-6, "{mid}");
    // Texel centres give the texels exactly.
    assert_eq!(
        sample_texture(&texels, &s, Vec2::new(0.25, 0.5)),
        get_texel(&texels, &s, IVec2::ZERO)
    );
    assert_eq!(
        sample_texture(&texels, &s, Vec2::new(0.75, 0.5)),
        get_texel(&texels, &s, IVec2::X)
    );
    // Clamp: beyond the edge the edge texel.
    assert_eq!(
        sample_texture(&texels, &s, Vec2::new(-3.0, 0.5)),
        get_texel(&texels, &s, IVec2::ZERO)
    );
    // Repeat: u = 0 lies between texel 1 (from the left tile) and texel 0.
    let t = texture(2, 1, texels.clone(), WrapMode::Repeat, false);
    let s = slot(&t, false, &TextureTransform::identity());
    assert!(
        (sample_texture(&texels, &s, Vec2::new(0.0, 0.5)) - expected)
            .abs()
            .max_element()
            < 1e-6
    );
}

#[test]
fn srgb_is_decoded_before_filtering() {
    // sRGB 0 and 255 decode to 0 and 1, so the midpoint is 0.5 (not srgb_to_linear(0.5)).
    let texels = vec![[0, 0, 0, 0], [255, 255, 255, 255]];
    let t = texture(2, 1, texels.clone(), WrapMode::ClampToEdge, false);
    let s = slot(&t, true, &TextureTransform::identity());
    let mid = sample_texture(&texels, &s, Vec2::new(0.5, 0.0));
    assert!((mid - Vec4::splat(0.5)).abs().max_element() < 1e-6, "{mid}");
    // A single texel: sRGB 128 -> 0.21586; alpha 128 stays 128 / 255.
    let texels = vec![[128, 128, 128, 128]];
    let t = texture(1, 1, texels.clone(), WrapMode::Repeat, true);
    let value = sample_texture(
        &texels,
        &slot(&t, true, &TextureTransform::identity()),
        Vec2::ZERO,
    );
    assert!((value.x - 0.2158605).abs() < 1e-6, "{value}");
    assert!((value.w - 128.0 / 255.0).abs() < 1e-7, "{value}");
}

#[test]
fn nearest_reads_the_texel_under_the_coordinate() {
    let texels: Vec<[u8; 4]> = (0..6).map(|i| [i * 10, 0, 0, 255]).collect();
    let t = texture(3, 2, texels.clone(), WrapMode::Repeat, true);
    let s = slot(&t, false, &TextureTransform::identity());
    let red =
        |u: f32, v: f32| (sample_texture(&texels, &s, Vec2::new(u, v)).x * 255.0).round() as u8;
    assert_eq!(red(0.0, 0.0), 0);
    assert_eq!(red(0.34, 0.0), 10);
    assert_eq!(red(0.99, 0.6), 50);
    assert_eq!(red(-0.01, -0.01), 50); // repeat: the bottom-right texel
    assert_eq!(red(1.0, 1.0), 0);
}

#[test]
fn transform_moves_the_lookup() {
    // KHR_texture_transform's example: uv (0, 0) reads the image's bottom-left corner.
    let texels: Vec<[u8; 4]> = (0..4).map(|i| [i * 60, 0, 0, 255]).collect();
    let t = texture(2, 2, texels.clone(), WrapMode::ClampToEdge, true);
    let transform =
        TextureTransform::from_gltf([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5]);
    let s = slot(&t, false, &transform);
    let moved = transform_tex_coord(&s, Vec2::new(0.1, 0.1));
    assert!(
        (moved - Vec2::new(0.05, 0.95)).abs().max_element() < 1e-6,
        "{moved}"
    );
    assert_eq!(
        sample_texture(&texels, &s, Vec2::new(0.1, 0.1)).x,
        120.0 * TEXEL_UNORM_SCALE
    );
}

#[test]
fn any_coordinate_reads_a_texel_of_the_texture() {
    let texels: Vec<[u8; 4]> = (0..6).map(|i| [i * 40, 255, 0, 255]).collect();
    let extremes = [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
        -f32::MAX,
        1e30,
        -1e4,
        0.0,
    ];
    for wrap in [
        WrapMode::Repeat,
        WrapMode::ClampToEdge,
        WrapMode::MirroredRepeat,
    ] {
        for nearest in [false, true] {
            let t = texture(3, 2, texels.clone(), wrap, nearest);
            for transform in [
                TextureTransform::identity(),
                TextureTransform::from_gltf([0.0, 0.0], 1.0, [1.0, 1.0]),
            ] {
                let s = slot(&t, true, &transform);
                for u in extremes {
                    for v in extremes {
                        let value = sample_texture(&texels, &s, Vec2::new(u, v));
                        assert!(value.is_finite(), "{u} {v}: {value}");
                        // Every texel of the texture has green 1 (the buffer's end reads 0).
                        assert!((value.y - 1.0).abs() < 1e-6, "{u} {v} {wrap:?}: {value}");
                    }
                }
            }
        }
    }
    // NaN reads texel coordinate 0: texel (0, 0).
    let t = texture(3, 2, texels.clone(), WrapMode::Repeat, false);
    let s = slot(&t, false, &TextureTransform::identity());
    assert_eq!(
        sample_texture(&texels, &s, Vec2::NAN),
        get_texel(&texels, &s, IVec2::ZERO)
    );
    // A slot past the end of the buffer reads zeros instead of panicking.
    let far = TextureSlot {
        first_texel: 100,
        ..s
    };
    assert_eq!(get_texel(&texels, &far, IVec2::ZERO), Vec4::ZERO);
}
