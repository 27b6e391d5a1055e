//! Rust twins of `glsl/environment.glsl`: the environment's lookup, its alias-table sampler
//! and the sampler's density, reading the same words the GPU reads
//! (`vkpath::lights::gpu_environment::gpu_environment_words`).

use glam::{Vec2, Vec3};

use crate::contract::{ENVIRONMENT_MAP, ENVIRONMENT_NONE};
use crate::cpu::texels::{fetch_float_texel, fetch_texel};
use crate::cpu::workshop::{sample_sphere, M_PI};

/// The words of `g_environment_texels` as the twins read them.
pub struct EnvironmentTexels<'a> {
    /// RGBA32_UINT texels, four words each.
    pub words: &'a [u32],
}

impl EnvironmentTexels<'_> {
    fn texel(&self, index: usize) -> [u32; 4] {
        fetch_texel(self.words, index).to_array()
    }

    fn float_texel(&self, index: usize) -> [f32; 4] {
        fetch_float_texel(self.words, index).to_array()
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

/// Twin of `sample_environment`: a texel from the alias table (`texel_randoms`: the bucket,
/// then the bucket's texel or its alias), a point uniform in solid angle over it
/// (`point_randoms`: phi, cos theta); uniform on the sphere (`texel_randoms`) for a constant
/// colour.
pub fn sample_environment(
    texels: &EnvironmentTexels,
    texel_randoms: Vec2,
    point_randoms: Vec2,
) -> Vec3 {
    let header = texels.texel(0);
    if header[2] != ENVIRONMENT_MAP {
        return sample_sphere(texel_randoms);
    }
    let count = header[0] * header[1];
    let bucket = ((texel_randoms[0] * count as f32) as u32).min(count - 1);
    let alias = texels.texel(4 + 2 * bucket as usize);
    let texel = if texel_randoms[1] < f32::from_bits(alias[0]) {
        bucket
    } else {
        alias[1]
    };
    let row = (texel / header[0]) as f32;
    let phi =
        (((texel % header[0]) as f32 + point_randoms[0]) / header[0] as f32 - 0.5) * 2.0 * M_PI;
    let cos_top = (M_PI * row / header[1] as f32).cos();
    let cos_bottom = (M_PI * (row + 1.0) / header[1] as f32).cos();
    let cos_theta = cos_top + point_randoms[1] * (cos_bottom - cos_top);
    let sin_theta = ((1.0 - cos_theta) * (1.0 + cos_theta)).max(0.0).sqrt();
    let map_direction = Vec3::new(sin_theta * phi.sin(), cos_theta, -sin_theta * phi.cos());
    let rotation = texels.float_texel(1);
    rotate_about_y(map_direction, rotation[1], rotation[2])
}

/// Twin of `get_environment_density`.
pub fn get_environment_density(texels: &EnvironmentTexels, direction: Vec3) -> f32 {
    if get_environment_kind(texels) != ENVIRONMENT_MAP {
        return 1.0 / (4.0 * M_PI);
    }
    let index = 3 + 2 * get_environment_texel_index(texels, direction) as usize;
    texels.float_texel(index)[3]
}

/// Whether the environment is black (nothing to sample).
pub fn is_black(texels: &EnvironmentTexels) -> bool {
    get_environment_kind(texels) == ENVIRONMENT_NONE
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::workshop::get_random_numbers;
    use crate::lights::gpu_environment::gpu_environment_words;
    use crate::lights::{Environment, EnvironmentMap};
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
            .map(|_| {
                let texel_randoms = get_random_numbers(&mut seed);
                sample_environment(&texels, texel_randoms, get_random_numbers(&mut seed))
            })
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

#[cfg(test)]
mod sun_tests {
    //! Issue 18: nee and mis were 0.2-0.3 % dark under a large map with a sharp sun. These
    //! tests run the twins' light estimator on such a map, against the closed form.
    use super::*;
    use crate::cpu::importance_sampling::{
        get_hemisphere_cosine_density, get_power_heuristic_weight, sample_hemisphere_cosine,
    };
    use crate::cpu::sobol::get_sobol_sample_2d;
    use crate::cpu::workshop::get_random_numbers;
    use crate::lights::gpu_environment::gpu_environment_words;
    use crate::lights::{Environment, EnvironmentMap};
    use glam::{DVec3, UVec2};
    use std::f64::consts::{PI, TAU};

    /// A 512 x 256 sky (0.2, 0.3, 0.5) with a Gaussian sun (sigma 1.5 degrees, 40 degrees
    /// up, peak ~1000x the sky's luminance), black below the horizon, turned by 30 degrees.
    fn sun_sky() -> Environment {
        let (width, height) = (512u32, 256u32);
        let sun = DVec3::new(0.3, 0.64, -0.7).normalize();
        let sigma = 1.5f64.to_radians();
        let mut texels = Vec::new();
        for y in 0..height {
            let theta = PI * (f64::from(y) + 0.5) / f64::from(height);
            for x in 0..width {
                let phi = ((f64::from(x) + 0.5) / f64::from(width) - 0.5) * TAU;
                let d = DVec3::new(
                    theta.sin() * phi.sin(),
                    theta.cos(),
                    -theta.sin() * phi.cos(),
                );
                let angle = d.dot(sun).clamp(-1.0, 1.0).acos();
                let falloff = (-0.5 * (angle / sigma).powi(2)).exp() as f32;
                let radiance =
                    Vec3::new(0.2, 0.3, 0.5) + Vec3::new(1.0, 0.9, 0.7) * 300.0 * falloff;
                texels.push(if 2 * y < height { radiance } else { Vec3::ZERO });
            }
        }
        Environment {
            map: Some(EnvironmentMap {
                width,
                height,
                texels,
            }),
            background: Vec3::ZERO,
            strength: 1.0,
            rotation_degrees: 30.0,
        }
    }

    /// The irradiance on a surface facing +Y, divided by pi: per texel row [theta_0, theta_1]
    /// of the upper hemisphere, L delta_phi (sin^2 theta_1 - sin^2 theta_0) / 2 exactly (a
    /// turn about +Y changes nothing).
    fn exact(environment: &Environment) -> DVec3 {
        let map = environment.map.as_ref().unwrap();
        let theta = |row: u32| PI * f64::from(row) / f64::from(map.height);
        let mut total = DVec3::ZERO;
        for y in 0..map.height / 2 {
            let band = 0.5 * TAU / f64::from(map.width)
                * (theta(y + 1).sin().powi(2) - theta(y).sin().powi(2));
            for x in 0..map.width {
                total += map.texels[(y * map.width + x) as usize].as_dvec3() * band;
            }
        }
        total / PI
    }

    #[test]
    fn light_samples_of_a_sharp_sun_in_a_large_map_are_unbiased_to_a_few_hundredths_of_a_percent() {
        let environment = sun_sky();
        let words = gpu_environment_words(Some(&environment));
        let texels = EnvironmentTexels { words: &words };
        let normal = Vec3::Y;
        let reference = exact(&environment);
        // 2^22 samples: the light estimator's relative standard deviation is ~0.5 per sample
        // (L / p is constant in luminance; the cosine and the colour vary), so ~0.025 % for
        // the mean (measured: 0.024-0.030 %). Before the fix the kernels were 0.27 % dark in
        // red with PCG on this map (tests/lights_render.rs, measured on lavapipe).
        let count = 1u32 << 22;
        for sobol in [false, true] {
            let mut seed = UVec2::new(3, 9);
            let (mut nee, mut nee_squares, mut mis, mut mis_squares) =
                (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
            for s in 0..count {
                // Three pairs per sample, drawn as the kernels draw them: the texel, the point
                // in it, then the cosine direction that MIS weighs against it.
                let mut draw = |pair: u32| {
                    if sobol {
                        get_sobol_sample_2d(s & 4095, pair, s >> 12)
                    } else {
                        get_random_numbers(&mut seed)
                    }
                };
                let (texel_randoms, point_randoms, cosine_randoms) = (draw(0), draw(1), draw(2));
                let light = sample_environment(&texels, texel_randoms, point_randoms);
                let density = get_environment_density(&texels, light);
                let mut light_estimate = Vec3::ZERO;
                if density > 0.0 && light.y > 0.0 {
                    light_estimate =
                        get_environment_radiance(&texels, light) * light.y / M_PI / density;
                }
                let cosine_density = get_hemisphere_cosine_density(normal, light);
                let mut mis_estimate =
                    light_estimate * get_power_heuristic_weight(density, cosine_density);
                let bounce = sample_hemisphere_cosine(cosine_randoms, normal);
                let bounce_density = get_hemisphere_cosine_density(normal, bounce);
                if bounce_density > 0.0 {
                    let weight = get_power_heuristic_weight(
                        bounce_density,
                        get_environment_density(&texels, bounce),
                    );
                    mis_estimate += get_environment_radiance(&texels, bounce) * bounce.y
                        / M_PI
                        / bounce_density
                        * weight;
                }
                let (l, m) = (light_estimate.as_dvec3(), mis_estimate.as_dvec3());
                nee += l;
                nee_squares += l * l;
                mis += m;
                mis_squares += m * m;
            }
            let n = f64::from(count);
            for (name, sum, squares) in [("nee", nee, nee_squares), ("mis", mis, mis_squares)] {
                let mean = sum / n;
                let sigma = ((squares / n - mean * mean) / (n - 1.0))
                    .max(DVec3::ZERO)
                    .powf(0.5);
                let z = (mean - reference) / sigma;
                println!(
                    "sobol {sobol} {name}: mean / exact - 1 = {:+.5?} %, z {z:.2?}",
                    (mean / reference - DVec3::ONE) * 100.0
                );
                // |z| < 4 in each channel (a false alarm in 6e-5 of them); sigma below 0.05 %
                // so that the 0.27 % of issue 18 is more than 5 sigma. (For Sobol the
                // sample variance overstates the error, which only makes the test stricter.)
                assert!(z.abs().max_element() < 4.0, "sobol {sobol} {name}: z {z:?}");
                assert!((sigma / reference).max_element() < 5e-4, "{sigma:?}");
            }
        }
    }
}
