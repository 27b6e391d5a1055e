//! The per-block statistics of `vkpath compare`: for every block of pixels and channel, the
//! difference of the two images' block means and the estimated variance of that difference,
//! from the images' moments or, without moments, from the spread within the block.

use crate::image_io::data::RenderedImage;

/// Relative size below which a difference of two block means is float rounding, not bias:
/// the images hold f32 (relative ulp 1.2e-7) and each pixel mean is within a few ulps of the
/// exact mean of its samples, so 1e-5 (about 84 ulps) is ample; it matters only where both
/// variances are zero (e.g. unshaded ray tracing with the pixel-centre filter), where it
/// keeps `z = d / 0` from turning an ulp into a failure.
pub const ROUNDING_TOLERANCE: f64 = 1e-5;

/// The difference of two block means in one channel and what is known of its noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockDifference {
    /// Mean of image A over the block minus mean of image B.
    pub difference: f64,
    /// The larger of the two block means' magnitudes (for `ROUNDING_TOLERANCE`).
    pub scale: f64,
    /// Estimated variance of `difference`; 0 for two exact values, infinite when unknown.
    pub variance: f64,
    /// Degrees of freedom of `variance` when it was estimated from the m pixels of the block
    /// (m - 1: the z-score is then Student-t distributed); `None` when it comes from the
    /// moments, which pool so many samples that z is close to normal.
    pub degrees_of_freedom: Option<f64>,
}

/// Where the variances of the block means come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VarianceSource {
    /// Both images have moments: var(A) + var(B).
    BothMoments,
    /// Only A has moments: B is taken as exact (a reference), var(A).
    MomentsOfA,
    /// Only B has moments: A is taken as exact, var(B).
    MomentsOfB,
    /// Neither has moments: the spread of the pixel differences A - B within each block.
    WithinBlockSpread,
}

/// The per-pixel variance of the mean, (E[L^2] - E[L]^2) / (n - 1), in f64, or `None` when
/// the image has no usable moments (no moment channels, or a pixel with fewer than two
/// samples, whose variance is unknown).
pub fn pixel_variances(image: &RenderedImage, has_moments: bool) -> Option<Vec<[f64; 3]>> {
    if !has_moments || image.sample_count.iter().any(|&n| n.is_nan() || n < 2.0) {
        return None;
    }
    Some(
        image
            .mean
            .iter()
            .zip(&image.second_moment)
            .zip(&image.sample_count)
            .map(|((mean, square), &n)| {
                std::array::from_fn(|c| {
                    let mean = f64::from(mean[c]);
                    // The difference cancels; rounding may leave it slightly negative.
                    (f64::from(square[c]) - mean * mean).max(0.0) / (f64::from(n) - 1.0)
                })
            })
            .collect(),
    )
}

/// The pixels (x, y) of block (block_x, block_y), clipped to the image.
fn block_pixels(
    a: &RenderedImage,
    block_size: usize,
    block_x: usize,
    block_y: usize,
) -> impl Iterator<Item = usize> + '_ {
    let (width, height) = (a.width as usize, a.height as usize);
    let xs = block_x * block_size..((block_x + 1) * block_size).min(width);
    let ys = block_y * block_size..((block_y + 1) * block_size).min(height);
    ys.flat_map(move |y| xs.clone().map(move |x| y * width + x))
}

/// Block differences from the moments: the block mean of a pixel quantity is the plain
/// average of its m pixels, whose estimates are independent, so the variance of the block
/// mean is the sum of the pixel variances / m^2. A missing variance image counts as exact.
pub fn moment_differences(
    a: &RenderedImage,
    b: &RenderedImage,
    variances_a: Option<&[[f64; 3]]>,
    variances_b: Option<&[[f64; 3]]>,
    block_size: usize,
    block_x: usize,
    block_y: usize,
) -> [BlockDifference; 3] {
    std::array::from_fn(|c| {
        let (mut sum_a, mut sum_b, mut variance, mut m) = (0.0, 0.0, 0.0, 0.0);
        for i in block_pixels(a, block_size, block_x, block_y) {
            sum_a += f64::from(a.mean[i][c]);
            sum_b += f64::from(b.mean[i][c]);
            variance += variances_a.map_or(0.0, |v| v[i][c]) + variances_b.map_or(0.0, |v| v[i][c]);
            m += 1.0;
        }
        BlockDifference {
            difference: (sum_a - sum_b) / m,
            scale: (sum_a / m).abs().max((sum_b / m).abs()),
            variance: variance / (m * m),
            degrees_of_freedom: None,
        }
    })
}

