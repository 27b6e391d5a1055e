#version 460
// Probe of ray_mesh_intersection(): the closest hit of each input ray with the scene bound at
// BINDING_TRIANGLES. Host side: vkpath::probe (RayInput, MeshIntersectionOutput).

#include "probe_common.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

struct probe_input_t {
    vec4 ray_origin;    // xyz: world space, w: unused
    vec4 ray_direction; // xyz: world space, w: unused
};

struct probe_output_t {
    vec4 t; // x: out_t (meaningful on a hit), yzw: 0
    // x: 1 if the function returned true, else 0; y: g_hit_triangle_index (set by the
    // reference version only: a user's version cannot know it); zw: 0
    uvec4 hit;
    // out_triangle as the function returned it (meaningful on a hit), so that the host can
    // tell which triangle was hit without g_hit_triangle_index
    packed_triangle_t triangle;
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
    // Defined starting values, for versions that leave the out-parameters alone on a miss.
    float t = 0.0;
    triangle_t triangle = unpack_triangle(packed_triangle_t(vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)),
                                                            vec4(0.0), vec4(0.0), vec4(0.0)));
    g_hit_triangle_index = 0xFFFFFFFFu;
    bool hit = ray_mesh_intersection(t, triangle, probe_input.ray_origin.xyz, probe_input.ray_direction.xyz);
    g_outputs[index].t = vec4(t, 0.0, 0.0, 0.0);
    g_outputs[index].hit = uvec4(hit ? 1u : 0u, g_hit_triangle_index, 0u, 0u);
    g_outputs[index].triangle = pack_triangle(triangle);
    FINISH_PROBE(index);
}
