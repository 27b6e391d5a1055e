// The emissive triangles, the lights room's first kind (glsl/lights.glsl): their words on
// the device, choosing one (in proportion to its power from a CDF, or with
// LIGHT_SELECTION_TREE by the light tree's importance to the shading point,
// glsl/light_tree.glsl), the probability of that choice that MIS weighs a found emitter by,
// a direction towards a point of the chosen triangle by solid angle or area
// (sample_light_direction()) and its density w.r.t. solid angle (get_light_density()).
// glsl/lights.glsl turns these into a light sample (sample_emissive_triangle_light()) and
// the density of an emitter a path found (get_emissive_triangle_density()), and draws the
// random numbers they take: this file draws none.
//
// Host side: src/lights/gpu_emissive.rs writes the words (the light list and its tree at
// BINDING_LIGHTS, the selection words at BINDING_LIGHT_SELECTION). Rust twins:
// src/cpu/lights.rs, src/cpu/importance_sampling.rs, src/cpu/light_tree.rs. Needs INTEGRATOR,
// LIGHT_SAMPLING and LIGHT_SELECTION defined by the includer.
#ifndef VKPATH_EMISSIVE_LIGHTS_GLSL
#define VKPATH_EMISSIVE_LIGHTS_GLSL

#include "importance_sampling.glsl"
#include "surface.glsl"

// Emissive triangles, a texel buffer of RGBA32_UINT (16 bytes a texel). Texel 0 is the header,
// `vkpath::lights::gpu_emissive::GpuLightHeader`: x = number of lights, yzw = 0. Texel 1 + i is
// light i, `vkpath::lights::gpu_emissive::GpuLight`: x = its scene triangle index, y = the
// cumulative probability (float bits) of choosing this light or an earlier one
// (power-proportional; the last is 1), zw = 0. Written by
// `vkpath::lights::gpu_emissive::gpu_light_bytes`, whose layout tests check these offsets.
// With the light tree, header.yz and each light's z say where the tree is
// (glsl/light_tree.glsl).
layout(set = 0, binding = BINDING_LIGHTS) uniform utextureBuffer g_light_texels;

// Each scene triangle's selection word, for MIS, a texel buffer of R32_UINT (one word per
// triangle, in the order of the triangle buffer): its selection probability as float bits (0
// for non-emitters), or with the light tree its index in the light list (NO_LIGHT for
// non-emitters). Written by `vkpath::lights::gpu_emissive::gpu_light_selection_words`.
layout(set = 0, binding = BINDING_LIGHT_SELECTION) uniform utextureBuffer g_light_selection_words;

#include "light_tree.glsl"

// Number of emissive triangles.
uint get_light_count() {
    return texelFetch(g_light_texels, 0).x;
}

// Scene triangle index of light i.
uint get_light_triangle_index(uint light_index) {
    return texelFetch(g_light_texels, int(light_index) + 1).x;
}

// Probability of choosing light i or an earlier one.
float get_light_cumulative_probability(uint light_index) {
    return uintBitsToFloat(texelFetch(g_light_texels, int(light_index) + 1).y);
}

// Chooses an emissive triangle in proportion to its power by binary search in the CDF.
// \param random_number Uniform in [0,1)
// \return Index of a light; only valid when get_light_count() > 0
uint sample_light_index(float random_number) {
    uint low = 0u;
    uint high = get_light_count() - 1u;
    // ceil(log2(count)) halvings, findMSB(count - 1) + 1 (32 at most, for any uint count),
    // a trip count the same in every lane: a lane whose search has ended skips the rest.
    // A divergent exit (`low < high` in the loop's condition) made GPU compilers unroll the
    // loop into 32 nested branches, each holding its exec mask in scalar registers (RDNA3,
    // mis on materials.gltf: 142 scalar registers, 32 spilled into a vector register).
    int iterations = findMSB(high) + 1;
    for (int i = 0; i != iterations; ++i) {
        if (low < high) {
            uint middle = (low + high) / 2u;
            if (random_number < get_light_cumulative_probability(middle))
                high = middle;
            else
                low = middle + 1u;
        }
    }
    return low;
}

// Probability that sample_light_index() picks the given scene triangle (0 for non-emitters).
float get_light_selection_probability(uint triangle_index) {
    return uintBitsToFloat(texelFetch(g_light_selection_words, int(triangle_index)).x);
}

// Probability that the light selection (sample_light_index() or sample_light_tree()) at a
// shading point picks the given scene triangle (0 for non-emitters); the tree's depends on
// the point (get_light_selection_point()).
// \param selection_position, selection_normal Where the light sample was taken and the
//        normal of its receiving side (get_light_selection_normal())
float get_light_selection_probability(uint triangle_index, vec3 selection_position, vec3 selection_normal) {
    if (LIGHT_SELECTION != LIGHT_SELECTION_TREE)
        return get_light_selection_probability(triangle_index);
    uint light_index = texelFetch(g_light_selection_words, int(triangle_index)).x;
    if (light_index == NO_LIGHT)
        return 0.0;
    return get_light_tree_probability(light_index, selection_position, selection_normal);
}

// Iterations of the light search per ray, as path_tracer.comp's loop bound counts them: the
// bits of the light count (sample_light_index()), or with the tree its two walks
// (sample_light_tree() for a light sample, get_light_tree_probability() for an MIS weight)
// of at most depth + 1 trips each.
uint get_light_search_iterations() {
    if (LIGHT_SELECTION == LIGHT_SELECTION_TREE)
        return 2u * (get_light_tree_depth() + 1u);
    return uint(findMSB(max(get_light_count(), 1u)) + 1);
}

// Density w.r.t. solid angle, at the origin of `spherical` (the light as seen from there), of
// a light sample that lands on the emitter at `distance` along `direction`: p_select / solid
// angle for lights sampled by solid angle, else p_select / area * distance^2 / |n_light.omega|.
float get_light_density(float selection_probability, triangle_t light, spherical_triangle_t spherical, vec3 direction, float distance) {
    if (use_spherical_sampling(spherical))
        return selection_probability / spherical.solid_angle;
    float cosine = abs(dot(light.normal, direction));
    return selection_probability * distance * distance / (get_triangle_area(light) * max(cosine, MIN_LIGHT_COSINE));
}

// A direction from `origin` towards a point of a light triangle and the distance to it
// along that direction: by solid angle or by area, as use_spherical_sampling() says.
// \param spherical The light as seen from `origin` (get_spherical_triangle())
void sample_light_direction(vec2 point_randoms, triangle_t light, vec3 origin, spherical_triangle_t spherical, out vec3 out_direction, out float out_distance) {
    if (use_spherical_sampling(spherical)) {
        out_direction = sample_spherical_triangle(point_randoms, spherical);
        // The distance from the triangle test that shadow rays run, so that get_shadow_transmittance()'s
        // margin excludes exactly this triangle; where rounding put the direction just
        // outside the triangle, the distance to its plane.
        if (!ray_triangle_intersection(out_distance, origin, out_direction, light))
            out_distance = dot(light.normal, light.positions[0] - origin) / dot(light.normal, out_direction);
    } else {
        vec3 to_light = sample_triangle_point(point_randoms, light) - origin;
        out_distance = length(to_light);
        out_direction = to_light / out_distance;
    }
}

#endif
