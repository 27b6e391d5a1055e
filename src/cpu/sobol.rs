//! Rust twins of `glsl/sobol.glsl`, the random numbers of the importance-sampled integrators
//! at fixed dimension pairs (`crate::cpu::sample_dimensions`): the first two Sobol dimensions
//! with Burley's hash-based Owen scrambling and index shuffling (Brent Burley 2020, "Practical
//! Hash-based Owen Scrambling", JCGT 9(4)), and the hashed PCG of `--sampler pcg`. Same names,
//! parameters and maths as the GLSL, operation for operation; everything is integer arithmetic
//! plus one exact conversion to float, so the twins agree bit for bit. Change both together.

use glam::{UVec2, Vec2};

use crate::contract::SAMPLER_SOBOL;

/// Twin of GLSL `sobol_reverse_bits` (`bitfieldReverse`): bit 0 becomes bit 31.
pub fn sobol_reverse_bits(x: u32) -> u32 {
    x.reverse_bits()
}

/// Twin of GLSL `laine_karras_permutation`: Burley's improved Laine-Karras hash, a
/// permutation of the u32s in which each bit depends only on the bits below it.
/// \param x The value to permute
/// \param seed Selects the permutation
pub fn laine_karras_permutation(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Twin of GLSL `nested_uniform_scramble`: an Owen scramble of a 32-bit fixed-point number
/// in [0, 1) (reverse the bits, `laine_karras_permutation`, reverse back).
pub fn nested_uniform_scramble(mut x: u32, seed: u32) -> u32 {
    x = sobol_reverse_bits(x);
    x = laine_karras_permutation(x, seed);
    sobol_reverse_bits(x)
}

/// Twin of GLSL `sobol_dimension_0`: the van der Corput sequence, 32-bit fixed point.
pub fn sobol_dimension_0(index: u32) -> u32 {
    sobol_reverse_bits(index)
}

/// Twin of GLSL `sobol_dimension_1`: the second Sobol dimension, 32-bit fixed point, with
/// direction numbers v_0 = 2^-1, v_j = v_{j-1} ^ (v_{j-1} >> 1), in closed form: bit 31 - k
/// of the result is the XOR of the index bits j over all bit-supersets j of k.
pub fn sobol_dimension_1(index: u32) -> u32 {
    let mut superset_xor = index;
    superset_xor ^= (superset_xor >> 1) & 0x5555_5555;
    superset_xor ^= (superset_xor >> 2) & 0x3333_3333;
    superset_xor ^= (superset_xor >> 4) & 0x0f0f_0f0f;
    superset_xor ^= (superset_xor >> 8) & 0x00ff_00ff;
    superset_xor ^= (superset_xor >> 16) & 0x0000_ffff;
    sobol_reverse_bits(superset_xor)
}

/// Twin of GLSL `sobol_hash`: the PCG hash (Jarzynski and Olano 2020, JCGT 9(3)).
pub fn sobol_hash(value: u32) -> u32 {
    let state = value.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// Twin of GLSL `sobol_hash_combine` (boost's `hash_combine`).
pub fn sobol_hash_combine(seed: u32, value: u32) -> u32 {
    seed ^ value
        .wrapping_add(0x9e37_79b9)
        .wrapping_add(seed << 6)
        .wrapping_add(seed >> 2)
}

/// Twin of GLSL `get_sobol_pixel_seed`: the seed of a pixel's Sobol sequences.
/// \param pixel Pixel index from the bottom-left
/// \param user_seed The `--seed` option
pub fn get_sobol_pixel_seed(pixel: UVec2, user_seed: u32) -> u32 {
    sobol_hash(sobol_hash_combine(
        sobol_hash_combine(sobol_hash(user_seed), pixel.x),
        pixel.y,
    ))
}

/// 2^-24, exact in f32.
const TWO_TO_MINUS_24: f32 = 5.960_464_5e-8;

/// Twin of GLSL `sobol_to_float`: the top 24 bits of a 32-bit fixed-point number as a float
/// in [0, 1), exactly (`x as f32 * 2^-32` would round values near 2^32 up to 1.0).
pub fn sobol_to_float(x: u32) -> f32 {
    (x >> 8) as f32 * TWO_TO_MINUS_24
}

/// Twin of GLSL `get_sobol_sample_2d`: sample `sample_index` of the shuffled, Owen-scrambled
/// 2D Sobol sequence of one dimension pair of one pixel (Burley 2020, listing 3).
/// \param sample_index Index of the sample within the pixel, from 0
/// \param dimension_pair Which pair of random numbers of the sample
///        (`crate::cpu::sample_dimensions`)
/// \param pixel_seed `get_sobol_pixel_seed` of the pixel
/// \return Two numbers in [0, 1); for sample indices 0..2^k they form a (0,k,2)-net
pub fn get_sobol_sample_2d(sample_index: u32, dimension_pair: u32, pixel_seed: u32) -> Vec2 {
    let seed = sobol_hash(sobol_hash_combine(pixel_seed, dimension_pair));
    let index = nested_uniform_scramble(sample_index, seed);
    let x = nested_uniform_scramble(sobol_dimension_0(index), sobol_hash_combine(seed, 0));
    let y = nested_uniform_scramble(sobol_dimension_1(index), sobol_hash_combine(seed, 1));
    Vec2::new(sobol_to_float(x), sobol_to_float(y))
}

/// Twin of GLSL `pcg2d_hash`: PCG2D (Jarzynski and Olano 2020, JCGT 9(3)) as a hash of two
/// words, the state update of `crate::cpu::workshop::get_random_numbers`.
pub fn pcg2d_hash(v: UVec2) -> UVec2 {
    use crate::cpu::workshop::{PCG_INCREMENT, PCG_MULTIPLIER};
    // v = 1664525u * v + 1013904223u;
    let mut x = PCG_MULTIPLIER.wrapping_mul(v.x).wrapping_add(PCG_INCREMENT);
    let mut y = PCG_MULTIPLIER.wrapping_mul(v.y).wrapping_add(PCG_INCREMENT);
    // v.x += 1664525u * v.y; v.y += 1664525u * v.x; v ^= (v >> 16u); twice
    for _ in 0..2 {
        x = x.wrapping_add(PCG_MULTIPLIER.wrapping_mul(y));
        y = y.wrapping_add(PCG_MULTIPLIER.wrapping_mul(x));
        x ^= x >> 16;
        y ^= y >> 16;
    }
    UVec2::new(x, y)
}

/// Twin of GLSL `get_pcg_sample_2d`: independent uniform numbers for one sample and
/// dimension pair of one pixel, hashed from the pair's seed and the sample index.
/// \param sample_index Index of the sample within the pixel, from 0
/// \param dimension_pair Which pair of random numbers of the sample
/// \param pixel_seed `get_sobol_pixel_seed` of the pixel
/// \return Two numbers in [0, 1) (24 bits each, `sobol_to_float`)
pub fn get_pcg_sample_2d(sample_index: u32, dimension_pair: u32, pixel_seed: u32) -> Vec2 {
    let pair_seed = sobol_hash(sobol_hash_combine(pixel_seed, dimension_pair));
    let hashed = pcg2d_hash(UVec2::new(
        pair_seed,
        sobol_hash(sobol_hash_combine(pair_seed, sample_index)),
    ));
    Vec2::new(sobol_to_float(hashed.x), sobol_to_float(hashed.y))
}

/// The sample whose random numbers the importance-sampled integrators draw: the shader's
/// `SAMPLER` and `g_path.sample_index`, `g_path.pixel_seed`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathSample {
    /// `SAMPLER_PCG` or `SAMPLER_SOBOL` of `crate::contract`.
    pub sampler: u32,
    /// Index of the sample within the pixel, from 0.
    pub sample_index: u32,
    /// `get_sobol_pixel_seed` of the pixel.
    pub pixel_seed: u32,
}

impl PathSample {
    /// Sample `sample_index` of `pixel` (from the bottom-left) with the user's seed, as
    /// `main()` sets `g_path` up before each sample.
    pub fn new(sampler: u32, pixel: UVec2, sample_index: u32, user_seed: u32) -> PathSample {
        PathSample {
            sampler,
            sample_index,
            pixel_seed: get_sobol_pixel_seed(pixel, user_seed),
        }
    }
}

/// Twin of GLSL `get_path_random_numbers`: the numbers at dimension pair `dimension_pair` of
/// `sample` (`crate::cpu::sample_dimensions`), Sobol's or hashed PCG's: the same however many
/// others were drawn before, and in which order.
pub fn get_path_random_numbers(sample: &PathSample, dimension_pair: u32) -> Vec2 {
    if sample.sampler == SAMPLER_SOBOL {
        get_sobol_sample_2d(sample.sample_index, dimension_pair, sample.pixel_seed)
    } else {
        get_pcg_sample_2d(sample.sample_index, dimension_pair, sample.pixel_seed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::workshop::get_random_numbers;

    /// Whether the points (32-bit fixed point) form a (0,k,2)-net in base 2: for every
    /// split k = a + b, each of the 2^k elementary intervals [i 2^-a, (i+1) 2^-a) x
    /// [j 2^-b, (j+1) 2^-b) holds exactly one point.
    fn is_net(points: &[(u32, u32)], k: u32) -> bool {
        assert_eq!(points.len(), 1 << k);
        (0..=k).all(|a| {
            let b = k - a;
            let mut counts = vec![0u32; 1 << k];
            for &(x, y) in points {
                // The top a bits of x and the top b bits of y name the interval.
                let i = if a == 0 { 0 } else { x >> (32 - a) };
                let j = if b == 0 { 0 } else { y >> (32 - b) };
                counts[((i << b) | j) as usize] += 1;
            }
            counts.iter().all(|&count| count == 1)
        })
    }

    #[test]
    fn direction_numbers_of_dimension_1() {
        let expected = [
            0x8000_0000u32,
            0xc000_0000,
            0xa000_0000,
            0xf000_0000,
            0x8800_0000,
        ];
        for (bit, &direction) in expected.iter().enumerate() {
            assert_eq!(sobol_dimension_1(1 << bit), direction, "bit {bit}");
        }
        // In index order (not Gray-code order) the second dimension starts
        // 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8.
        let start: Vec<f64> = (0..8)
            .map(|i| f64::from(sobol_dimension_1(i)) / 2f64.powi(32))
            .collect();
        assert_eq!(start, [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875]);
    }

    /// The definition: the XOR of the direction numbers of the index's set bits.
    fn sobol_dimension_1_by_definition(mut index: u32) -> u32 {
        let mut result = 0u32;
        let mut direction = 0x8000_0000u32;
        while index != 0 {
            if index & 1 != 0 {
                result ^= direction;
            }
            direction ^= direction >> 1;
            index >>= 1;
        }
        result
    }

    #[test]
    fn dimension_1_closed_form_matches_its_definition() {
        // All 2^16 small indices, and 2^16 scattered ones (a multiplicative walk over all
        // 32 bits, as the shuffled indices of get_sobol_sample_2d are).
        let small = 0..1u32 << 16;
        let scattered = (0..1u32 << 16).map(|i| i.wrapping_mul(0x9e37_79b9) ^ (i << 16));
        for index in small.chain(scattered).chain([u32::MAX]) {
            assert_eq!(
                sobol_dimension_1(index),
                sobol_dimension_1_by_definition(index),
                "index {index:#x}"
            );
        }
    }

    #[test]
    fn unscrambled_sobol_points_are_nets() {
        for k in 0..=10 {
            let points: Vec<(u32, u32)> = (0..1u32 << k)
                .map(|i| (sobol_dimension_0(i), sobol_dimension_1(i)))
                .collect();
            assert!(is_net(&points, k), "first 2^{k} points");
        }
    }

    #[test]
    fn scrambled_shuffled_sobol_points_are_nets() {
        // Owen scrambling permutes elementary intervals, and the shuffle maps indices
        // 0..2^k to an aligned block of 2^k Sobol points, which is a net too.
        for pixel_seed in [
            0u32,
            1,
            0xdead_beef,
            get_sobol_pixel_seed(UVec2::new(3, 7), 42),
        ] {
            for dimension_pair in [0u32, 1, 5, 63, 1000] {
                let seed = sobol_hash(sobol_hash_combine(pixel_seed, dimension_pair));
                for k in 0..=10 {
                    let points: Vec<(u32, u32)> = (0..1u32 << k)
                        .map(|i| {
                            let index = nested_uniform_scramble(i, seed);
                            (
                                nested_uniform_scramble(
                                    sobol_dimension_0(index),
                                    sobol_hash_combine(seed, 0),
                                ),
                                nested_uniform_scramble(
                                    sobol_dimension_1(index),
                                    sobol_hash_combine(seed, 1),
                                ),
                            )
                        })
                        .collect();
                    assert!(
                        is_net(&points, k),
                        "seed {pixel_seed:#x} pair {dimension_pair} k {k}"
                    );
                    // The floats agree with the fixed-point points and lie in [0, 1).
                    for (i, &(x, y)) in points.iter().enumerate() {
                        let sample = get_sobol_sample_2d(i as u32, dimension_pair, pixel_seed);
                        assert_eq!(sample, Vec2::new(sobol_to_float(x), sobol_to_float(y)));
                        assert!(sample.x < 1.0 && sample.y < 1.0);
                    }
                }
            }
        }
    }

    #[test]
    fn to_float_stays_below_one() {
        assert_eq!(sobol_to_float(u32::MAX), 1.0 - 2f32.powi(-24));
        assert_eq!(sobol_to_float(0), 0.0);
        assert_eq!(sobol_to_float(0x8000_0000), 0.5);
    }

    #[test]
    fn nested_uniform_scramble_is_a_permutation_of_prefixes() {
        // Owen scrambling maps each interval [i 2^-8, (i+1) 2^-8) to one interval: the top
        // 8 output bits depend only on the top 8 input bits.
        let seed = 0x1234_5678;
        for top in 0u32..256 {
            let expected = nested_uniform_scramble(top << 24, seed) >> 24;
            for low in [1u32, 0x00ff_ffff, 0x0012_3456] {
                assert_eq!(
                    nested_uniform_scramble((top << 24) | low, seed) >> 24,
                    expected
                );
            }
        }
    }

    /// The smooth test integrand f(u, v) = exp(-(u-0.3)^2 - (v-0.6)^2) (1 + 0.5 sin(2 pi u)).
    fn integrand(u: f64, v: f64) -> f64 {
        (-(u - 0.3).powi(2) - (v - 0.6).powi(2)).exp()
            * (1.0 + 0.5 * (2.0 * std::f64::consts::PI * u).sin())
    }

    /// The integral over [0,1]^2 by the midpoint rule on a 2000 x 2000 grid: its error is
    /// O(h^2 f'') ~ 1e-7, far below the smallest RMS error measured (~1e-4 at N = 1024).
    fn reference_integral() -> f64 {
        let n = 2000;
        let h = 1.0 / n as f64;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                sum += integrand((i as f64 + 0.5) * h, (j as f64 + 0.5) * h);
            }
        }
        sum * h * h
    }

    /// Least-squares slope of log(error) against log(N).
    fn log_log_slope(counts: &[u32], errors: &[f64]) -> f64 {
        let xs: Vec<f64> = counts.iter().map(|&n| f64::from(n).ln()).collect();
        let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
        let mean_x = xs.iter().sum::<f64>() / xs.len() as f64;
        let mean_y = ys.iter().sum::<f64>() / ys.len() as f64;
        let covariance: f64 = xs
            .iter()
            .zip(&ys)
            .map(|(x, y)| (x - mean_x) * (y - mean_y))
            .sum();
        let variance: f64 = xs.iter().map(|x| (x - mean_x).powi(2)).sum();
        covariance / variance
    }

    #[test]
    fn sobol_converges_faster_than_pcg_on_a_smooth_integrand() {
        let reference = reference_integral();
        let counts = [16u32, 64, 256, 1024];
        // 64 independent pixels. PCG2D: one stream per pixel, seeded with a hash of the
        // pixel, which measured the errors of independent samples (sigma(f) / sqrt(N) with
        // sigma(f) = 0.379: 0.095 at N = 16, 0.0118 at N = 1024). The workshop's per-sample
        // seeds (get_sample_seed) differ only in bits 16 and up from sample to sample; one
        // PCG2D step from each measured a slope of -0.70 here (half the independent error at
        // N = 1024): correlated samples, which this baseline should not have.
        // Sobol: get_sobol_pixel_seed, as the path tracer seeds it.
        let pixels: Vec<UVec2> = (0..64).map(|i| UVec2::new(i % 8, i / 8)).collect();
        let rms = |estimate: &dyn Fn(UVec2, u32) -> f64, n: u32| -> f64 {
            let squared: f64 = pixels
                .iter()
                .map(|&pixel| (estimate(pixel, n) - reference).powi(2))
                .sum();
            (squared / pixels.len() as f64).sqrt()
        };
        let pcg = |pixel: UVec2, n: u32| -> f64 {
            let mut seed = UVec2::new(sobol_hash(pixel.x), sobol_hash(pixel.y + 1000));
            (0..n)
                .map(|_| {
                    let u = get_random_numbers(&mut seed);
                    integrand(f64::from(u.x), f64::from(u.y))
                })
                .sum::<f64>()
                / f64::from(n)
        };
        let sobol = |pixel: UVec2, n: u32| -> f64 {
            let pixel_seed = get_sobol_pixel_seed(pixel, 7);
            (0..n)
                .map(|s| {
                    let u = get_sobol_sample_2d(s, 0, pixel_seed);
                    integrand(f64::from(u.x), f64::from(u.y))
                })
                .sum::<f64>()
                / f64::from(n)
        };
        let pcg_errors: Vec<f64> = counts.iter().map(|&n| rms(&pcg, n)).collect();
        let sobol_errors: Vec<f64> = counts.iter().map(|&n| rms(&sobol, n)).collect();
        let pcg_slope = log_log_slope(&counts, &pcg_errors);
        let sobol_slope = log_log_slope(&counts, &sobol_errors);
        println!("reference integral {reference:.9}");
        for (i, n) in counts.iter().enumerate() {
            println!(
                "N = {n:4}: RMS error PCG2D {:.3e}, Sobol {:.3e}",
                pcg_errors[i], sobol_errors[i]
            );
        }
        println!("log-log slopes: PCG2D {pcg_slope:.3}, Sobol {sobol_slope:.3}");
        // Monte Carlo error falls as N^-1/2; with 64 pixels the RMS itself is uncertain by
        // about 1/sqrt(2*64) ~ 9% per N, a standard error of ~0.03 on the fitted slope, so
        // +-0.15 is about 5 standard errors.
        assert!((pcg_slope + 0.5).abs() <= 0.15, "PCG2D slope {pcg_slope}");
        // Owen-scrambled nets reach N^-3/2 (up to log factors) for smooth integrands;
        // -0.9 is a conservative bound that independent samples could never reach.
        assert!(sobol_slope < -0.9, "Sobol slope {sobol_slope}");
        let last = counts.len() - 1;
        assert!(
            sobol_errors[last] * 10.0 <= pcg_errors[last],
            "at N = 1024, Sobol {} vs PCG2D {}",
            sobol_errors[last],
            pcg_errors[last]
        );
    }

    #[test]
    fn hashed_pcg_converges_as_independent_samples() {
        // --sampler pcg at a fixed pair: over sample indices, the error of independent samples
        // (slope -1/2, bound as in the test above), unlike Sobol's.
        let reference = reference_integral();
        let counts = [16u32, 64, 256, 1024];
        let pixels: Vec<UVec2> = (0..64).map(|i| UVec2::new(i % 8, i / 8)).collect();
        let errors: Vec<f64> = counts
            .iter()
            .map(|&n| {
                let squared: f64 = pixels
                    .iter()
                    .map(|&pixel| {
                        let pixel_seed = get_sobol_pixel_seed(pixel, 7);
                        let mean = (0..n)
                            .map(|s| {
                                let u = get_pcg_sample_2d(s, 5, pixel_seed);
                                integrand(f64::from(u.x), f64::from(u.y))
                            })
                            .sum::<f64>()
                            / f64::from(n);
                        (mean - reference).powi(2)
                    })
                    .sum();
                (squared / pixels.len() as f64).sqrt()
            })
            .collect();
        let slope = log_log_slope(&counts, &errors);
        println!("hashed PCG: RMS errors {errors:?}, slope {slope:.3}");
        assert!((slope + 0.5).abs() <= 0.15, "hashed PCG slope {slope}");
    }

    /// Pearson's correlation of two equally long series.
    fn correlation(a: &[f64], b: &[f64]) -> f64 {
        let n = a.len() as f64;
        let mean_a = a.iter().sum::<f64>() / n;
        let mean_b = b.iter().sum::<f64>() / n;
        let covariance: f64 = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - mean_a) * (y - mean_b))
            .sum();
        let variance_a: f64 = a.iter().map(|x| (x - mean_a).powi(2)).sum();
        let variance_b: f64 = b.iter().map(|y| (y - mean_b).powi(2)).sum();
        covariance / (variance_a * variance_b).sqrt()
    }

    #[test]
    fn hashed_pcg_is_independent_across_samples_pixels_and_pairs() {
        // 64 pixels x 64 samples: the numbers of one (pixel, sample, pair) against those of
        // the next sample, the next pixel, the next pair, and its own second number. For
        // independent uniforms each correlation is about N(0, 1/N): 4/sqrt(N) = 0.0625 is four
        // standard errors, while the structured seeds that differ only in a few bits (what a
        // weak hash would leave) correlate far more.
        let numbers = |pixel: UVec2, sample: u32, pair: u32| {
            get_pcg_sample_2d(sample, pair, get_sobol_pixel_seed(pixel, 3))
        };
        let mut keys = Vec::new();
        for i in 0..64u32 {
            for sample in 0..64u32 {
                keys.push((UVec2::new(i % 8, i / 8), sample));
            }
        }
        let bound = 4.0 / (keys.len() as f64).sqrt();
        let series = |f: &dyn Fn(UVec2, u32) -> f32| -> Vec<f64> {
            keys.iter().map(|&(p, s)| f64::from(f(p, s))).collect()
        };
        for pair in [0u32, 3, 14, 50] {
            let base = series(&|p, s| numbers(p, s, pair).x);
            let others: [(&str, Vec<f64>); 5] = [
                ("its second number", series(&|p, s| numbers(p, s, pair).y)),
                ("the next sample", series(&|p, s| numbers(p, s + 1, pair).x)),
                (
                    "the next pixel",
                    series(&|p, s| numbers(p + UVec2::X, s, pair).x),
                ),
                ("the next pair", series(&|p, s| numbers(p, s, pair + 1).x)),
                (
                    "the next pair's second",
                    series(&|p, s| numbers(p, s, pair + 1).y),
                ),
            ];
            let mean = base.iter().sum::<f64>() / base.len() as f64;
            // The mean of N uniforms has standard error sqrt(1/12/N).
            assert!(
                (mean - 0.5).abs() < 4.0 * (1.0 / 12.0 / base.len() as f64).sqrt(),
                "pair {pair}: mean {mean}"
            );
            for (name, other) in &others {
                let r = correlation(&base, other);
                assert!(r.abs() < bound, "pair {pair} against {name}: r = {r:.4}");
            }
        }
    }

    #[test]
    fn path_random_numbers_follow_the_sampler() {
        let pcg = PathSample::new(crate::contract::SAMPLER_PCG, UVec2::new(2, 3), 17, 9);
        let sobol = PathSample {
            sampler: SAMPLER_SOBOL,
            ..pcg
        };
        for pair in [0u32, 4, 40] {
            assert_eq!(
                get_path_random_numbers(&sobol, pair),
                get_sobol_sample_2d(17, pair, get_sobol_pixel_seed(UVec2::new(2, 3), 9))
            );
            assert_eq!(
                get_path_random_numbers(&pcg, pair),
                get_pcg_sample_2d(17, pair, pcg.pixel_seed)
            );
        }
        // PCG2D as a hash is the workshop's state update.
        let mut state = UVec2::new(123, 456);
        crate::cpu::workshop::get_random_numbers(&mut state);
        assert_eq!(pcg2d_hash(UVec2::new(123, 456)), state);
    }
}
