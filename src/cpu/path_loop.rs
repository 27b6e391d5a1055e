//! Rust twin of `glsl/path_loop.glsl` on the workshop's diffuse triangles (the Lambert
//! model): the one path loop of the importance-sampled integrators (cosine, nee, mis), its
//! named steps over the surface seam (`crate::cpu::surface`) and the lights room
//! (`crate::cpu::lights`). Same names, same maths, same random-number consumption (PCG2D).

use glam::{UVec2, Vec2, Vec3};

use crate::cpu::importance_sampling::get_power_heuristic_weight;
use crate::cpu::integrator::ray_mesh_intersection;
use crate::cpu::integrators::{
    is_direct_illumination, is_importance_sampled, samples_cosine_directions,
    samples_uniform_directions, takes_light_samples, weighs_by_mis,
};
use crate::cpu::lights::{get_emissive_triangle_density, sample_direct_light, LightScene};
use crate::cpu::surface::{
    get_camera_emission, get_departure_origin, get_surface, get_volume_transmittance, has_layers,
    is_transmissive, sample_bsdf, sample_cosine_direction, sample_uniform_direction, BsdfSample,
    Surface,
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
    /// Whether the previous vertex took light samples.
    pub light_sampled: bool,
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
        );
        return throughput_weight
            * emission
            * get_power_heuristic_weight(found.direction_density, light_density);
    }
    Vec3::ZERO
}

/// Twin of `sample_path_direction`.
pub fn sample_path_direction(
    integrator: u32,
    surface: &Surface,
    view: Vec3,
    seed: &mut UVec2,
) -> BsdfSample {
    let transmissive = is_transmissive(surface);
    if samples_uniform_directions(integrator) && !transmissive {
        return sample_uniform_direction(surface, view, get_random_numbers(seed));
    }
    let random_numbers: Vec2 = get_random_numbers(seed);
    if samples_cosine_directions(integrator) && !transmissive {
        return sample_cosine_direction(surface, view, random_numbers);
    }
    let lobe_random = if has_layers(surface) {
        get_random_numbers(seed)[0]
    } else {
        0.0
    };
    sample_bsdf(surface, view, random_numbers, lobe_random)
}

/// Twin of `get_path_radiance`; `max_path_length` and `russian_roulette_start` are the
/// kernel's `MAX_PATH_LENGTH` and `RUSSIAN_ROULETTE_START`.
pub fn get_path_radiance(
    scene: &LightScene,
    mut ray_origin: Vec3,
    mut ray_direction: Vec3,
    seed: &mut UVec2,
    max_path_length: u32,
    russian_roulette_start: u32,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    let mut throughput_weight = Vec3::ONE;
    let mut direction_density = 0.0f32;
    let mut light_sampled = false;
    let mut eta_scale = 1.0f32;
    let mut previous_position = ray_origin;
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
        let view = -ray_direction;
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
            },
        );
        if i + 1 == vertex_count {
            break;
        }
        // 2. Light samples (none at glass)
        light_sampled = takes_light_samples(scene.integrator) && !is_transmissive(&surface);
        if light_sampled {
            radiance +=
                throughput_weight * sample_direct_light(scene, ray_origin, &surface, view, seed);
        }
        // 3. Continue the path
        let direction = sample_path_direction(scene.integrator, &surface, view, seed);
        if direction.weight == Vec3::ZERO {
            break;
        }
        ray_direction = direction.direction;
        direction_density = direction.density;
        eta_scale *= direction.eta * direction.eta;
        throughput_weight *= direction.weight;
        ray_origin = get_departure_origin(&surface, ray_origin, direction.lobes);
        previous_position = ray_origin;
        if is_importance_sampled(scene.integrator)
            && russian_roulette_start > 0
            && i + 1 >= russian_roulette_start
        {
            let survival = (throughput_weight.max_element() * eta_scale).min(1.0);
            if get_random_numbers(seed)[0] >= survival {
                break;
            }
            throughput_weight /= survival;
        }
    }
    radiance
}
