// The lights room: every light of the scene in one list, sampled by one estimator for the
// path loop (glsl/path_loop.glsl). This file is the dispatcher; each kind of light lives in
// its own file, with its words on the device and its own sampling maths:
// - emissive triangles (every kernel), chosen in proportion to their power from a CDF, or
//   with LIGHT_SELECTION_TREE by the light tree's importance to the shading point
//   (glsl/emissive_lights.glsl, glsl/light_tree.glsl);
// - the environment, a constant colour or an equirectangular map (glsl/environment.glsl);
// - KHR_lights_punctual's point, spot and directional lights (glsl/punctual_lights.glsl);
// the last two in kernels built with USE_MATERIALS, whose scenes may have them.
// Here each kind's sampler becomes a light_sample_t (direction, distance, radiance, density,
// or a delta light's weight: sample_emissive_triangle_light(), sample_environment_light(),
// sample_punctual_light()); estimate_light_sample() turns any of them into scattered light
// at the path's scattering vertex (glsl/scattering_vertex.glsl: a surface point or a point
// in the global medium), the shadow ray's transmittance (get_shadow_transmittance()) and
// MIS; sample_direct_light() takes one sample of each kind at a vertex, whose sum estimates
// all the direct light. The density that MIS
// weighs an emitter a path found by is here too (get_emissive_triangle_density(); the
// environment's is get_environment_density()). A new kind of light is a file of its own,
// included here, a light_sample_t sampler here and a term of sample_direct_light() (and the
// host's src/lights/ that writes its words).
//
// Random numbers: each kind's sampler here draws its get_path_random_numbers() pairs at the
// vertex's fixed dimension pairs (glsl/sample_dimensions.glsl): the emissive triangle's
// VERTEX_PAIR_LIGHT_SELECTION and VERTEX_PAIR_LIGHT_POINT, the environment's
// VERTEX_PAIR_ENVIRONMENT_TEXEL and (a map) VERTEX_PAIR_ENVIRONMENT_POINT, the punctual
// light's VERTEX_PAIR_PUNCTUAL_SELECTION. Which kinds draw, and in which order, moves no other
// number of the path; a new kind of light takes a new row there. The kinds' files draw none
// themselves.
//
// Rust twins: src/cpu/lights.rs (emissive triangles and the estimator),
// src/cpu/environment.rs, src/cpu/punctual_lights.rs. Needs INTEGRATOR, SAMPLER,
// LIGHT_SAMPLING and LIGHT_SELECTION defined by the includer.
#ifndef VKPATH_LIGHTS_GLSL
#define VKPATH_LIGHTS_GLSL

#include "integrators.glsl"
#include "importance_sampling.glsl"
#include "sobol.glsl"
#include "scattering_vertex.glsl"
#include "path_guiding.glsl"
#ifdef USE_MATERIALS
#include "environment.glsl"
#include "punctual_lights.glsl"
#endif
#include "emissive_lights.glsl"

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

// The fraction of light per channel that a shadow ray from `origin` carries along
// `direction` out of the scene (distance NO_HIT_T: the environment, a directional light) or
// from the light `distance` away (the light at its end excluded by a relative margin of
// SHADOW_RAY_MARGIN = 2^-14): 0 where a triangle blocks it (every surface is opaque to
// shadow rays, glass too), else the global medium's transmittance exp(-sigma_t distance)
// (glsl/medium.glsl: 0 towards infinity where sigma_t > 0), 1 without a medium. The medium is
// taken to fill the whole segment: a shadow ray inside a refracting volume is blocked by its
// walls anyway, but for a light inside the same closed volume as the vertex it would be
// attenuated wrongly (docs/media.md).
vec3 get_shadow_transmittance(vec3 origin, vec3 direction, float distance) {
    float t_max = (distance >= NO_HIT_T) ? NO_HIT_T : distance * (1.0 - SHADOW_RAY_MARGIN);
    if (ray_mesh_any_hit(origin, direction, t_max))
        return vec3(0.0);
    return SCENE_HAS_MEDIUM ? get_medium_transmittance(get_global_medium(), distance) : vec3(1.0);
}

