//! Path guiding's guide (`glsl/guiding.glsl`) on the GPU (`glsl/probe_guiding.comp`)
//! against its Rust twins (`vkpath::cpu::guiding`) on the same words: the same cell for
//! every point (inside, on faces, outside the grid), the same bin and density for every
//! direction up to the GPU's arctangent at bin edges, the same sampled direction up to its
//! sine and cosine. The test asserts that the validation layer stayed silent.

use crate::common;

use glam::{Vec2, Vec3};
use vkpath::cpu::guiding::{
    get_guide_bin_index, get_guide_cell_index, get_guide_density, is_guided_cell,
    sample_guide_direction, GuideTexels,
};
use vkpath::guiding::{GuideGrid, GuideSplats};
use vkpath::probe::guiding_probe::{GuidingProbeInput, GuidingProbeRunner};
use vkpath::probe::inputs::InputRng;

/// A guide on a 4 x 2 x 3 grid over [0, 4] x [0, 2] x [0, 3] whose cells (each position's
/// six orientations) learned lobes around directions of their own; cells with x >= 3 got too
/// few splats and stay unguided.
fn trained_guide(rng: &mut InputRng) -> vkpath::guiding::Guide {
    let grid = GuideGrid::around(Vec3::ZERO, Vec3::new(4.0, 2.0, 3.0), 4);
    assert_eq!(grid.resolution.to_array(), [4, 2, 3]);
    let mut splats = GuideSplats::new(grid);
    for _ in 0..60_000 {
        let position = rng.in_box(Vec3::ZERO, Vec3::new(3.0, 2.0, 3.0));
        let axis = (position - Vec3::new(1.5, 3.0, -1.0)).normalize();
        let direction = rng.unit_vector();
        splats.splat(
            position,
            rng.unit_vector(),
            direction,
            axis.dot(direction).max(0.0).powi(6) * 10.0,
        );
    }
    for _ in 0..20 {
        splats.splat(
            rng.in_box(Vec3::new(3.0, 0.0, 0.0), Vec3::new(4.0, 2.0, 3.0)),
            rng.unit_vector(),
            rng.unit_vector(),
            1.0,
        );
    }
    splats.build()
}

