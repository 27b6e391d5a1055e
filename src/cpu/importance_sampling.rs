//! Rust twins of `glsl/importance_sampling.glsl`: cosine-weighted hemisphere sampling,
//! points and directions on light triangles (by area, or by solid angle on spherical
//! triangles) and the power heuristic. Same names, same maths.

use glam::{Vec2, Vec3};

use crate::contract::{
    LIGHT_SAMPLING_SOLID_ANGLE, MAX_SPHERICAL_SAMPLING_SOLID_ANGLE,
    MIN_SPHERICAL_SAMPLING_SOLID_ANGLE,
};
use crate::cpu::shading_basis::get_shading_basis;
use crate::cpu::workshop::M_PI;
use crate::scene::Triangle;

/// Twin of `sample_hemisphere_cosine`: Malley's method in the Duff et al. (2017) basis.
pub fn sample_hemisphere_cosine(random_numbers: Vec2, normal: Vec3) -> Vec3 {
    // The shading basis around n (`crate::cpu::shading_basis`).
    let basis = get_shading_basis(normal);
    let radius = random_numbers[0].sqrt();
    let phi = 2.0 * M_PI * random_numbers[1];
    let x = radius * phi.cos();
    let y = radius * phi.sin();
    let z = (1.0 - random_numbers[0]).max(0.0).sqrt();
    x * basis.x_axis + y * basis.y_axis + z * basis.z_axis
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

/// Twin of `spherical_triangle_t`: a triangle's vertices projected onto the unit sphere around
/// a point, and the solid angle it subtends there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphericalTriangle {
    /// Unit vectors from the point to the triangle's vertices A, B, C.
    pub vertices: [Vec3; 3],
    /// The solid angle the triangle subtends (`get_solid_angle`).
    pub solid_angle: f32,
}

/// Twin of `get_solid_angle`: Van Oosterom and Strackee's
/// tan(omega / 2) = |a.(b x c)| / (1 + a.b + b.c + c.a) for unit vectors a, b, c.
pub fn get_solid_angle(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let numerator = a.dot(b.cross(c)).abs();
    let denominator = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
    2.0 * numerator.atan2(denominator)
}

/// Twin of `get_spherical_triangle`.
pub fn get_spherical_triangle(origin: Vec3, triangle: &Triangle) -> SphericalTriangle {
    let vertices = triangle
        .positions
        .map(|position| (position - origin).normalize());
    SphericalTriangle {
        vertices,
        solid_angle: get_solid_angle(vertices[0], vertices[1], vertices[2]),
    }
}

/// Twin of `use_spherical_sampling`; `light_sampling` is the kernel's `LIGHT_SAMPLING`. The
/// solid-angle thresholds (steradians) are `glsl/shared.h`'s, which says why they are there.
pub fn use_spherical_sampling(light_sampling: u32, spherical: &SphericalTriangle) -> bool {
    light_sampling == LIGHT_SAMPLING_SOLID_ANGLE
        && (MIN_SPHERICAL_SAMPLING_SOLID_ANGLE..=MAX_SPHERICAL_SAMPLING_SOLID_ANGLE)
            .contains(&spherical.solid_angle)
}

