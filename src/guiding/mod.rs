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

use glam::{IVec3, UVec3, Vec3};

use crate::contract::{
    GUIDE_BIN_COUNT, GUIDE_HEADER_TEXEL_COUNT, GUIDE_MIN_SPLATS, GUIDE_ORIENTATION_COUNT,
    GUIDE_UNIFORM_FRACTION,
};
use crate::cpu::guiding::{
    get_guide_bin_index, get_guide_splat_units, get_guide_table_slot, GuideTexels, GUIDE_NO_CELL,
};
use crate::error::{Error, Result};

#[cfg(test)]
mod tests;
pub mod training;

/// Grid positions along the longest axis of the scene's box (the other axes get as many as
/// keep them near cubes): 16^3 positions at most, each with a cell per orientation that a
/// surface there can face, so 6 x 16^3 cells (24 MB of guide) at the very most.
pub const GUIDE_MAX_CELLS_PER_AXIS: u32 = 16;

/// How far past a triangle's box (in cells) a grid position still counts as touched by it:
/// a hit point the GPU computes can stray a rounding error outside the triangle's box.
const TRIANGLE_CELL_MARGIN: f32 = 1e-3;

/// How much smaller than a normal's largest component another may be and still count as
/// dominant: where two are (nearly) equal, float rounding on the GPU may take either axis
/// (`get_guide_orientation`), so both get a cell.
const ORIENTATION_TIE_TOLERANCE: f32 = 1e-4;

/// The guide's uniform grid over a box, and its cells: each grid position has a cell for
/// each orientation (`get_guide_orientation`: a normal's dominant axis and sign) that a
/// surface there can face, found through the cell table.
#[derive(Clone, Debug, PartialEq)]
pub struct GuideGrid {
    /// Grid positions along x, y and z.
    pub resolution: UVec3,
    /// The grid's lower corner, world space.
    pub bounds_min: Vec3,
    /// Grid positions per unit length along each axis.
    pub cells_per_unit: Vec3,
    /// For each orientation and grid position (x fastest, then y, z, orientation), its cell
    /// or `GUIDE_NO_CELL`; the cells are numbered in this order. Padded with
    /// `GUIDE_NO_CELL` to whole texels.
    cell_table: Vec<u32>,
    /// Cells in the table.
    cell_count: u32,
}

/// Words of the cell table of a grid of `resolution`: one per orientation and grid position,
/// rounded up to whole texels of four (`None` if that overflows).
fn cell_table_word_count(resolution: UVec3) -> Option<usize> {
    let slots = u64::from(GUIDE_ORIENTATION_COUNT)
        * u64::from(resolution.x)
        * u64::from(resolution.y)
        * u64::from(resolution.z);
    usize::try_from(slots.div_ceil(4) * 4).ok()
}

impl GuideGrid {
    /// The grid over the box from `bounds_min` to `bounds_max`, padded by 10^-3 of its
    /// largest extent so that points on its faces fall inside, with
    /// `max_cells_per_axis` positions along the longest axis and the nearest whole number in
    /// proportion along the others (at least 1), and a cell for every position and
    /// orientation.
    pub fn around(bounds_min: Vec3, bounds_max: Vec3, max_cells_per_axis: u32) -> GuideGrid {
        let mut grid = GuideGrid::without_cells(bounds_min, bounds_max, max_cells_per_axis);
        let last = grid.resolution - UVec3::ONE;
        for orientation in 0..GUIDE_ORIENTATION_COUNT {
            grid.give_cells(orientation, UVec3::ZERO, last);
        }
        grid.number_cells();
        grid
    }

