//! z-tests that compare two Monte Carlo estimates of the same image (e.g. GPU against CPU,
//! or a render against an analytic answer): per pixel or per block of pixels and channel,
//! z = (mean_a - mean_b) / sqrt(var_a + var_b) with the variances of the two means, two-sided
//! normal p-values, and a Šidák correction over all the tests.
//!
//! The normal approximation needs enough samples per tested element: with variances
//! estimated from few samples, z has heavier tails than a normal. Averaging over blocks
//! (`MeanImage::block_average`) pools samples and keeps the test honest.

use statrs::distribution::{ContinuousCDF, Normal};

use crate::stats::{sidak_alpha, StatsError};

/// The z-score of the difference of two independent estimates.
/// \param mean_a, mean_b The estimates
/// \param variance_of_mean_a, variance_of_mean_b Their variances (of the means, not of
///        single samples), >= 0; an infinite variance means "unknown" and gives z = 0
/// \return (mean_a - mean_b) / sqrt(variance_of_mean_a + variance_of_mean_b); with both
///         variances 0 (two exact values) 0 where the means are equal and +-infinity where
///         not; NaN if a mean is NaN
pub fn z_score(mean_a: f64, variance_of_mean_a: f64, mean_b: f64, variance_of_mean_b: f64) -> f64 {
    let difference = mean_a - mean_b;
    let variance = variance_of_mean_a + variance_of_mean_b;
    if variance == 0.0 {
        return if difference == 0.0 {
            0.0
        } else {
            difference * f64::INFINITY
        };
    }
    if variance.is_infinite() && difference.is_finite() {
        return 0.0;
    }
    difference / variance.sqrt()
}

/// The two-sided p-value of a z-score, P(|Z| >= |z|) = 2 (1 - Phi(|z|)), from the normal
/// survival function (precise far into the tail). A NaN z-score (a NaN estimate) gives 0:
/// such an estimate is wrong, not uncertain.
pub fn two_sided_p_value(z: f64) -> f64 {
    if z.is_nan() {
        return 0.0;
    }
    2.0 * Normal::standard().sf(z.abs())
}

/// Estimates of the mean of every element of an image: per pixel (or block) and channel,
/// with the estimated variance of each mean.
#[derive(Clone, Debug, PartialEq)]
pub struct MeanImage {
    /// Width in elements.
    pub width: usize,
    /// Height in elements.
    pub height: usize,
    /// Channels per element.
    pub channel_count: usize,
    /// Means, index (y * width + x) * channel_count + channel.
    pub means: Vec<f64>,
    /// Variances of the means, same indexing; 0 for exact values, infinite for unknown ones.
    pub variances_of_mean: Vec<f64>,
}

/// The size a row-major image of `width * height` elements with `channel_count` channels
/// must have, or an error naming `what`.
fn check_size(
    what: &str,
    actual: usize,
    width: usize,
    height: usize,
    channel_count: usize,
) -> Result<(), StatsError> {
    if actual != width * height * channel_count {
        return Err(StatsError::SizeMismatch(format!(
            "{what} has {actual} values, not {width} x {height} x {channel_count}"
        )));
    }
    Ok(())
}

impl MeanImage {
    /// The RGB channels of an RGBA mean image (alpha ignored) with their variances of the
    /// mean, as `CpuImage::mean` and `CpuImage::variance_of_mean` give them.
    pub fn from_rgb(
        width: usize,
        height: usize,
        mean: &[[f32; 4]],
        variance_of_mean: &[[f64; 3]],
    ) -> Result<MeanImage, StatsError> {
        check_size("the mean image", mean.len(), width, height, 1)?;
        check_size(
            "the variance image",
            variance_of_mean.len(),
            width,
            height,
            1,
        )?;
        Ok(MeanImage {
            width,
            height,
            channel_count: 3,
            means: mean
                .iter()
                .flat_map(|rgba| rgba[..3].iter().map(|&v| v as f64))
                .collect(),
            variances_of_mean: variance_of_mean.iter().flatten().copied().collect(),
        })
    }

