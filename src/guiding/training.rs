//! How a render trains its guide (`--guiding`): iterations over the whole image that double
//! their samples (1, 2, 4, ... per pixel, the last taking what is left of the training
//! budget), each rendered with the guide the iterations before it built and splatting into
//! the next one; then the render proper takes its `--spp` samples with the final guide.
//! Training images are thrown away, so `--spp` counts the render's samples only.
//!
//! Training samples are samples `GUIDE_TRAINING_FIRST_SAMPLE..` of every pixel's sequence,
//! which no render takes, and `get_sample_seed` gives every sample index its own PCG2D seed,
//! so the guide is independent of the samples it guides: the same random numbers for both
//! would correlate them, a bias the furnace test measured at -0.6 % when the seed still kept
//! only the index's low 16 bits. Training is deterministic, so every shard
//! and resumed render of one image trains the same guide.

use crate::guiding::{Guide, GuideGrid, GuideSplats};

/// The first sample index of the training iterations: 2^31, past every render's samples
/// (`RenderSettings::validate` keeps guided renders below it).
pub const GUIDE_TRAINING_FIRST_SAMPLE: u32 = 1 << 31;

/// Training paths that the default budget aims at, all iterations together: about a
/// million, one per directional bin of the Cornell box's 4406 cells. A budget in paths, not
/// per pixel, because the guide's cells do not grow with the image: on the Cornell box at
/// 256x256 (256 spp) 16 training spp per pixel train as good a guide as 64 (relMSE 0.00152
/// against 0.00151) in a quarter of the training time (CPU efficiency against plain mis
/// 1.00x against 0.75x, docs/guiding.md); on the opening scene at 80x60 the quarter of
/// spp stays the smaller budget.
pub const GUIDE_TRAINING_DEFAULT_PATHS: u64 = 1 << 20;

/// The smallest default budget per pixel where spp allows it: two iterations (1 + 3), so
/// that the last one samples with a guide.
pub const GUIDE_TRAINING_MIN_DEFAULT_SPP: u32 = 4;

/// A guided render's training budget.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GuideTraining {
    /// Samples per pixel that train the guide, in all iterations together (at least 1).
    pub samples: u32,
}

impl GuideTraining {
    /// The default budget for a render of `spp` samples over `pixels` pixels (its area):
    /// what gives `GUIDE_TRAINING_DEFAULT_PATHS` paths in all (at least
    /// `GUIDE_TRAINING_MIN_DEFAULT_SPP` per pixel), but never more than a quarter of `spp`
    /// (and at least 1).
    pub fn default_for(spp: u32, pixels: u64) -> GuideTraining {
        let for_paths = GUIDE_TRAINING_DEFAULT_PATHS
            .div_ceil(pixels.max(1))
            .max(u64::from(GUIDE_TRAINING_MIN_DEFAULT_SPP));
        let quarter = u64::from((spp / 4).max(1));
        GuideTraining {
            // At most a quarter of a u32: the conversion cannot fail.
            samples: u32::try_from(for_paths.min(quarter)).unwrap_or(u32::MAX),
        }
    }

    /// Samples per pixel of each iteration: 1, 2, 4, ... while the budget allows, the last
    /// taking the rest; they sum to `samples`.
    pub fn iterations(&self) -> Vec<u32> {
        let mut iterations = Vec::new();
        let mut left = self.samples.max(1);
        let mut next = 1u32;
        while left > 0 {
            // The last iteration takes the rest when the one after it would not fit.
            let take = if left < next.saturating_mul(3) {
                left
            } else {
                next
            };
            iterations.push(take);
            left -= take;
            next = next.saturating_mul(2);
        }
        iterations
    }
}

/// The host's side of training: every iteration's splats so far and the guide built from
/// them, which the next iteration samples with. The GPU render (`Renderer::train_guide`)
/// and the CPU twin (`vkpath::cpu::renderer::train_cpu_guide`) both build their guides
/// through it.
#[derive(Clone, Debug)]
pub struct GuideTrainer {
    splats: GuideSplats,
    guide: Guide,
}

impl GuideTrainer {
    /// No splats yet: the guide has no guided cell.
    pub fn new(grid: GuideGrid) -> GuideTrainer {
        let splats = GuideSplats::new(grid);
        let guide = splats.build();
        GuideTrainer { splats, guide }
    }

    /// The guide built from the iterations so far.
    pub fn guide(&self) -> &Guide {
        &self.guide
    }

    /// Adds one iteration's splats and rebuilds the guide from all of them, each cell pooled
    /// with its face neighbours' paths: measured on scenes/opening.gltf (mis, 3 vertices,
    /// 80x60, 256 spp), relMSE 2.8e-4 from each cell's own splats, 1.3e-4 pooled
    /// (unguided: 2.3e-4).
    pub fn add_iteration(&mut self, splats: &GuideSplats) -> &Guide {
        self.splats.merge(splats);
        self.guide = self.splats.pooled_with_neighbours().build();
        &self.guide
    }

    /// The guide built from every iteration.
    pub fn into_guide(self) -> Guide {
        self.guide
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iterations_double_and_sum_to_the_budget() {
        assert_eq!(GuideTraining { samples: 1 }.iterations(), [1]);
        assert_eq!(GuideTraining { samples: 2 }.iterations(), [2]);
        assert_eq!(GuideTraining { samples: 3 }.iterations(), [1, 2]);
        assert_eq!(GuideTraining { samples: 7 }.iterations(), [1, 2, 4]);
        assert_eq!(GuideTraining { samples: 10 }.iterations(), [1, 2, 7]);
        assert_eq!(
            GuideTraining { samples: 256 }.iterations(),
            [1, 2, 4, 8, 16, 32, 64, 129]
        );
        for samples in 1..300 {
            let iterations = GuideTraining { samples }.iterations();
            assert_eq!(iterations.iter().sum::<u32>(), samples);
            // Each iteration takes at least as many samples as the one before.
            assert!(
                iterations.windows(2).all(|w| w[1] >= w[0]),
                "{iterations:?}"
            );
        }
    }

    #[test]
    fn the_default_budget_is_a_million_paths_at_most_a_quarter_of_spp() {
        let default =
            |spp, width: u64, height: u64| GuideTraining::default_for(spp, width * height).samples;
        // Small images: a quarter of spp (at least 1).
        assert_eq!(default(256, 80, 60), 64);
        assert_eq!(default(1024, 64, 64), 256);
        assert_eq!(default(2, 64, 64), 1);
        // The Cornell box at 256x256: 16 spp, 2^20 paths.
        assert_eq!(default(256, 256, 256), 16);
        assert_eq!(
            default(256, 256, 256) as u64 * 256 * 256,
            GUIDE_TRAINING_DEFAULT_PATHS
        );
        // Rounded up: 2^20 / 300^2 = 11.65.
        assert_eq!(default(256, 300, 300), 12);
        // Large images: at least two iterations' 4 spp, where a quarter of spp allows.
        assert_eq!(default(256, 1920, 1080), GUIDE_TRAINING_MIN_DEFAULT_SPP);
        assert_eq!(default(8, 1920, 1080), 2);
        // No pixels (never rendered) do not divide by zero.
        assert_eq!(default(256, 0, 0), 64);
    }
}