    /// As `around`, with no cells yet.
    fn without_cells(bounds_min: Vec3, bounds_max: Vec3, max_cells_per_axis: u32) -> GuideGrid {
        let extent = (bounds_max - bounds_min).max(Vec3::ZERO);
        let padding = (extent.max_element() * 1e-3).max(1e-6);
        let low = bounds_min - Vec3::splat(padding);
        let size = extent + Vec3::splat(2.0 * padding);
        let longest = size.max_element();
        let cells = max_cells_per_axis.clamp(1, GUIDE_MAX_CELLS_PER_AXIS) as f32;
        let resolution = (size / longest * cells).round().max(Vec3::ONE).as_uvec3();
        let table_words = cell_table_word_count(resolution).expect("at most 6 x 16^3 slots");
        GuideGrid {
            resolution,
            bounds_min: low,
            cells_per_unit: resolution.as_vec3() / size,
            cell_table: vec![GUIDE_NO_CELL; table_words],
            cell_count: 0,
        }
    }

    /// Numbers the table's marked slots (any value but `GUIDE_NO_CELL`) 0, 1, 2, … in slot
    /// order.
    fn number_cells(&mut self) {
        let mut next = 0u32;
        for slot in &mut self.cell_table {
            if *slot != GUIDE_NO_CELL {
                *slot = next;
                next += 1;
            }
        }
        self.cell_count = next;
    }

    /// The grid over the box of the scene's `triangles` (`GUIDE_MAX_CELLS_PER_AXIS` positions
    /// along its longest axis), with a cell at each grid position that a triangle's box
    /// touches for each orientation its normal has on either side (a ray may hit either):
    /// the orientations of empty space get none, which keeps the guide about as small as a
    /// grid without orientations (each surface is mostly one orientation) while the two
    /// faces of a wall learn apart.
    pub fn around_triangles(triangles: impl IntoIterator<Item = [Vec3; 3]>) -> GuideGrid {
        let triangles: Vec<[Vec3; 3]> = triangles.into_iter().collect();
        let (low, high) = triangles.iter().flatten().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(low, high), &p| (low.min(p), high.max(p)),
        );
        let (low, high) = if low.cmple(high).all() {
            (low, high)
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        };
        let mut grid = GuideGrid::without_cells(low, high, GUIDE_MAX_CELLS_PER_AXIS);
        let last = grid.resolution.as_vec3() - Vec3::ONE;
        for [a, b, c] in triangles {
            let normal = (b - a).cross(c - a).normalize_or_zero();
            if normal == Vec3::ZERO {
                continue;
            }
            let largest = normal.abs().max_element();
            let to_cells = |p: Vec3| (p - grid.bounds_min) * grid.cells_per_unit;
            let first = (to_cells(a.min(b).min(c)) - Vec3::splat(TRIANGLE_CELL_MARGIN))
                .floor()
                .clamp(Vec3::ZERO, last)
                .as_uvec3();
            let end = (to_cells(a.max(b).max(c)) + Vec3::splat(TRIANGLE_CELL_MARGIN))
                .floor()
                .clamp(Vec3::ZERO, last)
                .as_uvec3();
            let axes = (0..3u32)
                .filter(|&axis| normal[axis as usize].abs() >= largest - ORIENTATION_TIE_TOLERANCE);
            for orientation in axes.flat_map(|axis| [2 * axis, 2 * axis + 1]) {
                grid.give_cells(orientation, first, end);
            }
        }
        grid.number_cells();
        grid
    }

    /// Marks the table's slots of `orientation` at the grid positions from `first` to `last`
    /// (inclusive) as cells, to be numbered by `number_cells`.
    fn give_cells(&mut self, orientation: u32, first: UVec3, last: UVec3) {
        for z in first.z..=last.z {
            for y in first.y..=last.y {
                for x in first.x..=last.x {
                    let slot = self.table_slot(orientation, UVec3::new(x, y, z));
                    self.cell_table[slot] = 0;
                }
            }
        }
    }

    /// The table's slot of `orientation` at grid position `position` (orientation slowest,
    /// then z, y, x fastest: `get_guide_table_slot`'s order).
    fn table_slot(&self, orientation: u32, position: UVec3) -> usize {
        let [nx, ny, nz] = self.resolution.to_array().map(|n| n as usize);
        let [x, y, z] = position.to_array().map(|n| n as usize);
        ((orientation as usize * nz + z) * ny + y) * nx + x
    }

    /// The orientation and grid position of table slot `slot` (the inverse of `table_slot`).
    fn slot_position(&self, slot: usize) -> (u32, UVec3) {
        let [nx, ny, nz] = self.resolution.to_array().map(|n| n as usize);
        let position = UVec3::new(
            (slot % nx) as u32,
            (slot / nx % ny) as u32,
            (slot / (nx * ny) % nz) as u32,
        );
        ((slot / (nx * ny * nz)) as u32, position)
    }

    /// Number of cells.
    pub fn cell_count(&self) -> u32 {
        self.cell_count
    }

    /// The cell of a point at `position` on a surface facing `normal` (as
    /// `get_guide_cell_index` finds it), `GUIDE_NO_CELL` where there is none.
    pub fn cell_index(&self, position: Vec3, normal: Vec3) -> u32 {
        let header = self.header_words();
        let (slot, _) = get_guide_table_slot(GuideTexels { words: &header }, position, normal);
        self.cell_table
            .get(slot as usize)
            .copied()
            .unwrap_or(GUIDE_NO_CELL)
    }

    /// Words of the path tracer's training buffer (`BINDING_GUIDE_SPLATS`) for this grid:
    /// two per cell and bin (a 64-bit sum), then one count per cell.
    pub fn splat_word_count(&self) -> usize {
        self.cell_count() as usize * (2 * GUIDE_BIN_COUNT as usize + 1)
    }

    /// The header texels' words (`GUIDE_HEADER_TEXEL_COUNT` texels).
    fn header_words(&self) -> [u32; 4 * GUIDE_HEADER_TEXEL_COUNT as usize] {
        let [x, y, z] = self.bounds_min.to_array().map(f32::to_bits);
        let [u, v, w] = self.cells_per_unit.to_array().map(f32::to_bits);
        [
            self.resolution.x,
            self.resolution.y,
            self.resolution.z,
            self.cell_count(),
            x,
            y,
            z,
            0,
            u,
            v,
            w,
            0,
        ]
    }
}

