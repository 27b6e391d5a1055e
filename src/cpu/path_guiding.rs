//! Rust twins of `glsl/path_guiding.glsl` on the workshop's diffuse triangles (the Lambert
//! model): path guiding in the path loop. Where the GLSL reads the current vertex's guided
//! cell from `g_path.guide_cell` and the guide from `g_guide_texels` (bound only with
//! `GUIDING_ON`), the twins take them as arguments: `None` for the guide is `GUIDING_OFF`.
//! The training records are the shader's private arrays (`GuideRecords`), and the splats go
//! to words of the device's layout with the same wrapping 32-bit atomics, so a CPU
//! iteration's words can be compared with the GPU's word for word.

use std::sync::atomic::{AtomicU32, Ordering};

use glam::{Vec2, Vec3};

use crate::contract::{GUIDE_BIN_COUNT, GUIDE_BSDF_FRACTION, GUIDE_TRAINING_VERTEX_COUNT};
use crate::cpu::brdf::get_luminance;
use crate::cpu::guiding::{
    get_guide_bin_index, get_guide_cell_index, get_guide_density, get_guide_splat_units,
    get_guided_mixture_density, is_guided_cell, sample_guide_direction, GuideTexels, GUIDE_NO_CELL,
};
use crate::cpu::scattering_vertex::{
    get_vertex_scattering, get_vertex_scattering_density, ScatteringVertex,
};
use crate::cpu::surface::{BsdfSample, Surface, BSDF_LOBE_DELTA, BSDF_LOBE_REFLECT};
use crate::cpu::texels::fetch_texel;
use crate::cpu::workshop::M_PI;

/// Twin of `get_path_guide_grid_cell`: the cell of a vertex that takes light samples, at
/// its position, facing its surface's geometric normal; `GUIDE_NO_CELL` without guiding,
/// where the guide has no cell or no light samples are taken.
pub fn get_path_guide_grid_cell(
    guide: Option<GuideTexels>,
    vertex: &ScatteringVertex,
    light_sampled: bool,
) -> u32 {
    match guide {
        Some(texels) if light_sampled => {
            get_guide_cell_index(texels, vertex.position, vertex.surface.geometric_normal)
        }
        _ => GUIDE_NO_CELL,
    }
}

/// Twin of `is_guided_surface` (Lambert: always; the glTF model's exceptions, smooth metals
/// and layered materials, have no Lambert counterpart).
pub fn is_guided_surface(_surface: &Surface) -> bool {
    true
}

/// Twin of `is_guided_vertex`: a surface vertex asks `is_guided_surface`.
pub fn is_guided_vertex(vertex: &ScatteringVertex) -> bool {
    is_guided_surface(&vertex.surface)
}

/// Twin of `get_path_guide_cell`: `grid_cell` where the guide learned it and the vertex is
/// guided, else `GUIDE_NO_CELL`.
pub fn get_path_guide_cell(
    guide: Option<GuideTexels>,
    grid_cell: u32,
    vertex: &ScatteringVertex,
) -> u32 {
    match guide {
        Some(texels) if is_guided_cell(texels, grid_cell) && is_guided_vertex(vertex) => grid_cell,
        _ => GUIDE_NO_CELL,
    }
}

/// Twin of `get_path_direction_density`: the density with which the path loop samples
/// `direction` at a vertex whose guided cell is `guide_cell`.
pub fn get_path_direction_density(
    guide: Option<GuideTexels>,
    guide_cell: u32,
    vertex: &ScatteringVertex,
    direction: Vec3,
) -> f32 {
    let bsdf_density = get_vertex_scattering_density(vertex, direction);
    match guide {
        Some(texels) if guide_cell != GUIDE_NO_CELL => get_guided_mixture_density(
            bsdf_density,
            get_guide_density(texels, guide_cell, direction),
        ),
        _ => bsdf_density,
    }
}

