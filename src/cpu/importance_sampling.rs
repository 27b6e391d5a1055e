//! Rust twins of `glsl/importance_sampling.glsl`: cosine-weighted hemisphere sampling, light
//! sampling (next event estimation), the power heuristic, Russian roulette, and the
//! importance-sampled path loop. Same names, same maths, same random-number consumption.

use glam::{UVec2, Vec2, Vec3};

use crate::contract::{INTEGRATOR_COSINE, INTEGRATOR_MIS};
use crate::cpu::integrator::{
    is_double_sided, offset_ray_origin, orient_towards_ray, ray_mesh_intersection,
};
use crate::cpu::workshop::{get_random_numbers, ray_triangle_intersection, M_PI};
use crate::lights::LightTable;
use crate::scene::Triangle;

/// Twin of `sample_hemisphere_cosine`: Malley's method in the Duff et al. (2017) basis.
pub fn sample_hemisphere_cosine(random_numbers: Vec2, normal: Vec3) -> Vec3 {
    let sign_z = if normal.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign_z + normal.z);
    let b = normal.x * normal.y * a;
    let tangent = Vec3::new(
        1.0 + sign_z * normal.x * normal.x * a,
        sign_z * b,
        -sign_z * normal.x,
    );
    let bitangent = Vec3::new(b, sign_z + normal.y * normal.y * a, -normal.y);
    let radius = random_numbers[0].sqrt();
    let phi = 2.0 * M_PI * random_numbers[1];
    let x = radius * phi.cos();
    let y = radius * phi.sin();
    let z = (1.0 - random_numbers[0]).max(0.0).sqrt();
    x * tangent + y * bitangent + z * normal
}

/// Twin of `get_hemisphere_cosine_density`: max(0, n.omega) / pi w.r.t. solid angle.
pub fn get_hemisphere_cosine_density(normal: Vec3, direction: Vec3) -> f32 {
    normal.dot(direction).max(0.0) / M_PI
}

/// Twin of `get_triangle_area`.
pub fn get_triangle_area(triangle: &Triangle) -> f32 {
    0.5 * (triangle.positions[1] - triangle.positions[0])
        .cross(triangle.positions[2] - triangle.positions[0])
        .length()
}

/// Twin of `sample_triangle_point`: uniform on the triangle, density 1 / area.
pub fn sample_triangle_point(random_numbers: Vec2, triangle: &Triangle) -> Vec3 {
    let root = random_numbers[0].sqrt();
    let b_0 = 1.0 - root;
    let b_1 = random_numbers[1] * root;
    b_0 * triangle.positions[0]
        + b_1 * triangle.positions[1]
        + (1.0 - b_0 - b_1) * triangle.positions[2]
}

/// Twin of `sample_light_index`: binary search for the first CDF entry above the number.
pub fn sample_light_index(lights: &LightTable, random_number: f32) -> usize {
    let (mut low, mut high) = (0usize, lights.cdf.len().saturating_sub(1));
    for _ in 0..32 {
        if low >= high {
            break;
        }
        let middle = (low + high) / 2;
        if random_number < lights.cdf[middle] {
            high = middle;
        } else {
            low = middle + 1;
        }
    }
    low
}

