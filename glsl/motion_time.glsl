// Motion blur: the time within the shutter that a sample sees the scene at (g_motion_time,
// read by glsl/scene.glsl's get_packed_triangle() and get_camera_at_time()), and the camera
// ray at it. Uniform in the
// shutter, as a box shutter opens it (Blender's and pbrt's default).
// Needs SAMPLER defined and glsl/integrators.glsl included by the includer.
#ifndef VKPATH_MOTION_TIME_GLSL
#define VKPATH_MOTION_TIME_GLSL

#include "workshop.glsl"
#include "sobol.glsl"
#include "sample_dimensions.glsl"
#include "thin_lens.glsl"

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

// Motion blur: draws the sample's time into g_motion_time and makes the camera ray the one
// the camera at that time (get_camera_at_time()) shoots through the same point of the image,
// through the same point of the lens.
// \param out_ray_origin, out_ray_direction The camera ray, world space
// \param tex_coord The sample's point of the image in [0,1]^2
// \param sample_seed get_sample_seed() of the sample
void get_moving_camera_ray(out vec3 out_ray_origin, out vec3 out_ray_direction, vec2 tex_coord, uvec2 sample_seed) {
    g_motion_time = get_time_random_number(sample_seed);
    vec4 position, left_bottom, right, up;
    get_camera_at_time(position, left_bottom, right, up);
    out_ray_direction = get_primary_ray_direction(tex_coord.x, tex_coord.y, position.xyz, left_bottom.xyz, right.xyz, up.xyz);
    out_ray_origin = position.xyz;
    if (position.w > 0.0) {
        vec3 image_plane_middle = left_bottom.xyz + 0.5 * (right.xyz + up.xyz);
        apply_thin_lens(out_ray_origin, out_ray_direction, right.xyz, up.xyz, image_plane_middle, position.w, left_bottom.w, uint(right.w), up.w, get_lens_random_numbers(sample_seed));
    }
}

#endif
