//! Rust twins of `glsl/integrators.glsl`: what each integrator (a kernel's `INTEGRATOR`, an
//! `INTEGRATOR_*` of the contract) does, asked in one place.

use crate::contract::{
    INTEGRATOR_COSINE, INTEGRATOR_DEPTH, INTEGRATOR_DIRECT_ILLUMINATION, INTEGRATOR_MATERIAL,
    INTEGRATOR_MIS, INTEGRATOR_NEE, INTEGRATOR_NORMAL, INTEGRATOR_PATH_TRACING,
    INTEGRATOR_RAY_TRACING, INTEGRATOR_TRIANGLE,
};

/// Twin of `is_importance_sampled`: cosine, nee and mis.
pub fn is_importance_sampled(integrator: u32) -> bool {
    matches!(
        integrator,
        INTEGRATOR_COSINE | INTEGRATOR_NEE | INTEGRATOR_MIS
    )
}

/// Twin of `takes_light_samples`: nee and mis.
pub fn takes_light_samples(integrator: u32) -> bool {
    matches!(integrator, INTEGRATOR_NEE | INTEGRATOR_MIS)
}

/// Twin of `weighs_by_mis`: mis.
pub fn weighs_by_mis(integrator: u32) -> bool {
    integrator == INTEGRATOR_MIS
}

/// Twin of `samples_cosine_directions`: cosine.
pub fn samples_cosine_directions(integrator: u32) -> bool {
    integrator == INTEGRATOR_COSINE
}

/// Twin of `samples_uniform_directions`: the workshop's Exercises 6 and 7.
pub fn samples_uniform_directions(integrator: u32) -> bool {
    matches!(
        integrator,
        INTEGRATOR_PATH_TRACING | INTEGRATOR_DIRECT_ILLUMINATION
    )
}

/// Twin of `is_direct_illumination`: Exercise 6.
pub fn is_direct_illumination(integrator: u32) -> bool {
    integrator == INTEGRATOR_DIRECT_ILLUMINATION
}

/// Twin of `shows_first_hit`: ray tracing, normal, depth, material and the hit triangle.
pub fn shows_first_hit(integrator: u32) -> bool {
    matches!(
        integrator,
        INTEGRATOR_RAY_TRACING
            | INTEGRATOR_NORMAL
            | INTEGRATOR_DEPTH
            | INTEGRATOR_MATERIAL
            | INTEGRATOR_TRIANGLE
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_integrator_is_in_exactly_one_family() {
        // Each integrator is a first-hit view, a workshop estimator or importance sampled;
        // light samples only for importance-sampled ones, MIS only with light samples.
        for integrator in 0..=INTEGRATOR_TRIANGLE {
            let families = [
                shows_first_hit(integrator),
                samples_uniform_directions(integrator),
                is_importance_sampled(integrator),
            ];
            assert_eq!(families.iter().filter(|f| **f).count(), 1, "{integrator}");
            assert!(!takes_light_samples(integrator) || is_importance_sampled(integrator));
            assert!(!weighs_by_mis(integrator) || takes_light_samples(integrator));
            assert!(!samples_cosine_directions(integrator) || is_importance_sampled(integrator));
        }
    }
}
