// One pass of a ShaderToy program as a compute kernel (`vkpath shadertoy`): the user's
// mainImage() runs once per pixel, at the pixel's centre with the origin at the bottom left
// as in ShaderToy, and its colour is stored in the pass's rgba32f target (row 0 at the
// bottom, so that texture() and texelFetch() on a buffer read what fragCoord wrote).
//
// Not in glsl/: it is no path-tracer kernel, and `vkpath check` treats every name declared
// in glsl/ as vkpath's own. Compiled at run time with the includes below resolved to the
// user's Common tab and pass (src/shadertoy/kernel.rs).
#version 460
#extension GL_GOOGLE_include_directive : require

// Mirrors SHADERTOY_WORKGROUP_SIZE in src/shadertoy/kernel.rs.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

// The pass's target (binding 0) and its four channels (bindings 1-4, linear filtering,
// clamp to edge; an unbound channel is a black 1 x 1 texture).
layout(set = 0, binding = 0, rgba32f) uniform writeonly image2D vkpath_pass_target;
layout(set = 0, binding = 1) uniform sampler2D iChannel0;
layout(set = 0, binding = 2) uniform sampler2D iChannel1;
layout(set = 0, binding = 3) uniform sampler2D iChannel2;
layout(set = 0, binding = 4) uniform sampler2D iChannel3;

// ShaderToy's inputs that stay the same through a run. Mirrors
// `vkpath::shadertoy::inputs::PassConstants` (std140).
layout(set = 0, binding = 5, std140) uniform vkpath_pass_constants {
    // Viewport in pixels (z: pixel aspect ratio, 1).
    vec3 iResolution;
    // Frames per second: 60.
    float iFrameRate;
    // Mouse: (0, 0, 0, 0), never clicked.
    vec4 iMouse;
    // (year, month from 0, day, seconds since midnight): fixed, so that runs repeat.
    vec4 iDate;
    // Size of each channel's texture in texels (z: 1).
    vec3 iChannelResolution[4];
    // Sound sample rate: 44100.
    float iSampleRate;
};

// ShaderToy's inputs that change per frame. Mirrors
// `vkpath::shadertoy::inputs::FramePushConstants` (std430).
layout(push_constant) uniform vkpath_frame_constants {
    // Seconds since the start: iFrame / 60.
    float iTime;
    // Seconds per frame: 1 / 60.
    float iTimeDelta;
    // Frame index from 0.
    int iFrame;
    // Playback time of each channel: iTime.
    float iChannelTime[4];
};

// Where a pass reports that its loops ran past the limit (binding 6): each pass ORs its
// bit, VKPATH_PASS_BIT, into vkpath_loop_limit_passes. Mirrors BINDING_LOOP_REPORT in
// src/shadertoy/runner.rs.
layout(set = 0, binding = 6, std430) buffer vkpath_loop_report {
    uint vkpath_loop_limit_passes;
};
// This pass's bit (specialization constant 0): 1 << its index in the frame.
layout(constant_id = 0) const uint VKPATH_PASS_BIT = 1u;
// Loop iterations one invocation's loops may run together (specialization constant 1; 0: no
// limit): every loop of the user's code calls vkpath_loop_guard() in its condition, which
// ends the loops past the limit and sets g_user_loop_limit_hit. On lavapipe the limit keeps
// an invocation below llvmpipe's own, which would end a loop silently (see
// LLVMPIPE_LOOP_LIMIT in glsl/shared.h); elsewhere it stops an endless loop before a GPU
// watchdog does. Mirrors `crate::glsl_intake::loop_guard_declarations`.
layout(constant_id = 1) const uint VKPATH_LOOP_LIMIT = 8191u;
uint g_user_loop_iterations = 0u;
bool g_user_loop_limit_hit = false;
bool vkpath_loop_guard() {
    if (VKPATH_LOOP_LIMIT != 0u && ++g_user_loop_iterations > VKPATH_LOOP_LIMIT) {
        g_user_loop_limit_hit = true;
        return false;
    }
    return true;
}

// gl_FragCoord and gl_FragColor, which a compute kernel lacks: the intake renames them in
// the user's code (fragCoord at the pixel's centre).
vec4 vkpath_FragCoord = vec4(0.0);
vec4 vkpath_FragColor = vec4(0.0);

#include "shadertoy_common.glsl"
#include "shadertoy_pass.glsl"

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(iResolution.x) || pixel.y >= int(iResolution.y))
        return;
    vec2 frag_coord = vec2(pixel) + vec2(0.5);
    vec4 color = vec4(0.0);
    vkpath_FragCoord = vec4(frag_coord, 0.5, 1.0);
#ifdef VKPATH_PAGE_SHADER
    // A page shader's main() reads gl_FragCoord and writes its output variable.
    vkpath_user_main();
    color = VKPATH_PAGE_SHADER_OUTPUT;
#else
    mainImage(color, frag_coord);
#endif
    if (g_user_loop_limit_hit)
        atomicOr(vkpath_loop_limit_passes, VKPATH_PASS_BIT);
    imageStore(vkpath_pass_target, pixel, color);
}
