//! Rust twins of `glsl/emissive_lights.glsl` and `glsl/lights.glsl`, the lights room, for
//! the emissive triangles (the environment's twins are `crate::cpu::environment`): choosing
//! a light, sampling a point of it, the density MIS weighs by (`emissive_lights.glsl`), and
//! the estimator that turns a light sample into reflected light through the surface seam
//! (`crate::cpu::surface`; `lights.glsl`). Same names, same maths, the same random numbers at
//! the same dimension pairs (`crate::cpu::sample_dimensions`).

use glam::{Vec2, Vec3};

use crate::contract::{MIN_LIGHT_COSINE, NO_HIT_T, SHADOW_RAY_MARGIN};
use crate::cpu::guiding::GuideTexels;
use crate::cpu::importance_sampling::{
    get_power_heuristic_weight, get_spherical_triangle, get_triangle_area,
    sample_spherical_triangle, sample_triangle_point, use_spherical_sampling, SphericalTriangle,
};
use crate::cpu::integrator::is_double_sided;
use crate::cpu::integrators::weighs_by_mis;
use crate::cpu::light_tree::{
    get_light_tree_probability, sample_light_tree, LightTexels, NO_LIGHT,
};
use crate::cpu::medium::get_medium_transmittance;
use crate::cpu::path_guiding::get_path_direction_density;
use crate::cpu::sample_dimensions::{VERTEX_PAIR_LIGHT_POINT, VERTEX_PAIR_LIGHT_SELECTION};
use crate::cpu::scattering_vertex::{
    get_vertex_scattered_radiance, get_vertex_scattering, has_only_delta_scattering,
    ScatteringVertex,
};
use crate::cpu::sobol::{get_path_random_numbers, PathSample};
use crate::cpu::surface::get_front_emission;
use crate::cpu::workshop::ray_triangle_intersection;
use crate::lights::EmissiveTriangles;
use crate::medium::Medium;
use crate::scene::Triangle;

/// What the light estimators read of a scene: its triangles, its emissive triangles and the
/// kernel's `INTEGRATOR` and `LIGHT_SAMPLING`.
#[derive(Clone, Copy, Debug)]
pub struct LightScene<'a> {
    /// All triangles of the scene.
    pub scene_triangles: &'a [Triangle],
    /// The emissive triangles and their selection distribution.
    pub lights: &'a EmissiveTriangles,
    /// The kernel's `INTEGRATOR`.
    pub integrator: u32,
    /// The kernel's `LIGHT_SAMPLING`.
    pub light_sampling: u32,
    /// The guide of a guided render (`--guiding`, `GUIDING_ON`), `None` without guiding.
    pub guide: Option<GuideTexels<'a>>,
    /// With `LIGHT_SELECTION_TREE`: the lights' texel buffer with its tree
    /// (`gpu_light_bytes_with_tree` over `lights`) that `crate::cpu::light_tree` walks;
    /// `None`: `LIGHT_SELECTION_POWER`.
    pub light_tree: Option<LightTexels<'a>>,
}

/// Twin of `get_light_selection_probability(triangle_index, selection_position,
/// selection_normal)`: the power CDF's probability, or the tree's at the selection point.
/// The GPU finds a triangle's place in the light list in its selection word
/// (`gpu_light_index_words`); here it is searched in the list, which is in triangle order.
pub fn get_light_selection_probability(
    scene: &LightScene,
    triangle_index: usize,
    selection_position: Vec3,
    selection_normal: Vec3,
) -> f32 {
    let Some(texels) = scene.light_tree else {
        return scene.lights.selection_probability[triangle_index];
    };
    match scene
        .lights
        .triangle_indices
        .binary_search(&(triangle_index as u32))
    {
        Ok(light_index) => get_light_tree_probability(
            texels,
            light_index as u32,
            selection_position,
            selection_normal,
        ),
        Err(_) => 0.0,
    }
}