/// Twin of `sample_spherical_triangle` (Arvo 1995): uniform in the spherical triangle's solid
/// angle.
pub fn sample_spherical_triangle(random_numbers: Vec2, spherical: &SphericalTriangle) -> Vec3 {
    let [a, b, c] = spherical.vertices;
    let normal_ab = a.cross(b).normalize();
    let normal_ac = a.cross(c).normalize();
    let cos_alpha = normal_ab.dot(normal_ac);
    let sin_alpha = normal_ab.cross(normal_ac).length();
    let sub_area = random_numbers[0] * spherical.solid_angle;
    let sin_sub_area = sub_area.sin();
    let cos_sub_area = sub_area.cos();
    let sin_phi = sin_sub_area * cos_alpha - cos_sub_area * sin_alpha;
    let cos_phi = cos_sub_area * cos_alpha + sin_sub_area * sin_alpha;
    let u = cos_phi - cos_alpha;
    let v = sin_phi + sin_alpha * a.dot(b);
    let sin_half_area = (0.5 * sub_area).sin();
    let sin_half_area_minus_alpha = sin_half_area * cos_alpha - (0.5 * sub_area).cos() * sin_alpha;
    let denominator = (v * sin_phi + u * cos_phi) * sin_alpha;
    let one_minus_q =
        (2.0 * sin_half_area * (v * sin_half_area - sin_half_area_minus_alpha * sin_sub_area)
            / denominator)
            .clamp(0.0, 2.0);
    let c_sub = (1.0 - one_minus_q) * a
        + (one_minus_q * (2.0 - one_minus_q)).sqrt() * (c - c.dot(a) * a).normalize();
    let one_minus_z = random_numbers[1] * 0.5 * (c_sub - b).length_squared();
    (1.0 - one_minus_z) * b
        + (one_minus_z * (2.0 - one_minus_z)).sqrt() * (c_sub - c_sub.dot(b) * b).normalize()
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::workshop::get_random_numbers;
    use crate::stats::chi2::{chi2_direction_test, chi2_test, Chi2Config};
    use crate::stats::sphere_histogram::{SphereFrame, TargetDensity};
    use glam::DVec3;
    use glam::UVec2;

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

    /// Van Oosterom and Strackee's solid angle in f64: the reference for the f32 twins.
    fn solid_angle_f64(origin: DVec3, vertices: [DVec3; 3]) -> f64 {
        let [a, b, c] = vertices.map(|v| (v - origin).normalize());
        2.0 * a
            .dot(b.cross(c))
            .abs()
            .atan2(1.0 + a.dot(b) + b.dot(c) + c.dot(a))
    }

    /// The 4 children of a triangle under midpoint subdivision: the corners at v_0, v_1, v_2,
    /// then the middle one.
    fn subdivide(vertices: [DVec3; 3]) -> [[DVec3; 3]; 4] {
        let [v0, v1, v2] = vertices;
        let (m12, m20, m01) = ((v1 + v2) / 2.0, (v2 + v0) / 2.0, (v0 + v1) / 2.0);
        [
            [v0, m01, m20],
            [m01, v1, m12],
            [m20, m12, v2],
            [m12, m20, m01],
        ]
    }

    /// The leaves of `levels` midpoint subdivisions, in the order of `leaf_index`.
    fn leaves(vertices: [DVec3; 3], levels: u32) -> Vec<[DVec3; 3]> {
        if levels == 0 {
            return vec![vertices];
        }
        subdivide(vertices)
            .into_iter()
            .flat_map(|child| leaves(child, levels - 1))
            .collect()
    }

    /// Barycentric coordinates of a point in a triangle's plane.
    fn barycentrics(point: DVec3, [v0, v1, v2]: [DVec3; 3]) -> [f64; 3] {
        let normal = (v1 - v0).cross(v2 - v0);
        let area = normal.length_squared();
        let b1 = (point - v0).cross(v2 - v0).dot(normal) / area;
        let b2 = (v1 - v0).cross(point - v0).dot(normal) / area;
        [1.0 - b1 - b2, b1, b2]
    }

    /// Which leaf of `leaves(vertices, levels)` holds a point of the triangle's plane; None
    /// when the point lies outside the triangle by more than rounding.
    fn leaf_index(point: DVec3, mut vertices: [DVec3; 3], levels: u32) -> Option<usize> {
        if barycentrics(point, vertices).iter().any(|&b| b < -1e-4) {
            return None;
        }
        let mut index = 0;
        for _ in 0..levels {
            let b = barycentrics(point, vertices);
            let child = (0..3).find(|&i| b[i] >= 0.5).unwrap_or(3);
            index = 4 * index + child;
            vertices = subdivide(vertices)[child];
        }
        Some(index)
    }

    #[test]
    fn solid_angles_of_a_cube_around_the_point_sum_to_the_sphere() {
        // The 12 triangles of the cube [-1, 1]^3 seen from an off-centre point inside it.
        let origin = Vec3::new(0.3, -0.2, 0.55);
        let corner = |i: u32| {
            Vec3::new(
                if i & 1 != 0 { 1.0 } else { -1.0 },
                if i & 2 != 0 { 1.0 } else { -1.0 },
                if i & 4 != 0 { 1.0 } else { -1.0 },
            )
        };
        let faces = [
            [0, 1, 3, 2],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 3, 7, 5],
        ];
        let mut total = 0.0f64;
        for [p, q, r, s] in faces {
            for vertices in [[p, q, r], [p, r, s]] {
                let [a, b, c] = vertices.map(|i| (corner(i) - origin).normalize());
                total += f64::from(get_solid_angle(a, b, c));
            }
        }
        // 12 f32 atan2 results, each within a few ulps of at most 2 pi.
        assert!((total - 4.0 * std::f64::consts::PI).abs() < 1e-5, "{total}");
    }

    #[test]
    fn spherical_triangle_sampler_passes_chi2_on_sub_triangles() {
        // Each case: a triangle seen from the origin. Solid angles from just above
        // MIN_SPHERICAL_SAMPLING_SOLID_ANGLE to just below MAX_...; a sliver; an oblique one.
        let cases: [[Vec3; 3]; 5] = [
            [
                Vec3::new(-1.0, -1.0, 0.5),
                Vec3::new(1.0, -1.0, 0.5),
                Vec3::new(0.0, 1.0, 0.5),
            ],
            [
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(0.07, 0.0, 1.0),
                Vec3::new(0.0, 0.07, 1.0),
            ],
            [
                Vec3::new(-2.0, 0.0, 1.0),
                Vec3::new(2.0, 0.05, 1.0),
                Vec3::new(2.0, -0.05, 1.0),
            ],
            [
                Vec3::new(-30.0, -30.0, 1.0),
                Vec3::new(30.0, -30.0, 1.0),
                Vec3::new(0.0, 30.0, 1.0),
            ],
            [
                Vec3::new(0.2, 0.1, 0.3),
                Vec3::new(1.5, -0.4, 2.0),
                Vec3::new(-0.6, 0.9, 1.2),
            ],
        ];
        let levels = 3;
        let sample_count = 400_000u64;
        let config = Chi2Config {
            test_count: cases.len(),
            ..Chi2Config::default()
        };
        for (case, positions) in cases.into_iter().enumerate() {
            let triangle = Triangle::new(positions, Vec3::ONE, Vec3::ONE, false).unwrap();
            let spherical = get_spherical_triangle(Vec3::ZERO, &triangle);
            let vertices = positions.map(|p| p.as_dvec3());
            let total = solid_angle_f64(DVec3::ZERO, vertices);
            assert!(
                use_spherical_sampling(LIGHT_SAMPLING_SOLID_ANGLE, &spherical),
                "case {case}: solid angle {total}"
            );
            // Van Oosterom-Strackee in f32 against f64.
            assert!(
                (f64::from(spherical.solid_angle) - total).abs() < 1e-5 * total,
                "case {case}: {} vs {total}",
                spherical.solid_angle
            );
            let expected: Vec<f64> = leaves(vertices, levels)
                .into_iter()
                .map(|leaf| solid_angle_f64(DVec3::ZERO, leaf) / total * sample_count as f64)
                .collect();
            let mut observed = vec![0u64; expected.len()];
            let mut invalid = 0u64;
            let mut seed = UVec2::new(3, case as u32);
            let normal = triangle.normal.as_dvec3();
            for _ in 0..sample_count {
                let direction =
                    sample_spherical_triangle(get_random_numbers(&mut seed), &spherical).as_dvec3();
                let t = normal.dot(vertices[0]) / normal.dot(direction);
                match leaf_index(t * direction, vertices, levels) {
                    Some(index) if t > 0.0 && (direction.length() - 1.0).abs() < 1e-5 => {
                        observed[index] += 1
                    }
                    _ => invalid += 1,
                }
            }
            let result = chi2_test(&observed, &expected, invalid, &config).unwrap();
            println!("case {case}, solid angle {total:.4}: {result:?}");
            assert!(result.passed, "case {case}: {result:?}");
        }
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
