#version 460
// Probe of ray_triangle_intersection(): one ray against one triangle per input. Host side:
// vkpath::probe (RayTriangleInput, IntersectionOutput).

#include "probe_common.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

struct probe_input_t {
    vec4 ray_origin;            // xyz: world space, w: unused
    vec4 ray_direction;         // xyz: world space (not necessarily normalized), w: unused
    packed_triangle_t triangle; // the triangle, packed as in the scene buffer
};

struct probe_output_t {
    vec4 t;    // x: out_t as the function left it (meaningful on a hit), yzw: 0
    uvec4 hit; // x: 1 if the function returned true, else 0; yzw: 0
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
    // A function that does not write out_t on a miss leaves it undefined: start from 0.
    float t = 0.0;
    bool hit = ray_triangle_intersection(t, probe_input.ray_origin.xyz, probe_input.ray_direction.xyz,
                                         unpack_triangle(probe_input.triangle));
    g_outputs[index].t = vec4(t, 0.0, 0.0, 0.0);
    g_outputs[index].hit = uvec4(hit ? 1u : 0u, 0u, 0u, 0u);
    FINISH_PROBE(index);
}
