#version 460
// Probe of the texture functions (glsl/textures.glsl): for each input, sample_texture(),
// get_texel(), transform_tex_coord(), wrap_texel_coordinate() and srgb_to_linear() on the
// input's slot and arguments. Host side: vkpath::probe::texture_probe (TextureProbeInput,
// TextureProbeOutput), tests/texture_twins.rs.
//
// Descriptor set 0: BINDING_TEXTURE_TEXELS (the atlas), PROBE_BINDING_TEXTURE_SLOTS (packed
// texture_slot_t, TEXTURE_SLOT_TEXEL_COUNT uvec4s each), PROBE_BINDING_INPUTS and
// PROBE_BINDING_OUTPUTS. Self-contained: unlike probe_common.glsl it binds no scene.

#include "shared.h"
#include "textures.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

// Which inputs this dispatch covers. Mirrors `vkpath::probe::ProbePushConstants`.
layout(push_constant) uniform probe_push_constants {
    // Index of the input that invocation 0 of this dispatch evaluates.
    uint g_probe_first;
    // Number of inputs in the buffer: invocations past it do nothing.
    uint g_probe_count;
};

struct probe_input_t {
    vec4 tex_coord;        // xy: texture coordinates for sample_texture(); z: the argument of
                           // srgb_to_linear(); w: unused
    ivec4 texel_and_wrap;  // xy: the texel of get_texel(); z, w: coordinate and size for
                           // wrap_texel_coordinate()
    uvec4 slot_and_mode;   // x: index of the slot; y: wrap mode for wrap_texel_coordinate();
                           // zw: unused
};

struct probe_output_t {
    vec4 sampled;                // sample_texture(slot, tex_coord.xy)
    vec4 texel;                  // get_texel(slot, texel_and_wrap.xy)
    vec4 transformed_and_linear; // xy: transform_tex_coord(slot, tex_coord.xy);
                                 // z: srgb_to_linear(tex_coord.z); w: 0
    ivec4 wrapped;               // x: wrap_texel_coordinate(...); yzw: 0
};

layout(std430, set = 0, binding = PROBE_BINDING_TEXTURE_SLOTS) readonly buffer probe_texture_slots {
    uvec4 g_texture_slot_texels[];
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
    uint first = probe_input.slot_and_mode.x * TEXTURE_SLOT_TEXEL_COUNT;
    texture_slot_t slot = unpack_texture_slot(g_texture_slot_texels[first],
                                              g_texture_slot_texels[first + 1],
                                              g_texture_slot_texels[first + 2]);
    probe_output_t result;
    result.sampled = sample_texture(slot, probe_input.tex_coord.xy);
    result.texel = get_texel(slot, probe_input.texel_and_wrap.xy);
    result.transformed_and_linear = vec4(transform_tex_coord(slot, probe_input.tex_coord.xy),
                                         srgb_to_linear(probe_input.tex_coord.z), 0.0);
    result.wrapped = ivec4(wrap_texel_coordinate(probe_input.texel_and_wrap.z,
                                                 probe_input.texel_and_wrap.w,
                                                 probe_input.slot_and_mode.y), 0, 0, 0);
    g_outputs[index] = result;
}
