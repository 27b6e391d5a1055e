// Small scenes compiled into the kernel, as the workshop's ShaderToy keeps its triangles in a
// constant array: the vertex positions of up to CONSTANT_TRIANGLE_CAPACITY triangles (the
// material kernels: MATERIAL_CONSTANT_TRIANGLE_CAPACITY) arrive as specialization constants,
// and ray_mesh_intersection() and ray_mesh_any_hit() test them in a loop that the
// preprocessor unrolls. Every position is then a constant of the compiled code, so the
// driver reads nothing per triangle; on lavapipe, where each texel fetch is a per-lane
// gather, this makes rays 2-4x as fast (docs/performance.md). The other members of the hit
// triangle still come from the texel buffer (get_triangle()). Alpha-tested materials are not
// tested there: the host gives constant triangles only to scenes without them
// (`Traversal::choose`).
#ifndef VKPATH_CONSTANT_TRIANGLES_GLSL
#define VKPATH_CONSTANT_TRIANGLES_GLSL

#include "shared.h"

// How many of the constant triangles are in use (0: none; the kernel reads the texel buffer).
layout(constant_id = SPEC_CONSTANT_TRIANGLE_COUNT) const uint CONSTANT_TRIANGLE_COUNT = 0u;

#if CONSTANT_TRIANGLE_CAPACITY != 64 || MATERIAL_CONSTANT_TRIANGLE_CAPACITY != 16 || FEW_CONSTANT_TRIANGLE_CAPACITY != 32
#error the FOR_EACH_*CONSTANT_TRIANGLE lists hold 64, 16 and 32 triangles: change them with the capacities
#endif
// M(i) for the triangles 0-15, 16-31 and 32-63, with literal indices.
#define FOR_CONSTANT_TRIANGLES_0_TO_15(M) \
    M(0) M(1) M(2) M(3) M(4) M(5) M(6) M(7) \
    M(8) M(9) M(10) M(11) M(12) M(13) M(14) M(15)
#define FOR_CONSTANT_TRIANGLES_16_TO_31(M) \
    M(16) M(17) M(18) M(19) M(20) M(21) M(22) M(23) \
    M(24) M(25) M(26) M(27) M(28) M(29) M(30) M(31)
#define FOR_CONSTANT_TRIANGLES_32_TO_63(M) \
    M(32) M(33) M(34) M(35) M(36) M(37) M(38) M(39) \
    M(40) M(41) M(42) M(43) M(44) M(45) M(46) M(47) \
    M(48) M(49) M(50) M(51) M(52) M(53) M(54) M(55) \
    M(56) M(57) M(58) M(59) M(60) M(61) M(62) M(63)
// Calls M(i) for every i < CONSTANT_TRIANGLE_CAPACITY (64).
#define FOR_EACH_CONSTANT_TRIANGLE(M) \
    FOR_CONSTANT_TRIANGLES_0_TO_15(M) FOR_CONSTANT_TRIANGLES_16_TO_31(M) FOR_CONSTANT_TRIANGLES_32_TO_63(M)

// Calls M(i) for every constant triangle that this kernel tests: the first
// MATERIAL_CONSTANT_TRIANGLE_CAPACITY (16) in the material kernels, the first
// FEW_CONSTANT_TRIANGLE_CAPACITY (32) in the build for few triangles, all 64 in the others.
#if defined(USE_MATERIALS)
#define FOR_EACH_TESTED_CONSTANT_TRIANGLE(M) FOR_CONSTANT_TRIANGLES_0_TO_15(M)
#elif defined(FEW_CONSTANT_TRIANGLES)
#define FOR_EACH_TESTED_CONSTANT_TRIANGLE(M) FOR_CONSTANT_TRIANGLES_0_TO_15(M) FOR_CONSTANT_TRIANGLES_16_TO_31(M)
#else
#define FOR_EACH_TESTED_CONSTANT_TRIANGLE(M) FOR_EACH_CONSTANT_TRIANGLE(M)
#endif

// The 9 coordinates of constant triangle i.
#define DECLARE_CONSTANT_TRIANGLE(i) \
    layout(constant_id = SPEC_CONSTANT_TRIANGLES + 9 * i + 0) const float g_constant_triangle_##i##_0 = 0.0; \
    layout(constant_id = SPEC_CONSTANT_TRIANGLES + 9 * i + 1) const float g_constant_triangle_##i##_1 = 0.0; \
    layout(constant_id = SPEC_CONSTANT_TRIANGLES + 9 * i + 2) const float g_constant_triangle_##i##_2 = 0.0; \
    layout(constant_id = SPEC_CONSTANT_TRIANGLES + 9 * i + 3) const float g_constant_triangle_##i##_3 = 0.0; \
    layout(constant_id = SPEC_CONSTANT_TRIANGLES + 9 * i + 4) const float g_constant_triangle_##i##_4 = 0.0; \
    layout(constant_id = SPEC_CONSTANT_TRIANGLES + 9 * i + 5) const float g_constant_triangle_##i##_5 = 0.0; \
    layout(constant_id = SPEC_CONSTANT_TRIANGLES + 9 * i + 6) const float g_constant_triangle_##i##_6 = 0.0; \
    layout(constant_id = SPEC_CONSTANT_TRIANGLES + 9 * i + 7) const float g_constant_triangle_##i##_7 = 0.0; \
    layout(constant_id = SPEC_CONSTANT_TRIANGLES + 9 * i + 8) const float g_constant_triangle_##i##_8 = 0.0;
FOR_EACH_CONSTANT_TRIANGLE(DECLARE_CONSTANT_TRIANGLE)

// Constant triangle i as the workshop's struct; only the positions are set (all that
// ray_triangle_intersection() reads).
#define GET_CONSTANT_TRIANGLE(i) triangle_t(vec3[3]( \
    vec3(g_constant_triangle_##i##_0, g_constant_triangle_##i##_1, g_constant_triangle_##i##_2), \
    vec3(g_constant_triangle_##i##_3, g_constant_triangle_##i##_4, g_constant_triangle_##i##_5), \
    vec3(g_constant_triangle_##i##_6, g_constant_triangle_##i##_7, g_constant_triangle_##i##_8)), \
    vec3(0.0), vec3(0.0), vec3(0.0))

#endif