    /// An image of exact values (variance 0), e.g. an analytic answer.
    pub fn exact(
        width: usize,
        height: usize,
        channel_count: usize,
        values: Vec<f64>,
    ) -> Result<MeanImage, StatsError> {
        check_size(
            "the exact image",
            values.len(),
            width,
            height,
            channel_count,
        )?;
        let variances_of_mean = vec![0.0; values.len()];
        Ok(MeanImage {
            width,
            height,
            channel_count,
            means: values,
            variances_of_mean,
        })
    }

    /// Averages blocks of `block_size` x `block_size` elements (partial blocks at the right
    /// and bottom edges average what they hold). The elements are independent estimates, so
    /// the variance of a block's mean of m elements is the sum of their variances / m^2.
    pub fn block_average(&self, block_size: usize) -> Result<MeanImage, StatsError> {
        if block_size == 0 {
            return Err(StatsError::InvalidParameter("block size 0".into()));
        }
        let width = self.width.div_ceil(block_size);
        let height = self.height.div_ceil(block_size);
        let channels = self.channel_count;
        let mut means = vec![0.0; width * height * channels];
        let mut variances_of_mean = vec![0.0; width * height * channels];
        let mut element_counts = vec![0.0f64; width * height];
        for y in 0..self.height {
            for x in 0..self.width {
                let block = (y / block_size) * width + x / block_size;
                element_counts[block] += 1.0;
                for channel in 0..channels {
                    let source = (y * self.width + x) * channels + channel;
                    means[block * channels + channel] += self.means[source];
                    variances_of_mean[block * channels + channel] += self.variances_of_mean[source];
                }
            }
        }
        for (index, (mean, variance)) in means
            .iter_mut()
            .zip(variances_of_mean.iter_mut())
            .enumerate()
        {
            let m = element_counts[index / channels];
            *mean /= m;
            *variance /= m * m;
        }
        Ok(MeanImage {
            width,
            height,
            channel_count: channels,
            means,
            variances_of_mean,
        })
    }
}

/// The outcome of z-tests over all elements and channels of two images.
#[derive(Clone, Debug, PartialEq)]
pub struct ZTestReport {
    /// Number of tests (elements times channels).
    pub test_count: usize,
    /// Per-test significance level after the Šidák correction.
    pub significance: f64,
    /// The smallest p-value of all tests.
    pub min_p_value: f64,
    /// The z-score of that test.
    pub worst_z: f64,
    /// Where that test is: (x, y, channel), y in the images' row order.
    pub worst_element: (usize, usize, usize),
    /// Tests whose p-value is below `significance`.
    pub rejected_count: usize,
    /// No test rejected: the images agree up to their noise.
    pub passed: bool,
}

