// The integrators on glTF materials (kernels built with USE_MATERIALS): the same six as on
// the workshop's diffuse triangles, with the BRDF of glsl/brdf.glsl in place of albedo / pi.
// Each estimates the same integral, of get_surface_reflection() times incoming radiance:
// - ray tracing: the base colour of the first hit;
// - direct illumination (Exercise 6) and path tracing (Exercise 7): uniform hemisphere
//   directions around the geometric normal, weight 2 pi f (n_s . l);
// - cosine: cosine-weighted directions around the geometric normal, weight
//   f (n_s . l) / p(l);
// - nee and mis: BRDF importance sampling (sample_brdf()) and light samples, MIS-weighted
//   with the power heuristic for mis.
// Needs MAX_PATH_LENGTH, INTEGRATOR, RUSSIAN_ROULETTE_START, SAMPLER and LIGHT_SAMPLING.
#ifndef VKPATH_MATERIAL_INTEGRATORS_GLSL
#define VKPATH_MATERIAL_INTEGRATORS_GLSL

#include "importance_sampling.glsl"
#include "materials.glsl"
#include "environment.glsl"
#include "punctual_lights.glsl"

// Whether a shadow ray from `origin` leaves the scene along `direction` (reaches the
// environment or a directional light) or reaches a point light `distance` away.
bool is_visible(vec3 origin, vec3 direction, float distance) {
    float t_max = (distance >= NO_HIT_T) ? NO_HIT_T : distance * (1.0 - SHADOW_RAY_MARGIN);
    return !ray_mesh_any_hit(origin, direction, t_max);
}

// One sample of the environment's light at a surface point, MIS-weighted against BRDF
// sampling for INTEGRATOR_MIS: f (n_s . l) L_env(l) / p_env(l) * w. Random numbers: none for
// a black environment, one pair for a constant colour, two for a map (the texel, then the
// point in it).
vec3 sample_environment_light(vec3 shading_position, surface_t surface, vec3 view, inout uvec2 seed) {
    uint kind = get_environment_kind();
    if (kind == ENVIRONMENT_NONE)
        return vec3(0.0);
    vec2 texel_randoms = get_path_random_numbers(seed);
    vec2 point_randoms = vec2(0.0);
    if (kind == ENVIRONMENT_MAP)
        point_randoms = get_path_random_numbers(seed);
    vec3 direction = sample_environment(texel_randoms, point_randoms);
    float density = get_environment_density(direction);
    vec3 reflection = get_surface_reflection(surface, view, direction);
    if (reflection == vec3(0.0) || !(density > 0.0))
        return vec3(0.0);
    if (!is_visible(offset_ray_origin(shading_position, surface.geometric_normal), direction, NO_HIT_T))
        return vec3(0.0);
    float weight = (INTEGRATOR == INTEGRATOR_MIS) ? get_power_heuristic_weight(density, get_brdf_density(surface.material, surface.shading_normal, view, direction)) : 1.0;
    return reflection * get_environment_radiance(direction) / density * weight;
}

// The light of one punctual light, chosen uniformly (so times their count): delta lights
// have no density to weigh against, so no MIS.
vec3 sample_punctual_light(vec3 shading_position, surface_t surface, vec3 view, inout uvec2 seed) {
    uint count = get_punctual_light_count();
    if (count == 0u)
        return vec3(0.0);
    uint index = min(uint(get_path_random_numbers(seed)[0] * float(count)), count - 1u);
    vec3 origin = offset_ray_origin(shading_position, surface.geometric_normal);
    vec3 direction;
    float distance;
    vec3 irradiance = get_punctual_irradiance(get_punctual_light(index), origin, direction, distance);
    vec3 reflection = get_surface_reflection(surface, view, direction);
    if (reflection == vec3(0.0) || irradiance == vec3(0.0) || !is_visible(origin, direction, distance))
        return vec3(0.0);
    return reflection * irradiance * float(count);
}