/// Twin of `sample_light_index`: binary search for the first CDF entry above the number.
pub fn sample_light_index(lights: &EmissiveTriangles, random_number: f32) -> usize {
    let (mut low, mut high) = (0usize, lights.cdf.len().saturating_sub(1));
    // The GLSL's trip count, `findMSB(high) + 1`, with the end of the search inside the loop
    let iterations = usize::BITS - high.leading_zeros();
    for _ in 0..iterations {
        if low < high {
            let middle = (low + high) / 2;
            if random_number < lights.cdf[middle] {
                high = middle;
            } else {
                low = middle + 1;
            }
        }
    }
    low
}

/// Twin of `get_light_density`: at the origin of `spherical` (the light as seen from there),
/// p_select / solid angle for lights sampled by solid angle, else
/// p_select / area * distance^2 / |n_light.omega|.
pub fn get_light_density(
    light_sampling: u32,
    selection_probability: f32,
    light: &Triangle,
    spherical: &SphericalTriangle,
    direction: Vec3,
    distance: f32,
) -> f32 {
    if use_spherical_sampling(light_sampling, spherical) {
        return selection_probability / spherical.solid_angle;
    }
    let cosine = light.normal.dot(direction).abs();
    selection_probability * distance * distance
        / (get_triangle_area(light) * cosine.max(MIN_LIGHT_COSINE))
}

/// Twin of `ray_mesh_any_hit` (brute force, the kernels without USE_BVH): whether any
/// triangle is hit at a ray parameter t < t_max.
pub fn ray_mesh_any_hit(
    scene_triangles: &[Triangle],
    ray_origin: Vec3,
    ray_direction: Vec3,
    t_max: f32,
) -> bool {
    scene_triangles.iter().any(|triangle| {
        ray_triangle_intersection(ray_origin, ray_direction, triangle).is_some_and(|t| t < t_max)
    })
}

/// Twin of `sample_light_direction`: a direction from `origin` towards a point of `light`
/// (by solid angle or by area, as `use_spherical_sampling` says) and the distance along it.
pub fn sample_light_direction(
    light_sampling: u32,
    point_randoms: Vec2,
    light: &Triangle,
    origin: Vec3,
    spherical: &SphericalTriangle,
) -> (Vec3, f32) {
    if use_spherical_sampling(light_sampling, spherical) {
        let direction = sample_spherical_triangle(point_randoms, spherical);
        let distance = ray_triangle_intersection(origin, direction, light).unwrap_or_else(|| {
            light.normal.dot(light.positions[0] - origin) / light.normal.dot(direction)
        });
        (direction, distance)
    } else {
        let to_light = sample_triangle_point(point_randoms, light) - origin;
        let distance = to_light.length();
        (to_light / distance, distance)
    }
}

/// Twin of `light_sample_t`: one light sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction towards the light.
    pub direction: Vec3,
    /// Distance to the light (`NO_HIT_T` for lights at infinity).
    pub distance: f32,
    /// Radiance arriving (delta lights: irradiance).
    pub radiance: Vec3,
    /// Density w.r.t. solid angle; 0 for delta lights and for no sample.
    pub density: f32,
    /// Delta lights only: 1 / the probability of choosing the light; else 0.
    pub delta_weight: f32,
}

/// Twin of `get_no_light_sample`.
pub fn get_no_light_sample() -> LightSample {
    LightSample {
        direction: Vec3::Z,
        distance: 0.0,
        radiance: Vec3::ZERO,
        density: 0.0,
        delta_weight: 0.0,
    }
}

