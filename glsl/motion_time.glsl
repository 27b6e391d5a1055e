// Motion blur: the time within the shutter that a sample sees the scene at (g_path.time,
// read by glsl/scene.glsl's get_packed_triangle() and get_camera_at_time()). Uniform in the
// shutter, as a box shutter opens it (Blender's and pbrt's default).
// Needs SAMPLER defined and glsl/integrators.glsl included by the includer.
#ifndef VKPATH_MOTION_TIME_GLSL
#define VKPATH_MOTION_TIME_GLSL

#include "workshop.glsl"
#include "sobol.glsl"
#include "sample_dimensions.glsl"

// XORed into a sample's PCG2D seed to give the workshop integrators' time sample a stream of
// its own ("time" in ASCII, and a second odd word).
const uvec2 TIME_SEED_MASK = uvec2(0x74696d65u, 0x9e3779b1u);

// The sample's time within the shutter, uniform in [0, 1), at a dimension of its own: for
// the importance-sampled integrators the first number of the fixed pair CAMERA_PAIR_TIME
// (glsl/sample_dimensions.glsl: Sobol, stratified across a pixel's samples, or hashed PCG);
// for the workshop's, PCG2D of the sample's seed XOR TIME_SEED_MASK, which leaves the
// sample's own PCG2D stream (and so the workshop's draws) as it was.
// \param sample_seed get_sample_seed() of the sample
float get_time_random_number(uvec2 sample_seed) {
    if (is_importance_sampled())
        return get_path_random_numbers(CAMERA_PAIR_TIME)[0];
    uvec2 time_seed = sample_seed ^ TIME_SEED_MASK;
    return get_random_numbers(time_seed)[0];
}

#endif