// An emissive triangle chosen by power (or by the light tree), and a point of it by solid
// angle or area (use_spherical_sampling()): its direction, distance, emitted radiance (glTF:
// the emissive texture at that point) and density. No sample from the back of a one-sided
// emitter.
// \param origin Where the shadow ray starts (get_light_sample_origin())
// \param normal The light tree's bound at origin (get_light_selection_normal())
// \param vertex_pairs The vertex's first dimension pair (get_vertex_dimension_pair())
light_sample_t sample_emissive_triangle_light(vec3 origin, vec3 normal, uint vertex_pairs) {
    vec2 selection = get_path_random_numbers(vertex_pairs + VERTEX_PAIR_LIGHT_SELECTION);
    vec2 point_randoms = get_path_random_numbers(vertex_pairs + VERTEX_PAIR_LIGHT_POINT);
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
// \param vertex_pairs The vertex's first dimension pair (get_vertex_dimension_pair())
light_sample_t sample_environment_light(uint vertex_pairs) {
    light_sample_t light_sample = get_no_light_sample();
    uint kind = get_environment_kind();
    if (kind == ENVIRONMENT_NONE)
        return light_sample;
    vec2 texel_randoms = get_path_random_numbers(vertex_pairs + VERTEX_PAIR_ENVIRONMENT_TEXEL);
    vec2 point_randoms = vec2(0.0);
    if (kind == ENVIRONMENT_MAP)
        point_randoms = get_path_random_numbers(vertex_pairs + VERTEX_PAIR_ENVIRONMENT_POINT);
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
// \param vertex_pairs The vertex's first dimension pair (get_vertex_dimension_pair())
light_sample_t sample_punctual_light(vec3 origin, uint vertex_pairs) {
    light_sample_t light_sample = get_no_light_sample();
    uint count = SCENE_HAS_PUNCTUAL_LIGHTS ? get_punctual_light_count() : 0u;
    if (count == 0u)
        return light_sample;
    uint index = min(uint(get_path_random_numbers(vertex_pairs + VERTEX_PAIR_PUNCTUAL_SELECTION)[0] * float(count)), count - 1u);
    light_sample.radiance = get_punctual_irradiance(get_punctual_light(index), origin, light_sample.direction, light_sample.distance);
    if (light_sample.radiance != vec3(0.0))
        light_sample.delta_weight = float(count);
    return light_sample;
}
#endif

// The light that a light sample brings to a scattering vertex towards its view, times the
// shadow ray's transmittance T, MIS-weighted against the path's direction sampling for mis:
// f (n_s . l) L(l) T / p_light(l) * w_light, or f (n_s . l) E T * delta_weight for a delta
// light. The shadow ray starts at vertex.light_sample_origin.
vec3 estimate_light_sample(scattering_vertex_t vertex, light_sample_t light_sample) {
    bool delta = light_sample.delta_weight > 0.0;
    if (!delta && !(light_sample.density > 0.0))
        return vec3(0.0);
    vec3 bsdf = get_vertex_scattering(vertex, light_sample.direction);
    if (bsdf == vec3(0.0))
        return vec3(0.0);
    // The contribution before the shadow ray, so that only it and the ray stay live while
    // the ray is traced: the same arithmetic in fewer registers (RDNA3, mis on the Cornell
    // box: 108 -> 96 VGPRs, 14 -> 16 subgroups per SIMD, scripts/kernel-statistics.sh). The
    // early return below, not a `?:` on the shadow ray, which cost lavapipe 29% more
    // instructions per sample.
    vec3 reflected = get_vertex_scattered_radiance(vertex, light_sample.direction, bsdf, light_sample.radiance);
    vec3 contribution;
    if (delta)
        contribution = reflected * light_sample.delta_weight;
    else {
        float weight = weighs_by_mis() ? get_power_heuristic_weight(light_sample.density, get_path_direction_density(vertex, light_sample.direction)) : 1.0;
        contribution = reflected / light_sample.density * weight;
    }
    // The early return keeps a blocked sample's cost where it was; without a medium T is 1
    // or 0, and the product with 1 is exact, so images keep every bit.
    vec3 transmittance = get_shadow_transmittance(vertex.light_sample_origin, light_sample.direction, light_sample.distance);
    if (transmittance == vec3(0.0))
        return vec3(0.0);
    return contribution * transmittance;
}

#ifdef USE_MATERIALS
// Whether the scene has emissive triangles (the host specializes it; glsl/shared.h).
layout(constant_id = SPEC_SCENE_HAS_EMISSIVE_TRIANGLES) const bool SCENE_HAS_EMISSIVE_TRIANGLES = true;
#else
const bool SCENE_HAS_EMISSIVE_TRIANGLES = true;
#endif

// Next event estimation: one sample of each kind of light at a scattering vertex, whose sum
// estimates all the direct light arriving there (the path loop's light-samples step).
// \param vertex_pairs The vertex's first dimension pair (get_vertex_dimension_pair())
vec3 sample_direct_light(scattering_vertex_t vertex, uint vertex_pairs) {
    // Every sample's get_vertex_scattering() would be 0 (a smooth metal)
    if (has_only_delta_scattering(vertex))
        return vec3(0.0);
    vec3 origin = vertex.light_sample_origin;
    light_sample_t emissive_sample = sample_emissive_triangle_light(origin, vertex.light_selection_normal, vertex_pairs);
    vec3 direct = SCENE_HAS_EMISSIVE_TRIANGLES ? estimate_light_sample(vertex, emissive_sample) : vec3(0.0);
#ifdef USE_MATERIALS
    if (SCENE_SAMPLES_ENVIRONMENT)
        direct += estimate_light_sample(vertex, sample_environment_light(vertex_pairs));
    if (SCENE_HAS_PUNCTUAL_LIGHTS)
        direct += estimate_light_sample(vertex, sample_punctual_light(origin, vertex_pairs));
#endif
    return direct;
}

#endif