/// Block differences without moments. The pixel differences d_i = A_i - B_i of a block are
/// independent; if A and B estimate the same image, each has mean 0 whatever the image looks
/// like (its edges and gradients cancel), so their sample variance s^2 estimates the average
/// pixel variance and s^2 / m the variance of the block's mean difference, with m - 1
/// degrees of freedom. The assumption is only that the pixels' noise is independent; a block
/// of a single pixel has no spread and is not tested (infinite variance).
pub fn spread_differences(
    a: &RenderedImage,
    b: &RenderedImage,
    block_size: usize,
    block_x: usize,
    block_y: usize,
) -> [BlockDifference; 3] {
    std::array::from_fn(|c| {
        let pixels: Vec<(f64, f64)> = block_pixels(a, block_size, block_x, block_y)
            .map(|i| (f64::from(a.mean[i][c]), f64::from(b.mean[i][c])))
            .collect();
        let m = pixels.len() as f64;
        let mean_a = pixels.iter().map(|p| p.0).sum::<f64>() / m;
        let mean_b = pixels.iter().map(|p| p.1).sum::<f64>() / m;
        let difference = mean_a - mean_b;
        let variance = if pixels.len() < 2 {
            f64::INFINITY
        } else {
            let sum_of_squares: f64 = pixels
                .iter()
                .map(|p| (p.0 - p.1 - difference).powi(2))
                .sum();
            sum_of_squares / (m - 1.0) / m
        };
        BlockDifference {
            difference,
            scale: mean_a.abs().max(mean_b.abs()),
            variance,
            degrees_of_freedom: Some(m - 1.0),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: &[f32], second_moment: f32, count: f32) -> RenderedImage {
        RenderedImage {
            width: values.len() as u32,
            height: 1,
            mean: values.iter().map(|&v| [v, v, v, 1.0]).collect(),
            second_moment: values.iter().map(|&v| [v * v + second_moment; 3]).collect(),
            sample_count: vec![count; values.len()],
        }
    }

    #[test]
    fn moments_give_the_variance_of_the_block_mean() {
        // E[L^2] - E[L]^2 = 0.3 with 4 samples: variance of each pixel mean 0.1.
        let a = image(&[1.0, 2.0], 0.3, 4.0);
        let b = image(&[1.0, 1.0], 0.3, 4.0);
        let variances_a = pixel_variances(&a, true).unwrap();
        assert!((variances_a[0][0] - 0.1).abs() < 1e-7);
        let [red, ..] = moment_differences(&a, &b, Some(&variances_a), None, 2, 0, 0);
        assert_eq!(red.difference, 0.5);
        // Two pixels of variance 0.1, averaged: 0.2 / 4.
        assert!((red.variance - 0.05).abs() < 1e-7);
        assert_eq!(pixel_variances(&a, false), None);
        assert_eq!(pixel_variances(&image(&[1.0], 0.0, 1.0), true), None);
    }

    #[test]
    fn spread_ignores_the_image_structure() {
        // Same structure plus noise of +-0.1: the ramp does not inflate the variance.
        let a = image(&[1.1, 1.9, 3.1, 3.9], 0.0, 1.0);
        let b = image(&[1.0, 2.0, 3.0, 4.0], 0.0, 1.0);
        let [red, ..] = spread_differences(&a, &b, 4, 0, 0);
        assert!(red.difference.abs() < 1e-6);
        // d = (0.1, -0.1, 0.1, -0.1): s^2 = 0.04 / 3, variance of the mean s^2 / 4.
        assert!(
            (red.variance - 0.04 / 3.0 / 4.0).abs() < 1e-7,
            "{}",
            red.variance
        );
        assert_eq!(red.degrees_of_freedom, Some(3.0));
        let [single, ..] = spread_differences(&a, &b, 1, 0, 0);
        assert!(single.variance.is_infinite());
    }
}
