//! Rust twins of `glsl/scene.glsl`'s `ray_mesh_intersection`, of `glsl/integrator.glsl`
//! (Exercise 6 and 7 of the workshop) and of `get_sample_radiance` in
//! `glsl/path_tracer.comp`. Same maths in the same order and the same consumption of random
//! numbers, so that with the same seed the CPU traces the same paths as the GPU. Where the
//! shader reads the global triangle buffer, the twins take the scene's triangles as their
//! first parameter.

use glam::{UVec2, Vec3};

use crate::contract::{
    INTEGRATOR_PATH_TRACING, INTEGRATOR_RAY_TRACING, NO_HIT_T, RAY_ORIGIN_OFFSET,
};
use crate::cpu::workshop::{
    get_random_numbers, ray_triangle_intersection, sample_hemisphere, M_PI,
};
use crate::scene::Triangle;

/// The closest hit of a ray with the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    /// Ray parameter of the hit (in units of |ray_direction|).
    pub t: f32,
    /// Index of the hit triangle in the scene's triangles (the shader's
    /// `g_hit_triangle_index`).
    pub triangle_index: usize,
}

/// Finds the closest triangle that a ray hits (Part 1), brute force over all triangles, twin
/// of GLSL `ray_mesh_intersection`. Ties keep the triangle with the lower index, as the
/// shader's strict `t < out_t` does.
/// \param scene_triangles All triangles of the scene (the shader's `g_triangles`)
/// \param ray_origin, ray_direction The ray, world space
/// \return The closest hit, `None` iff no triangle was hit at t < `NO_HIT_T` (1e38)
pub fn ray_mesh_intersection(
    scene_triangles: &[Triangle],
    ray_origin: Vec3,
    ray_direction: Vec3,
) -> Option<MeshHit> {
    let mut out_t = NO_HIT_T;
    let mut hit = None;
    for (index, triangle) in scene_triangles.iter().enumerate() {
        if let Some(t) = ray_triangle_intersection(ray_origin, ray_direction, triangle) {
            if t < out_t {
                out_t = t;
                hit = Some(MeshHit {
                    t,
                    triangle_index: index,
                });
            }
        }
    }
    hit
}

/// Whether triangle `index` of the scene emits from both sides, twin of GLSL
/// `is_double_sided` (which reads `TRIANGLE_FLAG_DOUBLE_SIDED` from the packed triangle).
pub fn is_double_sided(scene_triangles: &[Triangle], index: usize) -> bool {
    scene_triangles[index].double_sided
}

/// Prepares a hit triangle for shading, twin of GLSL `orient_towards_ray`: the normal is
/// flipped to face the ray's origin, and emission seen from the back is zero unless the
/// triangle is double-sided.
/// \param triangle The hit triangle, updated in place
/// \param ray_direction Direction of the ray that hit it, world space
/// \param double_sided Whether the triangle emits from both sides (`Triangle::double_sided`)
pub fn orient_towards_ray(triangle: &mut Triangle, ray_direction: Vec3, double_sided: bool) {
    if triangle.normal.dot(ray_direction) > 0.0 {
        triangle.normal = -triangle.normal;
        if !double_sided {
            triangle.emission = Vec3::ZERO;
        }
    }
}

/// Moves the origin of a ray that leaves a surface slightly off it, against
/// self-intersection, twin of GLSL `offset_ray_origin`. The offset, `RAY_ORIGIN_OFFSET`
/// (2^-17, `glsl/shared.h`), is about 64 float ulps of the largest coordinate: far above the
/// rounding error of `ray_triangle_intersection` and far below any feature of a sensible
/// scene.
/// \param position Point on the surface, world space
/// \param normal Unit normal on the side the ray leaves to
/// \return position + max(1, max_i |position_i|) * 2^-17 * normal
pub fn offset_ray_origin(position: Vec3, normal: Vec3) -> Vec3 {
    let magnitude = position.abs();
    let scale = 1.0f32.max(magnitude.x.max(magnitude.y.max(magnitude.z)));
    position + (scale * RAY_ORIGIN_OFFSET) * normal
}

