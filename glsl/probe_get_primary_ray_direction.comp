#version 460
// Probe of get_primary_ray_direction(): the pinhole camera's ray direction for each input.
// Host side: vkpath::probe (PrimaryRayInput, DirectionOutput).

#include "probe_common.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

struct probe_input_t {
    vec4 tex_coord;       // xy: point of the image in [0,1]^2 (the function's x, y), zw: unused
    vec4 camera_position; // xyz: the pinhole, world space, w: unused
    vec4 left_bottom;     // xyz: the image plane's left-bottom corner, w: unused
    vec4 right;           // xyz: the image plane's full-width edge vector, w: unused
    vec4 up;              // xyz: the image plane's full-height edge vector, w: unused
};

struct probe_output_t {
    vec4 direction; // xyz: the ray direction, w: 0
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
    vec3 direction = get_primary_ray_direction(probe_input.tex_coord.x, probe_input.tex_coord.y, probe_input.camera_position.xyz,
                                               probe_input.left_bottom.xyz, probe_input.right.xyz,
                                               probe_input.up.xyz);
    g_outputs[index].direction = vec4(direction, 0.0);
    FINISH_PROBE(index);
}