/// Twin of `get_shadow_transmittance`: the fraction of light per channel that the shadow ray
/// carries: 0 where a triangle lies within the segment (which ends `SHADOW_RAY_MARGIN`,
/// 2^-14, short of a light at a finite distance; every surface is opaque to shadow rays),
/// else the global medium's transmittance over `distance` (`medium`: the GLSL's
/// `get_global_medium()` where `SCENE_HAS_MEDIUM`, here `None` without one), else 1.
pub fn get_shadow_transmittance(
    scene_triangles: &[Triangle],
    medium: Option<&Medium>,
    origin: Vec3,
    direction: Vec3,
    distance: f32,
) -> Vec3 {
    let t_max = if distance >= NO_HIT_T {
        NO_HIT_T
    } else {
        distance * (1.0 - SHADOW_RAY_MARGIN)
    };
    if ray_mesh_any_hit(scene_triangles, origin, direction, t_max) {
        return Vec3::ZERO;
    }
    medium.map_or(Vec3::ONE, |medium| {
        get_medium_transmittance(medium, distance)
    })
}

/// Twin of `sample_emissive_triangle_light`: a light by the power CDF or, with
/// `scene.light_tree`, by the tree's importance to `origin` with `normal` (the twins of
/// `crate::cpu::light_tree`), from the numbers of `sample` at the vertex's dimension pairs
/// `vertex_pairs` (`get_vertex_dimension_pair`).
pub fn sample_emissive_triangle_light(
    scene: &LightScene,
    origin: Vec3,
    normal: Vec3,
    sample: &PathSample,
    vertex_pairs: u32,
) -> LightSample {
    let selection = get_path_random_numbers(sample, vertex_pairs + VERTEX_PAIR_LIGHT_SELECTION);
    let point_randoms = get_path_random_numbers(sample, vertex_pairs + VERTEX_PAIR_LIGHT_POINT);
    let lights = scene.lights;
    if lights.triangle_indices.is_empty() {
        return get_no_light_sample();
    }
    let (light_list_index, tree_probability) = match scene.light_tree {
        Some(texels) => {
            let (index, probability) = sample_light_tree(texels, selection[0], origin, normal);
            if index == NO_LIGHT {
                return get_no_light_sample();
            }
            (index as usize, probability)
        }
        None => (sample_light_index(lights, selection[0]), 0.0),
    };
    let light_index = lights.triangle_indices[light_list_index] as usize;
    let light = &scene.scene_triangles[light_index];
    let spherical = get_spherical_triangle(origin, light);
    let (direction, distance) = sample_light_direction(
        scene.light_sampling,
        point_randoms,
        light,
        origin,
        &spherical,
    );
    let front = light.normal.dot(direction) < 0.0;
    if !(distance > 0.0) || (!front && !is_double_sided(scene.scene_triangles, light_index)) {
        return get_no_light_sample();
    }
    LightSample {
        direction,
        distance,
        radiance: get_front_emission(light),
        density: get_light_density(
            scene.light_sampling,
            if scene.light_tree.is_some() {
                tree_probability
            } else {
                lights.selection_probability[light_index]
            },
            light,
            &spherical,
            direction,
            distance,
        ),
        delta_weight: 0.0,
    }
}

/// Twin of `get_emissive_triangle_density`: the light's selection probability at
/// `selection_position` with `selection_normal` (the tree's depends on them).
pub fn get_emissive_triangle_density(
    scene: &LightScene,
    triangle_index: usize,
    origin: Vec3,
    direction: Vec3,
    distance: f32,
    selection_position: Vec3,
    selection_normal: Vec3,
) -> f32 {
    let triangle = &scene.scene_triangles[triangle_index];
    get_light_density(
        scene.light_sampling,
        get_light_selection_probability(
            scene,
            triangle_index,
            selection_position,
            selection_normal,
        ),
        triangle,
        &get_spherical_triangle(origin, triangle),
        direction,
        distance,
    )
}