/// Exercise 6, twin of GLSL `compute_direct_illumination`: radiance leaving a point of a
/// triangle towards the camera, with one uniform hemisphere sample (density 1/(2 pi) w.r.t.
/// solid angle) for direct illumination: L_e(x) + a(x)/pi * 2 pi * L_e(y) * n(x).omega.
/// Consumes one pair of random numbers.
/// \param scene_triangles All triangles of the scene
/// \param shading_position The point x on the triangle, world space
/// \param triangle The triangle at x, oriented by `orient_towards_ray`
/// \param seed The sample's random state
pub fn compute_direct_illumination(
    scene_triangles: &[Triangle],
    shading_position: Vec3,
    triangle: &Triangle,
    seed: &mut UVec2,
) -> Vec3 {
    let ray_direction = sample_hemisphere(get_random_numbers(seed), triangle.normal);
    let mut incoming_emission = Vec3::ZERO;
    let origin = offset_ray_origin(shading_position, triangle.normal);
    if let Some(hit) = ray_mesh_intersection(scene_triangles, origin, ray_direction) {
        let mut light_triangle = scene_triangles[hit.triangle_index];
        orient_towards_ray(
            &mut light_triangle,
            ray_direction,
            is_double_sided(scene_triangles, hit.triangle_index),
        );
        incoming_emission = light_triangle.emission;
    }
    // Left to right as in GLSL: ((((a / pi) * 2) * pi) * L_e(y)) * n.omega
    triangle.emission
        + triangle.color / M_PI
            * 2.0
            * M_PI
            * incoming_emission
            * triangle.normal.dot(ray_direction)
}

/// Exercise 7, twin of GLSL `get_ray_radiance`: a Monte Carlo estimate of the radiance
/// L(x_0, omega_0) arriving along a ray, with paths of up to `max_path_length` surface hits
/// and uniform hemisphere sampling:
/// L_{j+1} = L_j + T_j L_e(x_{j+1}), L_0 = 0;
/// T_{j+1} = T_j a(x_{j+1}) 2 n(x_{j+1}).omega_{j+1}, T_0 = 1.
/// Consumes one pair of random numbers per surface hit.
/// \param scene_triangles All triangles of the scene
/// \param ray_origin, ray_direction The camera ray, world space
/// \param seed The sample's random state
/// \param max_path_length The shader's `MAX_PATH_LENGTH` specialization constant
pub fn get_ray_radiance(
    scene_triangles: &[Triangle],
    mut ray_origin: Vec3,
    mut ray_direction: Vec3,
    seed: &mut UVec2,
    max_path_length: u32,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    let mut throughput_weight = Vec3::ONE;
    for _ in 0..max_path_length {
        // Trace ray x_j, omega_j, break if it hits nothing
        let Some(hit) = ray_mesh_intersection(scene_triangles, ray_origin, ray_direction) else {
            break;
        };
        let mut triangle = scene_triangles[hit.triangle_index];
        orient_towards_ray(
            &mut triangle,
            ray_direction,
            is_double_sided(scene_triangles, hit.triangle_index),
        );
        // x_{j+1} = x_j + t_j omega_j
        ray_origin += hit.t * ray_direction;
        // Add T_j L_e(x_{j+1}) to the radiance
        radiance += throughput_weight * triangle.emission;
        // Sample omega_{j+1} in Omega(x_{j+1})
        ray_direction = sample_hemisphere(get_random_numbers(seed), triangle.normal);
        // Multiply the throughput by a(x_{j+1}) 2 n(x_{j+1}).omega_{j+1}
        throughput_weight *= triangle.color * 2.0 * triangle.normal.dot(ray_direction);
        ray_origin = offset_ray_origin(ray_origin, triangle.normal);
    }
    radiance
}

