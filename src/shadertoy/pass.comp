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
// clamp to edge; an unbound channel is a black 1 x 1 texture). A cube-map channel
// (VKPATH_CHANNELn_CUBE, set by src/shadertoy/kernel.rs) is a samplerCube, sampled by
// direction as in ShaderToy: texture(iChannel1, direction).
layout(set = 0, binding = 0, rgba32f) uniform writeonly image2D vkpath_pass_target;
#ifdef VKPATH_CHANNEL0_CUBE
layout(set = 0, binding = 1) uniform samplerCube iChannel0;
#else
layout(set = 0, binding = 1) uniform sampler2D iChannel0;
#endif
#ifdef VKPATH_CHANNEL1_CUBE
layout(set = 0, binding = 2) uniform samplerCube iChannel1;
#else
layout(set = 0, binding = 2) uniform sampler2D iChannel1;
#endif
#ifdef VKPATH_CHANNEL2_CUBE
layout(set = 0, binding = 3) uniform samplerCube iChannel2;
#else
layout(set = 0, binding = 3) uniform sampler2D iChannel2;
#endif
#ifdef VKPATH_CHANNEL3_CUBE
layout(set = 0, binding = 4) uniform samplerCube iChannel3;
#else
layout(set = 0, binding = 4) uniform sampler2D iChannel3;
#endif

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
// Set by the user's `discard` (src/shadertoy/discard.rs rewrites each into a return): the
// pixel is not stored, so its texel keeps what the target held, as a fragment shader's
// discarded fragment leaves its render target. Loops still running in the callers end at
// their next test.
bool vkpath_discarded = false;
bool vkpath_loop_guard() {
    if (vkpath_discarded)
        return false;
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

#ifdef VKPATH_KEYBOARD
// VS Code Shader Toy's `#iKeyboard` (set by src/shadertoy/kernel.rs when a tab has it): its
// key codes (the browser's key codes) and its four queries, headless: no key is ever down,
// as iMouse is never clicked.
const int Key_Backspace = 8, Key_Tab = 9, Key_Enter = 13, Key_Shift = 16, Key_Ctrl = 17,
    Key_Alt = 18, Key_Pause = 19, Key_Caps = 20, Key_Escape = 27, Key_PageUp = 33,
    Key_PageDown = 34, Key_End = 35, Key_Home = 36, Key_LeftArrow = 37, Key_UpArrow = 38,
    Key_RightArrow = 39, Key_DownArrow = 40, Key_Insert = 45, Key_Delete = 46,
    Key_0 = 48, Key_1 = 49, Key_2 = 50, Key_3 = 51, Key_4 = 52, Key_5 = 53, Key_6 = 54,
    Key_7 = 55, Key_8 = 56, Key_9 = 57,
    Key_A = 65, Key_B = 66, Key_C = 67, Key_D = 68, Key_E = 69, Key_F = 70, Key_G = 71,
    Key_H = 72, Key_I = 73, Key_J = 74, Key_K = 75, Key_L = 76, Key_M = 77, Key_N = 78,
    Key_O = 79, Key_P = 80, Key_Q = 81, Key_R = 82, Key_S = 83, Key_T = 84, Key_U = 85,
    Key_V = 86, Key_W = 87, Key_X = 88, Key_Y = 89, Key_Z = 90,
    Key_LeftWindow = 91, Key_RightWindows = 92, Key_Select = 93,
    Key_Numpad0 = 96, Key_Numpad1 = 97, Key_Numpad2 = 98, Key_Numpad3 = 99, Key_Numpad4 = 100,
    Key_Numpad5 = 101, Key_Numpad6 = 102, Key_Numpad7 = 103, Key_Numpad8 = 104,
    Key_Numpad9 = 105, Key_NumpadMultiply = 106, Key_NumpadAdd = 107,
    Key_NumpadSubtract = 109, Key_NumpadPeriod = 110, Key_NumpadDivide = 111,
    Key_F1 = 112, Key_F2 = 113, Key_F3 = 114, Key_F4 = 115, Key_F5 = 116, Key_F6 = 117,
    Key_F7 = 118, Key_F8 = 119, Key_F9 = 120, Key_F10 = 121, Key_F11 = 122, Key_F12 = 123,
    Key_NumLock = 144, Key_ScrollLock = 145, Key_SemiColon = 186, Key_Equal = 187,
    Key_Comma = 188, Key_Dash = 189, Key_Period = 190, Key_ForwardSlash = 191,
    Key_GraveAccent = 192, Key_OpenBracket = 219, Key_BackSlash = 220,
    Key_CloseBraket = 221, Key_SingleQuote = 222;
bool isKeyDown(int key) { return false; }
bool isKeyPressed(int key) { return false; }
bool isKeyToggled(int key) { return false; }
bool isKeyReleased(int key) { return false; }
#endif

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
    if (!vkpath_discarded)
        imageStore(vkpath_pass_target, pixel, color);
}
