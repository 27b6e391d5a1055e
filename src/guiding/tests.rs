//! The guide's construction and its twins' sampling: every guided cell's density integrates
//! to 1, the sampler follows the density (alone and mixed with a BSDF), splats sum the same
//! in any order, sparse cells stay unguided.

use glam::{Vec2, Vec3};

use super::*;
use crate::cpu::guiding::{
    get_guide_bin_probability, get_guide_cell_index, get_guide_density, get_guided_mixture_density,
    is_guided_cell, sample_guide_direction,
};
use crate::cpu::importance_sampling::{get_hemisphere_cosine_density, sample_hemisphere_cosine};
use crate::probe::inputs::InputRng;
use crate::stats::chi2::{chi2_direction_test, Chi2Config};
use crate::stats::sphere_histogram::{SphereFrame, TargetDensity};

/// A 2 x 1 x 1 grid over the box [0, 2] x [0, 1] x [0, 1], with a cell for each position and
/// orientation: cells 0 and 1 face +x.
fn two_cells() -> GuideGrid {
    GuideGrid::around(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0), 2)
}

/// Splats in cell 0 of `two_cells()` (a surface facing +x) shaped like a lobe around `axis` (value
/// max(0, axis . l)^8 at uniform directions) plus a dim uniform floor: a learned distribution
/// with a peak, a tail and empty bins' neighbours.
fn lobe_splats(axis: Vec3, count: usize, seed: u64) -> GuideSplats {
    let mut splats = GuideSplats::new(two_cells());
    let mut rng = InputRng::new(seed);
    for _ in 0..count {
        let direction = rng.unit_vector();
        let value = axis.dot(direction).max(0.0).powi(8) + 1e-3;
        assert!(splats.splat(Vec3::new(0.5, 0.5, 0.5), Vec3::X, direction, value));
    }
    splats
}

#[test]
fn the_grid_keeps_cells_near_cubes_and_holds_its_box() {
    let grid = GuideGrid::around(Vec3::ZERO, Vec3::new(4.0, 1.0, 2.0), 16);
    assert_eq!(grid.resolution, UVec3::new(16, 4, 8));
    assert_eq!(grid.cell_count(), 6 * 16 * 4 * 8);
    let guide = GuideSplats::new(grid.clone()).build();
    let texels = guide.texels();
    // The box's corners are inside (the first cell faces +x, the last -z); a point beyond
    // it is not.
    let lookups = [
        (Vec3::ZERO, Vec3::X, 0),
        (Vec3::new(4.0, 1.0, 2.0), -Vec3::Z, grid.cell_count() - 1),
        (Vec3::new(4.1, 0.5, 0.5), Vec3::X, GUIDE_NO_CELL),
        (Vec3::new(f32::NAN, 0.5, 0.5), Vec3::X, GUIDE_NO_CELL),
    ];
    for (position, normal, cell) in lookups {
        assert_eq!(
            get_guide_cell_index(texels, position, normal),
            cell,
            "{position}"
        );
        assert_eq!(grid.cell_index(position, normal), cell, "{position}");
    }
}

#[test]
fn orientations_are_the_normals_dominant_axis_and_sign() {
    use crate::cpu::guiding::get_guide_orientation;
    let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    for (orientation, axis) in axes.into_iter().enumerate() {
        assert_eq!(get_guide_orientation(axis), orientation as u32);
        let tilted = (axis + 0.4 * Vec3::ONE.cross(axis).normalize_or_zero()).normalize();
        assert_eq!(
            get_guide_orientation(tilted),
            orientation as u32,
            "{tilted}"
        );
    }
    // A tie goes to the first axis.
    assert_eq!(
        get_guide_orientation(Vec3::new(-1.0, 1.0, 0.0).normalize()),
        1
    );
    assert_eq!(
        get_guide_orientation(Vec3::new(0.0, 1.0, -1.0).normalize()),
        2
    );
}