#[test]
fn gpu_and_cpu_find_the_same_cells_bins_densities_and_samples() {
    let mut rng = InputRng::new(2202);
    let guide = trained_guide(&mut rng);
    assert_eq!(guide.guided_cell_count(), 6 * 18);
    let texels = GuideTexels {
        words: guide.words(),
    };
    let mut inputs = Vec::new();
    for index in 0..20_000 {
        let position = rng.in_box(Vec3::splat(-0.2), Vec3::new(4.2, 2.2, 3.2));
        // Every 10th direction lies on a bin edge of phi (the meridians at multiples of
        // 2 pi / 16, the seam at phi = pi) or at a pole.
        let direction = match index % 40 {
            0 => Vec3::Z,
            10 => -Vec3::Z,
            20 => -Vec3::X,
            30 => Vec3::new(0.6, 0.0, 0.8),
            _ => rng.unit_vector(),
        };
        // Every 7th normal is a tie of two axes (the first wins) or an axis.
        let normal = match index % 7 {
            0 => Vec3::new(-1.0, 1.0, 0.0).normalize(),
            1 => Vec3::new(0.0, 1.0, -1.0).normalize(),
            2 => -Vec3::Z,
            _ => rng.unit_vector(),
        };
        let random_numbers = match index % 50 {
            0 => Vec2::ZERO,
            25 => Vec2::splat(vkpath::contract::ONE_MINUS_EPSILON),
            _ => Vec2::new(rng.uniform(), rng.uniform()),
        };
        inputs.push(GuidingProbeInput::new(
            position,
            normal,
            direction,
            random_numbers,
        ));
    }
    let context = common::validated_context();
    let runner = GuidingProbeRunner::new(&context, guide.words()).expect("the probe runs");
    let outputs = runner.run(&inputs).expect("the probe runs");
    let (mut guided, mut outside, mut bin_mismatches) = (0usize, 0usize, 0usize);
    let (mut worst_density, mut worst_angle) = (0f32, 0f32);
    for (input, output) in inputs.iter().zip(&outputs) {
        let position = Vec3::from_slice(&input.position[..3]);
        let normal = Vec3::from_slice(&input.normal[..3]);
        let direction = Vec3::from_slice(&input.direction[..3]);
        let random_numbers = Vec2::from_slice(&input.random_numbers[..2]);
        let cell = get_guide_cell_index(texels, position, normal);
        // Cells: the same arithmetic (a subtraction, a product, floor; comparisons of the
        // normal's components), correctly rounded on every Vulkan device, so the same index.
        assert_eq!(output.cell_bin[0], cell, "cell of {position}");
        assert_eq!(
            output.cell_bin[1] == 1,
            is_guided_cell(texels, cell),
            "cell {cell}"
        );
        outside += usize::from(cell == u32::MAX);
        // Bins: GLSL's atan is not correctly rounded, so a direction within rounding of a
        // bin edge may fall in the neighbouring bin; count those (below).
        let bin = get_guide_bin_index(direction);
        if output.cell_bin[2] != bin {
            bin_mismatches += 1;
            let (gpu_row, gpu_column) = (output.cell_bin[2] / 16, output.cell_bin[2] % 16);
            let (row, column) = (bin / 16, bin % 16);
            let column_step = (gpu_column + 16 - column) % 16;
            assert!(
                gpu_row.abs_diff(row) <= 1 && (column_step <= 1 || column_step == 15),
                "direction {direction}: GPU bin {} against CPU bin {bin}",
                output.cell_bin[2]
            );
        }
        if !is_guided_cell(texels, cell) {
            assert_eq!(output.sampled_density, [0.0; 4]);
            continue;
        }
        guided += 1;
        if output.cell_bin[2] == bin {
            let density = get_guide_density(texels, cell, direction);
            worst_density =
                worst_density.max((output.sampled_density[3] - density).abs() / density);
        }
        let sample = sample_guide_direction(texels, cell, random_numbers);
        let (sampled, sampled_bin) = (sample.direction, sample.bin);
        assert_eq!(
            output.cell_bin[3], sampled_bin,
            "bin sampled with {random_numbers}"
        );
        let gpu_sampled = Vec3::from_slice(&output.sampled_density[..3]);
        assert!(
            (gpu_sampled.length() - 1.0).abs() < 1e-5,
            "GPU sample {gpu_sampled}"
        );
        worst_angle = worst_angle.max(gpu_sampled.cross(sampled).length().asin());
    }
    println!(
        "{guided} guided inputs, {outside} outside the grid; {bin_mismatches} bin mismatches; \
         worst density difference {worst_density:.2e} (relative), worst sample angle {worst_angle:.2e} rad"
    );
    assert!(
        guided > 8_000 && outside > 3_000,
        "the inputs cover both kinds"
    );
    // The densities of the same bin are the same two floats subtracted and scaled (exact
    // on every device); the directions differ by the GPU's division, sine and cosine (a few
    // ulps each, ~1e-6 rad), far below the 1e-4 allowed; a bin edge is met by chance only
    // within atan's error (~1e-6 rad of the 2 pi circumference), so 1 % is generous while
    // catching any systematic mapping difference.
    assert!(worst_density <= 1e-6, "densities differ by {worst_density}");
    assert!(
        worst_angle < 1e-4,
        "sampled directions differ by {worst_angle} rad"
    );
    assert!(
        bin_mismatches * 100 <= inputs.len(),
        "{bin_mismatches} bin mismatches"
    );
    common::assert_validation_silent(&context);
}

#[test]
fn gpu_samples_fall_in_the_bin_they_were_sampled_from() {
    // The density of a guided sample is that of the bin sample_guide_direction() chose; MIS
    // and the mixture evaluate it again through get_guide_bin_index() (an arctangent), so a
    // sample that the GPU's lookup puts in a neighbouring bin gets the wrong density. Feed
    // the GPU's samples back through the GPU's lookup and count how often that happens.
    let mut rng = InputRng::new(2203);
    let guide = trained_guide(&mut rng);
    let texels = GuideTexels {
        words: guide.words(),
    };
    let position = Vec3::new(1.5, 1.0, 1.5);
    let cell = get_guide_cell_index(texels, position, Vec3::Y);
    assert!(is_guided_cell(texels, cell));
    let random: Vec<Vec2> = (0..50_000)
        .map(|_| Vec2::new(rng.uniform(), rng.uniform()))
        .collect();
    let context = common::validated_context();
    let runner = GuidingProbeRunner::new(&context, guide.words()).expect("the probe runs");
    let first: Vec<GuidingProbeInput> = random
        .iter()
        .map(|&r| GuidingProbeInput::new(position, Vec3::Y, Vec3::Z, r))
        .collect();
    let sampled = runner.run(&first).expect("the probe runs");
    let again: Vec<GuidingProbeInput> = sampled
        .iter()
        .map(|s| {
            GuidingProbeInput::new(
                position,
                Vec3::Y,
                Vec3::from_slice(&s.sampled_density[..3]),
                Vec2::ZERO,
            )
        })
        .collect();
    let looked_up = runner.run(&again).expect("the probe runs");
    let mut mismatches = 0;
    for (r, output) in random.iter().zip(&looked_up) {
        let bin = sample_guide_direction(texels, cell, *r).bin;
        mismatches += usize::from(output.cell_bin[2] != bin);
    }
    println!(
        "{mismatches} of {} GPU samples looked up in another bin",
        random.len()
    );
    assert_eq!(mismatches, 0);
    common::assert_validation_silent(&context);
}
