//! `vkpath compare`: is image A an unbiased estimate of image B? Both are split into blocks of
//! N x N pixels (8 by default); for every block and colour channel, the difference of the two
//! block means is z-tested against its estimated noise, with a Šidák correction so that the
//! chance of any false alarm over all tests is `alpha` (0.01 by default).
//!
//! Why blocks and not pixels: a pixel's variance estimated from few samples is itself very
//! noisy and heavy-tailed (path tracing's rare bright paths, fireflies, make the sample
//! variance usually too small and occasionally huge), so per-pixel z-scores have much heavier
//! tails than a normal and a Šidák threshold over tens of thousands of pixels fails
//! consistent images. A block pools the samples of m pixels: its mean and variance are far
//! closer to normal, and a bias shared by the block's pixels adds up over them, so blocks
//! also have more power against the biases that matter (a wrong estimator is wrong
//! everywhere). `--block 1` tests single pixels all the same.
//!
//! The noise comes from the moments that `vkpath render --moments` stores (second moment and
//! sample count per pixel), from both images where both have them. A reference without
//! moments (rendered elsewhere, or with many more samples) is taken as exact; if neither has
//! moments, the variance of each block's mean difference is estimated from the spread of the
//! pixel differences A - B within the block (see `blocks::spread_differences`).

pub mod blocks;
pub mod heatmap;

use statrs::distribution::{ContinuousCDF, StudentsT};

use crate::image_io::data::RenderedImage;
use crate::image_io::exr_input::ExrImage;
use crate::stats::sidak_alpha;
use crate::stats::ztest::{two_sided_p_value, z_score};
pub use blocks::VarianceSource;
use blocks::{moment_differences, pixel_variances, spread_differences, BlockDifference};

/// The default family-wise significance level.
pub const DEFAULT_ALPHA: f64 = 0.01;
/// The default block size in pixels (8 x 8 = 64 pixels per block).
pub const DEFAULT_BLOCK_SIZE: usize = 8;

/// Why two images cannot be compared.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CompareError {
    /// The images differ in size.
    #[error("the images differ in size: {0}x{1} vs {2}x{3}")]
    SizeMismatch(u32, u32, u32, u32),
    /// An option is out of range.
    #[error("{0}")]
    InvalidOption(String),
}

/// How to compare.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompareOptions {
    /// Family-wise significance level in (0, 1): the chance that consistent images are
    /// reported inconsistent.
    pub alpha: f64,
    /// Side of the square blocks in pixels, >= 1.
    pub block_size: usize,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            alpha: DEFAULT_ALPHA,
            block_size: DEFAULT_BLOCK_SIZE,
        }
    }
}

/// The test with the strongest evidence of a difference.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct WorstTest {
    /// Block column.
    pub block_x: usize,
    /// Block row, from the top.
    pub block_y: usize,
    /// Channel: 0 red, 1 green, 2 blue.
    pub channel: usize,
    /// Block mean of A minus block mean of B.
    pub difference: f64,
    /// The z-score (Student t with the block-spread variance).
    pub z: f64,
    /// Its two-sided p-value.
    pub p_value: f64,
}

/// Relative MSE of `image` against `reference`: mean of (x - r)^2 / (r^2 + 0.01) over all
/// pixels and colour channels (the 0.01 keeps dark pixels from dominating).
pub fn relative_mse(image: &RenderedImage, reference: &RenderedImage) -> f64 {
    let squared_errors = image.mean.iter().zip(&reference.mean).map(|(x, r)| {
        std::array::from_fn(|c| {
            let (x, r) = (f64::from(x[c]), f64::from(r[c]));
            (x - r) * (x - r)
        })
    });
    mean_relative_to_reference(squared_errors.zip(&reference.mean), image.mean.len())
}

/// The relMSE that `reference`'s own noise adds, in expectation, to every `relative_mse`
/// measured against it: the mean of its pixels' variance of the mean over (r^2 + 0.01), from
/// its moments. `None` when it has no moments (fewer than two samples in some pixel).
pub fn reference_noise_relative_mse(reference: &RenderedImage) -> Option<f64> {
    let variances = pixel_variances(reference, true)?;
    Some(mean_relative_to_reference(
        variances.into_iter().zip(&reference.mean),
        reference.mean.len(),
    ))
}