/// Twin of `estimate_light_sample`: the light `sample` brings to `vertex` towards its view,
/// times the shadow ray's transmittance (from `vertex.light_sample_origin`); `guide_cell`
/// is the vertex's guided cell (`g_path.guide_cell`), whose mixture density MIS weighs
/// against.
pub fn estimate_light_sample(
    scene: &LightScene,
    vertex: &ScatteringVertex,
    guide_cell: u32,
    sample: &LightSample,
) -> Vec3 {
    let delta = sample.delta_weight > 0.0;
    if !delta && !(sample.density > 0.0) {
        return Vec3::ZERO;
    }
    let bsdf = get_vertex_scattering(vertex, sample.direction);
    if bsdf == Vec3::ZERO {
        return Vec3::ZERO;
    }
    // The contribution before the shadow ray, as the GLSL computes it (fewer live registers
    // while the ray is traced there).
    let reflected = get_vertex_scattered_radiance(vertex, sample.direction, bsdf, sample.radiance);
    let contribution = if delta {
        reflected * sample.delta_weight
    } else {
        let weight = if weighs_by_mis(scene.integrator) {
            get_power_heuristic_weight(
                sample.density,
                get_path_direction_density(scene.guide, guide_cell, vertex, sample.direction),
            )
        } else {
            1.0
        };
        reflected / sample.density * weight
    };
    // The CPU reference renders no media
    let transmittance = get_shadow_transmittance(
        scene.scene_triangles,
        None,
        vertex.light_sample_origin,
        sample.direction,
        sample.distance,
    );
    if transmittance == Vec3::ZERO {
        return Vec3::ZERO;
    }
    contribution * transmittance
}

