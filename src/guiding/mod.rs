//! Path guiding's guide on the host: the grid of cells over the scene (`GuideGrid`), the
//! training splats that learn where light arrives from in each cell (`GuideSplats`), and the
//! guide they build (`Guide`): the words of `glsl/guiding.glsl`'s texel buffer, which the
//! Rust twins (`crate::cpu::guiding`) read too.
//!
//! Deterministic by construction: a splat is a fixed-point integer (`GUIDE_FIXED_POINT_SCALE`
//! units of its value), so that sums do not depend on the order in which they were added —
//! the GPU's integer atomics and a CPU loop give the same bits — and the build turns the
//! integer sums into probabilities in one fixed order.

use glam::{UVec3, Vec3};

use crate::contract::{
    GUIDE_BIN_COUNT, GUIDE_CELL_TEXEL_COUNT, GUIDE_HEADER_TEXEL_COUNT, GUIDE_MIN_SPLATS,
    GUIDE_UNIFORM_FRACTION,
};
use crate::cpu::guiding::{get_guide_bin_index, get_guide_cell_index, GuideTexels, GUIDE_NO_CELL};

#[cfg(test)]
mod tests;

/// Cells along the longest axis of the scene's box (the other axes get as many as keep the
/// cells near cubes): 16^3 cells at most, 4 MB of guide.
pub const GUIDE_MAX_CELLS_PER_AXIS: u32 = 16;

/// Units of a splat's value in its fixed-point sum: 2^20, so that a value of 10^-6 still
/// counts and a cell's sum reaches u64's limit only past 10^13 in total.
pub const GUIDE_FIXED_POINT_SCALE: f64 = 1_048_576.0;

/// The largest fixed-point value one splat may add (2^40 units, a value of 10^6): a firefly
/// cannot swamp a cell's histogram, nor overflow it.
pub const GUIDE_MAX_SPLAT_UNITS: u64 = 1 << 40;

/// The guide's uniform grid of cells over a box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuideGrid {
    /// Cells along x, y and z.
    pub resolution: UVec3,
    /// The grid's lower corner, world space.
    pub bounds_min: Vec3,
    /// Cells per unit length along each axis.
    pub cells_per_unit: Vec3,
}

impl GuideGrid {
    /// The grid over the box from `bounds_min` to `bounds_max`, padded by 10^-3 of its
    /// largest extent so that points on its faces fall inside, with
    /// `max_cells_per_axis` cells along the longest axis and the nearest whole number in
    /// proportion along the others (at least 1).
    pub fn around(bounds_min: Vec3, bounds_max: Vec3, max_cells_per_axis: u32) -> GuideGrid {
        let extent = (bounds_max - bounds_min).max(Vec3::ZERO);
        let padding = (extent.max_element() * 1e-3).max(1e-6);
        let low = bounds_min - Vec3::splat(padding);
        let size = extent + Vec3::splat(2.0 * padding);
        let longest = size.max_element();
        let cells = max_cells_per_axis.max(1) as f32;
        let resolution = (size / longest * cells).round().max(Vec3::ONE).as_uvec3();
        GuideGrid {
            resolution,
            bounds_min: low,
            cells_per_unit: resolution.as_vec3() / size,
        }
    }

    /// Number of cells.
    pub fn cell_count(&self) -> u32 {
        self.resolution.x * self.resolution.y * self.resolution.z
    }

    /// The header texels' words (`GUIDE_HEADER_TEXEL_COUNT` texels).
    fn header_words(&self) -> Vec<u32> {
        let mut words = vec![
            self.resolution.x,
            self.resolution.y,
            self.resolution.z,
            self.cell_count(),
        ];
        for corner in [self.bounds_min, self.cells_per_unit] {
            words.extend(corner.to_array().map(f32::to_bits));
            words.push(0);
        }
        debug_assert_eq!(words.len(), 4 * GUIDE_HEADER_TEXEL_COUNT as usize);
        words
    }
}

/// Training data: per cell and directional bin, the fixed-point sum of the splatted
/// estimates of the radiance arriving there divided by the density of the direction that
/// found it (so that a bin's sum estimates its share of the cell's incident radiance,
/// whatever distribution sampled the directions), and the number of splats per cell.
#[derive(Clone, Debug, PartialEq)]
pub struct GuideSplats {
    grid: GuideGrid,
    header: Vec<u32>,
    sums: Vec<u64>,
    counts: Vec<u32>,
}

impl GuideSplats {
    /// No splats yet on `grid`.
    pub fn new(grid: GuideGrid) -> GuideSplats {
        let cells = grid.cell_count() as usize;
        GuideSplats {
            grid,
            header: grid.header_words(),
            sums: vec![0; cells * GUIDE_BIN_COUNT as usize],
            counts: vec![0; cells],
        }
    }

