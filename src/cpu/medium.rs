//! Rust twin of `glsl/medium.glsl`: a homogeneous medium's transmittance and its chromatic
//! distance sampler (a channel chosen uniformly, weights divided by the mean density over the
//! channels). Same names, same maths as the GLSL; `crate::medium::Medium` is the twin of
//! `medium_t`.

use glam::{Vec2, Vec3};

use crate::contract::NO_HIT_T;
use crate::medium::Medium;

/// Twin of `get_medium_extinction`: sigma_t = sigma_a + sigma_s.
pub fn get_medium_extinction(medium: &Medium) -> Vec3 {
    medium.absorption + medium.scattering
}

/// Twin of `get_medium_transmittance`: exp(-sigma_t distance) per channel.
pub fn get_medium_transmittance(medium: &Medium, distance: f32) -> Vec3 {
    (-get_medium_extinction(medium) * distance).exp()
}

/// Twin of `sample_medium_distance`: channel c = floor(3 u_0), t = -ln(1 - u_1) / sigma_t,c;
/// `NO_HIT_T` where sigma_t,c = 0.
pub fn sample_medium_distance(medium: &Medium, random_numbers: Vec2) -> f32 {
    let extinction = get_medium_extinction(medium);
    let channel = ((random_numbers[0] * 3.0) as usize).min(2);
    let sigma = extinction[channel];
    if sigma > 0.0 {
        -(1.0 - random_numbers[1]).ln() / sigma
    } else {
        NO_HIT_T
    }
}

/// Twin of `get_medium_distance_density`: the mean over the channels of
/// sigma_t,c exp(-sigma_t,c distance), w.r.t. distance.
pub fn get_medium_distance_density(medium: &Medium, distance: f32) -> f32 {
    let extinction = get_medium_extinction(medium);
    let densities = extinction * (-extinction * distance).exp();
    (densities.x + densities.y + densities.z) / 3.0
}

/// Twin of `get_medium_passing_probability`: the mean over the channels of
/// exp(-sigma_t,c distance).
pub fn get_medium_passing_probability(medium: &Medium, distance: f32) -> f32 {
    let transmittance = get_medium_transmittance(medium, distance);
    (transmittance.x + transmittance.y + transmittance.z) / 3.0
}

/// Twin of `get_medium_scattering_weight`: sigma_s T(distance) / the distance density.
pub fn get_medium_scattering_weight(medium: &Medium, distance: f32) -> Vec3 {
    let density = get_medium_distance_density(medium, distance);
    if density > 0.0 {
        medium.scattering * get_medium_transmittance(medium, distance) / density
    } else {
        Vec3::ZERO
    }
}