/// relMSE's normalisation: the mean over `pixel_count` pixels and the colour channels of
/// each pixel's term over (r^2 + 0.01), r the reference's value there.
fn mean_relative_to_reference<'a>(
    terms: impl Iterator<Item = ([f64; 3], &'a [f32; 4])>,
    pixel_count: usize,
) -> f64 {
    let mut total = 0.0f64;
    for (term, r) in terms {
        for c in 0..3 {
            let r = f64::from(r[c]);
            total += term[c] / (r * r + 0.01);
        }
    }
    total / (3 * pixel_count.max(1)) as f64
}

/// The outcome of a comparison.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CompareReport {
    /// Whether no test rejected: A is consistent with being an unbiased estimate of B.
    pub consistent: bool,
    /// Where the variances came from.
    pub variance_source: VarianceSource,
    /// Family-wise significance level.
    pub alpha: f64,
    /// Significance level of each test after the Šidák correction.
    pub per_test_significance: f64,
    /// Block side in pixels.
    pub block_size: usize,
    /// Blocks per row.
    pub blocks_x: usize,
    /// Blocks per column.
    pub blocks_y: usize,
    /// Tests run: blocks times 3 channels.
    pub test_count: usize,
    /// Tests whose p-value is below `per_test_significance`.
    pub failing_tests: usize,
    /// Blocks with at least one failing channel.
    pub failing_blocks: usize,
    /// `failing_blocks` / (`blocks_x` * `blocks_y`).
    pub failing_block_fraction: f64,
    /// The test with the smallest p-value.
    pub worst: WorstTest,
    /// `relative_mse` of A against B: how far A is from B, whatever the test says (with a
    /// converged reference as B, A's error as `vkpath bench` measures it).
    pub relative_mse: f64,
    /// Per block (row-major, top-down), the smallest p-value of its channels, for the heat
    /// map.
    #[serde(skip)]
    pub block_p_values: Vec<f64>,
}

/// The p-value of a block's difference: two-sided normal, or Student t when the variance
/// was estimated from the block's own pixels. Differences within float rounding count as
/// none (see `blocks::ROUNDING_TOLERANCE`).
fn test_block(block: &BlockDifference) -> (f64, f64) {
    if block.difference.abs() <= blocks::ROUNDING_TOLERANCE * block.scale {
        return (0.0, 1.0);
    }
    let z = z_score(block.difference, block.variance, 0.0, 0.0);
    let p_value = match block.degrees_of_freedom {
        Some(freedom) if z.is_finite() => match StudentsT::new(0.0, 1.0, freedom) {
            Ok(t) => 2.0 * t.sf(z.abs()),
            // A single-pixel block has infinite variance and z = 0 before it gets here.
            Err(_) => 1.0,
        },
        _ => two_sided_p_value(z),
    };
    (z, p_value)
}