#[test]
fn a_scenes_grid_has_cells_only_where_its_triangles_face() {
    // A floor (normal +y) over [0, 4] x [0, 4] and a thin wall at x = 2 (normal +x) up to
    // y = 2, on a 16 x 8 x 16 grid: the floor's layer of positions gets cells facing +y and
    // -y, the wall's slab +x and -x; nothing else.
    let floor = [
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 4.0),
            Vec3::new(4.0, 0.0, 4.0),
        ],
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(4.0, 0.0, 4.0),
            Vec3::new(4.0, 0.0, 0.0),
        ],
    ];
    let wall = [
        [
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(2.0, 2.0, 4.0),
        ],
        [
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 2.0, 4.0),
            Vec3::new(2.0, 0.0, 4.0),
        ],
    ];
    let triangles: Vec<[Vec3; 3]> = floor.into_iter().chain(wall).collect();
    let grid = GuideGrid::around_triangles(triangles);
    assert_eq!(grid.resolution, UVec3::new(16, 8, 16));
    // Floor: 16 x 1 x 16 positions, two orientations. The wall at x = 2 lies on the boundary
    // of positions 7 and 8 (within the margin of both) and spans the grid's height: 2 x 8 x
    // 16 positions, two other orientations, so the counts add up.
    assert_eq!(grid.cell_count(), 2 * 16 * 16 + 2 * (2 * 8 * 16));
    let on_floor = Vec3::new(1.0, 0.0, 1.0);
    let up = grid.cell_index(on_floor, Vec3::Y);
    let down = grid.cell_index(on_floor, -Vec3::Y);
    assert!(up != GUIDE_NO_CELL && down != GUIDE_NO_CELL && up != down);
    assert_eq!(grid.cell_index(on_floor, Vec3::X), GUIDE_NO_CELL);
    // The wall's two faces learn apart.
    let on_wall = Vec3::new(2.0, 1.0, 1.0);
    let east = grid.cell_index(on_wall, Vec3::X);
    let west = grid.cell_index(on_wall, -Vec3::X);
    assert!(east != GUIDE_NO_CELL && west != GUIDE_NO_CELL && east != west);
    // Empty space has no cells.
    assert_eq!(
        grid.cell_index(Vec3::new(1.0, 1.5, 1.0), Vec3::Y),
        GUIDE_NO_CELL
    );
    // A triangle whose normal lies between two axes gets both (the GPU may round either way).
    let diagonal = [[
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(1.0, 1.0, 0.0),
    ]];
    let grid = GuideGrid::around_triangles(diagonal);
    let middle = Vec3::new(0.5, 0.5, 0.5);
    for normal in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y] {
        assert_ne!(grid.cell_index(middle, normal), GUIDE_NO_CELL, "{normal}");
    }
    assert_eq!(grid.cell_index(middle, Vec3::Z), GUIDE_NO_CELL);
    // A guide built on it finds the same cells through the table (get_guide_cell_index).
    let guide = GuideSplats::new(grid.clone()).build();
    let mut rng = InputRng::new(21);
    for _ in 0..2_000 {
        let position = rng.in_box(Vec3::splat(-0.1), Vec3::splat(1.1));
        let normal = rng.unit_vector();
        assert_eq!(
            get_guide_cell_index(guide.texels(), position, normal),
            grid.cell_index(position, normal)
        );
    }
}

#[test]
fn every_guided_cell_integrates_to_one() {
    let guide = lobe_splats(Vec3::new(0.3, -0.5, 0.81).normalize(), 20_000, 1).build();
    assert_eq!(guide.guided_cell_count(), 1);
    assert!(is_guided_cell(guide.texels(), 0) && !is_guided_cell(guide.texels(), 1));
    // Midpoint quadrature over the equal-area map (cos theta, phi): 512 x 1024 cells, 32 x 64
    // per bin, so every quadrature cell lies inside one bin and the sum is exact up to f32
    // rounding of the densities (about 1e-6 relative).
    let (rows, columns) = (512, 1024);
    let mut integral = 0.0f64;
    for row in 0..rows {
        let z = -1.0 + 2.0 * (row as f64 + 0.5) / rows as f64;
        for column in 0..columns {
            let phi = 2.0 * std::f64::consts::PI * (column as f64 + 0.5) / columns as f64;
            let radius = (1.0 - z * z).sqrt();
            let direction = Vec3::new(
                (radius * phi.cos()) as f32,
                (radius * phi.sin()) as f32,
                z as f32,
            );
            integral += f64::from(get_guide_density(guide.texels(), 0, direction));
        }
    }
    integral *= 4.0 * std::f64::consts::PI / (rows * columns) as f64;
    assert!(
        (integral - 1.0).abs() < 1e-4,
        "the density integrates to {integral}"
    );
    // And by Monte Carlo over 10^6 uniform directions, as the issue asks: within 1 %
    // (the estimate's standard deviation is about 0.3 % for this lobe).
    let mut rng = InputRng::new(2);
    let count = 1_000_000;
    let mean: f64 = (0..count)
        .map(|_| f64::from(get_guide_density(guide.texels(), 0, rng.unit_vector())))
        .sum::<f64>()
        / count as f64;
    let estimate = mean * 4.0 * std::f64::consts::PI;
    assert!(
        (estimate - 1.0).abs() < 0.01,
        "Monte Carlo gives {estimate}"
    );
}

