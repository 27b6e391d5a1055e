//! A rendered image in linear radiance, with what statistics need: per-pixel mean, second
//! moment and sample count.

/// The result of a render, rows top-down.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderedImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Per pixel: mean radiance (linear RGB), alpha 1.
    pub mean: Vec<[f32; 4]>,
    /// Per pixel: mean of the squared radiance samples (RGB), E[L^2].
    pub second_moment: Vec<[f32; 3]>,
    /// Per pixel: number of samples.
    pub sample_count: Vec<f32>,
}

impl RenderedImage {
    /// Builds the image from the accumulation layers (sum + count, Kahan compensation, sum
    /// of squares), each `width * height` texels in that order.
    pub fn from_accumulation(width: u32, height: u32, texels: &[[f32; 4]]) -> RenderedImage {
        let n = (width * height) as usize;
        let (sums, rest) = texels.split_at(n);
        let (compensations, rest) = rest.split_at(n);
        let squares = &rest[..n];
        let mut image = RenderedImage {
            width,
            height,
            mean: Vec::with_capacity(n),
            second_moment: Vec::with_capacity(n),
            sample_count: Vec::with_capacity(n),
        };
        for ((sum, compensation), square) in sums.iter().zip(compensations).zip(squares) {
            let (mean, second_moment, count) = resolve_pixel(sum, compensation, square);
            image.mean.push(mean);
            image.second_moment.push(second_moment);
            image.sample_count.push(count);
        }
        image
    }

    /// An image of `width * height` pixels with no samples (mean 0, alpha 1), for a render
    /// that fills it in part by part (`resolve_pixel`).
    pub fn empty(width: u32, height: u32) -> RenderedImage {
        let n = width as usize * height as usize;
        RenderedImage {
            width,
            height,
            mean: vec![[0.0, 0.0, 0.0, 1.0]; n],
            second_moment: vec![[0.0; 3]; n],
            sample_count: vec![0.0; n],
        }
    }

    /// The mean radiance of the pixel at column `x`, row `y` (from the top).
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 4] {
        self.mean[(y * self.width + x) as usize]
    }

    /// Estimated variance of each pixel's mean (RGB): (E[L^2] - E[L]^2) / (n - 1), the
    /// unbiased sample variance divided by n. Zero where fewer than two samples exist.
    pub fn variance_of_mean(&self) -> Vec<[f32; 3]> {
        self.mean
            .iter()
            .zip(&self.second_moment)
            .zip(&self.sample_count)
            .map(|((mean, square), &n)| {
                if n < 2.0 {
                    return [0.0; 3];
                }
                let variance = |c: usize| (square[c] - mean[c] * mean[c]).max(0.0) / (n - 1.0);
                [variance(0), variance(1), variance(2)]
            })
            .collect()
    }

    /// Average of the mean over all pixels (RGB).
    pub fn average(&self) -> [f64; 3] {
        let mut total = [0.0f64; 3];
        for pixel in &self.mean {
            for c in 0..3 {
                total[c] += f64::from(pixel[c]);
            }
        }
        total.map(|t| t / self.mean.len().max(1) as f64)
    }
}

/// One pixel of the image from its accumulation texels (`LAYER_SUM`, `LAYER_COMPENSATION`,
/// `LAYER_SUM_OF_SQUARES`): its mean radiance (alpha 1), second moment and sample count.
/// `RenderedImage::from_accumulation` and a render finished tile by tile both resolve
/// pixels with it, so they agree bit for bit.
pub fn resolve_pixel(
    sum: &[f32; 4],
    compensation: &[f32; 4],
    square: &[f32; 4],
) -> ([f32; 4], [f32; 3], f32) {
    let count = sum[3];
    let scale = if count > 0.0 { 1.0 / count } else { 0.0 };
    // Kahan summation leaves sum - compensation as the better estimate of the sum.
    let mean = |c: usize| (sum[c] - compensation[c]) / count.max(1.0);
    (
        [mean(0), mean(1), mean(2), 1.0],
        [square[0] * scale, square[1] * scale, square[2] * scale],
        count,
    )
}
