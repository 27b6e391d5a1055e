//! The raw state of a progressive render, as the accumulation image holds it: per pixel the
//! Kahan sum of the radiance samples with the sample count, the Kahan compensation with the
//! number of rays traced, and the sum of the squared samples. A checkpoint saves it, a
//! resumed render uploads it again and goes on bit for bit, and shards of one image (disjoint
//! ranges of every pixel's sample sequence) are merged from it.

use std::ops::Range;
use std::sync::Arc;

use crate::contract;
use crate::guiding::Guide;
use crate::image_io::data::RenderedImage;

/// The accumulation image of a render and the samples it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Accumulation {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The `ACCUMULATION_LAYER_COUNT` layers, one after the other, each `width * height`
    /// texels, rows top-down: `LAYER_SUM` (rgb: Kahan sum of the samples, a: sample count),
    /// `LAYER_COMPENSATION` (rgb: Kahan compensation, so that sum - compensation is the
    /// better estimate of the sum; a: rays traced), `LAYER_SUM_OF_SQUARES` (rgb).
    pub texels: Vec<[f32; 4]>,
    /// Which samples of every pixel's sequence it holds (sample indices, as the kernel seeds
    /// them).
    pub samples: Range<u32>,
    /// The guide a guided render (`--guiding`) sampled them with: frozen into its
    /// checkpoints and shards, so that a resumed render samples with it again instead of
    /// training anew.
    pub guide: Option<Arc<Guide>>,
}

/// Why shards cannot be merged.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[non_exhaustive]
pub enum MergeError {
    /// Nothing to merge.
    #[error("no shards to merge")]
    Empty,
    /// The shards differ in size.
    #[error("the shards differ in size: {0}x{1} and {2}x{3}")]
    SizeMismatch(u32, u32, u32, u32),
    /// Two shards hold some of the same samples.
    #[error("the shards' sample ranges {0}..{1} and {2}..{3} overlap")]
    Overlap(u32, u32, u32, u32),
    /// A range of samples between two shards is missing.
    #[error("samples {0}..{1} are in no shard")]
    Gap(u32, u32),
}

impl Accumulation {
    /// An empty accumulation (no samples yet) of the given size, starting at sample `first`.
    pub fn empty(width: u32, height: u32, first: u32) -> Accumulation {
        let texels = (width * height * contract::ACCUMULATION_LAYER_COUNT) as usize;
        Accumulation {
            width,
            height,
            texels: vec![[0.0; 4]; texels],
            samples: first..first,
            guide: None,
        }
    }

    /// The image it holds: per pixel the mean (sum - compensation) / count, the second
    /// moment and the sample count.
    pub fn image(&self) -> RenderedImage {
        RenderedImage::from_accumulation(self.width, self.height, &self.texels)
    }

    /// Rays traced over all pixels.
    pub fn rays_traced(&self) -> f64 {
        let pixels = (self.width * self.height) as usize;
        let layer = contract::LAYER_COMPENSATION as usize * pixels;
        self.texels[layer..layer + pixels]
            .iter()
            .map(|texel| f64::from(texel[3]))
            .sum()
    }

    /// Whether all `parts` sampled with the same guide (or none). Shards of one guided
    /// render train the same guide on devices of one kind; another device's rounding may
    /// train another, whose samples are unbiased too, so a merge of such shards is an
    /// unbiased image but not the single render's.
    pub fn same_guide(parts: &[&Accumulation]) -> bool {
        parts.windows(2).all(|pair| pair[0].guide == pair[1].guide)
    }