/// Twin of `sample_direct_light` at `vertex` (the workshop's scenes: emissive triangles
/// only); `guide_cell` as for `estimate_light_sample`, `sample` and `vertex_pairs` as for
/// `sample_emissive_triangle_light`.
pub fn sample_direct_light(
    scene: &LightScene,
    vertex: &ScatteringVertex,
    guide_cell: u32,
    sample: &PathSample,
    vertex_pairs: u32,
) -> Vec3 {
    // Every sample's `get_vertex_scattering` would be 0 (a smooth metal)
    if has_only_delta_scattering(vertex) {
        return Vec3::ZERO;
    }
    let light_sample = sample_emissive_triangle_light(
        scene,
        vertex.light_sample_origin,
        vertex.light_selection_normal,
        sample,
        vertex_pairs,
    );
    estimate_light_sample(scene, vertex, guide_cell, &light_sample)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contract::{LIGHT_SAMPLING_AREA, LIGHT_SAMPLING_SOLID_ANGLE};

    #[test]
    fn shadow_rays_carry_all_or_nothing_and_scale_the_light_sample() {
        use crate::cpu::scattering_vertex::get_surface_vertex;
        use crate::cpu::surface::Surface;
        // A light 1 above the origin, a blocker halfway that covers only x < 0.
        let light = Triangle::new(
            [
                Vec3::new(-1.0, 1.0, -1.0),
                Vec3::new(-1.0, 1.0, 1.0),
                Vec3::new(1.0, 1.0, 0.0),
            ],
            Vec3::ZERO,
            Vec3::ONE,
            true,
        )
        .unwrap();
        let blocker = Triangle::new(
            [
                Vec3::new(-0.1, 0.5, -1.0),
                Vec3::new(-0.1, 0.5, 1.0),
                Vec3::new(-2.0, 0.5, 0.0),
            ],
            Vec3::ONE,
            Vec3::ZERO,
            true,
        )
        .unwrap();
        let triangles = [light, blocker];
        let open = Vec3::new(0.5, 0.0, 0.0);
        let shaded = Vec3::new(-0.5, 0.0, 0.0);
        // Segments that stop short of the light (as a light sample's, by SHADOW_RAY_MARGIN).
        assert_eq!(
            get_shadow_transmittance(&triangles, None, open, Vec3::Y, 0.99),
            Vec3::ONE
        );
        assert_eq!(
            get_shadow_transmittance(&triangles, None, shaded, Vec3::Y, 0.99),
            Vec3::ZERO
        );
        // A ray that leaves the scene (NO_HIT_T) is blocked by whatever lies on it.
        assert_eq!(
            get_shadow_transmittance(&triangles, None, shaded, -Vec3::Y, NO_HIT_T),
            Vec3::ONE
        );
        assert_eq!(
            get_shadow_transmittance(&triangles, None, shaded, Vec3::Y, NO_HIT_T),
            Vec3::ZERO
        );
        // A medium attenuates an open segment by Beer-Lambert, and one to infinity to 0
        // where it has extinction (here in two channels), not a blocked one
        let medium = Medium {
            absorption: Vec3::new(0.5, 0.0, 0.0),
            scattering: Vec3::new(0.0, 1.0, 0.0),
            anisotropy: 0.0,
        };
        let open_fog = get_shadow_transmittance(&triangles, Some(&medium), open, Vec3::Y, 0.99);
        assert_eq!(open_fog, (Vec3::new(-0.5, -1.0, -0.0) * 0.99).exp());
        assert_eq!(open_fog.z, 1.0);
        assert_eq!(
            get_shadow_transmittance(&triangles, Some(&medium), shaded, -Vec3::Y, NO_HIT_T),
            Vec3::new(0.0, 0.0, 1.0)
        );
        assert_eq!(
            get_shadow_transmittance(&triangles, Some(&medium), shaded, Vec3::Y, 0.99),
            Vec3::ZERO
        );
        // The estimate is the unblocked contribution times the transmittance.
        let lights = EmissiveTriangles::new(&triangles);
        let scene = LightScene {
            scene_triangles: &triangles,
            lights: &lights,
            integrator: crate::contract::INTEGRATOR_NEE,
            light_sampling: LIGHT_SAMPLING_SOLID_ANGLE,
            guide: None,
            light_tree: None,
        };
        let floor = Surface {
            geometric_normal: Vec3::Y,
            shading_normal: Vec3::Y,
            base_color: Vec3::splat(0.5),
            emission: Vec3::ZERO,
        };
        let sample = LightSample {
            direction: Vec3::Y,
            distance: 0.99,
            radiance: Vec3::ONE,
            density: 2.0,
            delta_weight: 0.0,
        };
        let lit = estimate_light_sample(
            &scene,
            &get_surface_vertex(floor, open, Vec3::Y),
            0,
            &sample,
        );
        // f cos L / p = 0.5 / pi * 1 * 1 / 2
        assert!(
            (lit - Vec3::splat(0.25 / crate::cpu::workshop::M_PI))
                .abs()
                .max_element()
                < 1e-7
        );
        let dark = estimate_light_sample(
            &scene,
            &get_surface_vertex(floor, shaded, Vec3::Y),
            0,
            &sample,
        );
        assert_eq!(dark, Vec3::ZERO);
    }

    #[test]
    fn light_density_switches_to_area_outside_the_solid_angle_range() {
        let light = Triangle::new(
            [
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(0.01, 0.0, 1.0),
                Vec3::new(0.0, 0.01, 1.0),
            ],
            Vec3::ONE,
            Vec3::ONE,
            false,
        )
        .unwrap();
        let direction = Vec3::new(0.003, 0.003, 1.0).normalize();
        let distance = 1.0 / direction.z;
        // 5e-5 sr: too small for spherical sampling, so both settings give the area density.
        let area = get_light_density(
            LIGHT_SAMPLING_AREA,
            0.5,
            &light,
            &get_spherical_triangle(Vec3::ZERO, &light),
            direction,
            distance,
        );
        let solid_angle = get_light_density(
            LIGHT_SAMPLING_SOLID_ANGLE,
            0.5,
            &light,
            &get_spherical_triangle(Vec3::ZERO, &light),
            direction,
            distance,
        );
        assert_eq!(area, solid_angle);
        // From closer, 1/solid angle: it differs from the area density, whose 1/r^2 varies.
        let spherical = get_spherical_triangle(Vec3::new(0.0, 0.0, 0.99), &light);
        let near = get_light_density(
            LIGHT_SAMPLING_SOLID_ANGLE,
            0.5,
            &light,
            &spherical,
            direction,
            0.01 / direction.z,
        );
        assert_eq!(near, 0.5 / spherical.solid_angle);
    }
}