/// The χ² harness's settings for the two sampling tests of this file (Šidák-corrected). The
/// guide's density is piecewise constant, and Simpson's rule over a test bin that a guide
/// bin's edge crosses errs by about the jump times a quadrature interval: the default 6
/// intervals per bin gave a χ² 8 % above its degrees of freedom for a correct sampler
/// (p = 3e-5), 48 bring the error far below the noise of 10^6 samples.
fn chi2_config() -> Chi2Config {
    Chi2Config {
        test_count: 2,
        quadrature_resolution: 48,
        ..Chi2Config::default()
    }
}

/// Runs the χ² test of `samples` against `density` (w.r.t. solid angle) with
/// `chi2_config()`, prints its figures under `name` and fails unless it passed.
fn assert_follows_density(name: &str, samples: Vec<Vec3>, density: &dyn Fn(Vec3) -> f64) {
    let result = chi2_direction_test(
        samples,
        TargetDensity::SolidAngle(density),
        &SphereFrame::WORLD,
        &chi2_config(),
    )
    .unwrap();
    println!(
        "{name}: p = {:.4}, chi2 = {:.1}, dof {}",
        result.p_value, result.statistic, result.degrees_of_freedom
    );
    assert!(result.passed, "{result:?}");
}

/// The sampler's bin as a binary search over single bins finds it (the kernels' search until
/// it went over texels of four bins): the first bin whose cumulative probability exceeds u,
/// or the last.
fn first_bin_above(texels: GuideTexels, cell: u32, u: f32) -> (u32, f32) {
    let mut first = 0u32;
    let mut step = GUIDE_BIN_COUNT / 2;
    while step != 0 {
        if crate::cpu::guiding::get_guide_cumulative(texels, cell, first + step - 1) <= u {
            first += step;
        }
        step /= 2;
    }
    (first, get_guide_bin_probability(texels, cell, first))
}

#[test]
fn the_search_over_texels_finds_the_bin_and_probability_of_the_search_over_bins() {
    // Every u at and beside each cumulative probability of a peaked cell (so the ties, the
    // empty tail's equal sums and the last bin's 1), plus random ones: the same bin and the
    // same probability bit for bit, hence the same direction and image as the old search.
    let guide = lobe_splats(Vec3::new(0.3, -0.5, 0.81).normalize(), 20_000, 7).build();
    let texels = guide.texels();
    let mut us: Vec<f32> = vec![0.0, crate::contract::ONE_MINUS_EPSILON];
    for bin in 0..GUIDE_BIN_COUNT {
        let c = crate::cpu::guiding::get_guide_cumulative(texels, 0, bin);
        us.extend(
            [c, c.next_down(), c.next_up()]
                .into_iter()
                .filter(|u| (0.0..1.0).contains(u)),
        );
    }
    let mut rng = InputRng::new(8);
    us.extend((0..20_000).map(|_| rng.uniform()));
    for u in us {
        let sample = sample_guide_direction(texels, 0, Vec2::new(u, 0.5));
        let (bin, probability) = first_bin_above(texels, 0, u);
        assert_eq!(sample.bin, bin, "u = {u}");
        assert_eq!(
            sample.bin_probability.to_bits(),
            probability.to_bits(),
            "u = {u}"
        );
    }
}

#[test]
fn sample_guide_direction_follows_get_guide_density() {
    let guide = lobe_splats(Vec3::new(0.3, -0.5, 0.81).normalize(), 20_000, 3).build();
    let texels = guide.texels();
    let mut rng = InputRng::new(4);
    let samples: Vec<Vec3> = (0..1_000_000)
        .map(|_| {
            sample_guide_direction(texels, 0, Vec2::new(rng.uniform(), rng.uniform())).direction
        })
        .collect();
    let density = |direction: Vec3| f64::from(get_guide_density(texels, 0, direction));
    assert_follows_density("guide alone", samples, &density);
}