    /// Merges shards whose sample ranges tile one range without gaps or overlaps (in any
    /// order). Per pixel and channel, the better estimates of the shards' sums
    /// (sum - compensation) are added in float64 and rounded once to the merged sum, with
    /// the rounding error as its compensation; counts, ray counts and sums of squares add.
    ///
    /// The merged mean is not always bit-identical to that of a single render of the whole
    /// range, which adds the samples one by one in float32 with Kahan summation. Both are
    /// within 2 ulps of the exact mean: Kahan's error bound is (2 eps + O(N eps^2)) times
    /// the sum of |samples|, which for radiance (never negative) is the sum itself, and N
    /// eps^2 is below 2^-28 for N up to 2^20 samples; the merge rounds an almost exact
    /// float64 sum once. So they differ by at most 4 ulps (relative 2^-21), the tolerance
    /// the tests use.
    pub fn merge(parts: &[Accumulation]) -> Result<Accumulation, MergeError> {
        let mut order: Vec<&Accumulation> = parts.iter().collect();
        order.sort_by_key(|part| (part.samples.start, part.samples.end));
        let first = *order.first().ok_or(MergeError::Empty)?;
        for pair in order.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            if (a.width, a.height) != (b.width, b.height) {
                return Err(MergeError::SizeMismatch(
                    a.width, a.height, b.width, b.height,
                ));
            }
            if b.samples.start < a.samples.end {
                return Err(MergeError::Overlap(
                    a.samples.start,
                    a.samples.end,
                    b.samples.start,
                    b.samples.end,
                ));
            }
            if b.samples.start > a.samples.end {
                return Err(MergeError::Gap(a.samples.end, b.samples.start));
            }
        }
        let samples =
            first.samples.start..order.last().map_or(first.samples.end, |p| p.samples.end);
        Ok(Accumulation::sum(&order, samples))
    }

    /// The sum of parts of the same size, in the order given, labelled as holding
    /// `samples` (`merge` after its checks, in sample order; also the sum of shares that
    /// stopped early, whose ranges leave gaps). It keeps the parts' guide when they all
    /// sampled with the same one (`same_guide`), else none.
    pub fn sum(order: &[&Accumulation], samples: Range<u32>) -> Accumulation {
        let first = order[0];
        let pixels = (first.width * first.height) as usize;
        let sum_layer = contract::LAYER_SUM as usize * pixels;
        let compensation_layer = contract::LAYER_COMPENSATION as usize * pixels;
        let squares_layer = contract::LAYER_SUM_OF_SQUARES as usize * pixels;
        let mut merged = Accumulation::empty(first.width, first.height, samples.start);
        merged.samples = samples;
        if Accumulation::same_guide(order) {
            merged.guide = first.guide.clone();
        }
        for pixel in 0..pixels {
            let mut sum = [0.0f64; 3];
            let (mut count, mut rays) = (0.0f64, 0.0f64);
            let mut squares = [0.0f64; 3];
            for part in order {
                let s = part.texels[sum_layer + pixel];
                let c = part.texels[compensation_layer + pixel];
                let q = part.texels[squares_layer + pixel];
                for channel in 0..3 {
                    sum[channel] += f64::from(s[channel]) - f64::from(c[channel]);
                    squares[channel] += f64::from(q[channel]);
                }
                count += f64::from(s[3]);
                rays += f64::from(c[3]);
            }
            let rounded = sum.map(|s| s as f32);
            merged.texels[sum_layer + pixel] = [rounded[0], rounded[1], rounded[2], count as f32];
            let compensation = |c: usize| (f64::from(rounded[c]) - sum[c]) as f32;
            merged.texels[compensation_layer + pixel] = [
                compensation(0),
                compensation(1),
                compensation(2),
                rays as f32,
            ];
            merged.texels[squares_layer + pixel] =
                [squares[0] as f32, squares[1] as f32, squares[2] as f32, 0.0];
        }
        merged
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Adds samples to a one-pixel accumulation as the kernel does (Kahan, in order).
    fn accumulate(samples: &[f32], range: Range<u32>) -> Accumulation {
        let mut state = Accumulation::empty(1, 1, range.start);
        let (mut sum, mut compensation, mut squares) = (0.0f32, 0.0f32, 0.0f32);
        for &x in samples {
            let corrected = x - compensation;
            let new_sum = sum + corrected;
            compensation = (new_sum - sum) - corrected;
            sum = new_sum;
            squares += x * x;
        }
        let n = samples.len() as f32;
        state.texels = vec![
            [sum, sum, sum, n],
            [compensation, compensation, compensation, 2.0 * n],
            [squares, squares, squares, 0.0],
        ];
        state.samples = range;
        state
    }

    /// The difference of two floats in units in the last place.
    fn ulps(a: f32, b: f32) -> u32 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs() as u32
    }

    #[test]
    fn merged_shards_agree_with_one_render_within_four_ulps() {
        // Heavy-tailed positive samples like a path tracer's (mostly small, a few fireflies).
        let mut state = 12345u64;
        let samples: Vec<f32> = (0..4096)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let u = (state >> 40) as f32 / (1u64 << 24) as f32;
                if u > 0.999 {
                    100.0 * u
                } else {
                    u * u
                }
            })
            .collect();
        let whole = accumulate(&samples, 0..4096);
        let mut worst = 0;
        for cuts in [vec![1024, 2048, 3072], vec![1, 4095], vec![777]] {
            let mut parts = Vec::new();
            let mut start = 0;
            for &end in cuts.iter().chain(std::iter::once(&4096)) {
                parts.push(accumulate(&samples[start..end], start as u32..end as u32));
                start = end;
            }
            parts.reverse(); // any order
            let merged = Accumulation::merge(&parts).unwrap();
            assert_eq!(merged.samples, 0..4096);
            let (a, b) = (merged.image(), whole.image());
            assert_eq!(a.sample_count, b.sample_count);
            worst = worst.max(ulps(a.mean[0][0], b.mean[0][0]));
            assert_eq!(merged.rays_traced(), whole.rays_traced());
        }
        assert!(worst <= 4, "{worst} ulps");
    }

    #[test]
    fn gaps_overlaps_and_sizes_are_refused() {
        let a = accumulate(&[1.0], 0..4);
        let b = accumulate(&[1.0], 4..8);
        let c = accumulate(&[1.0], 6..9);
        let d = accumulate(&[1.0], 9..12);
        assert_eq!(Accumulation::merge(&[]), Err(MergeError::Empty));
        assert_eq!(
            Accumulation::merge(&[a.clone(), c.clone()]),
            Err(MergeError::Gap(4, 6))
        );
        assert_eq!(
            Accumulation::merge(&[b.clone(), c.clone()]),
            Err(MergeError::Overlap(4, 8, 6, 9))
        );
        let mut wide = d.clone();
        wide.width = 2;
        assert_eq!(
            Accumulation::merge(&[c, wide]),
            Err(MergeError::SizeMismatch(1, 1, 2, 1))
        );
        assert!(Accumulation::merge(&[b, a]).is_ok());
    }
}