// One light sample at a surface point with a glTF material (next event estimation),
// MIS-weighted against BRDF sampling when INTEGRATOR == INTEGRATOR_MIS:
// f(v, l) (n_s . l) L_e(y) / p_light(l) * w_light. As sample_direct_light(), plus the
// emitter's emissive texture at the sampled point.
vec3 sample_direct_light_with_material(vec3 shading_position, surface_t surface, vec3 view, inout uvec2 seed) {
    vec2 selection = get_path_random_numbers(seed);
    vec2 point_randoms = get_path_random_numbers(seed);
    if (get_light_count() == 0u)
        return vec3(0.0);
    uint light_triangle_index = get_light_triangle_index(sample_light_index(selection[0]));
    triangle_t light = get_triangle(light_triangle_index);
    vec3 origin = offset_ray_origin(shading_position, surface.geometric_normal);
    vec3 direction;
    float distance;
    spherical_triangle_t spherical = get_spherical_triangle(origin, light);
    sample_light_direction(point_randoms, light, origin, spherical, direction, distance);
    vec3 reflection = get_surface_reflection(surface, view, direction);
    bool front = dot(light.normal, direction) < 0.0;
    if (reflection == vec3(0.0) || !(distance > 0.0) || (!front && !is_double_sided(light_triangle_index)))
        return vec3(0.0);
    if (is_occluded(origin, direction, distance))
        return vec3(0.0);
    vec3 light_point = origin + distance * direction;
    vec3 emission = get_material_emission(get_material_index(light_triangle_index), get_tex_coord(light_triangle_index, get_barycentrics(light_point, light)));
    float light_density = get_light_density(get_light_selection_probability(light_triangle_index), light, spherical, direction, distance);
    float weight = (INTEGRATOR == INTEGRATOR_MIS) ? get_power_heuristic_weight(light_density, get_brdf_density(surface.material, surface.shading_normal, view, direction)) : 1.0;
    return reflection * emission / light_density * weight;
}

