//! Rust twins of `glsl/environment.glsl`: the environment's lookup, its alias-table sampler
//! and the sampler's density, reading the same words the GPU reads
//! (`vkpath::render::gpu_lights::gpu_environment_words`).

use glam::{Vec2, Vec3};

use crate::contract::{ENVIRONMENT_MAP, ENVIRONMENT_NONE};
use crate::cpu::workshop::{sample_sphere, M_PI};

/// The words of `g_environment_texels` as the twins read them.
pub struct EnvironmentTexels<'a> {
    /// RGBA32_UINT texels, four words each.
    pub words: &'a [u32],
}

impl EnvironmentTexels<'_> {
    fn texel(&self, index: usize) -> [u32; 4] {
        let start = 4 * index;
        [
            self.words[start],
            self.words[start + 1],
            self.words[start + 2],
            self.words[start + 3],
        ]
    }

    fn float_texel(&self, index: usize) -> [f32; 4] {
        self.texel(index).map(f32::from_bits)
    }
}

/// Twin of `get_environment_kind`.
pub fn get_environment_kind(texels: &EnvironmentTexels) -> u32 {
    texels.texel(0)[2]
}

/// Twin of `rotate_about_y`.
pub fn rotate_about_y(direction: Vec3, cosine: f32, sine: f32) -> Vec3 {
    Vec3::new(
        cosine * direction.x + sine * direction.z,
        direction.y,
        -sine * direction.x + cosine * direction.z,
    )
}

/// Twin of `get_environment_uv`.
pub fn get_environment_uv(map_direction: Vec3) -> Vec2 {
    Vec2::new(
        0.5 + map_direction.x.atan2(-map_direction.z) / (2.0 * M_PI),
        map_direction.y.clamp(-1.0, 1.0).acos() / M_PI,
    )
}

/// Twin of `get_environment_texel_index`.
pub fn get_environment_texel_index(texels: &EnvironmentTexels, direction: Vec3) -> u32 {
    let header = texels.texel(0);
    let rotation = texels.float_texel(1);
    let uv = get_environment_uv(rotate_about_y(direction, rotation[1], -rotation[2]));
    let x = ((uv.x * header[0] as f32).max(0.0) as u32).min(header[0] - 1);
    let y = ((uv.y * header[1] as f32).max(0.0) as u32).min(header[1] - 1);
    y * header[0] + x
}

/// Twin of `get_environment_radiance`.
pub fn get_environment_radiance(texels: &EnvironmentTexels, direction: Vec3) -> Vec3 {
    if get_environment_kind(texels) == ENVIRONMENT_MAP {
        let index = 3 + 2 * get_environment_texel_index(texels, direction) as usize;
        return Vec3::from_slice(&texels.float_texel(index)[..3]);
    }
    Vec3::from_slice(&texels.float_texel(2)[..3])
}

/// Twin of `sample_environment`.
pub fn sample_environment(texels: &EnvironmentTexels, random_numbers: Vec2) -> Vec3 {
    let header = texels.texel(0);
    if header[2] != ENVIRONMENT_MAP {
        return sample_sphere(random_numbers);
    }
    let count = header[0] * header[1];
    let scaled = random_numbers[0] * count as f32;
    let bucket = (scaled as u32).min(count - 1);
    let mut fraction = scaled - bucket as f32;
    let alias = texels.texel(4 + 2 * bucket as usize);
    let threshold = f32::from_bits(alias[0]);
    let mut texel = bucket;
    if fraction < threshold {
        fraction /= threshold;
    } else {
        texel = alias[1];
        fraction = (fraction - threshold) / (1.0 - threshold);
    }
    let u = ((texel % header[0]) as f32 + fraction.min(0.99999994)) / header[0] as f32;
    let v = ((texel / header[0]) as f32 + random_numbers[1]) / header[1] as f32;
    let theta = v * M_PI;
    let phi = (u - 0.5) * 2.0 * M_PI;
    let map_direction = Vec3::new(
        theta.sin() * phi.sin(),
        theta.cos(),
        -theta.sin() * phi.cos(),
    );
    let rotation = texels.float_texel(1);
    rotate_about_y(map_direction, rotation[1], rotation[2])
}

