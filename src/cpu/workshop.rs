//! Rust twins of `glsl/workshop.glsl`: the Path Tracing Workshop's random numbers, direction
//! samplers, ray-triangle intersection and pinhole camera. Each function has the name,
//! parameters and maths of its GLSL twin, operation for operation and in the same order, so
//! that both give the same floats up to the few ulps by which a GPU's `cos`, `sin`, `sqrt`,
//! `normalize` or a fused multiply-add may differ. Change both together. GLSL's
//! `triangle_t` is `crate::scene::Triangle` here (its `double_sided` flag is vkpath's
//! addition, which the shader keeps in the packed emission's w).

use glam::{UVec2, Vec2, Vec3};

use crate::scene::Triangle;

/// The workshop's `M_PI` (`3.141592653589793`), which GLSL reads as a 32-bit float literal:
/// exactly `std::f32::consts::PI`.
pub const M_PI: f32 = std::f32::consts::PI;

/// 2^-32 as GLSL writes it (`2.32830643654e-10`); the literal rounds to exactly 2^-32 in
/// f32 (it is within 1.3e-21 of 2^-32, far below half an ulp there, 1.4e-17).
#[allow(
    clippy::excessive_precision,
    reason = "the shader's literal, digit for digit"
)]
const TWO_TO_MINUS_32: f32 = 2.32830643654e-10;

/// The LCG multiplier of PCG2D (Numerical Recipes' 1664525).
pub(crate) const PCG_MULTIPLIER: u32 = 1664525;
/// The LCG increment of PCG2D (Numerical Recipes' 1013904223).
pub(crate) const PCG_INCREMENT: u32 = 1013904223;

/// A pseudo-random number generator, twin of GLSL `get_random_numbers`: PCG2D
/// (Jarzynski and Olano, JCGT 2020, <https://jcgt.org/published/0009/03/02/>) with u32
/// wrapping arithmetic, bit-exact with the shader.
/// \param seed Numbers that are different for each invocation; updated so that it can be
///        reused.
/// \return Two pseudo-random numbers (u_0, u_1), uniform in [0, 1]. The conversion
///         `vec2(seed) * 2^-32` rounds a u32 to the nearest f32 first, so seeds within 128
///         of 2^32 give exactly 1.0; the shader does the same.
pub fn get_random_numbers(seed: &mut UVec2) -> Vec2 {
    // seed = pcg2d(seed): the state update, written once (crate::cpu::sobol::pcg2d_hash)
    *seed = crate::cpu::sobol::pcg2d_hash(*seed);
    let (x, y) = (seed.x, seed.y);
    // Convert to float: round to nearest, then scale by 2^-32 (exact).
    Vec2::new(x as f32, y as f32) * TWO_TO_MINUS_32
}

/// Maps two uniform random numbers to a uniformly distributed direction on the unit sphere
/// (slide "Uniform sphere sampling", pbr-book.org 13.6.1), twin of GLSL `sample_sphere`.
/// \param random_numbers Uniform (u_0, u_1) in [0, 1)^2
/// \return A unit vector, density 1/(4 pi) w.r.t. solid angle
pub fn sample_sphere(random_numbers: Vec2) -> Vec3 {
    // omega_z = 2 u_1 - 1 is uniform in [-1, 1)
    let z = 2.0 * random_numbers[1] - 1.0;
    // phi = 2 pi u_0 (GLSL folds 2.0 * M_PI first, as Rust does here: left to right)
    let phi = 2.0 * M_PI * random_numbers[0];
    // omega_x = cos(phi) sqrt(1 - omega_z^2), omega_y = sin(phi) sqrt(1 - omega_z^2)
    let x = phi.cos() * (1.0 - z * z).sqrt();
    let y = phi.sin() * (1.0 - z * z).sqrt();
    Vec3::new(x, y, z)
}

/// Maps two uniform random numbers to a uniformly distributed direction on the hemisphere
/// around `normal` (slide "Uniform hemisphere sampling"), twin of GLSL `sample_hemisphere`.
/// \param random_numbers Uniform (u_0, u_1) in [0, 1)^2
/// \param normal Unit vector n, world space
/// \return A unit vector omega with dot(n, omega) >= 0 (up to rounding), density 1/(2 pi)
///         w.r.t. solid angle
pub fn sample_hemisphere(random_numbers: Vec2, normal: Vec3) -> Vec3 {
    let mut direction = sample_sphere(random_numbers);
    // Mirror if n . omega < 0: omega' = omega - 2 (n . omega) n
    if normal.dot(direction) < 0.0 {
        direction -= 2.0 * normal.dot(direction) * normal;
    }
    direction
}

