//! Rust twin of `glsl/path_loop.glsl` on the workshop's diffuse triangles (the Lambert
//! model): the one path loop of the importance-sampled integrators (cosine, nee, mis), its
//! named steps over the surface seam (`crate::cpu::surface`), the scattering vertex
//! (`crate::cpu::scattering_vertex`) and the lights room (`crate::cpu::lights`). Same names, same maths, the same random numbers at the same
//! dimension pairs (`crate::cpu::sample_dimensions`; the workshop's PCG2D from `seed` for the
//! uniform directions of Exercises 6 and 7).

use std::sync::atomic::AtomicU32;

use glam::{UVec2, Vec2, Vec3};

use crate::contract::GUIDE_BSDF_FRACTION;
use crate::cpu::guiding::{GuideTexels, GUIDE_NO_CELL};

use crate::cpu::importance_sampling::get_power_heuristic_weight;
use crate::cpu::integrator::ray_mesh_intersection;
use crate::cpu::integrators::{
    is_direct_illumination, is_importance_sampled, samples_cosine_directions,
    samples_uniform_directions, takes_light_samples, weighs_by_mis,
};
use crate::cpu::lights::{get_emissive_triangle_density, sample_direct_light, LightScene};
use crate::cpu::path_guiding::{
    get_guided_direction, get_path_guide_cell, get_path_guide_grid_cell, GuideRecords,
};
use crate::cpu::sample_dimensions::{
    get_vertex_dimension_pair, VERTEX_PAIR_DIRECTION, VERTEX_PAIR_GUIDE_CHOICE,
    VERTEX_PAIR_GUIDE_DIRECTION, VERTEX_PAIR_LOBE, VERTEX_PAIR_RUSSIAN_ROULETTE,
};
use crate::cpu::scattering_vertex::{
    get_surface_vertex, get_vertex_departure_origin, ScatteringVertex,
};
use crate::cpu::sobol::{get_path_random_numbers, PathSample};
use crate::cpu::surface::{
    get_camera_emission, get_surface, get_volume_transmittance, has_delta_lobe, has_layers,
    is_transmissive, sample_bsdf, sample_cosine_direction, sample_uniform_direction, BsdfSample,
    Surface, BSDF_LOBE_DELTA,
};
use crate::cpu::workshop::get_random_numbers;

/// Where a path found emission: what `get_found_emission` reads besides the throughput.
#[derive(Clone, Copy, Debug)]
pub struct FoundEmission<'a> {
    /// Index of the hit on the path (0: the camera ray's).
    pub vertex: u32,
    /// The surface hit.
    pub surface: &'a Surface,
    /// The hit triangle.
    pub triangle_index: usize,
    /// Origin of the ray that found it.
    pub previous_position: Vec3,
    /// Direction of that ray.
    pub ray_direction: Vec3,
    /// Its ray parameter at the hit.
    pub t: f32,
    /// Density of the direction sample that found it.
    pub direction_density: f32,
    /// Whether the previous vertex took light samples that could find this emission (not
    /// after a delta pick).
    pub light_sampled: bool,
    /// Where that vertex took its light sample, and the light tree's normal there.
    pub light_origin: Vec3,
    /// The light tree's normal at `light_origin`.
    pub light_normal: Vec3,
}

/// Twin of `get_found_emission`: throughput times the emission found, weighted as the
/// integrator says.
pub fn get_found_emission(
    scene: &LightScene,
    throughput_weight: Vec3,
    found: &FoundEmission,
) -> Vec3 {
    let emission = found.surface.emission;
    if found.vertex == 0 {
        return throughput_weight * get_camera_emission(found.surface);
    }
    if !found.light_sampled {
        return throughput_weight * emission;
    }
    if weighs_by_mis(scene.integrator) && emission != Vec3::ZERO {
        let light_density = get_emissive_triangle_density(
            scene,
            found.triangle_index,
            found.previous_position,
            found.ray_direction,
            found.t,
            found.light_origin,
            found.light_normal,
        );
        return throughput_weight
            * emission
            * get_power_heuristic_weight(found.direction_density, light_density);
    }
    Vec3::ZERO
}