/// Twin of `get_environment_density`.
pub fn get_environment_density(texels: &EnvironmentTexels, direction: Vec3) -> f32 {
    let header = texels.texel(0);
    if header[2] != ENVIRONMENT_MAP {
        return 1.0 / (4.0 * M_PI);
    }
    let index = 3 + 2 * get_environment_texel_index(texels, direction) as usize;
    let probability = texels.float_texel(index)[3];
    let sin_theta = (1.0 - direction.y * direction.y).max(0.0).sqrt();
    if sin_theta > 0.0 {
        probability * (header[0] * header[1]) as f32 / (2.0 * M_PI * M_PI * sin_theta)
    } else {
        0.0
    }
}

/// Whether the environment is black (nothing to sample).
pub fn is_black(texels: &EnvironmentTexels) -> bool {
    get_environment_kind(texels) == ENVIRONMENT_NONE
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::workshop::get_random_numbers;
    use crate::render::gpu_lights::gpu_environment_words;
    use crate::scene::environment::{Environment, EnvironmentMap};
    use crate::stats::chi2::{chi2_direction_test, Chi2Config};
    use crate::stats::sphere_histogram::{SphereFrame, TargetDensity};
    use glam::UVec2;

    fn test_map() -> Environment {
        // 16 x 8 texels: a gradient, a bright texel, a black row.
        let mut texels: Vec<Vec3> = (0..128)
            .map(|i| Vec3::new(0.1 + (i % 16) as f32 * 0.05, 0.2, 0.3))
            .collect();
        texels[3 * 16 + 5] = Vec3::splat(40.0);
        for texel in &mut texels[16 * 6..16 * 7] {
            *texel = Vec3::ZERO;
        }
        Environment {
            map: Some(EnvironmentMap {
                width: 16,
                height: 8,
                texels,
            }),
            background: Vec3::ZERO,
            strength: 2.0,
            rotation_degrees: 40.0,
        }
    }

    #[test]
    fn the_map_sampler_follows_its_density() {
        let words = gpu_environment_words(Some(&test_map()));
        let texels = EnvironmentTexels { words: &words };
        let mut seed = UVec2::new(5, 77);
        let samples: Vec<Vec3> = (0..1_000_000)
            .map(|_| sample_environment(&texels, get_random_numbers(&mut seed)))
            .collect();
        let density = |d: Vec3| f64::from(get_environment_density(&texels, d));
        // The density is piecewise constant with jumps at texel edges, which Simpson's rule
        // blurs in the bins they cross: with the default 6 (or 24) intervals per bin that
        // error alone rejected the correct sampler (chi2 5006 for 4613 dof at 24); 96
        // intervals put it below the noise of 10^6 samples.
        let config = Chi2Config {
            quadrature_resolution: 96,
            ..Chi2Config::default()
        };
        let result = chi2_direction_test(
            samples,
            TargetDensity::SolidAngle(&density),
            &SphereFrame::WORLD,
            &config,
        )
        .unwrap();
        println!(
            "environment sampler: p = {:.4}, chi2 = {:.1}, dof {}",
            result.p_value, result.statistic, result.degrees_of_freedom
        );
        assert!(result.passed, "{result:?}");
        // No sample lands in the black row (zero weight).
        assert_eq!(result.impossible_sample_count, 0);
    }

    #[test]
    fn convention_centre_is_minus_z_and_rotation_turns_minus_z_to_minus_x() {
        assert!((get_environment_uv(Vec3::NEG_Z) - Vec2::new(0.5, 0.5)).length() < 1e-6);
        assert!(get_environment_uv(Vec3::Y).y.abs() < 1e-6);
        let mut map = test_map();
        map.rotation_degrees = 90.0;
        map.strength = 1.0;
        let words = gpu_environment_words(Some(&map));
        let texels = EnvironmentTexels { words: &words };
        // Unrotated, -Z looks up the centre texel (8, 4); turned by 90 degrees, -X does.
        let centre = get_environment_radiance(&texels, Vec3::NEG_X);
        assert_eq!(centre, map.map.unwrap().texels[4 * 16 + 8]);
    }
}