// A path on glTF materials with the chosen integrator (see the file's comment): the
// workshop's loop of get_ray_radiance() and get_ray_radiance_importance_sampled(), with
// get_surface() at each hit.
//
// Random numbers, in the order drawn (the order decides every output bit; keep it): the
// pixel jitter (main(): a get_path_random_numbers() pair for cosine, nee and mis with the
// box filter, else the workshop's get_sample_tex_coord()); then at each vertex that is not
// the last: nee and mis: the emissive triangle's selection pair and point pair (drawn even
// without emissive triangles), the environment's pairs (none when black, one for a constant
// colour, two for a map: texel, then point), the punctual light's pair (only when there
// are punctual lights); the direction: workshop and direct illumination one
// get_random_numbers() pair (PCG2D even with SAMPLER_SOBOL), cosine, nee and mis one
// get_path_random_numbers() pair; cosine, nee and mis past RUSSIAN_ROULETTE_START: the
// survival pair. Alpha coverage (ALPHA_MODE_BLEND) hashes g_alpha_seed instead and draws
// nothing.
vec3 get_ray_radiance_with_materials(vec3 ray_origin, vec3 ray_direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    vec3 throughput_weight = vec3(1.0);
    // Density of the BRDF sample that produced ray_direction (0: the camera ray).
    float direction_density = 0.0;
    vec3 previous_position = ray_origin;
    bool importance_sampled = INTEGRATOR == INTEGRATOR_COSINE || INTEGRATOR == INTEGRATOR_NEE || INTEGRATOR == INTEGRATOR_MIS;
    int vertex_count = (INTEGRATOR == INTEGRATOR_DIRECT_ILLUMINATION) ? 2 : MAX_PATH_LENGTH;
    for (int i = 0; i != vertex_count; ++i) {
        float t;
        triangle_t triangle;
        if (!ray_mesh_intersection(t, triangle, ray_origin, ray_direction)) {
            // The environment: all of it for the camera ray, the workshop's integrators and
            // cosine sampling; none for NEE (its light samples account for it); MIS-weighted.
            if (INTEGRATOR != INTEGRATOR_RAY_TRACING && INTEGRATOR != INTEGRATOR_NORMAL && INTEGRATOR != INTEGRATOR_DEPTH && (i == 0 || !(INTEGRATOR == INTEGRATOR_NEE || INTEGRATOR == INTEGRATOR_MIS)))
                radiance += throughput_weight * get_environment_radiance(ray_direction);
            else if (INTEGRATOR == INTEGRATOR_MIS && get_environment_kind() != ENVIRONMENT_NONE)
                radiance += throughput_weight * get_environment_radiance(ray_direction) * get_power_heuristic_weight(direction_density, get_environment_density(ray_direction));
            break;
        }
        uint triangle_index = g_hit_triangle_index;
        ray_origin += t * ray_direction;
        surface_t surface = get_surface(triangle_index, triangle, ray_origin, ray_direction);
        vec3 view = -ray_direction;
        if (INTEGRATOR == INTEGRATOR_RAY_TRACING)
            return surface.material.base_color;
        if (INTEGRATOR == INTEGRATOR_NORMAL)
            return surface.shading_normal;
        if (INTEGRATOR == INTEGRATOR_DEPTH)
            return vec3(t);
        // Emission found by following the path: all of it for the workshop's integrators,
        // cosine sampling and the camera ray; none for NEE; MIS-weighted for MIS.
        if (i == 0 || !(INTEGRATOR == INTEGRATOR_NEE || INTEGRATOR == INTEGRATOR_MIS)) {
            radiance += throughput_weight * surface.emission;
        } else if (INTEGRATOR == INTEGRATOR_MIS && surface.emission != vec3(0.0)) {
            float light_density = get_light_density(get_light_selection_probability(triangle_index), triangle, get_spherical_triangle(previous_position, triangle), ray_direction, t);
            radiance += throughput_weight * surface.emission * get_power_heuristic_weight(direction_density, light_density);
        }
        // Exercise 6 is emission plus one bounce of direct light, whatever MAX_PATH_LENGTH.
        if (i + 1 == vertex_count)
            break;
        if (INTEGRATOR == INTEGRATOR_NEE || INTEGRATOR == INTEGRATOR_MIS) {
            // One sample of each kind of light: their sum estimates all the direct light.
            vec3 direct = sample_direct_light_with_material(ray_origin, surface, view, seed);
            direct += sample_environment_light(ray_origin, surface, view, seed);
            direct += sample_punctual_light(ray_origin, surface, view, seed);
            radiance += throughput_weight * direct;
        }
        vec3 reflection;
        if (INTEGRATOR == INTEGRATOR_PATH_TRACING || INTEGRATOR == INTEGRATOR_DIRECT_ILLUMINATION) {
            // The workshop's uniform hemisphere: weight f (n_s . l) / (1 / (2 pi))
            ray_direction = sample_hemisphere(get_random_numbers(seed), surface.geometric_normal);
            reflection = get_surface_reflection(surface, view, ray_direction) * 2.0 * M_PI;
        } else if (INTEGRATOR == INTEGRATOR_COSINE) {
            ray_direction = sample_hemisphere_cosine(get_path_random_numbers(seed), surface.geometric_normal);
            direction_density = get_hemisphere_cosine_density(surface.geometric_normal, ray_direction);
            reflection = (direction_density > 0.0) ? get_surface_reflection(surface, view, ray_direction) / direction_density : vec3(0.0);
        } else {
            ray_direction = sample_brdf(get_path_random_numbers(seed), surface.material, surface.shading_normal, view);
            direction_density = get_brdf_density(surface.material, surface.shading_normal, view, ray_direction);
            reflection = (direction_density > 0.0) ? get_surface_reflection(surface, view, ray_direction) / direction_density : vec3(0.0);
        }
        if (reflection == vec3(0.0))
            break;
        throughput_weight *= reflection;
        ray_origin = offset_ray_origin(ray_origin, surface.geometric_normal);
        previous_position = ray_origin;
        if (importance_sampled && RUSSIAN_ROULETTE_START > 0 && i + 1 >= RUSSIAN_ROULETTE_START) {
            float survival = min(1.0, max(throughput_weight.r, max(throughput_weight.g, throughput_weight.b)));
            if (get_path_random_numbers(seed)[0] >= survival)
                break;
            throughput_weight /= survival;
        }
    }
    return radiance;
}

#endif
