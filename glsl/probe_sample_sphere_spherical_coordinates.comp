#version 460
// Probe of sample_sphere_spherical_coordinates(): the naive sampler that the χ² test
// must reject (test-only). Host side: vkpath::probe (SamplerInput, DirectionOutput).

#include "probe_common.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

// The naive sampler of the slides' cautionary example, which is *not* uniform: spherical
// coordinates phi = 2 pi u_0, theta = pi u_1 crowd the poles (density 1 / (2 pi^2 sin(theta))
// w.r.t. solid angle). Test-only: the χ² tests show that they reject it. Rust twin:
// vkpath::cpu::workshop::sample_sphere_spherical_coordinates.
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \return A unit vector
vec3 sample_sphere_spherical_coordinates(vec2 random_numbers) {
    float phi = 2.0 * M_PI * random_numbers[0];
    float theta = M_PI * random_numbers[1];
    return vec3(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
}

struct probe_input_t {
    vec4 random_numbers; // xy: (u_0, u_1) in [0,1)^2, zw: unused
    vec4 normal;         // xyz: unit normal (sample_hemisphere() only), w: unused
};

struct probe_output_t {
    vec4 direction; // xyz: the sampled direction, w: 0
};

layout(std430, set = 0, binding = PROBE_BINDING_INPUTS) readonly buffer probe_inputs {
    probe_input_t g_inputs[];
};
layout(std430, set = 0, binding = PROBE_BINDING_OUTPUTS) writeonly buffer probe_outputs {
    probe_output_t g_outputs[];
};

void main() {
    uint index;
    if (!get_probe_index(index))
        return;
    probe_input_t probe_input = g_inputs[index];
    g_outputs[index].direction = vec4(sample_sphere_spherical_coordinates(probe_input.random_numbers.xy), 0.0);
}
