//! The CPU renderer's accumulation image: per pixel, the Kahan-compensated sum of the
//! radiance samples, their sum of squares and their count, as the three layers of the
//! shader's `g_accumulation` image hold them (`LAYER_SUM`, `LAYER_COMPENSATION`,
//! `LAYER_SUM_OF_SQUARES` in `glsl/shared.h`).

use glam::Vec3;

use crate::contract::{LAYER_COMPENSATION, LAYER_SUM, LAYER_SUM_OF_SQUARES};

/// The accumulated samples of one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelAccumulator {
    /// Kahan sum of the radiance samples, linear RGB (`LAYER_SUM`.rgb).
    pub sum: Vec3,
    /// Kahan compensation: what the sum lost to rounding, negated; the exact sum is close to
    /// `sum - compensation` (`LAYER_COMPENSATION`.rgb).
    pub compensation: Vec3,
    /// Plain sum of the squared samples (`LAYER_SUM_OF_SQUARES`.rgb).
    pub sum_of_squares: Vec3,
    /// Number of samples taken. The shader keeps it as a float in `LAYER_SUM`.a, which is
    /// exact below 2^24 samples.
    pub sample_count: u32,
}

impl PixelAccumulator {
    /// Adds one radiance sample exactly as `path_tracer.comp` does, in the same order
    /// (Kahan summation; the shader marks these operations `precise`, and Rust never
    /// reassociates or fuses float operations, so both round alike). The shader's
    /// sum of squares is not `precise`, so a GPU compiler may fuse it into an FMA there.
    pub fn add_sample(&mut self, radiance: Vec3) {
        let corrected = radiance - self.compensation;
        let new_sum = self.sum + corrected;
        self.compensation = (new_sum - self.sum) - corrected;
        self.sum = new_sum;
        self.sample_count += 1;
        self.sum_of_squares += radiance * radiance;
    }

    /// The mean of the samples, compensation included: (sum - compensation) / count, linear
    /// RGB; zero when no sample was taken.
    pub fn mean(&self) -> Vec3 {
        if self.sample_count == 0 {
            return Vec3::ZERO;
        }
        (self.sum - self.compensation) / self.sample_count as f32
    }

    /// The estimated variance of `mean()` per channel: the unbiased sample variance
    /// (sum of squares - n mean^2) / (n - 1), divided by n. Computed in f64 because the
    /// difference cancels; negative rounding residues are clamped to 0. Infinite for fewer
    /// than two samples, where the variance is unknown (a z-test then finds no evidence).
    pub fn variance_of_mean(&self) -> [f64; 3] {
        let n = self.sample_count as f64;
        if self.sample_count < 2 {
            return [f64::INFINITY; 3];
        }
        let mean = self.mean();
        std::array::from_fn(|channel| {
            let mean = mean[channel] as f64;
            let sample_variance =
                (self.sum_of_squares[channel] as f64 - n * mean * mean) / (n - 1.0);
            sample_variance.max(0.0) / n
        })
    }
}

/// An image of accumulated samples, `width * height` pixels in top-down row order (row 0 is
/// the top row, as the shader's texel y).
#[derive(Clone, Debug, PartialEq)]
pub struct CpuImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The pixels, index `row * width + x`.
    pub pixels: Vec<PixelAccumulator>,
}

impl CpuImage {
    /// An image with no samples yet.
    pub fn new(width: u32, height: u32) -> CpuImage {
        CpuImage {
            width,
            height,
            pixels: vec![PixelAccumulator::default(); width as usize * height as usize],
        }
    }

    /// The mean of each pixel, RGBA with alpha 1, top-down rows (see
    /// `PixelAccumulator::mean`).
    pub fn mean(&self) -> Vec<[f32; 4]> {
        self.pixels
            .iter()
            .map(|pixel| pixel.mean().extend(1.0).to_array())
            .collect()
    }

    /// The estimated variance of each pixel's mean, RGB, top-down rows (see
    /// `PixelAccumulator::variance_of_mean`).
    pub fn variance_of_mean(&self) -> Vec<[f64; 3]> {
        self.pixels
            .iter()
            .map(PixelAccumulator::variance_of_mean)
            .collect()
    }

    /// One layer of the image as the shader's `g_accumulation` stores it, for comparison with
    /// a GPU read-back: `LAYER_SUM` (rgb sum, a count), `LAYER_COMPENSATION` (rgb, a 0) or
    /// `LAYER_SUM_OF_SQUARES` (rgb, a 0). `None` for any other layer index.
    pub fn layer(&self, layer: u32) -> Option<Vec<[f32; 4]>> {
        let texel = |pixel: &PixelAccumulator| match layer {
            LAYER_SUM => Some(pixel.sum.extend(pixel.sample_count as f32).to_array()),
            LAYER_COMPENSATION => Some(pixel.compensation.extend(0.0).to_array()),
            LAYER_SUM_OF_SQUARES => Some(pixel.sum_of_squares.extend(0.0).to_array()),
            _ => None,
        };
        self.pixels.iter().map(texel).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kahan_sum_keeps_small_samples() {
        // 1 + 2^24 * 2^-24: a plain f32 sum would stay at 1.0 because each 2^-24 is below
        // half an ulp of 1 (2^-24 exactly: ties to even keep 1.0).
        let mut pixel = PixelAccumulator::default();
        pixel.add_sample(Vec3::ONE);
        for _ in 0..(1 << 16) {
            pixel.add_sample(Vec3::splat(2.0f32.powi(-24)));
        }
        let exact_sum = 1.0 + 2.0f64.powi(16 - 24);
        let kahan = pixel.sum.x as f64 - pixel.compensation.x as f64;
        assert!((kahan - exact_sum).abs() < 1e-7, "{kahan} vs {exact_sum}");
        assert_eq!(pixel.sample_count, (1 << 16) + 1);
    }

    #[test]
    fn mean_and_variance_of_mean() {
        let mut pixel = PixelAccumulator::default();
        for value in [1.0, 2.0, 3.0, 4.0] {
            pixel.add_sample(Vec3::new(value, 0.5, 0.0));
        }
        assert_eq!(pixel.mean(), Vec3::new(2.5, 0.5, 0.0));
        // Sample variance of 1, 2, 3, 4 is 5/3; of the mean of 4 samples 5/12.
        let variance = pixel.variance_of_mean();
        assert!((variance[0] - 5.0 / 12.0).abs() < 1e-12);
        assert_eq!(&variance[1..], &[0.0, 0.0]);
        assert_eq!(
            PixelAccumulator::default().variance_of_mean(),
            [f64::INFINITY; 3]
        );
        let image = CpuImage {
            width: 1,
            height: 1,
            pixels: vec![pixel],
        };
        assert_eq!(image.mean(), vec![[2.5, 0.5, 0.0, 1.0]]);
        assert_eq!(image.layer(LAYER_SUM), Some(vec![[10.0, 2.0, 0.0, 4.0]]));
        assert_eq!(image.layer(7), None);
    }
}
