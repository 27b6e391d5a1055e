// A homogeneous participating medium: absorption and scattering coefficients per RGB
// channel (per scene unit) and a Henyey-Greenstein phase function (glsl/phase_function.glsl).
// Here are its transmittance and its distance sampler, the pieces the path loop
// (glsl/path_loop.glsl) and the shadow rays (get_shadow_transmittance(), glsl/lights.glsl)
// need; no majorant or null scattering, which a heterogeneous medium will add.
//
// Chromatic media (pbrt-v4's VolPathIntegrator, Mitsuba 3's volpath): the extinction
// sigma_t = sigma_a + sigma_s differs per channel, so no one exponential distance density is
// proportional to every channel's transmittance. The sampler picks a channel c uniformly
// (u_0) and draws t ~ sigma_t,c exp(-sigma_t,c t) (u_1); the weights divide by the density of
// the whole mixture, the mean over channels (one-sample MIS with the balance heuristic over
// the channels, the spectral MIS of Miller, Georgiev and Jarosz 2019 for a homogeneous
// medium), which keeps every channel unbiased:
// - scattering at t < t_surface: weight sigma_s T(t) / mean_c(sigma_t,c T_c(t));
// - passing to the surface at t_surface: weight T(t_surface) / mean_c(T_c(t_surface)).
// For a grey medium both weights are the albedo sigma_s / sigma_t and 1, as in the textbook.
//
// The global medium of a render (--medium) is g_medium, from specialization constants:
// SCENE_HAS_MEDIUM false (every render without --medium) compiles the medium out of the path
// loop, the vertex functions and the shadow rays.
//
// Rust twin: src/cpu/medium.rs (same names, same maths).
#ifndef VKPATH_MEDIUM_GLSL
#define VKPATH_MEDIUM_GLSL

#include "shared.h"
#include "phase_function.glsl"

// A homogeneous medium. Coefficients per scene unit of length, linear RGB, each >= 0.
struct medium_t {
    // sigma_a: the fraction of light absorbed per unit length
    vec3 absorption;
    // sigma_s: the fraction of light scattered per unit length
    vec3 scattering;
    // g of the Henyey-Greenstein phase function, in (-1, 1)
    float anisotropy;
};

// sigma_t = sigma_a + sigma_s: the fraction of light taken out of a ray per unit length.
vec3 get_medium_extinction(medium_t medium) {
    return medium.absorption + medium.scattering;
}

// Beer-Lambert: the fraction of light per channel that crosses `distance` of the medium,
// exp(-sigma_t distance); 0 where sigma_t > 0 and distance is NO_HIT_T (infinitely far), 1
// where sigma_t = 0.
vec3 get_medium_transmittance(medium_t medium, float distance) {
    return exp(-get_medium_extinction(medium) * distance);
}

// A distance along a ray at which the medium scatters or absorbs: a channel c chosen by u_0,
// then t = -ln(1 - u_1) / sigma_t,c; NO_HIT_T (never) where sigma_t,c = 0.
// \param random_numbers (u_0, u_1) in [0, 1)^2
float sample_medium_distance(medium_t medium, vec2 random_numbers) {
    vec3 extinction = get_medium_extinction(medium);
    uint channel = min(uint(random_numbers[0] * 3.0), 2u);
    float sigma = extinction[channel];
    return (sigma > 0.0) ? -log(1.0 - random_numbers[1]) / sigma : NO_HIT_T;
}

// Density w.r.t. distance with which sample_medium_distance() returns `distance`: the mean
// over the channels of sigma_t,c exp(-sigma_t,c distance).
float get_medium_distance_density(medium_t medium, float distance) {
    vec3 extinction = get_medium_extinction(medium);
    vec3 densities = extinction * exp(-extinction * distance);
    return (densities.r + densities.g + densities.b) / 3.0;
}

// The probability that sample_medium_distance() returns a distance beyond `distance`: the
// mean over the channels of exp(-sigma_t,c distance).
float get_medium_passing_probability(medium_t medium, float distance) {
    vec3 transmittance = get_medium_transmittance(medium, distance);
    return (transmittance.r + transmittance.g + transmittance.b) / 3.0;
}

// The throughput weight of a scattering event sampled at `distance`:
// sigma_s T(distance) / get_medium_distance_density() (0 where the density underflowed).
vec3 get_medium_scattering_weight(medium_t medium, float distance) {
    float density = get_medium_distance_density(medium, distance);
    return (density > 0.0) ? medium.scattering * get_medium_transmittance(medium, distance) / density : vec3(0.0);
}

// The throughput weight of a ray that passed `distance` of the medium without an event:
// T(distance) / get_medium_passing_probability() (0 where the probability is 0).
vec3 get_medium_passing_weight(medium_t medium, float distance) {
    float probability = get_medium_passing_probability(medium, distance);
    return (probability > 0.0) ? get_medium_transmittance(medium, distance) / probability : vec3(0.0);
}

#endif
