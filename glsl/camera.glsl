// Per-sample setup shared by every kernel that renders: the random seed of a sample and the
// primary ray through a pixel. Rust twins: src/cpu/camera.rs. Needs PIXEL_FILTER defined.
#ifndef VKPATH_CAMERA_GLSL
#define VKPATH_CAMERA_GLSL

#include "scene.glsl"

// The random state of sample `sample_index` of a pixel. The workshop seeds frame s of the
// pixel at pixel_coord with uvec2(pixel_coord) ^ uvec2(iFrame << 16); sample s is seeded the
// same way, so that the stream depends only on (seed, pixel, sample) and not on how samples
// are split into frames. The user's seed is spread over both words by odd multipliers
// (golden-ratio and another Weyl constant), which is 0 for seed 0: seed 0 is exactly the
// workshop's formula. The workshop's shift keeps only the low 16 bits of the index, so
// sample s + 2^16 would repeat sample s's random numbers; the high 16 bits go into the
// second word's high half (XOR the low bits, which is the workshop's formula below 2^16),
// so that every (pixel, sample) of images up to 65536 pixels wide and high has its own seed.
// \param pixel Pixel index, counted from the bottom-left as ShaderToy does
// \param sample_index Index of the sample within the pixel, from 0
// \param user_seed The --seed option
uvec2 get_sample_seed(uvec2 pixel, uint sample_index, uint user_seed) {
    uvec2 sample_bits = uvec2(sample_index << 16, (sample_index ^ (sample_index >> 16)) << 16);
    return (pixel ^ sample_bits) ^ (uvec2(2654435769u, 2246822507u) * user_seed);
}

// The point of the image in [0,1]^2 that a sample of a pixel looks through: the centre with
// PIXEL_FILTER_CENTER (the workshop's fragCoord / iResolution), or a uniformly jittered point
// of the pixel with PIXEL_FILTER_BOX, which consumes one pair of random numbers.
// \param pixel Pixel index from the bottom-left
// \param resolution Image size in pixels
// \param seed The sample's random state
vec2 get_sample_tex_coord(uvec2 pixel, uvec2 resolution, inout uvec2 seed) {
    vec2 offset = (PIXEL_FILTER == PIXEL_FILTER_CENTER) ? vec2(0.5) : get_random_numbers(seed);
    return (vec2(pixel) + offset) / vec2(resolution);
}

#endif
