#version 460
// Probe of sample_hemisphere(): a direction for each pair of random
// numbers and normal. Host side: vkpath::probe (SamplerInput, DirectionOutput).

#include "probe_common.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

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
    g_outputs[index].direction = vec4(sample_hemisphere(probe_input.random_numbers.xy, probe_input.normal.xyz), 0.0);
    FINISH_PROBE(index);
}
