#version 460
// Probe of the guide (glsl/guiding.glsl): for each input, get_guide_cell_index() of its
// position, and in that cell (where guided) get_guide_bin_index(), get_guide_density() of
// its direction and sample_guide_direction() with its random numbers. Host side:
// vkpath::probe::guiding_probe (GuidingProbeInput, GuidingProbeOutput), tests/guiding.rs;
// Rust twins: src/cpu/guiding.rs.
//
// Descriptor set 0: BINDING_GUIDE (the guide's words), then PROBE_BINDING_INPUTS and
// PROBE_BINDING_OUTPUTS. Self-contained: it binds no scene.

#include "shared.h"
#include "workshop.glsl"

layout(set = 0, binding = BINDING_GUIDE) uniform utextureBuffer g_guide_texels;

#include "guiding.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

// Which inputs this dispatch covers. Mirrors `vkpath::probe::ProbePushConstants`.
layout(push_constant) uniform probe_push_constants {
    // Index of the input that invocation 0 of this dispatch evaluates.
    uint g_probe_first;
    // Number of inputs in the buffer: invocations past it do nothing.
    uint g_probe_count;
};

struct probe_input_t {
    vec4 position;        // xyz: world space; w: unused
    vec4 normal;          // xyz: the unit normal of the surface there; w: unused
    vec4 direction;       // xyz: a unit direction; w: unused
    vec4 random_numbers;  // xy: sample_guide_direction()'s; zw: unused
};

struct probe_output_t {
    uvec4 cell_bin;       // x: get_guide_cell_index(); y: is_guided_cell(); z: get_guide_bin_index() of the direction; w: the bin sample_guide_direction() chose
    vec4 sampled_density; // xyz: sample_guide_direction() (0 where the cell is not guided); w: get_guide_density() of the input's direction (0 likewise)
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
    vec3 direction = probe_input.direction.xyz;
    uint cell = get_guide_cell_index(probe_input.position.xyz, probe_input.normal.xyz);
    bool guided = is_guided_cell(cell);
    probe_output_t result;
    result.cell_bin = uvec4(cell, guided ? 1u : 0u, get_guide_bin_index(direction), 0u);
    result.sampled_density = vec4(0.0);
    if (guided) {
        uint sampled_bin;
        float sampled_probability;
        result.sampled_density = vec4(sample_guide_direction(cell, probe_input.random_numbers.xy, sampled_bin, sampled_probability), get_guide_density(cell, direction));
        result.cell_bin.w = sampled_bin;
    }
    g_outputs[index] = result;
}
