#version 460
// Probe of the light tree (glsl/light_tree.glsl): for each input, sample_light_tree() with
// its random number at its shading point, get_light_tree_probability() of the light it
// chose and of the input's light, and get_light_bounds_importance() of the root. Host side:
// vkpath::probe::light_tree_probe (LightTreeProbeInput, LightTreeProbeOutput),
// tests/light_tree.rs; Rust twins: src/cpu/light_tree.rs.
//
// Descriptor set 0: BINDING_LIGHTS (the words of gpu_light_bytes_with_tree), then
// PROBE_BINDING_INPUTS and PROBE_BINDING_OUTPUTS. Self-contained: it binds no scene.

#include "shared.h"

layout(set = 0, binding = BINDING_LIGHTS) uniform utextureBuffer g_light_texels;

#include "light_tree.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

// Which inputs this dispatch covers. Mirrors `vkpath::probe::ProbePushConstants`.
layout(push_constant) uniform probe_push_constants {
    // Index of the input that invocation 0 of this dispatch evaluates.
    uint g_probe_first;
    // Number of inputs in the buffer: invocations past it do nothing.
    uint g_probe_count;
};

struct probe_input_t {
    vec4 position_random; // xyz: the shading point, world space; w: the random number
    vec4 normal;          // xyz: the receiving side's unit normal (or 0); w: unused
    uvec4 light_index;    // x: the light of get_light_tree_probability(); yzw: unused
};

struct probe_output_t {
    uvec4 light;         // x: the light sample_light_tree() chose (NO_LIGHT: none); y: the
                         // tree's depth; zw: 0
    vec4 probabilities;  // x: its out_probability; y: get_light_tree_probability() of that
                         // light (0 for NO_LIGHT); z: of the input's light; w: the root's
                         // get_light_bounds_importance()
};

layout(std430, set = 0, binding = PROBE_BINDING_INPUTS) readonly buffer probe_inputs {
    probe_input_t g_inputs[];
};
layout(std430, set = 0, binding = PROBE_BINDING_OUTPUTS) writeonly buffer probe_outputs {
    probe_output_t g_outputs[];
};

void main() {
    uint index = g_probe_first + gl_GlobalInvocationID.x;
    if (index >= g_probe_count)
        return;
    probe_input_t probe_input = g_inputs[index];
    vec3 position = probe_input.position_random.xyz;
    vec3 normal = probe_input.normal.xyz;
    float probability;
    uint light = sample_light_tree(probe_input.position_random.w, position, normal, probability);
    probe_output_t result;
    result.light = uvec4(light, get_light_tree_depth(), 0u, 0u);
    float walked = (light == NO_LIGHT) ? 0.0 : get_light_tree_probability(light, position, normal);
    float given = get_light_tree_probability(probe_input.light_index.x, position, normal);
    float root = get_light_bounds_importance(get_light_tree_node(0u), position, normal);
    result.probabilities = vec4(probability, walked, given, root);
    g_outputs[index] = result;
}
