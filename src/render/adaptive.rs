//! Adaptive sampling (`--noise-threshold T`): a pixel stops taking samples once the
//! relative standard error of its mean, estimated from the accumulation's sum and sum of
//! squares, is at most `T`, judged every `min_spp` samples; `--spp` stays the cap. The
//! kernel decides before each sample from the pixel's state alone (`is_noise_check_due` and
//! `is_pixel_converged`, twins of `glsl/adaptive_sampling.glsl`), so the image does not
//! depend on how samples are split into frames, batches or tiles, and a resumed checkpoint
//! goes on bit for bit.
//!
//! It is slightly biased, as every adaptive sampler that stops on its own noise estimate
//! is: a pixel whose first samples happen to agree (a rare bright path not found yet)
//! stops early with too low an estimate. The minimum number of samples keeps this rare.

use crate::error::{Error, Result};

/// The samples a pixel takes at least before it may stop, unless `--noise-min-spp` says
/// otherwise: enough for a variance estimate that is not wildly off (with 16 samples the
/// sample variance of a normal is within a factor 2 of the truth 95% of the time).
pub const DEFAULT_MIN_SPP: u32 = 16;

/// When a pixel stops taking samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseThreshold {
    /// The relative standard error at which a pixel stops (> 0, finite).
    pub threshold: f32,
    /// Samples a pixel takes before it may stop, and the interval (in samples) at which it
    /// is judged after that (>= 2: a variance needs two).
    pub min_spp: u32,
}

impl NoiseThreshold {
    /// Checks the values; the error names the option.
    pub fn validate(&self) -> Result<()> {
        if !(self.threshold > 0.0 && self.threshold.is_finite()) {
            return Err(Error::InvalidSettings(format!(
                "--noise-threshold {} must be a finite number > 0 (e.g. 0.01: a relative standard error of 1%)",
                self.threshold
            )));
        }
        if self.min_spp < 2 {
            return Err(Error::InvalidSettings(format!(
                "--noise-min-spp {} must be at least 2 (a variance needs two samples)",
                self.min_spp
            )));
        }
        Ok(())
    }
}

/// Twin of GLSL `is_noise_check_due` (`glsl/adaptive_sampling.glsl`): whether a pixel that
/// holds `count` samples is judged now, every `min_samples` samples (at `min_samples`,
/// 2 `min_samples`, ...). Judging after every sample would stop pixels at every chance dip
/// of their noise estimate (each look is another chance to stop early, the bias of optional
/// stopping), and the counts it stops at keep Sobol points' strata whole.
pub fn is_noise_check_due(count: f32, min_samples: u32) -> bool {
    let n = count as u32;
    n >= min_samples && n.is_multiple_of(min_samples)
}

/// Twin of GLSL `is_pixel_converged` (`glsl/adaptive_sampling.glsl`), the same operations
/// in the same order: whether, for every channel, the estimated variance of the mean of
/// `count` samples with sum `sum` and sum of squares `sum_of_squares` is at most
/// (`threshold` times the brightest channel's mean) squared. Needs `count` >= 2.
pub fn is_pixel_converged(
    sum: [f32; 3],
    count: f32,
    sum_of_squares: [f32; 3],
    threshold: f32,
) -> bool {
    let mean = sum.map(|s| s / count);
    let denominator = (count - 1.0) * count;
    let variance_of_mean: [f32; 3] = std::array::from_fn(|c| {
        (sum_of_squares[c] - count * (mean[c] * mean[c])).max(0.0) / denominator
    });
    let largest_variance = variance_of_mean[0].max(variance_of_mean[1].max(variance_of_mean[2]));
    let limit = threshold * mean[0].max(mean[1].max(mean[2]));
    largest_variance <= limit * limit
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (sum, sum of squares) of samples, per channel the same.
    fn moments(samples: &[f32]) -> ([f32; 3], [f32; 3]) {
        let sum: f32 = samples.iter().sum();
        let squares: f32 = samples.iter().map(|x| x * x).sum();
        ([sum; 3], [squares; 3])
    }

    #[test]
    fn converges_exactly_when_the_standard_error_is_below_the_threshold() {
        // Samples 1, 3, 1, 3: mean 2, s^2 = 4/3, standard error sqrt(1/3) = 0.577, relative
        // 0.2887.
        let (sum, squares) = moments(&[1.0, 3.0, 1.0, 3.0]);
        assert!(is_pixel_converged(sum, 4.0, squares, 0.29));
        assert!(!is_pixel_converged(sum, 4.0, squares, 0.28));
        // Equal samples have no noise; all-black pixels too.
        let (sum, squares) = moments(&[0.5; 8]);
        assert!(is_pixel_converged(sum, 8.0, squares, 1e-6));
        let (sum, squares) = moments(&[0.0; 8]);
        assert!(is_pixel_converged(sum, 8.0, squares, 1e-6));
        // One sample of 1 among 16: mean 1/16, standard error exactly 1/16 (s^2 = 1/16),
        // relative error 1.
        let mut samples = [0.0f32; 16];
        samples[3] = 1.0;
        let (sum, squares) = moments(&samples);
        assert!(is_pixel_converged(sum, 16.0, squares, 1.0001));
        assert!(!is_pixel_converged(sum, 16.0, squares, 0.9999));
    }

    #[test]
    fn the_noisiest_channel_decides_relative_to_the_brightest() {
        // Red is bright and exact; blue is dim and noisy: its standard error (sqrt(1/3) =
        // 0.577) counts against red's mean (10): relative 0.0577.
        let sum = [40.0, 0.0, 4.0];
        let squares = [400.0, 0.0, 8.0]; // blue: samples 0, 2, 0, 2
        assert!(is_pixel_converged(sum, 4.0, squares, 0.06));
        assert!(!is_pixel_converged(sum, 4.0, squares, 0.05));
    }

    #[test]
    fn pixels_are_judged_every_min_samples() {
        let due: Vec<u32> = (0..70)
            .filter(|&n| is_noise_check_due(n as f32, 16))
            .collect();
        assert_eq!(due, [16, 32, 48, 64]);
    }

    #[test]
    fn bad_thresholds_are_refused() {
        for threshold in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let bad = NoiseThreshold {
                threshold,
                min_spp: 16,
            };
            assert!(bad.validate().is_err(), "{threshold}");
        }
        let few = NoiseThreshold {
            threshold: 0.1,
            min_spp: 1,
        };
        assert!(few
            .validate()
            .unwrap_err()
            .to_string()
            .contains("--noise-min-spp"));
    }
}