/// Twin of `get_guided_direction`: the one-sample mixture's direction at a guided vertex,
/// the BSDF's sample (`bsdf_sample`, drawn only when chosen) or the guide's, with the
/// balance heuristic's weight; a delta pick (`BSDF_LOBE_DELTA`) keeps its own weight over
/// `GUIDE_BSDF_FRACTION` and density 0.
pub fn get_guided_direction(
    texels: GuideTexels,
    vertex: &ScatteringVertex,
    guide_cell: u32,
    bsdf_sample: BsdfSample,
    bsdf_chosen: bool,
    guide_random_numbers: Vec2,
) -> BsdfSample {
    // A delta pick bypasses the mixture: its own f / p over the BSDF's turn.
    if bsdf_chosen && bsdf_sample.lobes & BSDF_LOBE_DELTA != 0 {
        return BsdfSample {
            weight: bsdf_sample.weight / GUIDE_BSDF_FRACTION,
            ..bsdf_sample
        };
    }
    let mut guided = bsdf_sample;
    let mut sampled = 0.0;
    if !bsdf_chosen {
        let sample = sample_guide_direction(texels, guide_cell, guide_random_numbers);
        guided.direction = sample.direction;
        guided.lobes = BSDF_LOBE_REFLECT;
        guided.eta = 1.0;
        sampled = sample.bin_probability * (GUIDE_BIN_COUNT as f32 / (4.0 * M_PI));
    }
    let looked_up = get_guide_density(texels, guide_cell, guided.direction);
    if bsdf_chosen {
        guided.density = get_guided_mixture_density(bsdf_sample.density, looked_up);
        guided.weight = if guided.density > 0.0 {
            bsdf_sample.weight * (bsdf_sample.density / guided.density)
        } else {
            Vec3::ZERO
        };
        return guided;
    }
    guided.density = get_guided_mixture_density(
        get_vertex_scattering_density(vertex, guided.direction),
        looked_up,
    );
    guided.weight = if guided.density > 0.0 {
        get_vertex_scattering(vertex, guided.direction) * (looked_up / (sampled * guided.density))
    } else {
        Vec3::ZERO
    };
    guided
}

/// Twin of the shader's training records (`g_guide_record_*`): the vertices a training path
/// recorded, at most `GUIDE_TRAINING_VERTEX_COUNT`.
#[derive(Clone, Debug, Default)]
pub struct GuideRecords {
    /// (grid cell, directional bin, radiance so far, |cos theta| / (throughput times
    /// density)).
    records: Vec<(u32, u32, Vec3, Vec3)>,
}

impl GuideRecords {
    /// Twin of `record_guide_vertex` in a training frame (theta measured from the vertex's
    /// shading normal).
    pub fn record_guide_vertex(
        &mut self,
        grid_cell: u32,
        vertex: &ScatteringVertex,
        direction: Vec3,
        density: f32,
        throughput_weight: Vec3,
        radiance: Vec3,
    ) {
        if grid_cell == GUIDE_NO_CELL
            || self.records.len() >= GUIDE_TRAINING_VERTEX_COUNT as usize
            || !(density > 0.0)
        {
            return;
        }
        let cosine = vertex.surface.shading_normal.dot(direction).abs();
        let scale = throughput_weight.to_array().map(|throughput| {
            if throughput > 0.0 {
                cosine / (throughput * density)
            } else {
                0.0
            }
        });
        self.records.push((
            grid_cell,
            get_guide_bin_index(direction),
            radiance,
            Vec3::from_array(scale),
        ));
    }

    /// Twin of `splat_guide_records`: each record's estimate of the radiance that arrived
    /// along its direction, as luminance times |cos theta| over the direction's density,
    /// into `words`.
    pub fn splat_guide_records(
        &mut self,
        texels: GuideTexels,
        words: &[AtomicU32],
        radiance: Vec3,
    ) {
        for &(cell, bin, recorded, scale) in &self.records {
            let incident = (radiance - recorded) * scale;
            add_guide_splat(texels, words, cell, bin, get_luminance(incident));
        }
        self.records.clear();
    }
}

