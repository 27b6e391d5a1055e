//! Rust twins of `glsl/guiding.glsl`: finding a point's cell in the guide, a direction's
//! bin, the guide's density and its sampler, read from the same words of the guide's texel
//! buffer that the GPU reads (`crate::guiding::Guide::words`), with the same maths.

use glam::{UVec3, Vec2, Vec3, Vec4};

use crate::contract::{
    GUIDE_BIN_COUNT, GUIDE_BSDF_FRACTION, GUIDE_CELL_TEXEL_COUNT, GUIDE_DIRECTION_RESOLUTION,
    GUIDE_FIXED_POINT_SCALE, GUIDE_HEADER_TEXEL_COUNT, GUIDE_MAX_SPLAT_UNITS, ONE_MINUS_EPSILON,
};
use crate::cpu::texels::{fetch_float_texel, fetch_texel};
use crate::cpu::workshop::M_PI;

/// Twin of `GUIDE_NO_CELL`: what `get_guide_cell_index` returns outside the grid.
pub const GUIDE_NO_CELL: u32 = u32::MAX;

/// The words of `g_guide_texels` (header, then the cells) as the twins read them.
#[derive(Clone, Copy, Debug)]
pub struct GuideTexels<'a> {
    /// RGBA32_UINT texels, four words each.
    pub words: &'a [u32],
}

/// Twin of `get_guide_orientation`: 2 axis + (1 if the normal points down it), the axis the
/// first of its largest components.
pub fn get_guide_orientation(normal: Vec3) -> u32 {
    let a = normal.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + u32::from(normal[axis as usize] < 0.0)
}

/// Twin of `get_guide_table_slot`, returning `(slot, cell_count)`. Reads only the header
/// texels.
pub fn get_guide_table_slot(texels: GuideTexels, position: Vec3, normal: Vec3) -> (u32, u32) {
    let header = fetch_texel(texels.words, 0);
    let cell_count = header.w;
    if header.w == 0 {
        return (GUIDE_NO_CELL, cell_count);
    }
    let bounds_min = fetch_float_texel(texels.words, 1).truncate();
    let cells_per_unit = fetch_float_texel(texels.words, 2).truncate();
    let cell = ((position - bounds_min) * cells_per_unit).floor();
    let resolution = header.truncate().as_vec3();
    if !(cell.cmpge(Vec3::ZERO).all() && cell.cmplt(resolution).all()) {
        return (GUIDE_NO_CELL, cell_count);
    }
    let coordinates: UVec3 = cell.as_uvec3();
    let slot = ((get_guide_orientation(normal) * header.z + coordinates.z) * header.y
        + coordinates.y)
        * header.x
        + coordinates.x;
    (slot, cell_count)
}

/// Twin of `get_guide_cell_index`.
pub fn get_guide_cell_index(texels: GuideTexels, position: Vec3, normal: Vec3) -> u32 {
    let (slot, cell_count) = get_guide_table_slot(texels, position, normal);
    if slot == GUIDE_NO_CELL {
        return GUIDE_NO_CELL;
    }
    let table_texel = GUIDE_HEADER_TEXEL_COUNT + cell_count * GUIDE_CELL_TEXEL_COUNT + slot / 4;
    fetch_texel(texels.words, table_texel as usize)[(slot % 4) as usize]
}

/// Twin of `get_guide_bin_index`.
pub fn get_guide_bin_index(direction: Vec3) -> u32 {
    let resolution = GUIDE_DIRECTION_RESOLUTION as f32;
    let z = direction.z.clamp(-1.0, 1.0);
    let mut phi = if direction.x == 0.0 && direction.y == 0.0 {
        0.0
    } else {
        direction.y.atan2(direction.x)
    };
    if phi < 0.0 {
        phi += 2.0 * M_PI;
    }
    let row = (((z + 1.0) * 0.5 * resolution) as u32).min(GUIDE_DIRECTION_RESOLUTION - 1);
    let column = ((phi * (resolution / (2.0 * M_PI))) as u32).min(GUIDE_DIRECTION_RESOLUTION - 1);
    row * GUIDE_DIRECTION_RESOLUTION + column
}

/// Twin of `get_guide_cumulative`.
pub fn get_guide_cumulative(texels: GuideTexels, cell_index: u32, bin: u32) -> f32 {
    let texel = GUIDE_HEADER_TEXEL_COUNT + cell_index * GUIDE_CELL_TEXEL_COUNT + bin / 4;
    fetch_float_texel(texels.words, texel as usize)[(bin % 4) as usize]
}