#[test]
fn the_mixture_with_a_bsdf_follows_its_density() {
    // A cosine lobe around a tilted normal mixed one-sample with the trained cell, as a
    // guided vertex samples: the BSDF with probability GUIDE_BSDF_FRACTION, else the guide.
    let guide = lobe_splats(Vec3::new(-0.6, 0.0, 0.8), 20_000, 5).build();
    let texels = guide.texels();
    let normal = Vec3::new(0.2, 0.3, 0.93).normalize();
    let mut rng = InputRng::new(6);
    let samples: Vec<Vec3> = (0..1_000_000)
        .map(|_| {
            let choice = rng.uniform();
            let random_numbers = Vec2::new(rng.uniform(), rng.uniform());
            if choice < crate::contract::GUIDE_BSDF_FRACTION {
                sample_hemisphere_cosine(random_numbers, normal)
            } else {
                sample_guide_direction(texels, 0, random_numbers).direction
            }
        })
        .collect();
    let density = |direction: Vec3| {
        f64::from(get_guided_mixture_density(
            get_hemisphere_cosine_density(normal, direction),
            get_guide_density(texels, 0, direction),
        ))
    };
    assert_follows_density("guide mixed with a cosine lobe", samples, &density);
}

#[test]
fn splats_sum_to_the_same_guide_in_any_order_and_split() {
    let mut rng = InputRng::new(7);
    let splats: Vec<(Vec3, Vec3, f32)> = (0..5_000)
        .map(|_| {
            let position = rng.in_box(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0));
            (position, rng.unit_vector(), rng.range(0.0, 50.0))
        })
        .collect();
    let mut forward = GuideSplats::new(two_cells());
    for &(p, d, v) in &splats {
        forward.splat(p, Vec3::X, d, v);
    }
    // Backwards, in two halves merged in the other order.
    let (mut first, mut second) = (GuideSplats::new(two_cells()), GuideSplats::new(two_cells()));
    for (index, &(p, d, v)) in splats.iter().enumerate().rev() {
        if index % 2 == 0 {
            &mut first
        } else {
            &mut second
        }
        .splat(p, Vec3::X, d, v);
    }
    second.merge(&first);
    assert_eq!(forward, second);
    assert_eq!(forward.build().words(), second.build().words());
    assert_eq!(forward.build().guided_cell_count(), 2);
}

#[test]
fn sparse_cells_stay_unguided_and_bad_values_do_not_count() {
    let mut splats = GuideSplats::new(two_cells());
    let inside = Vec3::new(1.5, 0.5, 0.5);
    for _ in 0..GUIDE_MIN_SPLATS - 1 {
        assert!(splats.splat(inside, Vec3::X, Vec3::Z, 1.0));
    }
    assert!(!splats.splat(inside, Vec3::X, Vec3::Z, f32::NAN));
    assert!(!splats.splat(inside, Vec3::X, Vec3::Z, -1.0));
    assert!(!splats.splat(inside, Vec3::X, Vec3::Z, f32::INFINITY));
    assert!(!splats.splat(Vec3::splat(9.0), Vec3::X, Vec3::Z, 1.0));
    assert_eq!(splats.splat_count(1), GUIDE_MIN_SPLATS - 1);
    let guide = splats.build();
    assert_eq!(guide.guided_cell_count(), 0);
    assert!(!is_guided_cell(guide.texels(), 1));
    // One more splat makes the cell guided, with the uniform floor in every bin and the
    // splatted bin holding the rest.
    splats.splat(inside, Vec3::X, Vec3::Z, 1.0);
    let guide = splats.build();
    assert!(is_guided_cell(guide.texels(), 1));
    let floor = GUIDE_UNIFORM_FRACTION / GUIDE_BIN_COUNT as f32;
    let peak = get_guide_bin_probability(guide.texels(), 1, get_guide_bin_index(Vec3::Z));
    assert!(
        (peak - (1.0 - GUIDE_UNIFORM_FRACTION + floor)).abs() < 1e-5,
        "{peak}"
    );
    let other = get_guide_bin_probability(guide.texels(), 1, get_guide_bin_index(-Vec3::Z));
    assert!((other - floor).abs() < 1e-6, "{other}");
    // 3 header texels, 64 per cell (2 positions x 6 orientations), and a table of 12 slots.
    assert_eq!(guide.memory_bytes(), 16 * (3 + 12 * 64 + 3));
}