/// Twin of `add_guide_splat`: adds one splat of `value` (>= 0 and finite, else nothing) to
/// the bin's 64-bit sum in `words` (the device's layout, `GuideGrid::splat_word_count`
/// words), with the carry of its low word, and counts it for the cell.
pub fn add_guide_splat(texels: GuideTexels, words: &[AtomicU32], cell: u32, bin: u32, value: f32) {
    if !(value >= 0.0) || value.is_infinite() {
        return;
    }
    let (low, mut high) = get_guide_splat_units(value);
    let slot = 2 * (cell * GUIDE_BIN_COUNT + bin) as usize;
    if low != 0 {
        let before = words[slot].fetch_add(low, Ordering::Relaxed);
        high += u32::from(before.wrapping_add(low) < before);
    }
    if high != 0 {
        words[slot + 1].fetch_add(high, Ordering::Relaxed);
    }
    let cell_count = fetch_texel(texels.words, 0).w;
    words[(2 * cell_count * GUIDE_BIN_COUNT + cell) as usize].fetch_add(1, Ordering::Relaxed);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contract::GUIDE_BSDF_FRACTION;
    use crate::cpu::scattering_vertex::get_surface_vertex;
    use crate::guiding::{GuideGrid, GuideSplats};

    /// A guide on a 2 x 1 x 1 grid whose cell 0 (facing +x) learned a lobe around +z and the
    /// others nothing.
    fn lobe_guide() -> crate::guiding::Guide {
        let grid = GuideGrid::around(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0), 2);
        let mut splats = GuideSplats::new(grid);
        let mut rng = crate::probe::inputs::InputRng::new(5);
        for _ in 0..20_000 {
            let direction = rng.unit_vector();
            splats.splat(
                Vec3::new(0.5, 0.5, 0.5),
                Vec3::X,
                direction,
                direction.z.max(0.0).powi(4),
            );
        }
        splats.build()
    }

    fn floor_surface() -> Surface {
        Surface {
            geometric_normal: Vec3::Z,
            shading_normal: Vec3::Z,
            base_color: Vec3::splat(0.5),
            emission: Vec3::ZERO,
        }
    }

    /// A vertex of `floor_surface` at `position`, its geometric normal `normal`.
    fn floor_vertex(position: Vec3, normal: Vec3) -> ScatteringVertex {
        let surface = Surface {
            geometric_normal: normal,
            ..floor_surface()
        };
        get_surface_vertex(surface, position, Vec3::Z)
    }

    #[test]
    fn guide_cells_follow_the_guide_and_the_light_samples() {
        let guide = lobe_guide();
        let texels = guide.texels();
        let inside = Vec3::new(0.5, 0.5, 0.5);
        let facing_x = floor_vertex(inside, Vec3::X);
        let surface = floor_vertex(inside, Vec3::Z);
        assert_eq!(
            get_path_guide_grid_cell(None, &facing_x, true),
            GUIDE_NO_CELL
        );
        assert_eq!(
            get_path_guide_grid_cell(Some(texels), &facing_x, false),
            GUIDE_NO_CELL
        );
        assert_eq!(get_path_guide_grid_cell(Some(texels), &facing_x, true), 0);
        // Facing +z, the same point is in another cell, which learned nothing.
        let facing_up = get_path_guide_grid_cell(Some(texels), &surface, true);
        assert_eq!(facing_up, 8);
        assert_eq!(
            get_path_guide_cell(Some(texels), facing_up, &surface),
            GUIDE_NO_CELL
        );
        assert_eq!(get_path_guide_cell(Some(texels), 0, &surface), 0);
        // Cell 1 learned nothing: the BSDF samples alone there.
        assert_eq!(
            get_path_guide_cell(Some(texels), 1, &surface),
            GUIDE_NO_CELL
        );
        assert_eq!(get_path_guide_cell(None, 0, &surface), GUIDE_NO_CELL);
    }

    #[test]
    fn a_delta_pick_bypasses_the_guide_mixture() {
        // The guide never proposes a delta lobe's peak: a BSDF sample of one keeps its
        // direction, lobes and density 0 (the path loop then counts what it finds in full),
        // and its weight f / p is divided by the BSDF's turn, GUIDE_BSDF_FRACTION. Had it
        // gone through the mixture, its weight would be 0 (f / p scaled by 0 / p~).
        let guide = lobe_guide();
        let view = Vec3::new(0.3, 0.0, 1.0).normalize();
        let delta = BsdfSample {
            direction: Vec3::new(-view.x, -view.y, view.z),
            density: 0.0,
            weight: Vec3::new(0.6, 0.5, 0.4),
            lobes: BSDF_LOBE_REFLECT | BSDF_LOBE_DELTA,
            eta: 1.0,
        };
        let guided = get_guided_direction(
            guide.texels(),
            &get_surface_vertex(floor_surface(), Vec3::ZERO, view),
            0,
            delta,
            true,
            Vec2::ZERO,
        );
        assert_eq!(
            (guided.direction, guided.density, guided.lobes, guided.eta),
            (delta.direction, 0.0, delta.lobes, 1.0)
        );
        assert_eq!(guided.weight, delta.weight / GUIDE_BSDF_FRACTION);
    }

    #[test]
    fn guided_directions_have_the_mixture_density_and_an_unbiased_weight() {
        let guide = lobe_guide();
        let texels = guide.texels();
        let surface = floor_surface();
        let view = Vec3::new(0.3, 0.0, 1.0).normalize();
        let vertex = get_surface_vertex(surface, Vec3::ZERO, view);
        let mut rng = crate::probe::inputs::InputRng::new(9);
        // E[weight] over the mixture = the integral of f cos = the albedo, for each channel
        // (Lambert: base_color); with 2^18 samples its standard error is below 0.3 %.
        let count = 1 << 18;
        let mut sum = Vec3::ZERO;
        for _ in 0..count {
            let chosen = rng.uniform() < GUIDE_BSDF_FRACTION;
            let bsdf_sample = crate::cpu::surface::sample_bsdf(
                &surface,
                view,
                Vec2::new(rng.uniform(), rng.uniform()),
                0.0,
            );
            let sample = get_guided_direction(
                texels,
                &vertex,
                0,
                bsdf_sample,
                chosen,
                Vec2::new(rng.uniform(), rng.uniform()),
            );
            let density = get_path_direction_density(Some(texels), 0, &vertex, sample.direction);
            // The density is the one MIS weighs against, wherever the sample came from.
            assert!((sample.density - density).abs() <= 1e-6 * density.max(1.0));
            sum += sample.weight;
        }
        let mean = sum / count as f32;
        for channel in mean.to_array() {
            assert!((channel - 0.5).abs() < 0.5 * 0.01, "mean weight {mean}");
        }
    }

    #[test]
    fn splats_add_with_carry_and_count_per_cell() {
        let guide = lobe_guide();
        let texels = guide.texels();
        let grid = guide.grid();
        let words: Vec<AtomicU32> = (0..grid.splat_word_count())
            .map(|_| AtomicU32::new(0))
            .collect();
        // Three splats just below 2^32 units each carry into the high word.
        let value = 4095.0 / crate::contract::GUIDE_FIXED_POINT_SCALE * 1_048_576.0;
        for _ in 0..3 {
            add_guide_splat(texels, &words, 1, 7, value);
        }
        add_guide_splat(texels, &words, 1, 7, f32::NAN);
        add_guide_splat(texels, &words, 1, 7, -1.0);
        let (low, high) = get_guide_splat_units(value);
        let total = 3 * (u64::from(high) << 32 | u64::from(low));
        let slot = 2 * (GUIDE_BIN_COUNT + 7) as usize;
        let sum = u64::from(words[slot + 1].load(Ordering::Relaxed)) << 32
            | u64::from(words[slot].load(Ordering::Relaxed));
        assert_eq!(sum, total);
        let counts = 2 * grid.cell_count() as usize * GUIDE_BIN_COUNT as usize;
        assert_eq!(words[counts + 1].load(Ordering::Relaxed), 3);
        assert_eq!(words[counts].load(Ordering::Relaxed), 0);
    }
}