/// Twin of `get_medium_passing_weight`: T(distance) / the passing probability.
pub fn get_medium_passing_weight(medium: &Medium, distance: f32) -> Vec3 {
    let probability = get_medium_passing_probability(medium, distance);
    if probability > 0.0 {
        get_medium_transmittance(medium, distance) / probability
    } else {
        Vec3::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::workshop::get_random_numbers;
    use glam::{DVec3, UVec2};

    /// A chromatic medium: every channel's extinction and albedo differ, one channel
    /// scatters nothing.
    fn chromatic() -> Medium {
        Medium {
            absorption: Vec3::new(0.05, 0.4, 1.2),
            scattering: Vec3::new(0.9, 0.6, 0.0),
            anisotropy: 0.3,
        }
    }

    /// The mean and the standard error of the mean of `n` estimates per channel.
    fn mean_and_error(n: usize, mut estimate: impl FnMut() -> Vec3) -> (DVec3, DVec3) {
        let (mut sum, mut sum_of_squares) = (DVec3::ZERO, DVec3::ZERO);
        for _ in 0..n {
            let x = estimate().as_dvec3();
            sum += x;
            sum_of_squares += x * x;
        }
        let mean = sum / n as f64;
        let variance = (sum_of_squares / n as f64 - mean * mean).max(DVec3::ZERO);
        (mean, (variance / n as f64).max(DVec3::ZERO).powf(0.5))
    }

    /// The estimator of the path loop over one segment of length d that ends at a surface of
    /// radiance `surface`, in a medium whose every point scatters radiance `inscattered`
    /// towards the ray (a constant source): scatter at t < d with weight
    /// get_medium_scattering_weight, or pass with get_medium_passing_weight. Its expectation
    /// is the closed form of the radiative transfer equation for a constant source:
    /// L = T(d) L_surface + sigma_s / sigma_t (1 - T(d)) L_inscattered per channel. The
    /// fixed-seed mean must lie within 5 standard errors of it in every channel (a normal
    /// deviation that large has probability 6e-7), and with the surface alone (sigma_s L = 0)
    /// the mean is the transmittance: Beer-Lambert by sampling.
    #[test]
    fn the_distance_sampler_is_unbiased_against_the_closed_forms() {
        let inscattered = Vec3::new(0.7, 1.3, 2.0);
        let surface = Vec3::new(1.0, 0.5, 3.0);
        for (medium, d) in [
            (chromatic(), 1.5),
            (chromatic(), 0.1),
            (chromatic(), NO_HIT_T),
            (
                Medium {
                    absorption: Vec3::ZERO,
                    scattering: Vec3::new(2.0, 0.5, 0.0),
                    anisotropy: 0.0,
                },
                0.8,
            ),
        ] {
            let mut seed = UVec2::new(6, 11);
            let (mean, error) = mean_and_error(400_000, || {
                let random_numbers = get_random_numbers(&mut seed);
                let t = sample_medium_distance(&medium, random_numbers);
                if t < d {
                    get_medium_scattering_weight(&medium, t) * inscattered
                } else {
                    get_medium_passing_weight(&medium, d) * surface
                }
            });
            let extinction = get_medium_extinction(&medium).as_dvec3();
            let transmittance = (-extinction * f64::from(d)).exp();
            let albedo = DVec3::select(
                extinction.cmpgt(DVec3::ZERO),
                medium.scattering.as_dvec3() / extinction,
                DVec3::ZERO,
            );
            let expected = transmittance * surface.as_dvec3()
                + albedo * (DVec3::ONE - transmittance) * inscattered.as_dvec3();
            for c in 0..3 {
                let allowed = 5.0 * error[c] + 1e-6 * expected[c];
                assert!(
                    (mean[c] - expected[c]).abs() <= allowed,
                    "d = {d}, channel {c}: mean {} expected {} (5 sigma {allowed})",
                    mean[c],
                    expected[c]
                );
            }
        }
    }

    /// The transmittance estimator alone: the passing weight times the indicator of passing,
    /// whose mean is exp(-sigma_t d) per channel (Beer-Lambert), within 5 standard errors.
    #[test]
    fn passing_weights_estimate_the_transmittance() {
        let medium = chromatic();
        for d in [0.3f32, 2.0, 5.0] {
            let mut seed = UVec2::new(1, 2);
            let (mean, error) = mean_and_error(200_000, || {
                let t = sample_medium_distance(&medium, get_random_numbers(&mut seed));
                if t < d {
                    Vec3::ZERO
                } else {
                    get_medium_passing_weight(&medium, d)
                }
            });
            let expected = get_medium_transmittance(&medium, d).as_dvec3();
            for c in 0..3 {
                assert!(
                    (mean[c] - expected[c]).abs() <= 5.0 * error[c] + 1e-6,
                    "d = {d}, channel {c}: {} vs {}",
                    mean[c],
                    expected[c]
                );
            }
        }
    }

    /// The density integrates to 1 - the passing probability: what is not sampled before d
    /// passes it (trapezoid rule over 10 000 steps, error far below 1e-4).
    #[test]
    fn the_distance_density_and_the_passing_probability_agree() {
        let medium = chromatic();
        let d = 3.0f64;
        let n = 10_000;
        let mut integral = 0.0;
        for i in 0..n {
            let (a, b) = (d * i as f64 / n as f64, d * (i + 1) as f64 / n as f64);
            integral += 0.5
                * (b - a)
                * f64::from(
                    get_medium_distance_density(&medium, a as f32)
                        + get_medium_distance_density(&medium, b as f32),
                );
        }
        let passing = f64::from(get_medium_passing_probability(&medium, d as f32));
        assert!(
            (integral + passing - 1.0).abs() < 1e-4,
            "{integral} + {passing}"
        );
        // A vacuum never scatters and always passes with weight 1
        let vacuum = Medium::VACUUM;
        assert_eq!(
            sample_medium_distance(&vacuum, Vec2::new(0.5, 0.5)),
            NO_HIT_T
        );
        assert_eq!(get_medium_passing_weight(&vacuum, NO_HIT_T), Vec3::ONE);
    }
}