/// Twin of `get_light_density`: p_select / area * distance^2 / |n_light.omega|.
pub fn get_light_density(
    selection_probability: f32,
    light: &Triangle,
    direction: Vec3,
    distance: f32,
) -> f32 {
    let cosine = light.normal.dot(direction).abs();
    selection_probability * distance * distance / (get_triangle_area(light) * cosine.max(1.0e-20))
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

/// Twin of `is_occluded`.
pub fn is_occluded(
    scene_triangles: &[Triangle],
    origin: Vec3,
    direction: Vec3,
    distance: f32,
) -> bool {
    ray_mesh_any_hit(
        scene_triangles,
        origin,
        direction,
        distance * (1.0 - 6.103_515_6e-5),
    )
}

/// Twin of `get_power_heuristic_weight`.
pub fn get_power_heuristic_weight(density: f32, other_density: f32) -> f32 {
    let squared = density * density;
    let other_squared = other_density * other_density;
    if squared + other_squared > 0.0 {
        squared / (squared + other_squared)
    } else {
        0.0
    }
}

/// Twin of `sample_direct_light`.
pub fn sample_direct_light(
    scene_triangles: &[Triangle],
    lights: &LightTable,
    integrator: u32,
    shading_position: Vec3,
    triangle: &Triangle,
    seed: &mut UVec2,
) -> Vec3 {
    let selection = get_random_numbers(seed);
    let point_randoms = get_random_numbers(seed);
    if lights.triangle_indices.is_empty() {
        return Vec3::ZERO;
    }
    let light_index = lights.triangle_indices[sample_light_index(lights, selection[0])] as usize;
    let light = &scene_triangles[light_index];
    let origin = offset_ray_origin(shading_position, triangle.normal);
    let to_light = sample_triangle_point(point_randoms, light) - origin;
    let distance = to_light.length();
    let direction = to_light / distance;
    let cosine = triangle.normal.dot(direction);
    let front = light.normal.dot(direction) < 0.0;
    if cosine <= 0.0
        || !(distance > 0.0)
        || (!front && !is_double_sided(scene_triangles, light_index))
    {
        return Vec3::ZERO;
    }
    if is_occluded(scene_triangles, origin, direction, distance) {
        return Vec3::ZERO;
    }
    let light_density = get_light_density(
        lights.selection_probability[light_index],
        light,
        direction,
        distance,
    );
    let weight = if integrator == INTEGRATOR_MIS {
        get_power_heuristic_weight(
            light_density,
            get_hemisphere_cosine_density(triangle.normal, direction),
        )
    } else {
        1.0
    };
    triangle.color / M_PI * light.emission * cosine / light_density * weight
}

/// Twin of `get_ray_radiance_importance_sampled` (INTEGRATOR_COSINE, _NEE or _MIS).
#[allow(clippy::too_many_arguments)]
pub fn get_ray_radiance_importance_sampled(
    scene_triangles: &[Triangle],
    lights: &LightTable,
    integrator: u32,
    mut ray_origin: Vec3,
    mut ray_direction: Vec3,
    seed: &mut UVec2,
    max_path_length: u32,
    russian_roulette_start: u32,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    let mut throughput_weight = Vec3::ONE;
    let mut direction_density = 0.0f32;
    for i in 0..max_path_length {
        let Some(hit) = ray_mesh_intersection(scene_triangles, ray_origin, ray_direction) else {
            break;
        };
        let mut triangle = scene_triangles[hit.triangle_index];
        orient_towards_ray(
            &mut triangle,
            ray_direction,
            is_double_sided(scene_triangles, hit.triangle_index),
        );
        ray_origin += hit.t * ray_direction;
        if i == 0 || integrator == INTEGRATOR_COSINE {
            radiance += throughput_weight * triangle.emission;
        } else if integrator == INTEGRATOR_MIS && triangle.emission != Vec3::ZERO {
            let light_density = get_light_density(
                lights.selection_probability[hit.triangle_index],
                &triangle,
                ray_direction,
                hit.t,
            );
            radiance += throughput_weight
                * triangle.emission
                * get_power_heuristic_weight(direction_density, light_density);
        }
        if i + 1 == max_path_length {
            break;
        }
        if integrator != INTEGRATOR_COSINE {
            radiance += throughput_weight
                * sample_direct_light(
                    scene_triangles,
                    lights,
                    integrator,
                    ray_origin,
                    &triangle,
                    seed,
                );
        }
        ray_direction = sample_hemisphere_cosine(get_random_numbers(seed), triangle.normal);
        direction_density = get_hemisphere_cosine_density(triangle.normal, ray_direction);
        if direction_density <= 0.0 {
            break;
        }
        throughput_weight *= triangle.color;
        ray_origin = offset_ray_origin(ray_origin, triangle.normal);
        if russian_roulette_start > 0 && i + 1 >= russian_roulette_start {
            let survival = throughput_weight.max_element().min(1.0);
            if get_random_numbers(seed)[0] >= survival {
                break;
            }
            throughput_weight /= survival;
        }
    }
    radiance
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::chi2::{chi2_direction_test, Chi2Config};
    use crate::stats::sphere_histogram::{SphereFrame, TargetDensity};

    #[test]
    fn cosine_sampler_passes_chi2_against_its_density() {
        let normal = Vec3::new(0.3, -0.5, 0.81).normalize();
        let mut seed = UVec2::new(7, 11);
        let samples: Vec<Vec3> = (0..1_000_000)
            .map(|_| sample_hemisphere_cosine(get_random_numbers(&mut seed), normal))
            .collect();
        let density = |direction: Vec3| f64::from(get_hemisphere_cosine_density(normal, direction));
        let frame = SphereFrame::from_normal(normal).unwrap();
        let result = chi2_direction_test(
            samples,
            TargetDensity::SolidAngle(&density),
            &frame,
            &Chi2Config::default(),
        )
        .unwrap();
        println!("cosine sampler: {result:?}");
        assert!(result.passed, "{result:?}");
    }

    #[test]
    fn triangle_points_are_uniform_and_inside() {
        let triangle = Triangle::new(
            [Vec3::ZERO, Vec3::X * 2.0, Vec3::Y],
            Vec3::ONE,
            Vec3::ZERO,
            false,
        )
        .unwrap();
        let mut seed = UVec2::new(1, 2);
        // Split the triangle by x < 1: the left part holds 3/4 of the area.
        let n = 200_000;
        let mut left = 0;
        for _ in 0..n {
            let p = sample_triangle_point(get_random_numbers(&mut seed), &triangle);
            assert!(p.x >= -1e-6 && p.y >= -1e-6 && p.x / 2.0 + p.y <= 1.0 + 1e-6);
            left += usize::from(p.x < 1.0);
        }
        let fraction = left as f64 / n as f64;
        // Binomial standard deviation sqrt(0.75 * 0.25 / n) ~ 1e-3; 5 sigma.
        assert!((fraction - 0.75).abs() < 5e-3, "{fraction}");
    }

    #[test]
    fn power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0f32, 2.0f32), (0.3, 0.0), (5.0, 5.0)] {
            let sum = get_power_heuristic_weight(a, b) + get_power_heuristic_weight(b, a);
            assert!((sum - 1.0).abs() < 1e-6);
        }
        assert_eq!(get_power_heuristic_weight(0.0, 0.0), 0.0);
    }
}
