//! Rust twins of `glsl/camera.glsl`: the random seed of a sample and the point of the image
//! it looks through. The shader's `PIXEL_FILTER` specialization constant is a parameter here.

use glam::{UVec2, Vec2};

use crate::contract::PIXEL_FILTER_CENTER;
use crate::cpu::workshop::get_random_numbers;

/// Odd multipliers that spread the user's seed over both seed words (the golden-ratio Weyl
/// constant 2^32 / phi and another odd constant), as in the shader.
const USER_SEED_MULTIPLIERS: UVec2 = UVec2::new(2654435769, 2246822507);

/// The random state of sample `sample_index` of a pixel, twin of GLSL `get_sample_seed`:
/// (pixel ^ sample bits) ^ (multipliers * user_seed), wrapping u32 arithmetic, where the
/// sample bits are (s << 16, (s ^ (s >> 16)) << 16). With user seed 0 and s below 2^16 this
/// is the workshop's `uvec2(pixel_coord) ^ uvec2(iFrame << 16)`; the index's high 16 bits
/// give samples from 2^16 on seeds of their own instead of repeating earlier samples'.
/// \param pixel Pixel index, counted from the bottom-left as ShaderToy does
/// \param sample_index Index of the sample within the pixel, from 0
/// \param user_seed The `--seed` option
pub fn get_sample_seed(pixel: UVec2, sample_index: u32, user_seed: u32) -> UVec2 {
    // Shifting by 16 drops the high bits, as GLSL's << does; the second word takes them back.
    let sample_bits = UVec2::new(
        sample_index << 16,
        (sample_index ^ (sample_index >> 16)) << 16,
    );
    (pixel ^ sample_bits) ^ USER_SEED_MULTIPLIERS.wrapping_mul(UVec2::splat(user_seed))
}

/// The point of the image in [0, 1]^2 that a sample of a pixel looks through, twin of GLSL
/// `get_sample_tex_coord`: the pixel centre with `PIXEL_FILTER_CENTER`, otherwise (as the
/// shader, for `PIXEL_FILTER_BOX`) a uniformly jittered point of the pixel, which consumes
/// one pair of random numbers.
/// \param pixel Pixel index from the bottom-left
/// \param resolution Image size in pixels
/// \param pixel_filter `PIXEL_FILTER_BOX` or `PIXEL_FILTER_CENTER` (`crate::contract`)
/// \param seed The sample's random state
pub fn get_sample_tex_coord(
    pixel: UVec2,
    resolution: UVec2,
    pixel_filter: u32,
    seed: &mut UVec2,
) -> Vec2 {
    let offset = if pixel_filter == PIXEL_FILTER_CENTER {
        Vec2::splat(0.5)
    } else {
        get_random_numbers(seed)
    };
    (pixel.as_vec2() + offset) / resolution.as_vec2()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contract::PIXEL_FILTER_BOX;

    #[test]
    fn seed_zero_is_the_workshop_formula() {
        let pixel = UVec2::new(17, 3);
        assert_eq!(
            get_sample_seed(pixel, 5, 0),
            UVec2::new(17 ^ (5 << 16), 3 ^ (5 << 16))
        );
        // The user seed changes both words, with wrapping multiplication.
        let seeded = get_sample_seed(pixel, 5, 3);
        let expected_x = (17 ^ (5 << 16)) ^ 2654435769u32.wrapping_mul(3);
        let expected_y = (3 ^ (5 << 16)) ^ 2246822507u32.wrapping_mul(3);
        assert_eq!(seeded, UVec2::new(expected_x, expected_y));
        // Sample indices past 2^16 keep their high bits in the second word's high half.
        assert_eq!(
            get_sample_seed(UVec2::ZERO, 1 << 16, 0),
            UVec2::new(0, 1 << 16)
        );
        assert_eq!(
            get_sample_seed(UVec2::ZERO, u32::MAX, 0),
            UVec2::new(0xffff_0000, 0)
        );
    }

    #[test]
    fn every_pixel_and_sample_has_its_own_seed() {
        // Injective over (pixel, sample) for pixels below 2^16: the first word's high half
        // gives the index's low bits, the second's XOR those its high bits. Checked on pixels
        // and indices that the old formula mapped together (s and s + 2^16, and pixels that
        // a high-bit term confined to the low halves would collide with).
        let mut seen = std::collections::HashMap::new();
        for pixel in [
            UVec2::new(0, 0),
            UVec2::new(0, 1),
            UVec2::new(1, 0),
            UVec2::new(65535, 65535),
        ] {
            for high in [0u32, 1, 2, 0x7fff, 0x8000, 0xffff] {
                for low in [0u32, 1, 0x8000, 0xffff] {
                    let sample = (high << 16) | low;
                    for user_seed in [0u32, 7] {
                        let seed = get_sample_seed(pixel, sample, user_seed);
                        let key = (seed, user_seed);
                        if let Some(earlier) = seen.insert(key, (pixel, sample)) {
                            panic!(
                                "{:?} and {:?} share seed {seed:?}",
                                earlier,
                                (pixel, sample)
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn tex_coord_centre_and_box() {
        let resolution = UVec2::new(4, 2);
        let mut seed = UVec2::new(1, 2);
        let centre =
            get_sample_tex_coord(UVec2::new(1, 0), resolution, PIXEL_FILTER_CENTER, &mut seed);
        assert_eq!(centre, Vec2::new(1.5 / 4.0, 0.5 / 2.0));
        assert_eq!(
            seed,
            UVec2::new(1, 2),
            "the centre consumes no random numbers"
        );
        for _ in 0..1000 {
            let jittered =
                get_sample_tex_coord(UVec2::new(3, 1), resolution, PIXEL_FILTER_BOX, &mut seed);
            assert!(
                jittered.x >= 0.75 && jittered.x <= 1.0 && jittered.y >= 0.5 && jittered.y <= 1.0
            );
        }
    }
}
