#version 460
// Probe of the punctual lights (glsl/punctual_lights.glsl): for each input,
// get_punctual_light_count(), get_punctual_light() of the input's light and
// get_punctual_irradiance() of that light at the input's origin. Host side:
// vkpath::probe::punctual_probe (PunctualProbeInput, PunctualProbeOutput),
// tests/punctual_twins.rs; Rust twins: src/cpu/punctual_lights.rs.
//
// Descriptor set 0: BINDING_PUNCTUAL_LIGHTS (the words of gpu_punctual_light_words), then
// PROBE_BINDING_INPUTS and PROBE_BINDING_OUTPUTS. Self-contained: unlike probe_common.glsl it
// binds no scene.

#include "shared.h"
#include "punctual_lights.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

// Which inputs this dispatch covers. Mirrors `vkpath::probe::ProbePushConstants`.
layout(push_constant) uniform probe_push_constants {
    // Index of the input that invocation 0 of this dispatch evaluates.
    uint g_probe_first;
    // Number of inputs in the buffer: invocations past it do nothing.
    uint g_probe_count;
};

struct probe_input_t {
    vec4 origin;       // xyz: the shading point of get_punctual_irradiance(), world space;
                       // w: unused
    uvec4 light_index; // x: the light of get_punctual_light(); yzw: unused
};

struct probe_output_t {
    vec4 irradiance_distance; // rgb: get_punctual_irradiance(); w: its out_distance
    vec4 direction;           // xyz: its out_direction; w: 0
    uvec4 kind_count;         // x: the light's kind; y: get_punctual_light_count(); zw: 0
    vec4 position;            // xyz: the light's position; w: 0
    vec4 light_direction;     // xyz: the light's direction; w: 0
    vec4 intensity;           // rgb: the light's intensity; a: 0
    vec4 cone;                // x: cone_scale; y: cone_offset; zw: 0
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
    punctual_light_t light = get_punctual_light(probe_input.light_index.x);
    vec3 direction;
    float distance;
    vec3 irradiance = get_punctual_irradiance(light, probe_input.origin.xyz, direction, distance);
    probe_output_t result;
    result.irradiance_distance = vec4(irradiance, distance);
    result.direction = vec4(direction, 0.0);
    result.kind_count = uvec4(light.kind, get_punctual_light_count(), 0, 0);
    result.position = vec4(light.position, 0.0);
    result.light_direction = vec4(light.direction, 0.0);
    result.intensity = vec4(light.intensity, 0.0);
    result.cone = vec4(light.cone_scale, light.cone_offset, 0.0, 0.0);
    g_outputs[index] = result;
}
