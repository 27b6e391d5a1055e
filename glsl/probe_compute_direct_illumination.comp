#version 460
// Probe of compute_direct_illumination() (Exercise 6): one estimate per input, at a point of
// a triangle of the scene bound at BINDING_TRIANGLES, with the input's random state. Host
// side: vkpath::probe (DirectIlluminationInput, RadianceOutput).

#include "probe_common.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

struct probe_input_t {
    vec4 shading_position; // xyz: a point on the triangle, world space, w: unused
    // xy: the random state, z: index of the triangle in the scene (passed as get_triangle()
    // returns it, not oriented), w: unused
    uvec4 seed_and_triangle;
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
    uvec2 seed = probe_input.seed_and_triangle.xy;
    triangle_t triangle = get_triangle(probe_input.seed_and_triangle.z);
    vec3 radiance = compute_direct_illumination(probe_input.shading_position.xyz, triangle, seed);
    g_outputs[index].radiance = vec4(radiance, 0.0);
    g_outputs[index].seed = uvec4(seed, 0u, 0u);
    FINISH_PROBE(index);
}
