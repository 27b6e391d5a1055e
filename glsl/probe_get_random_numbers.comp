#version 460
// Probe of get_random_numbers() (PCG2D): one step from each input seed. Host side:
// vkpath::probe (RandomNumbersInput, RandomNumbersOutput).

#include "probe_common.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

struct probe_input_t {
    uvec4 seed; // xy: the seed before the call, zw: unused
};

struct probe_output_t {
    // xy: the seed after the call, zw: the bits of the two random numbers (floatBitsToUint),
    // so that the host compares them bit for bit.
    uvec4 seed_and_numbers;
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
    uvec2 seed = g_inputs[index].seed.xy;
    vec2 numbers = get_random_numbers(seed);
    g_outputs[index].seed_and_numbers = uvec4(seed, floatBitsToUint(numbers));
    FINISH_PROBE(index);
}
