#version 460
// Probe of a homogeneous medium (glsl/medium.glsl) and its phase function
// (glsl/phase_function.glsl): for each input, the phase function, its density and its sample,
// the medium's distance sample, transmittance, distance density, passing probability and
// weights, on the input's medium, directions, distance and random numbers. Host side:
// vkpath::probe::medium_probe (MediumProbeInput, MediumProbeOutput), tests/medium_twins.rs;
// Rust twins: src/cpu/medium.rs, src/cpu/phase_function.rs.
//
// Descriptor set 0: PROBE_BINDING_INPUTS and PROBE_BINDING_OUTPUTS only. Self-contained:
// unlike probe_common.glsl it binds no scene.

#include "shared.h"
#include "medium.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

// Which inputs this dispatch covers. Mirrors `vkpath::probe::ProbePushConstants`.
layout(push_constant) uniform probe_push_constants {
    // Index of the input that invocation 0 of this dispatch evaluates.
    uint g_probe_first;
    // Number of inputs in the buffer: invocations past it do nothing.
    uint g_probe_count;
};

struct probe_input_t {
    vec4 absorption_anisotropy; // rgb: medium_t.absorption; a: medium_t.anisotropy
    vec4 scattering_distance;   // rgb: medium_t.scattering; a: the distance of the
                                // transmittance, densities and weights
    vec4 view;                  // xyz: unit view direction, world space; w: unused
    vec4 direction;             // xyz: unit direction of get_phase_function(); w: unused
    vec4 random_numbers;        // xy: of sample_medium_distance(); zw: of
                                // sample_phase_function()
};

struct probe_output_t {
    vec4 phase;         // x: get_phase_function(view, direction, g); y: its density;
                        // z: get_henyey_greenstein(dot(view, direction), g);
                        // w: sample_medium_distance()
    vec4 sampled;       // xyz: sample_phase_function(); w: get_phase_function_density() there
    vec4 transmittance; // rgb: get_medium_transmittance(distance);
                        // a: get_medium_distance_density(distance)
    vec4 scattering;    // rgb: get_medium_scattering_weight(distance);
                        // a: get_medium_passing_probability(distance)
    vec4 passing;       // rgb: get_medium_passing_weight(distance); a: 0
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
    medium_t medium;
    medium.absorption = probe_input.absorption_anisotropy.rgb;
    medium.scattering = probe_input.scattering_distance.rgb;
    medium.anisotropy = probe_input.absorption_anisotropy.a;
    float g = medium.anisotropy;
    float distance = probe_input.scattering_distance.a;
    vec3 view = probe_input.view.xyz;
    vec3 direction = probe_input.direction.xyz;

    probe_output_t result;
    result.phase = vec4(get_phase_function(view, direction, g),
                        get_phase_function_density(view, direction, g),
                        get_henyey_greenstein(dot(view, direction), g),
                        sample_medium_distance(medium, probe_input.random_numbers.xy));
    vec3 sampled = sample_phase_function(probe_input.random_numbers.zw, view, g);
    result.sampled = vec4(sampled, get_phase_function_density(view, sampled, g));
    result.transmittance = vec4(get_medium_transmittance(medium, distance),
                                get_medium_distance_density(medium, distance));
    result.scattering = vec4(get_medium_scattering_weight(medium, distance),
                             get_medium_passing_probability(medium, distance));
    result.passing = vec4(get_medium_passing_weight(medium, distance), 0.0);
    g_outputs[index] = result;
}