/// One sample of the radiance through a pixel with the chosen integrator, twin of
/// `get_sample_radiance` in `glsl/path_tracer.comp`. As in the shader, any `integrator` other
/// than `INTEGRATOR_PATH_TRACING` and `INTEGRATOR_RAY_TRACING` runs direct illumination.
/// \param scene_triangles All triangles of the scene
/// \param camera_position The pinhole, world space
/// \param ray_direction The primary ray's direction, world space
/// \param seed The sample's random state
/// \param integrator `INTEGRATOR_*` of `crate::contract`
/// \param max_path_length Maximal number of surface hits for path tracing
pub fn get_sample_radiance(
    scene_triangles: &[Triangle],
    camera_position: Vec3,
    ray_direction: Vec3,
    seed: &mut UVec2,
    integrator: u32,
    max_path_length: u32,
) -> Vec3 {
    if integrator == INTEGRATOR_PATH_TRACING {
        return get_ray_radiance(
            scene_triangles,
            camera_position,
            ray_direction,
            seed,
            max_path_length,
        );
    }
    let Some(hit) = ray_mesh_intersection(scene_triangles, camera_position, ray_direction) else {
        return Vec3::ZERO;
    };
    let mut triangle = scene_triangles[hit.triangle_index];
    if integrator == INTEGRATOR_RAY_TRACING {
        return triangle.color;
    }
    orient_towards_ray(
        &mut triangle,
        ray_direction,
        is_double_sided(scene_triangles, hit.triangle_index),
    );
    compute_direct_illumination(
        scene_triangles,
        camera_position + hit.t * ray_direction,
        &triangle,
        seed,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_at_z(z: f32, color: f32) -> [Triangle; 2] {
        let corner = |x: f32, y: f32| Vec3::new(x, y, z);
        let make = |positions| {
            Triangle::new(positions, Vec3::splat(color), Vec3::ZERO, false).expect("non-degenerate")
        };
        [
            make([corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0)]),
            make([corner(-1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)]),
        ]
    }

    #[test]
    fn mesh_intersection_picks_the_closest() {
        let mut triangles: Vec<Triangle> = square_at_z(3.0, 0.1).into();
        triangles.extend(square_at_z(1.0, 0.2));
        triangles.extend(square_at_z(2.0, 0.3));
        let hit =
            ray_mesh_intersection(&triangles, Vec3::new(0.2, 0.5, 0.0), Vec3::Z).expect("hits");
        assert_eq!(hit.t, 1.0);
        assert_eq!(triangles[hit.triangle_index].color, Vec3::splat(0.2));
        // Starting between the planes, the ray behind does not count.
        let hit =
            ray_mesh_intersection(&triangles, Vec3::new(0.2, 0.5, 1.5), Vec3::Z).expect("hits");
        assert_eq!(hit.t, 0.5);
        assert_eq!(
            ray_mesh_intersection(&triangles, Vec3::new(0.2, 0.5, 3.5), Vec3::Z),
            None
        );
        assert_eq!(ray_mesh_intersection(&[], Vec3::ZERO, Vec3::Z), None);
    }

    #[test]
    fn orientation_flips_normal_and_hides_back_emission() {
        let [mut triangle, _] = square_at_z(1.0, 0.5);
        triangle.emission = Vec3::ONE;
        // The normal is +z; a ray travelling +z sees the back.
        let mut back = triangle;
        orient_towards_ray(&mut back, Vec3::Z, false);
        assert_eq!((back.normal, back.emission), (-Vec3::Z, Vec3::ZERO));
        let mut double = triangle;
        orient_towards_ray(&mut double, Vec3::Z, true);
        assert_eq!((double.normal, double.emission), (-Vec3::Z, Vec3::ONE));
        let mut front = triangle;
        orient_towards_ray(&mut front, -Vec3::Z, false);
        assert_eq!(front, triangle);
    }

    #[test]
    fn ray_origin_offset_scales_with_magnitude() {
        assert_eq!(
            offset_ray_origin(Vec3::ZERO, Vec3::Z),
            Vec3::new(0.0, 0.0, RAY_ORIGIN_OFFSET)
        );
        let far = offset_ray_origin(Vec3::new(0.0, -1024.0, 0.0), Vec3::X);
        assert_eq!(far, Vec3::new(1024.0 * RAY_ORIGIN_OFFSET, -1024.0, 0.0));
    }

    #[test]
    fn integrators_consume_random_numbers_like_the_shader() {
        // A floor lit by nothing: path tracing takes one pair per hit, direct illumination
        // one pair, ray tracing none.
        let triangles = square_at_z(0.0, 0.5);
        let origin = Vec3::new(0.1, 0.2, 1.0);
        let start = UVec2::new(5, 6);
        let mut one_step = start;
        get_random_numbers(&mut one_step);
        for (integrator, expected) in [
            (INTEGRATOR_PATH_TRACING, one_step),
            (crate::contract::INTEGRATOR_DIRECT_ILLUMINATION, one_step),
            (INTEGRATOR_RAY_TRACING, start),
        ] {
            let mut seed = start;
            let radiance =
                get_sample_radiance(&triangles, origin, -Vec3::Z, &mut seed, integrator, 5);
            assert_eq!(seed, expected, "integrator {integrator}");
            let expected_radiance = if integrator == INTEGRATOR_RAY_TRACING {
                Vec3::splat(0.5)
            } else {
                Vec3::ZERO
            };
            assert_eq!(radiance, expected_radiance);
        }
    }
}
