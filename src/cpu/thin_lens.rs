//! Rust twins of `glsl/thin_lens.glsl`: depth of field, a thin lens in front of the
//! workshop's pinhole. The pinhole's ray meets the plane in focus (parallel to the image plane,
//! `focus_distance` from the pinhole); the lens's ray leaves from a point of the aperture
//! towards that point.

use glam::{UVec2, Vec2, Vec3};

use crate::camera::ImagePlane;
use crate::cpu::sample_dimensions::CAMERA_PAIR_LENS;
use crate::cpu::sobol::{get_path_random_numbers, PathSample};
use crate::cpu::workshop::{get_random_numbers, M_PI};

/// XORed into a sample's PCG2D seed for the workshop integrators' lens stream, twin of
/// `LENS_SEED_MASK`.
pub const LENS_SEED_MASK: UVec2 = UVec2::new(0x6c65_6e73, 0x44f3_a5c1);

/// Twin of GLSL `get_lens_random_numbers`: the two numbers of a sample's aperture point, at a
/// dimension of their own: `CAMERA_PAIR_LENS` of `sample` (Sobol or hashed PCG) for the
/// importance-sampled integrators, else PCG2D of the sample's seed XOR `LENS_SEED_MASK`, so
/// that the sample's other numbers are what they were without a lens.
pub fn get_lens_random_numbers(
    sample_seed: UVec2,
    sample: &PathSample,
    importance_sampled: bool,
) -> Vec2 {
    if importance_sampled {
        return get_path_random_numbers(sample, CAMERA_PAIR_LENS);
    }
    let mut lens_seed = sample_seed ^ LENS_SEED_MASK;
    get_random_numbers(&mut lens_seed)
}

/// Twin of GLSL `sample_aperture`: a point of the unit aperture, uniform in its area: the unit
/// disc (`blades` 0) by Shirley and Chiu's concentric map, else the regular polygon with
/// `blades` corners on the unit circle, one at angle pi/2 + `rotation`.
pub fn sample_aperture(random_numbers: Vec2, blades: u32, rotation: f32) -> Vec2 {
    if blades == 0 {
        let offset = 2.0 * random_numbers - Vec2::ONE;
        if offset.x == 0.0 && offset.y == 0.0 {
            return Vec2::ZERO;
        }
        let (radius, angle) = if offset.x.abs() > offset.y.abs() {
            (offset.x, 0.25 * M_PI * (offset.y / offset.x))
        } else {
            (offset.y, 0.5 * M_PI - 0.25 * M_PI * (offset.x / offset.y))
        };
        return radius * Vec2::new(angle.cos(), angle.sin());
    }
    let scaled = random_numbers.x * blades as f32;
    let corner = scaled.floor().min((blades - 1) as f32);
    let along = (scaled - corner).sqrt();
    let corner_angle = 2.0 * M_PI / blades as f32;
    let first_angle = 0.5 * M_PI + rotation + corner * corner_angle;
    let first_corner = Vec2::new(first_angle.cos(), first_angle.sin());
    let second_angle = first_angle + corner_angle;
    let second_corner = Vec2::new(second_angle.cos(), second_angle.sin());
    along * first_corner.lerp(second_corner, random_numbers.y)
}