/// Twin of `get_direction_random_numbers`: the numbers at `dimension_pair` of `sample` for
/// the importance-sampled integrators, the workshop's next PCG2D pair from `seed` otherwise.
pub fn get_direction_random_numbers(
    integrator: u32,
    sample: &PathSample,
    dimension_pair: u32,
    seed: &mut UVec2,
) -> Vec2 {
    if is_importance_sampled(integrator) {
        get_path_random_numbers(sample, dimension_pair)
    } else {
        get_random_numbers(seed)
    }
}

/// Twin of `sample_path_direction`, at `vertex`, whose first dimension pair is
/// `vertex_pairs` (`get_vertex_dimension_pair`).
pub fn sample_path_direction(
    integrator: u32,
    vertex: &ScatteringVertex,
    sample: &PathSample,
    vertex_pairs: u32,
    seed: &mut UVec2,
) -> BsdfSample {
    let surface = &vertex.surface;
    let view = vertex.view;
    let transmissive = is_transmissive(surface) || has_delta_lobe(surface);
    if samples_uniform_directions(integrator) && !transmissive {
        return sample_uniform_direction(surface, view, get_random_numbers(seed));
    }
    let random_numbers = get_direction_random_numbers(
        integrator,
        sample,
        vertex_pairs + VERTEX_PAIR_DIRECTION,
        seed,
    );
    if samples_cosine_directions(integrator) && !transmissive {
        return sample_cosine_direction(surface, view, random_numbers);
    }
    let lobe_random = if has_layers(surface) {
        get_direction_random_numbers(integrator, sample, vertex_pairs + VERTEX_PAIR_LOBE, seed)[0]
    } else {
        0.0
    };
    sample_bsdf(surface, view, random_numbers, lobe_random)
}

/// Twin of `sample_guided_path_direction`: at a vertex that path guiding guides (cell
/// `guide_cell` of `guide`), one number chooses between `sample_path_direction` and the
/// guide; elsewhere (no guide, or `GUIDE_NO_CELL`) `sample_path_direction` alone.
pub fn sample_guided_path_direction(
    integrator: u32,
    guide: Option<GuideTexels>,
    vertex: &ScatteringVertex,
    guide_cell: u32,
    sample: &PathSample,
    vertex_pairs: u32,
    seed: &mut UVec2,
) -> BsdfSample {
    let texels = match guide {
        Some(texels) if guide_cell != GUIDE_NO_CELL => texels,
        _ => return sample_path_direction(integrator, vertex, sample, vertex_pairs, seed),
    };
    let bsdf_chosen = get_path_random_numbers(sample, vertex_pairs + VERTEX_PAIR_GUIDE_CHOICE)[0]
        < GUIDE_BSDF_FRACTION;
    // The shader leaves its bsdf_sample unset where the guide samples: every member that
    // get_guided_direction() returns is then overwritten.
    let mut bsdf_sample = BsdfSample {
        direction: Vec3::ZERO,
        density: 0.0,
        weight: Vec3::ZERO,
        lobes: 0,
        eta: 1.0,
    };
    let mut guide_random_numbers = Vec2::ZERO;
    if bsdf_chosen {
        bsdf_sample = sample_path_direction(integrator, vertex, sample, vertex_pairs, seed);
    } else {
        guide_random_numbers =
            get_path_random_numbers(sample, vertex_pairs + VERTEX_PAIR_GUIDE_DIRECTION);
    }
    get_guided_direction(
        texels,
        vertex,
        guide_cell,
        bsdf_sample,
        bsdf_chosen,
        guide_random_numbers,
    )
}

