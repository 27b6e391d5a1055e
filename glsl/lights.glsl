// The lights room: every light of the scene in one list, sampled by one estimator for the
// path loop (glsl/path_loop.glsl). The list:
// - emissive triangles (every kernel), chosen in proportion to their power from a CDF, or
//   with LIGHT_SELECTION_TREE by the light tree's importance to the shading point
//   (glsl/light_tree.glsl);
// - the environment, a constant colour or an equirectangular map (glsl/environment.glsl);
// - KHR_lights_punctual's point, spot and directional lights (glsl/punctual_lights.glsl);
// the last two in kernels built with USE_MATERIALS, whose scenes may have them.
// Each kind's sampler returns a light_sample_t (direction, distance, radiance, density, or a
// delta light's weight); estimate_light_sample() turns any of them into reflected light
// with the surface seam (glsl/surface.glsl), visibility and MIS; sample_direct_light() takes
// one sample of each kind, whose sum estimates all the direct light. The densities that MIS
// weighs a found light by (get_light_density(), get_environment_density()) are here too.
// Replacing the selection (a light tree) or adding a light type touches this file (and the
// host's src/lights/ that writes the words).
//
// Random numbers, in the order drawn, each a get_path_random_numbers() pair: the emissive
// triangle's selection pair and point pair (drawn even without emissive triangles); the
// environment's (none when black, one for a constant colour, two for a map: texel, then
// point); the punctual light's pair (only when there are punctual lights). The order decides
// every output bit, with PCG2D and with Sobol's dimension pairs alike, so keep it.
//
// Rust twins: src/cpu/importance_sampling.rs (emissive triangles), src/cpu/environment.rs,
// src/cpu/light_tree.rs. Needs INTEGRATOR, SAMPLER, LIGHT_SAMPLING and LIGHT_SELECTION
// defined by the includer.
#ifndef VKPATH_LIGHTS_GLSL
#define VKPATH_LIGHTS_GLSL