#[test]
fn splat_units_are_the_floor_of_the_scaled_value_split_into_words() {
    use crate::cpu::guiding::get_guide_splat_units;
    // 2^20 units per unit of value, floored; exact across the 2^32 boundary of the words.
    assert_eq!(get_guide_splat_units(0.0), (0, 0));
    assert_eq!(get_guide_splat_units(1.0), (1 << 20, 0));
    assert_eq!(get_guide_splat_units(1.5e-6), (1, 0));
    assert_eq!(get_guide_splat_units(9e-7), (0, 0));
    assert_eq!(get_guide_splat_units(4096.0), (0, 1));
    assert_eq!(get_guide_splat_units(6144.0), (1 << 31, 1));
    // Clamped at 2^40 units (a value of 2^20), however large.
    assert_eq!(get_guide_splat_units(1e30), (0, 256));
    assert_eq!(get_guide_splat_units(f32::INFINITY), (0, 256));
    let mut rng = InputRng::new(12);
    for _ in 0..10_000 {
        let value = 10f32.powf(rng.range(-6.0, 6.0));
        let (low, high) = get_guide_splat_units(value);
        let units = u64::from(low) | (u64::from(high) << 32);
        let exact = (f64::from(value) * 1_048_576.0).floor() as u64;
        assert_eq!(units, exact, "{value}");
    }
}

#[test]
fn device_words_read_back_as_the_same_splats() {
    // The training buffer's layout (BINDING_GUIDE_SPLATS): a 64-bit sum per cell and bin as
    // (low, high) words, then a count per cell.
    let splats = lobe_splats(Vec3::Y, 5_000, 13);
    let grid = splats.grid().clone();
    let bins = GUIDE_BIN_COUNT as usize;
    let mut words = vec![0u32; grid.splat_word_count()];
    for cell in 0..grid.cell_count() as usize {
        for bin in 0..bins {
            let sum = splats.sums[cell * bins + bin];
            words[2 * (cell * bins + bin)] = sum as u32;
            words[2 * (cell * bins + bin) + 1] = (sum >> 32) as u32;
        }
        words[2 * grid.cell_count() as usize * bins + cell] = splats.counts[cell];
    }
    assert_eq!(
        GuideSplats::from_device_words(&grid, &words).unwrap(),
        splats
    );
    assert!(GuideSplats::from_device_words(&grid, &words[1..]).is_err());
}

#[test]
fn pooling_adds_each_cells_face_neighbours() {
    // A 3 x 3 x 1 grid with one splat of value 1 in each cell facing +z (cells 36 to 44): a
    // corner cell pools 3 cells, an edge cell 4, the centre 5, and the sums pool alike;
    // cells of other orientations pool nothing from them.
    let grid = GuideGrid::around(Vec3::ZERO, Vec3::new(3.0, 3.0, 0.1), 3);
    assert_eq!(grid.resolution, UVec3::new(3, 3, 1));
    let mut splats = GuideSplats::new(grid);
    let first = 4 * 9;
    for y in 0..3 {
        for x in 0..3 {
            let position = Vec3::new(x as f32 + 0.5, y as f32 + 0.5, 0.05);
            assert!(splats.splat(position, Vec3::Z, Vec3::Z, 1.0));
        }
    }
    let pooled = splats.pooled_with_neighbours();
    let counts: Vec<u32> = (0..9)
        .map(|cell| pooled.splat_count(first + cell))
        .collect();
    assert_eq!(counts, [3, 4, 3, 4, 5, 4, 3, 4, 3]);
    let bin = get_guide_bin_index(Vec3::Z) as usize;
    let bins = GUIDE_BIN_COUNT as usize;
    for (cell, &count) in counts.iter().enumerate() {
        assert_eq!(
            pooled.sums[(first as usize + cell) * bins + bin],
            u64::from(count) << 20
        );
    }
    assert!((0..first)
        .chain(first + 9..54)
        .all(|cell| pooled.splat_count(cell) == 0));
}