/// Twin of `get_path_radiance`; `max_path_length` and `russian_roulette_start` are the
/// kernel's `MAX_PATH_LENGTH` and `RUSSIAN_ROULETTE_START`. A training frame of a guided
/// render (`is_guide_training()`) passes the words its splats go to as `guide_splats`
/// (`scene.guide` must then be set). `sample` names the numbers of the importance-sampled
/// integrators, `seed` the workshop's PCG2D state of Exercises 6 and 7.
#[allow(clippy::too_many_arguments)]
pub fn get_path_radiance(
    scene: &LightScene,
    mut ray_origin: Vec3,
    mut ray_direction: Vec3,
    sample: &PathSample,
    seed: &mut UVec2,
    max_path_length: u32,
    russian_roulette_start: u32,
    guide_splats: Option<&[AtomicU32]>,
) -> Vec3 {
    let mut guide_records = GuideRecords::default();
    let mut radiance = Vec3::ZERO;
    let mut throughput_weight = Vec3::ONE;
    let mut direction_density = 0.0f32;
    let mut light_sampled = false;
    let mut eta_scale = 1.0f32;
    let mut previous_position = ray_origin;
    let mut light_origin = Vec3::ZERO;
    let mut light_normal = Vec3::ZERO;
    let vertex_count = if is_direct_illumination(scene.integrator) {
        2
    } else {
        max_path_length
    };
    for i in 0..vertex_count {
        let Some(hit) = ray_mesh_intersection(scene.scene_triangles, ray_origin, ray_direction)
        else {
            break;
        };
        ray_origin += hit.t * ray_direction;
        let surface = get_surface(scene.scene_triangles, hit.triangle_index, ray_direction);
        let vertex = get_surface_vertex(surface, ray_origin, -ray_direction);
        throughput_weight *= get_volume_transmittance(&surface, hit.t);
        // 1. The emission found
        radiance += get_found_emission(
            scene,
            throughput_weight,
            &FoundEmission {
                vertex: i,
                surface: &surface,
                triangle_index: hit.triangle_index,
                previous_position,
                ray_direction,
                t: hit.t,
                direction_density,
                light_sampled,
                light_origin,
                light_normal,
            },
        );
        if i + 1 == vertex_count {
            break;
        }
        // 2. Light samples (none at glass), weighed by MIS against the direction sampling of
        // step 3, guided where the guide knows the vertex's cell
        light_sampled = takes_light_samples(scene.integrator) && !is_transmissive(&surface);
        let guide_grid_cell = get_path_guide_grid_cell(scene.guide, &vertex, light_sampled);
        let guide_cell = get_path_guide_cell(scene.guide, guide_grid_cell, &vertex);
        // The Lambertian kernel's order: light samples, then the direction (each at its own
        // dimension pairs, so the order changes no number).
        let vertex_pairs = get_vertex_dimension_pair(i);
        if light_sampled {
            light_origin = vertex.light_sample_origin;
            light_normal = vertex.light_selection_normal;
            radiance += throughput_weight
                * sample_direct_light(scene, &vertex, guide_cell, sample, vertex_pairs);
        }
        // 3. Continue the path
        let direction = sample_guided_path_direction(
            scene.integrator,
            scene.guide,
            &vertex,
            guide_cell,
            sample,
            vertex_pairs,
            seed,
        );
        if direction.weight == Vec3::ZERO {
            break;
        }
        ray_direction = direction.direction;
        direction_density = direction.density;
        // A delta pick: no light sample finds what it finds, which counts in full
        if direction.lobes & BSDF_LOBE_DELTA != 0 {
            light_sampled = false;
        }
        eta_scale *= direction.eta * direction.eta;
        throughput_weight *= direction.weight;
        ray_origin = get_vertex_departure_origin(&vertex, direction.lobes);
        previous_position = ray_origin;
        if is_importance_sampled(scene.integrator)
            && russian_roulette_start > 0
            && i + 1 >= russian_roulette_start
        {
            let survival = (throughput_weight.max_element() * eta_scale).min(1.0);
            if get_path_random_numbers(sample, vertex_pairs + VERTEX_PAIR_RUSSIAN_ROULETTE)[0]
                >= survival
            {
                break;
            }
            throughput_weight /= survival;
        }
        // Training frames: where this vertex's light came from
        if guide_splats.is_some() {
            guide_records.record_guide_vertex(
                guide_grid_cell,
                &vertex,
                ray_direction,
                direction_density,
                throughput_weight,
                radiance,
            );
        }
    }
    if let (Some(words), Some(texels)) = (guide_splats, scene.guide) {
        guide_records.splat_guide_records(texels, words, radiance);
    }
    radiance
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contract::{INTEGRATOR_MIS, INTEGRATOR_NEE, SAMPLER_PCG, SAMPLER_SOBOL};
    use crate::cpu::sample_dimensions::{CAMERA_PAIRS, VERTEX_PAIRS};
    use crate::lights::EmissiveTriangles;
    use crate::scene::Scene;

    /// The point of fixed sample dimensions: the light samples that nee and mis take at a
    /// vertex, the direction and Russian roulette each draw at their own pairs, so drawing
    /// one moves none of the others, in either order (the Lambertian kernel takes the light
    /// samples first, the glTF kernel the direction). With the draw-order sampler before (one
    /// PCG2D stream, or Sobol's next pair), the direction drawn after `sample_direct_light`
    /// came from the pairs after the light's two, and differed from the one drawn alone.
    #[test]
    fn light_samples_move_no_other_number() {
        let scene_triangles = Scene::builtin_cornell_box().unwrap().triangles;
        let lights = EmissiveTriangles::new(&scene_triangles);
        // A point of the floor (the box's lowest, upward-facing, non-emissive triangle),
        // seen from above.
        let (floor_index, floor) = scene_triangles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.emission == Vec3::ZERO && t.normal.y.abs() > 0.99)
            .min_by(|(_, a), (_, b)| a.positions[0].y.total_cmp(&b.positions[0].y))
            .unwrap();
        let position = (floor.positions[0] + floor.positions[1] + floor.positions[2]) / 3.0;
        let ray_direction = Vec3::new(0.1, -1.0, 0.2).normalize();
        let surface = get_surface(&scene_triangles, floor_index, ray_direction);
        let floor_vertex = get_surface_vertex(surface, position, -ray_direction);
        let mut lit = 0;
        for integrator in [INTEGRATOR_NEE, INTEGRATOR_MIS] {
            let scene = LightScene {
                scene_triangles: &scene_triangles,
                lights: &lights,
                integrator,
                light_sampling: crate::contract::LIGHT_SAMPLING_SOLID_ANGLE,
                guide: None,
                light_tree: None,
            };
            for sampler in [SAMPLER_PCG, SAMPLER_SOBOL] {
                for sample_index in 0..32 {
                    let sample = PathSample::new(sampler, UVec2::new(5, 9), sample_index, 3);
                    for vertex in 0..4 {
                        let pairs = get_vertex_dimension_pair(vertex);
                        let direction = |seed: &mut UVec2| {
                            sample_guided_path_direction(
                                integrator,
                                None,
                                &floor_vertex,
                                GUIDE_NO_CELL,
                                &sample,
                                pairs,
                                seed,
                            )
                        };
                        let light = || {
                            sample_direct_light(
                                &scene,
                                &floor_vertex,
                                GUIDE_NO_CELL,
                                &sample,
                                pairs,
                            )
                        };
                        // One PCG2D state for all draws, as the path loop threads it; the
                        // importance-sampled integrators must leave it untouched.
                        let mut seed = UVec2::new(11, 13);
                        let alone = direction(&mut seed);
                        let light_first = light();
                        let after_light = direction(&mut seed);
                        let light_after = light();
                        assert_eq!(seed, UVec2::new(11, 13));
                        assert_eq!(alone.direction, after_light.direction);
                        assert_eq!(alone.weight, after_light.weight);
                        assert_eq!(light_first, light_after);
                        // The direction's and the light's numbers are other pairs.
                        let direction_numbers =
                            get_path_random_numbers(&sample, pairs + VERTEX_PAIR_DIRECTION);
                        assert_ne!(direction_numbers, get_path_random_numbers(&sample, pairs));
                        if light_first != Vec3::ZERO {
                            lit += 1;
                        }
                    }
                }
            }
        }
        // Not vacuous: most light samples reach the ceiling's light.
        assert!(
            lit > 2 * 2 * 32 * 4 / 2,
            "{lit} light samples lit the floor"
        );
        // The table leaves a vertex's block to it alone.
        assert_eq!(get_vertex_dimension_pair(1) - CAMERA_PAIRS, VERTEX_PAIRS);
    }
}