/// The naive sampler of the slides' cautionary example, which is *not* uniform: spherical
/// coordinates phi = 2 pi u_0, theta = pi u_1, giving density 1 / (2 pi^2 sin(theta)) w.r.t.
/// solid angle, crowded at the poles. Twin of `sample_sphere_spherical_coordinates` in
/// `glsl/exercise_samplers.glsl`; the χ² tests use it as the sampler that must fail.
/// \param random_numbers Uniform (u_0, u_1) in [0, 1)^2
/// \return A unit vector
pub fn sample_sphere_spherical_coordinates(random_numbers: Vec2) -> Vec3 {
    let phi = 2.0 * M_PI * random_numbers[0];
    let theta = M_PI * random_numbers[1];
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// Intersects a ray with a triangle (Part 1), twin of GLSL `ray_triangle_intersection`.
/// Solves ray_origin + t * ray_direction = v_0 + u (v_1 - v_0) + v (v_2 - v_0) for (t, u, v)
/// with Cramer's rule, spelled out exactly as the shader does.
/// \param ray_origin, ray_direction The ray, world space (the direction need not be
///        normalized)
/// \param triangle The triangle to intersect
/// \return The ray parameter t of the hit (distance in units of |ray_direction|) iff the ray
///         hits the triangle at t >= 0, edges and vertices included. The GLSL twin writes t
///         to `out_t` even on a miss; here a miss is `None`.
pub fn ray_triangle_intersection(
    ray_origin: Vec3,
    ray_direction: Vec3,
    triangle: &Triangle,
) -> Option<f32> {
    let edge_1 = triangle.positions[1] - triangle.positions[0];
    let edge_2 = triangle.positions[2] - triangle.positions[0];
    let origin_offset = ray_origin - triangle.positions[0];
    // The columns of the system's matrix are (-ray_direction, edge_1, edge_2); its
    // determinant is the scalar triple product det = dot(-ray_direction, cross(edge_1, edge_2)).
    let normal_unscaled = edge_1.cross(edge_2);
    let determinant = -ray_direction.dot(normal_unscaled);
    let direction_cross_offset = ray_direction.cross(origin_offset);
    let inverse_determinant = 1.0 / determinant;
    let t = origin_offset.dot(normal_unscaled) * inverse_determinant;
    let u = -edge_2.dot(direction_cross_offset) * inverse_determinant;
    let v = edge_1.dot(direction_cross_offset) * inverse_determinant;
    // A ray parallel to the triangle gives an infinite or NaN determinant inverse, which
    // fails these comparisons (an infinite u or v fails u >= 0, v >= 0 or u + v <= 1).
    if t >= 0.0 && u >= 0.0 && v >= 0.0 && u + v <= 1.0 {
        Some(t)
    } else {
        None
    }
}

/// The pinhole camera of Part 1, twin of GLSL `get_primary_ray_direction`: the direction
/// of the primary ray through a point of the image plane.
/// \param x, y Point of the image in [0, 1]^2, (0, 0) at the left bottom, y up
///        (ShaderToy's `pixel_coord / iResolution`)
/// \param camera_position The pinhole, world space
/// \param left_bottom The image plane's left-bottom corner, world space
/// \param right, up The image plane's edge vectors (full width and height), world space
/// \return The normalized ray direction, world space. glam normalizes as v * (1 / |v|); a
///         GPU may use inversesqrt, an ulp or two apart.
pub fn get_primary_ray_direction(
    x: f32,
    y: f32,
    camera_position: Vec3,
    left_bottom: Vec3,
    right: Vec3,
    up: Vec3,
) -> Vec3 {
    let image_plane_point = left_bottom + x * right + y * up;
    (image_plane_point - camera_position).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// PCG2D written out a second time, independently of the twin: scalar steps straight
    /// from the JCGT paper's listing.
    fn pcg2d_by_hand(seed: [u32; 2]) -> [u32; 2] {
        let mut v = seed.map(|s| s.wrapping_mul(1664525).wrapping_add(1013904223));
        v[0] = v[0].wrapping_add(v[1].wrapping_mul(1664525));
        v[1] = v[1].wrapping_add(v[0].wrapping_mul(1664525));
        v = v.map(|s| s ^ (s >> 16));
        v[0] = v[0].wrapping_add(v[1].wrapping_mul(1664525));
        v[1] = v[1].wrapping_add(v[0].wrapping_mul(1664525));
        v.map(|s| s ^ (s >> 16))
    }

    #[test]
    fn m_pi_is_the_workshops_literal() {
        // M_PI stays in glsl/workshop.glsl, as on the slides, rather than in glsl/shared.h;
        // this keeps the twin honest instead.
        let workshop = crate::shaders::GLSL_SOURCES
            .iter()
            .find(|(name, _)| *name == "workshop.glsl")
            .map(|(_, text)| *text)
            .expect("workshop.glsl is embedded");
        let literal = workshop
            .lines()
            .find_map(|line| line.strip_prefix("#define M_PI "))
            .expect("workshop.glsl defines M_PI");
        assert_eq!(literal.trim().parse::<f32>(), Ok(M_PI));
    }

    #[test]
    fn pcg2d_matches_the_formula_and_known_values() {
        for start in [
            [0u32, 0u32],
            [1, 2],
            [0xFFFF_FFFF, 0x8000_0000],
            [12345, 6789 << 16],
        ] {
            let mut seed = UVec2::from_array(start);
            let numbers = get_random_numbers(&mut seed);
            let expected = pcg2d_by_hand(start);
            assert_eq!(
                seed.to_array(),
                expected,
                "state after one step from {start:?}"
            );
            assert_eq!(numbers.x, expected[0] as f32 * 2.0f32.powi(-32));
            assert_eq!(numbers.y, expected[1] as f32 * 2.0f32.powi(-32));
        }
        // Known values, computed with Python's arbitrary-precision integers mod 2^32:
        // the first step from (0, 0) and the second step from (1, 2).
        let mut seed = UVec2::new(0, 0);
        get_random_numbers(&mut seed);
        assert_eq!(seed.to_array(), [0x18E4_31A7, 0x055D_F4D1]);
        let mut seed = UVec2::new(1, 2);
        get_random_numbers(&mut seed);
        get_random_numbers(&mut seed);
        assert_eq!(seed.to_array(), [0x74AE_F791, 0x44D0_3A21]);
    }

    #[test]
    fn random_numbers_cover_the_unit_square() {
        let mut seed = UVec2::new(7, 11);
        let mut mean = Vec2::ZERO;
        let count = 10_000;
        for _ in 0..count {
            let numbers = get_random_numbers(&mut seed);
            assert!(numbers.cmpge(Vec2::ZERO).all() && numbers.cmple(Vec2::ONE).all());
            mean += numbers / count as f32;
        }
        // The mean of 10^4 uniform numbers has standard deviation 0.0029; 0.015 is 5 of them.
        assert!(
            (mean - Vec2::splat(0.5)).abs().max_element() < 0.015,
            "{mean}"
        );
    }

    #[test]
    fn sphere_samples_are_unit_vectors() {
        let mut seed = UVec2::new(3, 5);
        for _ in 0..10_000 {
            let direction = sample_sphere(get_random_numbers(&mut seed));
            // f32 cos, sin and sqrt are each within an ulp or so: 1e-6 is a few ulps of 1.
            assert!((direction.length() - 1.0).abs() < 1e-6, "{direction}");
            let naive = sample_sphere_spherical_coordinates(get_random_numbers(&mut seed));
            assert!((naive.length() - 1.0).abs() < 1e-6, "{naive}");
        }
    }

    #[test]
    fn hemisphere_samples_lie_above_the_normal() {
        let mut seed = UVec2::new(9, 1);
        let normals = [Vec3::Z, -Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()];
        for normal in normals {
            for _ in 0..10_000 {
                let direction = sample_hemisphere(get_random_numbers(&mut seed), normal);
                assert!(normal.dot(direction) >= 0.0, "{direction} below {normal}");
                assert!((direction.length() - 1.0).abs() < 1e-5, "{direction}");
            }
        }
    }

    fn unit_triangle() -> Triangle {
        // In the plane z = 1, counter-clockwise seen from +z.
        let positions = [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        ];
        Triangle::new(positions, Vec3::ONE, Vec3::ZERO, false).expect("non-degenerate")
    }

    #[test]
    fn ray_triangle_hit_miss_and_t() {
        let triangle = unit_triangle();
        // A hit at t = 2 with a direction of length 1/2 (t is in units of |direction|).
        let t = ray_triangle_intersection(
            Vec3::new(0.25, 0.25, 0.0),
            Vec3::new(0.0, 0.0, 0.5),
            &triangle,
        );
        assert_eq!(t, Some(2.0));
        // From the other side, towards -z: a hit at t = 3.
        let t = ray_triangle_intersection(
            Vec3::new(0.25, 0.25, 4.0),
            Vec3::new(0.0, 0.0, -1.0),
            &triangle,
        );
        assert_eq!(t, Some(3.0));
        // Outside the triangle (u + v > 1).
        assert_eq!(
            ray_triangle_intersection(Vec3::new(0.75, 0.75, 0.0), Vec3::Z, &triangle),
            None
        );
        // Behind the origin (t < 0).
        assert_eq!(
            ray_triangle_intersection(Vec3::new(0.25, 0.25, 2.0), Vec3::Z, &triangle),
            None
        );
        // Parallel to the plane, in it and off it: the infinite or NaN inverse determinant
        // must not produce a hit.
        for origin in [
            Vec3::new(-1.0, 0.25, 1.0),
            Vec3::new(-1.0, 0.25, 0.5),
            Vec3::new(0.1, 0.1, 1.0),
        ] {
            for direction in [Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y] {
                assert_eq!(
                    ray_triangle_intersection(origin, direction, &triangle),
                    None,
                    "{origin} {direction}"
                );
            }
        }
    }

    #[test]
    fn primary_ray_through_the_image_centre() {
        let direction = get_primary_ray_direction(
            0.5,
            0.5,
            Vec3::ZERO,
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        );
        assert_eq!(direction, -Vec3::Z);
    }
}
