// What every probe kernel (glsl/probe_*.comp) shares. A probe evaluates one workshop function
// on a storage buffer of inputs and writes a storage buffer of outputs, one invocation per
// input, so that tests and `vkpath check` can compare the GPU's results with the CPU twins or
// with a user's version of the function. Host side: src/probe/. All input and output structs
// have vec4 / uvec4 members only (std430 lays them out as Rust's #[repr(C)] does).
//
// Descriptor set 0: the scene as the path tracer sees it (BINDING_TRIANGLES as a texel
// buffer, BINDING_RENDER_UNIFORMS whose .z is the triangle count), then PROBE_BINDING_INPUTS
// and PROBE_BINDING_OUTPUTS, declared by each kernel with its own structs.
#ifndef VKPATH_PROBE_COMMON_GLSL
#define VKPATH_PROBE_COMMON_GLSL

#include "shared.h"

layout(local_size_x = PROBE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

// Maximum number of surface hits per path, for get_ray_radiance() (as in path_tracer.comp).
layout(constant_id = SPEC_MAX_PATH_LENGTH) const int MAX_PATH_LENGTH = DEFAULT_MAX_PATH_LENGTH;

#include "integrator.glsl"

// Which inputs this dispatch covers. Mirrors `vkpath::probe::ProbePushConstants`.
layout(push_constant) uniform probe_push_constants {
    // Index of the input that invocation 0 of this dispatch evaluates.
    uint g_probe_first;
    // Number of inputs in the buffer: invocations past it do nothing.
    uint g_probe_count;
};

// The index of the input this invocation evaluates; false when it has none (past the end).
bool get_probe_index(out uint index) {
    index = g_probe_first + gl_GlobalInvocationID.x;
    return index < g_probe_count;
}

layout(std430, set = 0, binding = PROBE_BINDING_FLAGS) writeonly buffer probe_flags {
    uint g_probe_flags[];
};

// Ends a probe invocation: records whether the user's loops ran past their limit
// (src/check/source.rs guards them). A macro: the user's file, which declares the flag,
// comes after this one.
#ifdef USER_FUNCTIONS
#define FINISH_PROBE(index) g_probe_flags[index] = g_user_loop_limit_hit ? 1u : 0u
#else
#define FINISH_PROBE(index) g_probe_flags[index] = 0u
#endif

// Packs a triangle for output (flags 0: the workshop's struct has none).
packed_triangle_t pack_triangle(triangle_t triangle) {
    packed_triangle_t packed;
    packed.positions[0] = vec4(triangle.positions[0], 0.0);
    packed.positions[1] = vec4(triangle.positions[1], 0.0);
    packed.positions[2] = vec4(triangle.positions[2], 0.0);
    packed.normal = vec4(triangle.normal, 0.0);
    packed.color = vec4(triangle.color, 0.0);
    packed.emission = vec4(triangle.emission, 0.0);
    return packed;
}

#endif