#include "integrators.glsl"
#include "importance_sampling.glsl"
#include "sobol.glsl"
#include "surface.glsl"
#include "path_guiding.glsl"
#ifdef USE_MATERIALS
#include "environment.glsl"
#include "punctual_lights.glsl"
#endif

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
    // At most 32 halvings for any uint count.
    for (int i = 0; i != 32 && low < high; ++i) {
        uint middle = (low + high) / 2u;
        if (random_number < get_light_cumulative_probability(middle))
            high = middle;
        else
            low = middle + 1u;
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

// The normal with which the light tree bounds what a surface receives: the geometric
// normal on the ray's side (get_bsdf() is 0 below it); 0 (no bound) for layered materials.
vec3 get_light_selection_normal(surface_t surface) {
    return has_layers(surface) ? vec3(0.0) : surface.geometric_normal;
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
        // The distance from the triangle test that shadow rays run, so that is_visible()'s
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

// One light sample: where it comes from and what it brings.
struct light_sample_t {
    // Unit direction from the shading point towards the light, world space
    vec3 direction;
    // Distance to the light along `direction` (NO_HIT_T for the environment and directional
    // lights)
    float distance;
    // Radiance arriving along `direction` (delta lights: the irradiance they give a surface
    // facing them)
    vec3 radiance;
    // Density w.r.t. solid angle of choosing this light and direction; 0 for delta lights
    // and for no sample
    float density;
    // Delta lights only: 1 / the probability of choosing this light; else 0
    float delta_weight;
};

// A light sample that contributes nothing.
light_sample_t get_no_light_sample() {
    light_sample_t light_sample;
    light_sample.direction = vec3(0.0, 0.0, 1.0);
    light_sample.distance = 0.0;
    light_sample.radiance = vec3(0.0);
    light_sample.density = 0.0;
    light_sample.delta_weight = 0.0;
    return light_sample;
}

// Whether a shadow ray from `origin` leaves the scene along `direction` (distance NO_HIT_T:
// the environment, a directional light) or reaches the light `distance` away (the light at
// its end excluded by a relative margin of SHADOW_RAY_MARGIN = 2^-14).
bool is_visible(vec3 origin, vec3 direction, float distance) {
    float t_max = (distance >= NO_HIT_T) ? NO_HIT_T : distance * (1.0 - SHADOW_RAY_MARGIN);
    return !ray_mesh_any_hit(origin, direction, t_max);
}

// An emissive triangle chosen by power (or by the light tree), and a point of it by solid
// angle or area (use_spherical_sampling()): its direction, distance, emitted radiance (glTF:
// the emissive texture at that point) and density. No sample from the back of a one-sided
// emitter.
// \param origin Where the shadow ray starts (get_light_sample_origin())
// \param normal The light tree's bound at origin (get_light_selection_normal())
light_sample_t sample_emissive_triangle_light(vec3 origin, vec3 normal, inout uvec2 seed) {
    vec2 selection = get_path_random_numbers(seed);
    vec2 point_randoms = get_path_random_numbers(seed);
    light_sample_t light_sample = get_no_light_sample();
    if (get_light_count() == 0u)
        return light_sample;
    uint light_index;
    float tree_probability = 0.0;
    if (LIGHT_SELECTION == LIGHT_SELECTION_TREE) {
        light_index = sample_light_tree(selection[0], origin, normal, tree_probability);
        if (light_index == NO_LIGHT)
            return light_sample;
    } else
        light_index = sample_light_index(selection[0]);
    uint light_triangle_index = get_light_triangle_index(light_index);
    triangle_t light = get_triangle(light_triangle_index);
    spherical_triangle_t spherical = get_spherical_triangle(origin, light);
    vec3 direction;
    float distance;
    sample_light_direction(point_randoms, light, origin, spherical, direction, distance);
    // One-sided emitters shine only towards their normal.
    bool front = dot(light.normal, direction) < 0.0;
    if (!(distance > 0.0) || (!front && !is_double_sided(light_triangle_index)))
        return light_sample;
    light_sample.direction = direction;
    light_sample.distance = distance;
    light_sample.radiance = get_front_emission(light_triangle_index, light, origin + distance * direction);
    float selection_probability = (LIGHT_SELECTION == LIGHT_SELECTION_TREE) ? tree_probability : get_light_selection_probability(light_triangle_index);
    light_sample.density = get_light_density(selection_probability, light, spherical, direction, distance);
    return light_sample;
}

// Density w.r.t. solid angle with which sample_emissive_triangle_light() from `origin` finds
// the point of triangle i at `distance` along `direction` (MIS of emission a path found).
// \param selection_position, selection_normal The light sample's origin and normal at the
//        vertex that found it (the light tree's probability depends on them)
float get_emissive_triangle_density(uint triangle_index, triangle_t triangle, vec3 origin, vec3 direction, float distance, vec3 selection_position, vec3 selection_normal) {
    return get_light_density(get_light_selection_probability(triangle_index, selection_position, selection_normal), triangle, get_spherical_triangle(origin, triangle), direction, distance);
}

#ifdef USE_MATERIALS
// A direction towards the environment by its own sampler (sample_environment()), with its
// radiance and density.
light_sample_t sample_environment_light(inout uvec2 seed) {
    light_sample_t light_sample = get_no_light_sample();
    uint kind = get_environment_kind();
    if (kind == ENVIRONMENT_NONE)
        return light_sample;
    vec2 texel_randoms = get_path_random_numbers(seed);
    vec2 point_randoms = vec2(0.0);
    if (kind == ENVIRONMENT_MAP)
        point_randoms = get_path_random_numbers(seed);
    light_sample.direction = sample_environment(texel_randoms, point_randoms);
    light_sample.distance = NO_HIT_T;
    light_sample.density = get_environment_density(light_sample.direction);
    light_sample.radiance = get_environment_radiance(light_sample.direction);
    return light_sample;
}

// Whether the scene has punctual lights (the host specializes it; false compiles their light
// samples out).
layout(constant_id = SPEC_SCENE_HAS_PUNCTUAL_LIGHTS) const bool SCENE_HAS_PUNCTUAL_LIGHTS = true;

// One punctual light, chosen uniformly (delta_weight: their count): delta lights have no
// density to weigh against, so no MIS. No sample where it gives no light (outside a spot's
// cone).
light_sample_t sample_punctual_light(vec3 origin, inout uvec2 seed) {
    light_sample_t light_sample = get_no_light_sample();
    uint count = SCENE_HAS_PUNCTUAL_LIGHTS ? get_punctual_light_count() : 0u;
    if (count == 0u)
        return light_sample;
    uint index = min(uint(get_path_random_numbers(seed)[0] * float(count)), count - 1u);
    light_sample.radiance = get_punctual_irradiance(get_punctual_light(index), origin, light_sample.direction, light_sample.distance);
    if (light_sample.radiance != vec3(0.0))
        light_sample.delta_weight = float(count);
    return light_sample;
}
#endif

// The light that a light sample brings to a surface point towards `view`, MIS-weighted
// against BSDF sampling for mis: f (n_s . l) L(l) / p_light(l) * w_light, or
// f (n_s . l) E * delta_weight for a delta light.
// \param origin Where the shadow ray starts (get_light_sample_origin())
vec3 estimate_light_sample(surface_t surface, vec3 view, vec3 origin, light_sample_t light_sample) {
    bool delta = light_sample.delta_weight > 0.0;
    if (!delta && !(light_sample.density > 0.0))
        return vec3(0.0);
    vec3 bsdf = get_bsdf(surface, view, light_sample.direction);
    if (bsdf == vec3(0.0) || !is_visible(origin, light_sample.direction, light_sample.distance))
        return vec3(0.0);
    vec3 reflected = get_reflected_radiance(surface, light_sample.direction, bsdf, light_sample.radiance);
    if (delta)
        return reflected * light_sample.delta_weight;
    float weight = weighs_by_mis() ? get_power_heuristic_weight(light_sample.density, get_path_direction_density(surface, view, light_sample.direction)) : 1.0;
    return reflected / light_sample.density * weight;
}

#ifdef USE_MATERIALS
// Whether the scene has emissive triangles (the host specializes it; glsl/shared.h).
layout(constant_id = SPEC_SCENE_HAS_EMISSIVE_TRIANGLES) const bool SCENE_HAS_EMISSIVE_TRIANGLES = true;
#else
const bool SCENE_HAS_EMISSIVE_TRIANGLES = true;
#endif

// Next event estimation: one sample of each kind of light at a surface point, whose sum
// estimates all the direct light arriving there (the path loop's light-samples step).
// \param position The surface point, world space
// \param seed The pixel's PCG2D random state (see get_path_random_numbers())
vec3 sample_direct_light(vec3 position, surface_t surface, vec3 view, inout uvec2 seed) {
    vec3 origin = get_light_sample_origin(surface, position);
    light_sample_t emissive_sample = sample_emissive_triangle_light(origin, get_light_selection_normal(surface), seed);
    vec3 direct = SCENE_HAS_EMISSIVE_TRIANGLES ? estimate_light_sample(surface, view, origin, emissive_sample) : vec3(0.0);
#ifdef USE_MATERIALS
    if (SCENE_SAMPLES_ENVIRONMENT)
        direct += estimate_light_sample(surface, view, origin, sample_environment_light(seed));
    if (SCENE_HAS_PUNCTUAL_LIGHTS)
        direct += estimate_light_sample(surface, view, origin, sample_punctual_light(origin, seed));
#endif
    return direct;
}

#endif