/// A cell and its six face neighbours, as (dx, dy, dz).
const FACE_NEIGHBOURHOOD: [(i32, i32, i32); 7] = [
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
    sums: Vec<u64>,
    counts: Vec<u32>,
}

impl GuideSplats {
    /// No splats yet on `grid`.
    pub fn new(grid: GuideGrid) -> GuideSplats {
        let cells = grid.cell_count() as usize;
        GuideSplats {
            grid,
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
    pub fn splat(&mut self, position: Vec3, normal: Vec3, direction: Vec3, value: f32) -> bool {
        if !(value.is_finite() && value >= 0.0) {
            return false;
        }
        let cell = self.grid.cell_index(position, normal);
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
    pub fn from_device_words(grid: &GuideGrid, words: &[u32]) -> Result<GuideSplats> {
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
            grid: grid.clone(),
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
        let grid = &self.grid;
        let bins = GUIDE_BIN_COUNT as usize;
        // Cells whose sums are all zero add nothing to a neighbour's sums (only their count):
        // most cells, early in training. Found once, instead of adding zeros 7 times over.
        let has_sums: Vec<bool> = self
            .sums
            .chunks_exact(bins)
            .map(|sums| sums.iter().any(|&s| s != 0))
            .collect();
        let mut pooled = GuideSplats::new(grid.clone());
        for (slot, &cell) in grid.cell_table.iter().enumerate() {
            if cell == GUIDE_NO_CELL {
                continue;
            }
            let cell = cell as usize;
            let (orientation, position) = grid.slot_position(slot);
            for (dx, dy, dz) in FACE_NEIGHBOURHOOD {
                let neighbour = position.as_ivec3() + IVec3::new(dx, dy, dz);
                if neighbour.cmplt(IVec3::ZERO).any()
                    || neighbour.cmpge(grid.resolution.as_ivec3()).any()
                {
                    continue;
                }
                let other = grid.cell_table[grid.table_slot(orientation, neighbour.as_uvec3())];
                if other == GUIDE_NO_CELL {
                    continue;
                }
                let other = other as usize;
                if has_sums[other] {
                    let theirs = &self.sums[other * bins..(other + 1) * bins];
                    let ours = &mut pooled.sums[cell * bins..(cell + 1) * bins];
                    for (sum, &more) in ours.iter_mut().zip(theirs) {
                        *sum = sum.saturating_add(more);
                    }
                }
                pooled.counts[cell] = pooled.counts[cell].saturating_add(self.counts[other]);
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
    /// f64, the last set to exactly 1); other cells hold zeros and are not guided. The
    /// grid's cell table follows the cells.
    pub fn build(&self) -> Guide {
        let bins = GUIDE_BIN_COUNT as usize;
        let header = self.grid.header_words();
        let cells = self.counts.len();
        let mut words = vec![0u32; header.len() + cells * bins + self.grid.cell_table.len()];
        words[..header.len()].copy_from_slice(&header);
        words[header.len() + cells * bins..].copy_from_slice(&self.grid.cell_table);
        let uniform = f64::from(GUIDE_UNIFORM_FRACTION);
        // Unguided cells keep their zeros.
        let guided_cell_count = words[header.len()..header.len() + cells * bins]
            .chunks_exact_mut(bins)
            .zip(self.sums.chunks_exact(bins))
            .zip(&self.counts)
            .map(|((cumulatives, sums), &count)| {
                // Too few splats: not guided, whatever they sum to (not summed then).
                let total: u128 = if count < GUIDE_MIN_SPLATS {
                    0
                } else {
                    sums.iter().map(|&s| u128::from(s)).sum()
                };
                if total == 0 {
                    return 0u32;
                }
                let mut cumulative = 0.0f64;
                for (bin, (&sum, word)) in sums.iter().zip(cumulatives.iter_mut()).enumerate() {
                    cumulative +=
                        (1.0 - uniform) * (sum as f64 / total as f64) + uniform / bins as f64;
                    let stored = if bin + 1 == bins {
                        1.0
                    } else {
                        cumulative.min(1.0) as f32
                    };
                    *word = stored.to_bits();
                }
                1
            })
            .sum();
        Guide {
            grid: self.grid.clone(),
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
    /// The texel buffer's words (header, `GUIDE_CELL_TEXEL_COUNT` texels per cell, the cell table).
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

    /// The guide's words without its unguided cells (all zeros): the header, the cell
    /// table, then for each guided cell its index and its `GUIDE_BIN_COUNT` words. What a
    /// checkpoint stores: training often teaches a few percent of the cells.
    pub fn sparse_words(&self) -> Vec<u32> {
        let header_words = 4 * GUIDE_HEADER_TEXEL_COUNT as usize;
        let bins = GUIDE_BIN_COUNT as usize;
        let cells_end = header_words + self.grid.cell_count() as usize * bins;
        let mut sparse = self.words[..header_words].to_vec();
        sparse.extend_from_slice(&self.grid.cell_table);
        for (cell, cumulative) in self.words[header_words..cells_end].chunks(bins).enumerate() {
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
        if sparse.len() < header_words {
            return Err(invalid(format!("{} words, no header", sparse.len())));
        }
        let resolution =
            checked_resolution(&sparse[..3]).map_err(|error| invalid(error.to_string()))?;
        let table_words = cell_table_word_count(resolution).expect("a checked resolution");
        let cells_start = header_words + table_words;
        if sparse.len() < cells_start || !(sparse.len() - cells_start).is_multiple_of(bins + 1) {
            return Err(invalid(format!(
                "{} words do not make a header, a cell table and whole cells",
                sparse.len()
            )));
        }
        let cell_count = sparse[3] as usize;
        if cell_count > table_words {
            return Err(invalid(format!("{cell_count} cells")));
        }
        let mut words = sparse[..header_words].to_vec();
        words.resize(header_words + cell_count * bins, 0);
        let mut next = 0usize;
        for record in sparse[cells_start..].chunks(bins + 1) {
            let cell = record[0] as usize;
            if cell < next || cell >= cell_count {
                return Err(invalid(format!("cell {cell} out of order or range")));
            }
            let start = header_words + cell * bins;
            words[start..start + bins].copy_from_slice(&record[1..]);
            next = cell + 1;
        }
        words.extend_from_slice(&sparse[header_words..cells_start]);
        Guide::from_words(words)
    }

    /// The guide that `words` hold (as `words` gives them), checked: a header whose
    /// resolution is at most `GUIDE_MAX_CELLS_PER_AXIS` along each axis, one cell of
    /// `GUIDE_CELL_TEXEL_COUNT` texels per cell, in each cell either zeros (not guided) or
    /// cumulative probabilities that never fall, lie in [0, 1] and end at exactly 1, and a
    /// cell table that numbers the header's count of cells in slot order.
    pub fn from_words(words: Vec<u32>) -> Result<Guide> {
        let invalid = |why: String| Error::InvalidSettings(format!("not a guide: {why}"));
        let header_words = 4 * GUIDE_HEADER_TEXEL_COUNT as usize;
        if words.len() < header_words {
            return Err(invalid(format!("{} words, no header", words.len())));
        }
        let resolution =
            checked_resolution(&words[..3]).map_err(|error| invalid(error.to_string()))?;
        let table_words = cell_table_word_count(resolution).expect("a checked resolution");
        let float = |i: usize| f32::from_bits(words[i]);
        let cell_count = words[3] as usize;
        let bins = GUIDE_BIN_COUNT as usize;
        let cells_end = header_words + cell_count * bins;
        if cell_count > table_words || cells_end + table_words != words.len() {
            return Err(invalid(format!(
                "a {}x{}x{} grid of {} cells in {} words",
                resolution.x,
                resolution.y,
                resolution.z,
                words[3],
                words.len()
            )));
        }
        let cell_table = words[cells_end..].to_vec();
        let mut numbered = 0u32;
        for &slot in &cell_table {
            if slot == GUIDE_NO_CELL {
                continue;
            }
            if slot != numbered {
                return Err(invalid(
                    "its cell table does not number its cells in order".into(),
                ));
            }
            numbered += 1;
        }
        if numbered as usize != cell_count {
            return Err(invalid(format!(
                "its cell table has {numbered} cells, its header {cell_count}"
            )));
        }
        let grid = GuideGrid {
            resolution,
            bounds_min: Vec3::new(float(4), float(5), float(6)),
            cells_per_unit: Vec3::new(float(8), float(9), float(10)),
            cell_table,
            cell_count: numbered,
        };
        if grid.header_words() != words[..header_words] {
            return Err(invalid(
                "its header holds other words than its grid's".into(),
            ));
        }
        let mut guided_cell_count = 0;
        for (cell, cumulative) in words[header_words..cells_end].chunks(bins).enumerate() {
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

/// A guide's grid resolution outside 1..=`GUIDE_MAX_CELLS_PER_AXIS` on some axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("a {}x{}x{} grid", .0.x, .0.y, .0.z)]
struct GridResolutionError(UVec3);

/// The grid resolution of a guide's first three header words, if each lies in
/// 1..=`GUIDE_MAX_CELLS_PER_AXIS`.
fn checked_resolution(words: &[u32]) -> std::result::Result<UVec3, GridResolutionError> {
    let resolution = UVec3::new(words[0], words[1], words[2]);
    if resolution.min_element() == 0 || resolution.max_element() > GUIDE_MAX_CELLS_PER_AXIS {
        return Err(GridResolutionError(resolution));
    }
    Ok(resolution)
}