/// Twin of GLSL `apply_thin_lens`: the lens's ray (origin, direction) for the pinhole's ray
/// `(ray_origin, ray_direction)` through the image plane `plane`, whose `lens` it applies.
pub fn apply_thin_lens(
    ray_origin: Vec3,
    ray_direction: Vec3,
    plane: &ImagePlane,
    random_numbers: Vec2,
) -> (Vec3, Vec3) {
    let lens = &plane.lens;
    let right_direction = plane.right.normalize();
    let up_direction = plane.up.normalize();
    let image_plane_middle = plane.left_bottom + 0.5 * (plane.right + plane.up);
    let mut view_axis = plane.right.cross(plane.up).normalize();
    if view_axis.dot(image_plane_middle - ray_origin) < 0.0 {
        view_axis = -view_axis;
    }
    let focus_point =
        ray_origin + (lens.focus_distance / ray_direction.dot(view_axis)) * ray_direction;
    let aperture_point =
        lens.aperture_radius * sample_aperture(random_numbers, lens.blades, lens.rotation);
    let origin = ray_origin + aperture_point.x * right_direction + aperture_point.y * up_direction;
    (origin, (focus_point - origin).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Camera, Lens};

    fn uniform_grid(n: u32) -> impl Iterator<Item = Vec2> {
        (0..n * n).map(move |i| {
            Vec2::new(
                ((i % n) as f32 + 0.5) / n as f32,
                ((i / n) as f32 + 0.5) / n as f32,
            )
        })
    }

    #[test]
    fn a_disc_aperture_fills_the_unit_disc_evenly() {
        // 40,000 points of a Fibonacci lattice (evenly spread, no axis-aligned rows, whose
        // radii the concentric map would bunch) map into the disc, and each of 8 rings of
        // equal area times 8 sectors holds 1/64 of them: 625 each, within 3 % (the lattice's
        // discrepancy is far below that; a map that is not area-preserving, e.g. radius =
        // the first number, puts 1/64 of the points in the innermost ring, not 1/8 - 8x off).
        let count = 40_000u32;
        let golden = 0.5 * (5f64.sqrt() - 1.0);
        let mut cells = [[0u32; 8]; 8];
        for i in 0..count {
            let random = Vec2::new(
                (i as f32 + 0.5) / count as f32,
                (f64::from(i) * golden).fract() as f32,
            );
            let point = sample_aperture(random, 0, 0.0);
            let radius_squared = point.length_squared();
            assert!(radius_squared <= 1.0 + 1e-5, "{point} outside the disc");
            let ring = ((radius_squared * 8.0) as usize).min(7);
            let angle = point.y.atan2(point.x).rem_euclid(2.0 * M_PI);
            let sector = ((angle / (2.0 * M_PI) * 8.0) as usize).min(7);
            cells[ring][sector] += 1;
        }
        for count in cells.iter().flatten() {
            assert!((*count as f32 - 625.0).abs() <= 0.03 * 625.0, "{cells:?}");
        }
    }

    #[test]
    fn a_polygon_aperture_has_its_corners_and_nothing_outside() {
        for blades in [3u32, 5, 6, 8] {
            let rotation = 0.3;
            let corner_angle = 2.0 * M_PI / blades as f32;
            // The inscribed circle's radius: every point lies inside each edge's half plane.
            let apothem = (0.5 * corner_angle).cos();
            let mut farthest = 0.0f32;
            for random in uniform_grid(100) {
                let point = sample_aperture(random, blades, rotation);
                for k in 0..blades {
                    let mid = 0.5 * M_PI + rotation + (k as f32 + 0.5) * corner_angle;
                    let normal = Vec2::new(mid.cos(), mid.sin());
                    assert!(point.dot(normal) <= apothem + 1e-5, "{blades}: {point}");
                }
                farthest = farthest.max(point.length());
            }
            // Points reach close to the corners (radius 1), beyond the inscribed circle.
            assert!(
                farthest > 0.97 && farthest <= 1.0 + 1e-5,
                "{blades}: {farthest}"
            );
        }
        // The first corner points up for rotation 0: the end of triangle 0's range reaches
        // its first corner where the second number is 0.
        let corner = sample_aperture(Vec2::new(1.0 / 3.0 - 1e-7, 0.0), 3, 0.0);
        assert!(corner.abs_diff_eq(Vec2::new(0.0, 1.0), 1e-3), "{corner}");
    }

    #[test]
    fn rays_of_one_image_point_meet_on_the_focus_plane() {
        let mut camera = Camera::look_at(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, Vec3::Y, 0.8);
        camera.lens = Lens {
            aperture_radius: 0.2,
            focus_distance: 3.0,
            blades: 6,
            rotation: 0.1,
        };
        let plane = camera.image_plane(1.5);
        let pinhole = plane.camera_position;
        let direction =
            (plane.left_bottom + 0.3 * plane.right + 0.7 * plane.up - pinhole).normalize();
        let axis = (Vec3::ZERO - pinhole).normalize();
        let expected = pinhole + 3.0 / direction.dot(axis) * direction;
        for random in uniform_grid(7) {
            let (origin, lens_direction) = apply_thin_lens(pinhole, direction, &plane, random);
            // On the aperture: within its radius of the pinhole, in the lens plane.
            assert!((origin - pinhole).length() <= 0.2 + 1e-5);
            assert!((origin - pinhole).dot(axis).abs() < 1e-5);
            // Through the focus point.
            let t = (expected - origin).dot(axis) / lens_direction.dot(axis);
            let met = origin + t * lens_direction;
            assert!(met.abs_diff_eq(expected, 1e-4), "{met} != {expected}");
        }
    }

    #[test]
    fn lens_numbers_leave_the_sample_stream_alone_and_differ_from_it() {
        use crate::contract::{SAMPLER_PCG, SAMPLER_SOBOL};
        let seed = UVec2::new(12, 34);
        let mut stream = seed;
        let first = get_random_numbers(&mut stream);
        let pcg = PathSample::new(SAMPLER_PCG, UVec2::new(3, 4), 5, 7);
        let workshop = get_lens_random_numbers(seed, &pcg, false);
        assert_ne!(first, workshop);
        let sobol = PathSample::new(SAMPLER_SOBOL, UVec2::new(3, 4), 5, 7);
        let lens = get_lens_random_numbers(seed, &sobol, true);
        assert_eq!(lens, get_path_random_numbers(&sobol, CAMERA_PAIR_LENS));
        assert_ne!(lens, get_path_random_numbers(&sobol, 0));
    }
}
