#version 460
// Probe of get_ray_radiance() (Exercise 7): one path per input through the scene bound at
// BINDING_TRIANGLES, with the input's random state and MAX_PATH_LENGTH from the
// SPEC_MAX_PATH_LENGTH specialization constant. Host side: vkpath::probe (RayRadianceInput,
// RadianceOutput).

#include "probe_common.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

struct probe_input_t {
    vec4 ray_origin;    // xyz: world space, w: unused
    vec4 ray_direction; // xyz: world space, w: unused
    uvec4 seed;         // xy: the random state, zw: unused
};

struct probe_output_t {
    vec4 radiance; // rgb: the estimate, a: 0
    uvec4 seed;    // xy: the random state after the call, zw: 0
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
    uvec2 seed = probe_input.seed.xy;
    vec3 radiance = get_ray_radiance(probe_input.ray_origin.xyz, probe_input.ray_direction.xyz, seed);
    g_outputs[index].radiance = vec4(radiance, 0.0);
    g_outputs[index].seed = uvec4(seed, 0u, 0u);
    FINISH_PROBE(index);
}
