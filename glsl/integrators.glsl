// What each integrator (the kernel's INTEGRATOR, an INTEGRATOR_* of glsl/shared.h) does,
// asked in one place: the path loop (glsl/path_loop.glsl) and main() (glsl/path_tracer.comp)
// ask these questions rather than compare INTEGRATOR themselves. Rust twin:
// `vkpath::render::settings::Integrator` (its `is_importance_sampled()` and friends).
// Needs INTEGRATOR defined by the includer.
#ifndef VKPATH_INTEGRATORS_GLSL
#define VKPATH_INTEGRATORS_GLSL

#include "shared.h"

// cosine, nee and mis: directions by importance sampling (the workshop's closing slide),
// drawn with get_path_random_numbers() at fixed dimension pairs (hashed PCG or Sobol,
// glsl/sample_dimensions.glsl), and Russian roulette.
bool is_importance_sampled() {
    return INTEGRATOR == INTEGRATOR_COSINE || INTEGRATOR == INTEGRATOR_NEE || INTEGRATOR == INTEGRATOR_MIS;
}

// nee and mis: a light sample at every path vertex (next event estimation).
bool takes_light_samples() {
    return INTEGRATOR == INTEGRATOR_NEE || INTEGRATOR == INTEGRATOR_MIS;
}

// mis: light samples and emission found by the path weighed against each other with the
// power heuristic (Veach 1997).
bool weighs_by_mis() {
    return INTEGRATOR == INTEGRATOR_MIS;
}

// cosine: directions by the cosine-weighted hemisphere around the geometric normal, whatever
// the surface (nee and mis sample the BSDF).
bool samples_cosine_directions() {
    return INTEGRATOR == INTEGRATOR_COSINE;
}

// The workshop's Exercises 6 (direct illumination) and 7 (path tracing): uniform hemisphere
// directions from get_random_numbers() (PCG2D, whatever SAMPLER is).
bool samples_uniform_directions() {
    return INTEGRATOR == INTEGRATOR_PATH_TRACING || INTEGRATOR == INTEGRATOR_DIRECT_ILLUMINATION;
}

// Exercise 6: emission plus one bounce of direct light, whatever MAX_PATH_LENGTH.
bool is_direct_illumination() {
    return INTEGRATOR == INTEGRATOR_DIRECT_ILLUMINATION;
}

// ray tracing (the base colour), normal, depth, material and the hit triangle: what the first
// hit shows, no path.
bool shows_first_hit() {
    return INTEGRATOR == INTEGRATOR_RAY_TRACING || INTEGRATOR == INTEGRATOR_NORMAL || INTEGRATOR == INTEGRATOR_DEPTH || INTEGRATOR == INTEGRATOR_MATERIAL || INTEGRATOR == INTEGRATOR_TRIANGLE;
}

#endif
