//! Path guiding's guide on the host: the grid of cells over the scene (`GuideGrid`), the
//! training splats that learn where light arrives from in each cell (`GuideSplats`), and the
//! guide they build (`Guide`): the words of `glsl/guiding.glsl`'s texel buffer, which the
//! Rust twins (`crate::cpu::guiding`) read too.
//!
//! Deterministic by construction: a splat is a fixed-point integer (`GUIDE_FIXED_POINT_SCALE`
//! units of its value, `get_guide_splat_units`), so that sums do not depend on the order in
//! which they were added — the GPU's integer atomics and a CPU loop give the same bits — and
//! the build turns the integer sums into probabilities in one fixed order.
//!
//! How a render trains one: `training` (the schedule) and `crate::render::guide_buffers`.

use glam::{UVec3, Vec3};

use crate::contract::{
    GUIDE_BIN_COUNT, GUIDE_CELL_TEXEL_COUNT, GUIDE_HEADER_TEXEL_COUNT, GUIDE_MIN_SPLATS,
    GUIDE_UNIFORM_FRACTION,
};
use crate::cpu::guiding::{
    get_guide_bin_index, get_guide_cell_index, get_guide_splat_units, GuideTexels, GUIDE_NO_CELL,
};
use crate::error::{Error, Result};

#[cfg(test)]
mod tests;
pub mod training;