/// Compares A against B block by block (see the module documentation).
pub fn compare_images(
    a: &ExrImage,
    b: &ExrImage,
    options: &CompareOptions,
) -> Result<CompareReport, CompareError> {
    let (ia, ib) = (&a.image, &b.image);
    if (ia.width, ia.height) != (ib.width, ib.height) {
        return Err(CompareError::SizeMismatch(
            ia.width, ia.height, ib.width, ib.height,
        ));
    }
    if ia.width == 0 || ia.height == 0 {
        return Err(CompareError::InvalidOption("the images are empty".into()));
    }
    if options.block_size == 0 {
        return Err(CompareError::InvalidOption(
            "--block must be at least 1".into(),
        ));
    }
    let variances_a = pixel_variances(ia, a.has_moments);
    let variances_b = pixel_variances(ib, b.has_moments);
    let source = match (&variances_a, &variances_b) {
        (Some(_), Some(_)) => VarianceSource::BothMoments,
        (Some(_), None) => VarianceSource::MomentsOfA,
        (None, Some(_)) => VarianceSource::MomentsOfB,
        (None, None) => VarianceSource::WithinBlockSpread,
    };
    if source == VarianceSource::WithinBlockSpread && options.block_size < 2 {
        return Err(CompareError::InvalidOption(
            "neither image has moments (render with --moments), so the noise must be estimated within blocks: use --block 2 or more".into(),
        ));
    }
    let blocks_x = (ia.width as usize).div_ceil(options.block_size);
    let blocks_y = (ia.height as usize).div_ceil(options.block_size);
    let test_count = blocks_x * blocks_y * 3;
    let significance = sidak_alpha(options.alpha, test_count)
        .map_err(|e| CompareError::InvalidOption(format!("--alpha {}: {e}", options.alpha)))?;
    let mut report = CompareReport {
        consistent: true,
        variance_source: source,
        alpha: options.alpha,
        per_test_significance: significance,
        block_size: options.block_size,
        blocks_x,
        blocks_y,
        test_count,
        failing_tests: 0,
        failing_blocks: 0,
        failing_block_fraction: 0.0,
        worst: WorstTest {
            block_x: 0,
            block_y: 0,
            channel: 0,
            difference: 0.0,
            z: 0.0,
            p_value: 1.0,
        },
        relative_mse: relative_mse(ia, ib),
        block_p_values: Vec::with_capacity(blocks_x * blocks_y),
    };
    for block_y in 0..blocks_y {
        for block_x in 0..blocks_x {
            let differences = match source {
                VarianceSource::WithinBlockSpread => {
                    spread_differences(ia, ib, options.block_size, block_x, block_y)
                }
                _ => moment_differences(
                    ia,
                    ib,
                    variances_a.as_deref(),
                    variances_b.as_deref(),
                    options.block_size,
                    block_x,
                    block_y,
                ),
            };
            let mut block_p_value = 1.0f64;
            let mut block_failed = false;
            for (channel, difference) in differences.iter().enumerate() {
                let (z, p_value) = test_block(difference);
                if p_value < significance {
                    report.failing_tests += 1;
                    block_failed = true;
                }
                block_p_value = block_p_value.min(p_value);
                if p_value < report.worst.p_value
                    || (p_value == report.worst.p_value && z.abs() > report.worst.z.abs())
                {
                    report.worst = WorstTest {
                        block_x,
                        block_y,
                        channel,
                        difference: difference.difference,
                        z,
                        p_value,
                    };
                }
            }
            report.failing_blocks += usize::from(block_failed);
            report.block_p_values.push(block_p_value);
        }
    }
    report.consistent = report.failing_tests == 0;
    report.failing_block_fraction = report.failing_blocks as f64 / (blocks_x * blocks_y) as f64;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image_io::data::RenderedImage;

    /// An image of value `base` plus uniform noise of variance `noise_variance` per pixel,
    /// with moments that state that variance (with n = 5 samples, (E[L^2] - E[L]^2) / 4).
    fn noisy(
        (width, height): (u32, u32),
        base: f32,
        noise_variance: f32,
        noise_seed: u32,
        moments: bool,
    ) -> ExrImage {
        let mut state = glam::UVec2::new(noise_seed, 7);
        let mean: Vec<[f32; 4]> = (0..width * height)
            .map(|_| {
                let u = crate::cpu::workshop::get_random_numbers(&mut state);
                // Uniform noise on an interval of width w has variance w^2 / 12.
                let v = base + (u.x - 0.5) * (12.0 * noise_variance).sqrt();
                [v, v, v, 1.0]
            })
            .collect();
        let second_moment = mean
            .iter()
            .map(|m| [m[0] * m[0] + 4.0 * noise_variance; 3])
            .collect();
        ExrImage {
            image: RenderedImage {
                width,
                height,
                sample_count: vec![5.0; mean.len()],
                mean,
                second_moment,
            },
            has_moments: moments,
        }
    }

    #[test]
    fn a_references_noise_is_what_it_adds_to_the_relative_mse() {
        // The moments state a variance of the mean of 0.01 per pixel: the noise term is
        // 0.01 / (r^2 + 0.01) averaged over pixels, about 0.0099 for r = 1 +- 0.17.
        let size = (64, 64);
        let exact = noisy(size, 1.0, 0.0, 1, true).image;
        let (mut measured, mut predicted) = (0.0, 0.0);
        for seed in 2..6 {
            let reference = noisy(size, 1.0, 0.01, seed, true).image;
            measured += relative_mse(&exact, &reference) / 4.0;
            predicted += reference_noise_relative_mse(&reference).unwrap() / 4.0;
        }
        assert!((predicted - 0.0099).abs() < 0.0099 * 0.05, "{predicted}");
        // (1 - r)^2 of uniform noise has a standard deviation of 0.89 sigma^2: the mean over
        // 4 x 4096 pixels is within 0.7 % (one standard error) of its expectation; 5 % is
        // seven standard errors.
        assert!(
            (measured - predicted).abs() < predicted * 0.05,
            "{measured} vs {predicted}"
        );
        // Without moments (one sample per pixel) the noise is unknown.
        let single = noisy(size, 1.0, 0.01, 2, false).image;
        let single = RenderedImage {
            sample_count: vec![1.0; single.mean.len()],
            ..single
        };
        assert_eq!(reference_noise_relative_mse(&single), None);
    }

    #[test]
    fn consistent_and_biased_images_with_every_variance_source() {
        let options = CompareOptions::default();
        // An image without moments next to one with moments is a reference taken as exact:
        // it gets no noise here.
        let size = (32, 24);
        let noise = |moments: bool, other: bool| if moments || !other { 0.01 } else { 0.0 };
        for (moments_a, moments_b, source) in [
            (true, true, VarianceSource::BothMoments),
            (true, false, VarianceSource::MomentsOfA),
            (false, true, VarianceSource::MomentsOfB),
            (false, false, VarianceSource::WithinBlockSpread),
        ] {
            let (noise_a, noise_b) = (noise(moments_a, moments_b), noise(moments_b, moments_a));
            let a = noisy(size, 1.0, noise_a, 1, moments_a);
            let b = noisy(size, 1.0, noise_b, 2, moments_b);
            let report = compare_images(&a, &b, &options).unwrap();
            assert_eq!(report.variance_source, source);
            assert_eq!(
                (report.blocks_x, report.blocks_y, report.test_count),
                (4, 3, 36)
            );
            assert!(report.consistent, "{source:?}: {report:?}");
            // A 20% bias is at least 0.2 / sqrt(2 * 0.01 / 64) = 11 standard errors per
            // block; Šidák over 36 tests at 0.01 rejects beyond about 3.6.
            let biased = noisy(size, 1.2, noise_a, 1, moments_a);
            let report = compare_images(&biased, &b, &options).unwrap();
            assert!(!report.consistent, "{source:?}: {report:?}");
            assert_eq!(report.failing_blocks, 12, "{source:?}");
            assert_eq!(report.relative_mse, relative_mse(&biased.image, &b.image));
        }
        // The error beside the verdict: a constant 0.2 too bright against 1 is
        // 0.2^2 / 1.01 per channel.
        let flat = |value: f32| noisy((8, 8), value, 0.0, 1, true);
        let report = compare_images(&flat(1.2), &flat(1.0), &options).unwrap();
        assert!(
            (report.relative_mse - 0.04 / 1.01).abs() < 1e-6,
            "{report:?}"
        );
    }

    #[test]
    fn exact_equal_images_pass_and_bad_options_fail() {
        let a = noisy((9, 9), 1.0, 0.01, 1, false);
        let report = compare_images(&a, &a, &CompareOptions::default()).unwrap();
        assert!(report.consistent && report.worst.p_value == 1.0);
        let small = noisy((8, 9), 1.0, 0.01, 1, false);
        assert_eq!(
            compare_images(&a, &small, &CompareOptions::default()),
            Err(CompareError::SizeMismatch(9, 9, 8, 9))
        );
        for options in [
            CompareOptions {
                block_size: 0,
                ..Default::default()
            },
            CompareOptions {
                block_size: 1,
                ..Default::default()
            },
            CompareOptions {
                alpha: 1.5,
                ..Default::default()
            },
        ] {
            assert!(matches!(
                compare_images(&a, &a, &options),
                Err(CompareError::InvalidOption(_))
            ));
        }
        // Per pixel is fine with moments.
        let with_moments = noisy((9, 9), 1.0, 0.01, 1, true);
        let exact = noisy((9, 9), 1.0, 0.0, 2, false);
        let options = CompareOptions {
            block_size: 1,
            ..Default::default()
        };
        let report = compare_images(&with_moments, &exact, &options).unwrap();
        assert!(report.consistent && report.test_count == 243, "{report:?}");
    }
}
