//! Deterministic random inputs for the probes, shared by the tests and `vkpath check`: a
//! small seeded generator (SplitMix64) and generators of rays, triangles, seeds and camera
//! points, so that every run compares the same cases.

use glam::{UVec2, Vec2, Vec3};

use crate::camera::{Camera, ImagePlane};
use crate::cpu::camera::get_sample_seed;
use crate::cpu::workshop::get_random_numbers;
use crate::probe::layout::{
    DirectIlluminationInput, PrimaryRayInput, RayInput, RayRadianceInput, RayTriangleInput,
    SamplerInput,
};
use crate::scene::Triangle;

/// SplitMix64 (Steele, Lea and Flood, OOPSLA 2014): a fast, well-mixed 64-bit generator,
/// independent of the PCG2D under test.
#[derive(Clone, Debug)]
pub struct InputRng {
    state: u64,
}

impl InputRng {
    /// A generator whose sequence depends only on `seed`.
    pub fn new(seed: u64) -> InputRng {
        InputRng { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// The next 32 random bits.
    pub fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }

    /// Uniform in [0, 1): 24 random bits, every value exact in f32.
    pub fn uniform(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Uniform in [low, high).
    pub fn range(&mut self, low: f32, high: f32) -> f32 {
        low + (high - low) * self.uniform()
    }

    /// Uniform in the box [low, high) (per component).
    pub fn in_box(&mut self, low: Vec3, high: Vec3) -> Vec3 {
        Vec3::new(
            self.range(low.x, high.x),
            self.range(low.y, high.y),
            self.range(low.z, high.z),
        )
    }

    /// A uniformly distributed unit vector (z = 2u - 1, phi = 2 pi u', in f64).
    pub fn unit_vector(&mut self) -> Vec3 {
        let z = 2.0 * f64::from(self.uniform()) - 1.0;
        let phi = std::f64::consts::TAU * f64::from(self.uniform());
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32)
    }
}

/// `count` seeds for PCG2D: the per-pixel seeds of the renderer (`get_sample_seed` of a
/// 64 x 64 image, samples 0..4) first, then random 64-bit ones, and the corner cases 0 and
/// u32::MAX.
pub fn random_seeds(rng: &mut InputRng, count: usize) -> Vec<UVec2> {
    let mut seeds = vec![UVec2::ZERO, UVec2::MAX, UVec2::new(0, u32::MAX)];
    'pixels: for sample in 0..4 {
        for y in 0..64 {
            for x in 0..64 {
                if seeds.len() >= count / 2 {
                    break 'pixels;
                }
                let seed = get_sample_seed(UVec2::new(x, y), sample, 0);
                if seed != UVec2::ZERO {
                    seeds.push(seed);
                }
            }
        }
    }
    while seeds.len() < count {
        seeds.push(UVec2::new(rng.next_u32(), rng.next_u32()));
    }
    seeds.truncate(count);
    seeds
}

/// `count` pairs of random numbers from one sequential PCG2D stream (the CPU twin, which is
/// bit-exact with the shader), as a sampler receives them.
pub fn pcg_random_numbers(seed: UVec2, count: usize) -> Vec<Vec2> {
    let mut state = seed;
    (0..count).map(|_| get_random_numbers(&mut state)).collect()
}

/// Sampler inputs from `random_numbers`, all with the same `normal`.
pub fn sampler_inputs(random_numbers: &[Vec2], normal: Vec3) -> Vec<SamplerInput> {
    random_numbers
        .iter()
        .map(|&numbers| SamplerInput::new(numbers, normal))
        .collect()
}

/// `count` random rays against random triangles: vertices in [-1, 1]^3, origins in
/// [-3, 3]^3, each ray aimed at a point of the triangle's plane with barycentric
/// coordinates in [-0.25, 1.25]^2 (inside the triangle for 0.5 / 2.25 = 22% of them), with a
/// length in [0.25, 4], and a quarter pointing away (hits behind the origin must count as
/// misses): about 1/6 of the cases hit.
pub fn ray_triangle_cases(rng: &mut InputRng, count: usize) -> Vec<RayTriangleInput> {
    let mut cases = Vec::with_capacity(count);
    while cases.len() < count {
        let positions = [0; 3].map(|_| rng.in_box(Vec3::splat(-1.0), Vec3::splat(1.0)));
        let Some(triangle) = Triangle::new(positions, Vec3::splat(0.5), Vec3::ZERO, false) else {
            continue;
        };
        let origin = rng.in_box(Vec3::splat(-3.0), Vec3::splat(3.0));
        let (a, b) = (rng.range(-0.25, 1.25), rng.range(-0.25, 1.25));
        let target =
            positions[0] + a * (positions[1] - positions[0]) + b * (positions[2] - positions[0]);
        let Some(towards) = (target - origin).try_normalize() else {
            continue;
        };
        let sign = if rng.uniform() < 0.25 { -1.0 } else { 1.0 };
        let direction = sign * rng.range(0.25, 4.0) * towards;
        cases.push(RayTriangleInput::new(origin, direction, &triangle));
    }
    cases
}