#[test]
fn pooling_skips_no_splat_that_counts() {
    // pooled_with_neighbours() skips the bins of cells whose sums are all zero; against the
    // plain sum over every cell and its face neighbours, on a 4 x 4 x 4 grid with splats in
    // a few scattered cells, some of value 0 (they count, and add nothing).
    let grid = GuideGrid::around(Vec3::ZERO, Vec3::splat(4.0), 4);
    let mut splats = GuideSplats::new(grid.clone());
    let mut rng = InputRng::new(17);
    for k in 0..400 {
        let position = Vec3::new(
            rng.range(0.0, 4.0),
            rng.range(0.0, 4.0),
            rng.range(0.0, 1.5),
        );
        let normal = [Vec3::X, Vec3::NEG_Y, Vec3::Z][k % 3];
        let value = if k % 4 == 0 { 0.0 } else { rng.range(0.0, 5.0) };
        assert!(splats.splat(position, normal, rng.unit_vector(), value));
    }
    let bins = GUIDE_BIN_COUNT as usize;
    let mut expected = GuideSplats::new(grid.clone());
    for (slot, &cell) in grid.cell_table.iter().enumerate() {
        if cell == GUIDE_NO_CELL {
            continue;
        }
        let (orientation, position) = grid.slot_position(slot);
        for (dx, dy, dz) in FACE_NEIGHBOURHOOD {
            let neighbour = position.as_ivec3() + glam::IVec3::new(dx, dy, dz);
            if neighbour.cmplt(glam::IVec3::ZERO).any()
                || neighbour.cmpge(grid.resolution.as_ivec3()).any()
            {
                continue;
            }
            let other = grid.cell_table[grid.table_slot(orientation, neighbour.as_uvec3())];
            if other == GUIDE_NO_CELL {
                continue;
            }
            let (cell, other) = (cell as usize, other as usize);
            for bin in 0..bins {
                expected.sums[cell * bins + bin] += splats.sums[other * bins + bin];
            }
            expected.counts[cell] += splats.counts[other];
        }
    }
    let pooled = splats.pooled_with_neighbours();
    assert_eq!(pooled, expected);
    // Some cell has splats but no sums: the case the skip must get right.
    assert!((0..grid.cell_count() as usize).any(|c| splats.counts[c] > 0
        && splats.sums[c * bins..(c + 1) * bins]
            .iter()
            .all(|&s| s == 0)));
    assert_eq!(pooled.build(), expected.build());
}

#[test]
fn a_guide_survives_its_sparse_words_and_broken_words_are_refused() {
    let guide = lobe_splats(Vec3::Z, 20_000, 3).build();
    assert_eq!(guide.guided_cell_count(), 1);
    let sparse = guide.sparse_words();
    // The header, the cell table (12 slots), then one cell: its index and its bins.
    let header = 4 * GUIDE_HEADER_TEXEL_COUNT as usize;
    let table = 12;
    assert_eq!(sparse.len(), header + table + 1 + GUIDE_BIN_COUNT as usize);
    assert_eq!(Guide::from_sparse_words(&sparse).unwrap(), guide);
    assert_eq!(Guide::from_words(guide.words().to_vec()).unwrap(), guide);
    // An empty guide has no cells to store.
    let empty = GuideSplats::new(two_cells()).build();
    assert_eq!(
        Guide::from_sparse_words(&empty.sparse_words()).unwrap(),
        empty
    );
    let refused = |words: Vec<u32>| Guide::from_sparse_words(&words).unwrap_err().to_string();
    // Cut short, a cell out of range, a falling cumulative, a last bin below 1, a header
    // whose resolution does not give its cell count, a table that skips a cell.
    assert!(refused(sparse[..sparse.len() - 1].to_vec()).contains("whole cells"));
    let mut out_of_range = sparse.clone();
    out_of_range[header + table] = 12;
    assert!(refused(out_of_range).contains("out of order or range"));
    let mut falling = sparse.clone();
    falling[header + table + 10] = 0.99f32.to_bits();
    assert!(refused(falling).contains("no cumulative distribution"));
    let mut short_of_one = sparse.clone();
    *short_of_one.last_mut().unwrap() = 0.5f32.to_bits();
    assert!(refused(short_of_one).contains("no cumulative distribution"));
    let mut resolution = sparse.clone();
    resolution[0] = 3;
    assert!(refused(resolution).contains("not a guide"));
    let mut no_cells = sparse.clone();
    no_cells[0] = 0;
    let grid = format!("not a guide: a 0x{}x{} grid", sparse[1], sparse[2]);
    assert!(refused(no_cells).ends_with(&grid));
    let mut skipping = sparse.clone();
    skipping[header + 1] = 2;
    assert!(refused(skipping).contains("does not number its cells in order"));
}