/// Twin of `is_guided_cell`.
pub fn is_guided_cell(texels: GuideTexels, cell_index: u32) -> bool {
    cell_index != GUIDE_NO_CELL
        && get_guide_cumulative(texels, cell_index, GUIDE_BIN_COUNT - 1) > 0.0
}

/// Twin of `get_guide_bin_probability`.
pub fn get_guide_bin_probability(texels: GuideTexels, cell_index: u32, bin: u32) -> f32 {
    let before = if bin == 0 {
        0.0
    } else {
        get_guide_cumulative(texels, cell_index, bin - 1)
    };
    get_guide_cumulative(texels, cell_index, bin) - before
}

/// Twin of `get_guide_density`.
pub fn get_guide_density(texels: GuideTexels, cell_index: u32, direction: Vec3) -> f32 {
    get_guide_bin_probability(texels, cell_index, get_guide_bin_index(direction))
        * (GUIDE_BIN_COUNT as f32 / (4.0 * M_PI))
}

/// What `sample_guide_direction` returns: the direction and its `out` parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuideDirectionSample {
    /// The unit direction.
    pub direction: Vec3,
    /// The bin chosen (`out_bin`).
    pub bin: u32,
    /// That bin's probability (`out_bin_probability`).
    pub bin_probability: f32,
}

/// Twin of `get_guide_cumulative_texel`.
pub fn get_guide_cumulative_texel(texels: GuideTexels, cell_index: u32, texel: u32) -> Vec4 {
    fetch_float_texel(
        texels.words,
        (GUIDE_HEADER_TEXEL_COUNT + cell_index * GUIDE_CELL_TEXEL_COUNT + texel) as usize,
    )
}

/// Twin of `sample_guide_direction`: the search over texels of four bins, then within one.
pub fn sample_guide_direction(
    texels: GuideTexels,
    cell_index: u32,
    random_numbers: Vec2,
) -> GuideDirectionSample {
    let u = random_numbers[0];
    let mut texel = 0u32;
    let mut before = 0.0;
    let mut step = GUIDE_CELL_TEXEL_COUNT / 2;
    while step != 0 {
        let end = get_guide_cumulative_texel(texels, cell_index, texel + step - 1).w;
        if end <= u {
            texel += step;
            before = end;
        }
        step /= 2;
    }
    let cumulative = get_guide_cumulative_texel(texels, cell_index, texel);
    let within_texel =
        u32::from(cumulative.x <= u) + u32::from(cumulative.y <= u) + u32::from(cumulative.z <= u);
    if within_texel != 0 {
        before = cumulative[(within_texel - 1) as usize];
    }
    let first = 4 * texel + within_texel;
    let probability = cumulative[within_texel as usize] - before;
    let within = ((u - before) / probability).min(ONE_MINUS_EPSILON);
    let resolution = GUIDE_DIRECTION_RESOLUTION as f32;
    let row = (first / GUIDE_DIRECTION_RESOLUTION) as f32;
    let column = (first % GUIDE_DIRECTION_RESOLUTION) as f32;
    let z = -1.0 + 2.0 * (row + within) / resolution;
    let phi = 2.0 * M_PI * (column + random_numbers[1]) / resolution;
    let radius = (1.0 - z * z).max(0.0).sqrt();
    GuideDirectionSample {
        direction: Vec3::new(radius * phi.cos(), radius * phi.sin(), z),
        bin: first,
        bin_probability: probability,
    }
}

/// Twin of `get_guided_mixture_density`.
pub fn get_guided_mixture_density(bsdf_density: f32, guide_density: f32) -> f32 {
    GUIDE_BSDF_FRACTION * bsdf_density + (1.0 - GUIDE_BSDF_FRACTION) * guide_density
}

/// Twin of `get_guide_splat_units`: a splat's value in fixed point as (low, high) words of
/// floor(min(value GUIDE_FIXED_POINT_SCALE, GUIDE_MAX_SPLAT_UNITS)), in f32 as the GPU
/// computes it (exact: an f32 at or above 2^32 is a multiple of 2^9).
pub fn get_guide_splat_units(value: f32) -> (u32, u32) {
    let units = (value * GUIDE_FIXED_POINT_SCALE)
        .min(GUIDE_MAX_SPLAT_UNITS)
        .floor();
    let high = (units / 4_294_967_296.0).floor();
    ((units - high * 4_294_967_296.0) as u32, high as u32)
}