/// Cells along the longest axis of the scene's box (the other axes get as many as keep the
/// cells near cubes): 16^3 cells at most, 4 MB of guide.
pub const GUIDE_MAX_CELLS_PER_AXIS: u32 = 16;

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

    /// The grid over the box of every vertex of `positions` (a scene's triangles), as
    /// `around` with `GUIDE_MAX_CELLS_PER_AXIS`.
    pub fn around_points(positions: impl IntoIterator<Item = Vec3>) -> GuideGrid {
        let (low, high) = positions.into_iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(low, high), p| (low.min(p), high.max(p)),
        );
        let (low, high) = if low.cmple(high).all() {
            (low, high)
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        };
        GuideGrid::around(low, high, GUIDE_MAX_CELLS_PER_AXIS)
    }

    /// Number of cells.
    pub fn cell_count(&self) -> u32 {
        self.resolution.x * self.resolution.y * self.resolution.z
    }

    /// Words of the path tracer's training buffer (`BINDING_GUIDE_SPLATS`) for this grid:
    /// two per cell and bin (a 64-bit sum), then one count per cell.
    pub fn splat_word_count(&self) -> usize {
        self.cell_count() as usize * (2 * GUIDE_BIN_COUNT as usize + 1)
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

/// A cell and its six face neighbours, as (dx, dy, dz).
const FACE_NEIGHBOURHOOD: [(i64, i64, i64); 7] = [
    (0, 0, 0),
    (-1, 0, 0),
    (1, 0, 0),
    (0, -1, 0),
    (0, 1, 0),
    (0, 0, -1),
    (0, 0, 1),
];

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
        let (low, high) = get_guide_splat_units(value);
        let units = u64::from(low) | (u64::from(high) << 32);
        let bin = get_guide_bin_index(direction);
        let slot = cell as usize * GUIDE_BIN_COUNT as usize + bin as usize;
        self.sums[slot] = self.sums[slot].saturating_add(units);
        self.counts[cell as usize] = self.counts[cell as usize].saturating_add(1);
        true
    }

    /// The splats that the path tracer's training frames added up in `words` (its
    /// `BINDING_GUIDE_SPLATS` buffer, `GuideGrid::splat_word_count` words) on `grid`.
    pub fn from_device_words(grid: GuideGrid, words: &[u32]) -> Result<GuideSplats> {
        let cells = grid.cell_count() as usize;
        let bins = GUIDE_BIN_COUNT as usize;
        if words.len() < grid.splat_word_count() {
            return Err(Error::InvalidSettings(format!(
                "a guide's training buffer of {} words is too short for {cells} cells",
                words.len()
            )));
        }
        let sums = words[..2 * cells * bins]
            .chunks_exact(2)
            .map(|pair| u64::from(pair[0]) | (u64::from(pair[1]) << 32))
            .collect();
        let counts = words[2 * cells * bins..2 * cells * bins + cells].to_vec();
        Ok(GuideSplats {
            grid,
            header: grid.header_words(),
            sums,
            counts,
        })
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

    /// These splats with each cell's sums and counts pooled with its face neighbours' (a
    /// spatial box filter: a guide learns from 7 cells' paths instead of one, so it is
    /// smoother where training paths are few). Integer sums: still order-independent.
    pub fn pooled_with_neighbours(&self) -> GuideSplats {
        let [nx, ny, nz] = self.grid.resolution.to_array().map(|n| n as i64);
        let bins = GUIDE_BIN_COUNT as usize;
        let mut pooled = GuideSplats::new(self.grid);
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let cell = ((z * ny + y) * nx + x) as usize;
                    for (dx, dy, dz) in FACE_NEIGHBOURHOOD {
                        let (a, b, c) = (x + dx, y + dy, z + dz);
                        if a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz {
                            continue;
                        }
                        let other = ((c * ny + b) * nx + a) as usize;
                        for bin in 0..bins {
                            let sum = &mut pooled.sums[cell * bins + bin];
                            *sum = sum.saturating_add(self.sums[other * bins + bin]);
                        }
                        pooled.counts[cell] =
                            pooled.counts[cell].saturating_add(self.counts[other]);
                    }
                }
            }
        }
        pooled
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
                words.extend(std::iter::repeat_n(0, bins));
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

    /// The guide's words without its unguided cells (all zeros): the header, then for each
    /// guided cell its index and its `GUIDE_BIN_COUNT` words. What a checkpoint stores: a
    /// guide of 4096 cells takes 4 MB on the device, of which training often teaches a few
    /// percent.
    pub fn sparse_words(&self) -> Vec<u32> {
        let header_words = 4 * GUIDE_HEADER_TEXEL_COUNT as usize;
        let bins = GUIDE_BIN_COUNT as usize;
        let mut sparse = self.words[..header_words].to_vec();
        for (cell, cumulative) in self.words[header_words..].chunks(bins).enumerate() {
            if cumulative.iter().any(|&w| w != 0) {
                sparse.push(cell as u32);
                sparse.extend_from_slice(cumulative);
            }
        }
        sparse
    }

    /// The guide of `sparse_words`, checked as `from_words` checks; cells must come in
    /// increasing order.
    pub fn from_sparse_words(sparse: &[u32]) -> Result<Guide> {
        let invalid = |why: String| Error::InvalidSettings(format!("not a guide: {why}"));
        let header_words = 4 * GUIDE_HEADER_TEXEL_COUNT as usize;
        let bins = GUIDE_BIN_COUNT as usize;
        if sparse.len() < header_words || !(sparse.len() - header_words).is_multiple_of(bins + 1) {
            return Err(invalid(format!(
                "{} words do not make whole cells",
                sparse.len()
            )));
        }
        let cell_count = sparse[3] as usize;
        if cell_count > (GUIDE_MAX_CELLS_PER_AXIS as usize).pow(3) {
            return Err(invalid(format!("{cell_count} cells")));
        }
        let mut words = sparse[..header_words].to_vec();
        words.resize(header_words + cell_count * bins, 0);
        let mut next = 0usize;
        for record in sparse[header_words..].chunks(bins + 1) {
            let cell = record[0] as usize;
            if cell < next || cell >= cell_count {
                return Err(invalid(format!("cell {cell} out of order or range")));
            }
            let start = header_words + cell * bins;
            words[start..start + bins].copy_from_slice(&record[1..]);
            next = cell + 1;
        }
        Guide::from_words(words)
    }

    /// The guide that `words` hold (as `words` gives them), checked: a header whose resolution gives its cell count, one cell of
    /// `GUIDE_CELL_TEXEL_COUNT` texels per cell, and in each cell either zeros (not guided)
    /// or cumulative probabilities that never fall, lie in [0, 1] and end at exactly 1.
    pub fn from_words(words: Vec<u32>) -> Result<Guide> {
        let invalid = |why: String| Error::InvalidSettings(format!("not a guide: {why}"));
        let header_words = 4 * GUIDE_HEADER_TEXEL_COUNT as usize;
        if words.len() < header_words {
            return Err(invalid(format!("{} words, no header", words.len())));
        }
        let resolution = UVec3::new(words[0], words[1], words[2]);
        let float = |i: usize| f32::from_bits(words[i]);
        let grid = GuideGrid {
            resolution,
            bounds_min: Vec3::new(float(4), float(5), float(6)),
            cells_per_unit: Vec3::new(float(8), float(9), float(10)),
        };
        let cell_count =
            u64::from(resolution.x) * u64::from(resolution.y) * u64::from(resolution.z);
        let bins = GUIDE_BIN_COUNT as usize;
        let expected = header_words as u64 + cell_count * bins as u64;
        if cell_count != u64::from(words[3]) || expected != words.len() as u64 {
            return Err(invalid(format!(
                "a {}x{}x{} grid of {} cells in {} words",
                resolution.x,
                resolution.y,
                resolution.z,
                words[3],
                words.len()
            )));
        }
        if grid.header_words() != words[..header_words] {
            return Err(invalid(
                "its header holds other words than its grid's".into(),
            ));
        }
        let mut guided_cell_count = 0;
        for (cell, cumulative) in words[header_words..].chunks(bins).enumerate() {
            if cumulative.iter().all(|&w| w == 0) {
                continue;
            }
            let values: Vec<f32> = cumulative.iter().map(|&w| f32::from_bits(w)).collect();
            let rising = values.windows(2).all(|pair| pair[0] <= pair[1]);
            if !rising || !(values[0] >= 0.0) || values[bins - 1] != 1.0 {
                return Err(invalid(format!(
                    "cell {cell} holds no cumulative distribution"
                )));
            }
            guided_cell_count += 1;
        }
        Ok(Guide {
            grid,
            words,
            guided_cell_count,
        })
    }
}