    /// The grid the splats fall on.
    pub fn grid(&self) -> &GuideGrid {
        &self.grid
    }

    /// Adds `value` (radiance luminance / direction density, >= 0) at `position` in the bin
    /// of the unit `direction`. Returns whether it counted: points outside the grid and
    /// values that are negative or not finite are ignored; values are clamped to
    /// `GUIDE_MAX_SPLAT_UNITS`.
    pub fn splat(&mut self, position: Vec3, direction: Vec3, value: f32) -> bool {
        if !(value.is_finite() && value >= 0.0) {
            return false;
        }
        let cell = get_guide_cell_index(
            GuideTexels {
                words: &self.header,
            },
            position,
        );
        if cell == GUIDE_NO_CELL {
            return false;
        }
        let units = ((f64::from(value) * GUIDE_FIXED_POINT_SCALE).round() as u64)
            .min(GUIDE_MAX_SPLAT_UNITS);
        let bin = get_guide_bin_index(direction);
        let slot = cell as usize * GUIDE_BIN_COUNT as usize + bin as usize;
        self.sums[slot] = self.sums[slot].saturating_add(units);
        self.counts[cell as usize] = self.counts[cell as usize].saturating_add(1);
        true
    }

    /// Adds another set of splats on the same grid (a shard's, an iteration's): integer sums,
    /// so the result does not depend on the order of the parts.
    pub fn merge(&mut self, other: &GuideSplats) {
        assert_eq!(self.grid, other.grid, "guide splats on different grids");
        for (sum, more) in self.sums.iter_mut().zip(&other.sums) {
            *sum = sum.saturating_add(*more);
        }
        for (count, more) in self.counts.iter_mut().zip(&other.counts) {
            *count = count.saturating_add(*more);
        }
    }

    /// Number of splats that fell in `cell`.
    pub fn splat_count(&self, cell: u32) -> u32 {
        self.counts[cell as usize]
    }

    /// The guide these splats teach: in each cell with at least `GUIDE_MIN_SPLATS` splats
    /// and a positive sum, bin b's probability (1 - u) s_b / sum(s) + u / GUIDE_BIN_COUNT
    /// with u = GUIDE_UNIFORM_FRACTION, stored as cumulative f32 probabilities (summed in
    /// f64, the last set to exactly 1); other cells hold zeros and are not guided.
    pub fn build(&self) -> Guide {
        let bins = GUIDE_BIN_COUNT as usize;
        let mut words = self.header.clone();
        words.reserve(self.counts.len() * 4 * GUIDE_CELL_TEXEL_COUNT as usize);
        let mut guided_cell_count = 0;
        for (cell, &count) in self.counts.iter().enumerate() {
            let sums = &self.sums[cell * bins..(cell + 1) * bins];
            let total: u128 = sums.iter().map(|&s| u128::from(s)).sum();
            if count < GUIDE_MIN_SPLATS || total == 0 {
                words.extend(std::iter::repeat(0).take(bins));
                continue;
            }
            guided_cell_count += 1;
            let uniform = f64::from(GUIDE_UNIFORM_FRACTION);
            let mut cumulative = 0.0f64;
            for (bin, &sum) in sums.iter().enumerate() {
                cumulative += (1.0 - uniform) * (sum as f64 / total as f64) + uniform / bins as f64;
                let stored = if bin + 1 == bins {
                    1.0
                } else {
                    cumulative.min(1.0) as f32
                };
                words.push(stored.to_bits());
            }
        }
        Guide {
            grid: self.grid,
            words,
            guided_cell_count,
        }
    }
}

/// A built guide: the words of `glsl/guiding.glsl`'s texel buffer.
#[derive(Clone, Debug, PartialEq)]
pub struct Guide {
    grid: GuideGrid,
    words: Vec<u32>,
    guided_cell_count: u32,
}

impl Guide {
    /// The texel buffer's words (header, then `GUIDE_CELL_TEXEL_COUNT` texels per cell).
    pub fn words(&self) -> &[u32] {
        &self.words
    }

    /// The words as the twins read them.
    pub fn texels(&self) -> GuideTexels<'_> {
        GuideTexels { words: &self.words }
    }

    /// The grid it covers.
    pub fn grid(&self) -> &GuideGrid {
        &self.grid
    }

    /// Cells that hold a learned distribution.
    pub fn guided_cell_count(&self) -> u32 {
        self.guided_cell_count
    }

    /// Bytes the guide takes on the device.
    pub fn memory_bytes(&self) -> usize {
        4 * self.words.len()
    }
}