/// z-tests of every element and channel of `a` against `b`, at family-wise significance
/// `alpha` (Šidák-corrected over all tests).
pub fn z_test_images(a: &MeanImage, b: &MeanImage, alpha: f64) -> Result<ZTestReport, StatsError> {
    if (a.width, a.height, a.channel_count) != (b.width, b.height, b.channel_count) {
        return Err(StatsError::SizeMismatch(format!(
            "{}x{}x{} vs {}x{}x{}",
            a.width, a.height, a.channel_count, b.width, b.height, b.channel_count
        )));
    }
    check_size("image a", a.means.len(), a.width, a.height, a.channel_count)?;
    check_size("image b", b.means.len(), b.width, b.height, b.channel_count)?;
    check_size(
        "variances of a",
        a.variances_of_mean.len(),
        a.width,
        a.height,
        a.channel_count,
    )?;
    check_size(
        "variances of b",
        b.variances_of_mean.len(),
        b.width,
        b.height,
        b.channel_count,
    )?;
    let test_count = a.means.len();
    let significance = sidak_alpha(alpha, test_count.max(1))?;
    let mut report = ZTestReport {
        test_count,
        significance,
        min_p_value: 1.0,
        worst_z: 0.0,
        worst_element: (0, 0, 0),
        rejected_count: 0,
        passed: true,
    };
    for index in 0..test_count {
        let z = z_score(
            a.means[index],
            a.variances_of_mean[index],
            b.means[index],
            b.variances_of_mean[index],
        );
        let p_value = two_sided_p_value(z);
        if p_value < significance {
            report.rejected_count += 1;
        }
        if p_value < report.min_p_value {
            let element = index / a.channel_count;
            report.min_p_value = p_value;
            report.worst_z = z;
            report.worst_element = (
                element % a.width,
                element / a.width,
                index % a.channel_count,
            );
        }
    }
    report.passed = report.rejected_count == 0;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn p_values_of_known_z_scores() {
        // z_0.975 = 1.959963984540054; statrs' erfc is good to about 1e-10 relative here
        // (measured: 2.2e-12 absolute), ample for significance levels.
        assert!((two_sided_p_value(1.959963984540054) - 0.05).abs() < 1e-11);
        assert!((two_sided_p_value(-1.959963984540054) - 0.05).abs() < 1e-11);
        assert_eq!(two_sided_p_value(0.0), 1.0);
        // Far in the tail the survival function still resolves the p-value.
        assert!(two_sided_p_value(20.0) > 0.0 && two_sided_p_value(20.0) < 1e-80);
        assert_eq!(two_sided_p_value(f64::NAN), 0.0);
        assert_eq!(two_sided_p_value(f64::INFINITY), 0.0);
    }

    #[test]
    fn z_scores_with_exact_and_unknown_values() {
        assert_eq!(z_score(3.0, 0.5, 1.0, 0.5), 2.0);
        assert_eq!(z_score(1.0, 0.0, 1.0, 0.0), 0.0);
        assert_eq!(z_score(1.0, 0.0, 2.0, 0.0), f64::NEG_INFINITY);
        assert_eq!(z_score(1.0, f64::INFINITY, 2.0, 0.0), 0.0);
        assert!(z_score(f64::NAN, 1.0, 2.0, 0.0).is_nan());
    }

    #[test]
    fn image_comparison_finds_the_shifted_pixel() {
        let (width, height) = (8, 4);
        let values: Vec<f64> = (0..width * height * 3).map(|i| i as f64 * 0.1).collect();
        let noisy = MeanImage {
            width,
            height,
            channel_count: 3,
            means: values.clone(),
            variances_of_mean: vec![0.01; values.len()],
        };
        let exact = MeanImage::exact(width, height, 3, values).unwrap();
        let report = z_test_images(&noisy, &exact, 0.01).unwrap();
        assert!(report.passed && report.test_count == 96 && report.min_p_value == 1.0);
        // Shift pixel (5, 2), green, by 10 standard deviations.
        let mut shifted = noisy.clone();
        shifted.means[(2 * width + 5) * 3 + 1] += 1.0;
        let report = z_test_images(&shifted, &exact, 0.01).unwrap();
        assert!(!report.passed);
        assert_eq!(
            (report.rejected_count, report.worst_element),
            (1, (5, 2, 1))
        );
        assert!((report.worst_z - 10.0).abs() < 1e-9);
        assert!(z_test_images(
            &noisy,
            &MeanImage::exact(1, 1, 3, vec![0.0; 3]).unwrap(),
            0.01
        )
        .is_err());
    }

    #[test]
    fn block_average_divides_variance_by_element_count() {
        let image = MeanImage {
            width: 3,
            height: 2,
            channel_count: 1,
            means: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            variances_of_mean: vec![1.0; 6],
        };
        let blocks = image.block_average(2).unwrap();
        assert_eq!((blocks.width, blocks.height), (2, 1));
        // Block 0: 1, 2, 4, 5 -> mean 3, variance 4 / 16; block 1 (partial): 3, 6.
        assert_eq!(blocks.means, vec![3.0, 4.5]);
        assert_eq!(blocks.variances_of_mean, vec![0.25, 0.5]);
        assert!(image.block_average(0).is_err());
        let rgb = MeanImage::from_rgb(1, 1, &[[1.0, 2.0, 3.0, 1.0]], &[[0.1, 0.2, 0.3]]).unwrap();
        assert_eq!(rgb.means, vec![1.0, 2.0, 3.0]);
        assert!(MeanImage::from_rgb(2, 1, &[[1.0; 4]], &[[0.0; 3]]).is_err());
    }
}
