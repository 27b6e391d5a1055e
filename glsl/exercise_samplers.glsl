// Samplers that the workshop shows but does not use for rendering: the naive spherical-
// coordinates sampler of the slide "Non-uniform sphere sampling" ("Problem: Too many samples
// at the top"), which `vkpath exercise spherical-coords` displays next to the uniform
// sample_sphere() of Exercise 4. Rust twins: src/cpu/workshop.rs.
#ifndef VKPATH_EXERCISE_SAMPLERS_GLSL
#define VKPATH_EXERCISE_SAMPLERS_GLSL

#include "workshop.glsl"

vec3 sample_sphere_spherical_coordinates(vec2 random_numbers);

#ifndef USER_DEFINES_SAMPLE_SPHERE_SPHERICAL_COORDINATES
// Maps two uniform random numbers to a direction on the unit sphere with spherical
// coordinates, the slides' cautionary example. It is *not* uniform: the density is
// 1 / (2 pi^2 sin(theta)) w.r.t. solid angle, crowded at the poles (z = +-1).
// phi = 2 pi u_0, theta = pi u_1
// omega = (cos(phi) sin(theta), sin(phi) sin(theta), cos(theta))
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \return A unit vector
vec3 sample_sphere_spherical_coordinates(vec2 random_numbers) {
    float phi = 2.0 * M_PI * random_numbers[0];
    float theta = M_PI * random_numbers[1];
    return vec3(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
}
#endif

#endif