/// The box of the scene's vertices, shrunk by `margin` (a fraction of its size) on every
/// side.
fn inner_box(triangles: &[Triangle], margin: f32) -> (Vec3, Vec3) {
    let (low, high) = triangles.iter().flat_map(|t| t.positions).fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(low, high), p| (low.min(p), high.max(p)),
    );
    let inset = margin * (high - low);
    (low + inset, high - inset)
}

/// `count` rays from uniformly random points inside the scene's bounding box (shrunk by 5%
/// per side) in uniformly random directions.
pub fn rays_inside(rng: &mut InputRng, triangles: &[Triangle], count: usize) -> Vec<RayInput> {
    let (low, high) = inner_box(triangles, 0.05);
    (0..count)
        .map(|_| RayInput::new(rng.in_box(low, high), rng.unit_vector()))
        .collect()
}

/// `count` points of random pinhole cameras: positions in [-5, 5]^3 looking at points in
/// [-1, 1]^3, vertical field of view in [0.3, 2] radians, aspect ratio in [0.5, 2], and
/// image points in [0, 1]^2.
pub fn primary_ray_cases(rng: &mut InputRng, count: usize) -> Vec<PrimaryRayInput> {
    let mut cases = Vec::with_capacity(count);
    while cases.len() < count {
        let position = rng.in_box(Vec3::splat(-5.0), Vec3::splat(5.0));
        let target = rng.in_box(Vec3::splat(-1.0), Vec3::splat(1.0));
        let forward = target - position;
        if forward.length() < 0.5 || forward.normalize().cross(Vec3::Y).length() < 0.1 {
            continue;
        }
        let camera = Camera::look_at(position, target, Vec3::Y, rng.range(0.3, 2.0));
        let plane = camera.image_plane(rng.range(0.5, 2.0));
        let tex_coord = Vec2::new(rng.uniform(), rng.uniform());
        cases.push(PrimaryRayInput::new(tex_coord, &plane));
    }
    cases
}

/// A uniformly random point of a triangle (the square-root warp of two uniform numbers).
fn point_on_triangle(rng: &mut InputRng, positions: [Vec3; 3]) -> Vec3 {
    let (u, v) = (rng.uniform().sqrt(), rng.uniform());
    positions[0] * (1.0 - u) + positions[1] * (u * (1.0 - v)) + positions[2] * (u * v)
}

/// `count` inputs for `compute_direct_illumination`: a uniformly random triangle of the scene,
/// a uniformly random point on it and a random seed.
pub fn direct_illumination_cases(
    rng: &mut InputRng,
    triangles: &[Triangle],
    count: usize,
) -> Vec<DirectIlluminationInput> {
    if triangles.is_empty() {
        return Vec::new();
    }
    (0..count)
        .map(|_| {
            let index = (rng.next_u64() % triangles.len() as u64) as u32;
            let point = point_on_triangle(rng, triangles[index as usize].positions);
            let seed = UVec2::new(rng.next_u32(), rng.next_u32());
            DirectIlluminationInput::new(point, index, seed)
        })
        .collect()
}

/// `count` camera paths for `get_ray_radiance`: rays from the pinhole of `plane` through
/// uniformly random points of the image, each with a random seed.
pub fn camera_path_cases(
    rng: &mut InputRng,
    plane: &ImagePlane,
    count: usize,
) -> Vec<RayRadianceInput> {
    (0..count)
        .map(|_| {
            let point = plane.left_bottom + rng.uniform() * plane.right + rng.uniform() * plane.up;
            let direction = (point - plane.camera_position).normalize();
            let seed = UVec2::new(rng.next_u32(), rng.next_u32());
            RayRadianceInput::new(plane.camera_position, direction, seed)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generator_is_deterministic_and_uniform() {
        let mut a = InputRng::new(5);
        let mut b = InputRng::new(5);
        assert_eq!(a.next_u64(), b.next_u64());
        let mean: f64 = (0..10_000).map(|_| f64::from(a.uniform())).sum::<f64>() / 1e4;
        // Standard deviation of the mean of 10^4 uniforms: 0.0029; 0.015 is 5 of them.
        assert!((mean - 0.5).abs() < 0.015, "{mean}");
        for _ in 0..1000 {
            assert!((a.unit_vector().length() - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn ray_triangle_cases_hit_about_a_sixth_of_the_time() {
        let mut rng = InputRng::new(1);
        let cases = ray_triangle_cases(&mut rng, 4000);
        let hits = cases
            .iter()
            .filter(|c| {
                crate::probe::compare::ray_triangle_geometry(
                    c.ray_origin(),
                    c.ray_direction(),
                    c.positions(),
                )
                .is_some_and(|g| g.hits())
            })
            .count();
        // 3/4 point towards the triangle, and the aim point is inside for 22% of those:
        // 1/6 of all, 667 expected (binomial standard deviation 24).
        assert!(hits > 500 && hits < 850, "{hits} hits of 4000");
    }

    #[test]
    fn seeds_include_pixels_and_corners() {
        let seeds = random_seeds(&mut InputRng::new(2), 100);
        assert_eq!(seeds.len(), 100);
        assert_eq!(seeds[1], UVec2::MAX);
        assert!(seeds.contains(&get_sample_seed(UVec2::new(3, 0), 0, 0)));
    }
}
