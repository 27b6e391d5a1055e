// The path loop of every integrator but the workshop's own (which keep their teaching
// variants, glsl/integrator.glsl): one loop of named steps over the surface seam
// (glsl/surface.glsl) and the lights room (glsl/lights.glsl), for Lambert and glTF
// materials alike. Each hit becomes a scattering vertex (glsl/scattering_vertex.glsl:
// get_surface_vertex()), which the light samples, MIS, guiding and the direction sampling
// take; the hit's own terms (its emission, the first-hit views, the volume transmittance of
// the segment before it) read its surface. At each hit: 1. the emission the path found (get_found_emission()); 2. the
// light samples (nee, mis: sample_direct_light()); 3. continue the path: a direction
// (sample_path_direction()), the throughput weight, Russian roulette. Each step asks
// glsl/integrators.glsl what the integrator does:
// - cosine: cosine-weighted directions, weight f (n_s . l) / p(l) (the albedo for Lambert);
//   all emission found is added;
// - nee and mis: BSDF importance sampling and light samples, MIS-weighted with the power
//   heuristic for mis (nee adds found emission only for the camera ray);
// - on glTF materials, also the workshop's Exercises 6 (direct illumination: one bounce) and
//   7 (path tracing) with uniform hemisphere directions, weight 2 pi f (n_s . l).
// MAX_PATH_LENGTH bounds the number of surface hits as in the workshop: a light sample at
// vertex j stands for a hit j + 1, so it is taken only while j < MAX_PATH_LENGTH.
// Transmissive materials (glass): shadow rays see glass as opaque, and nee and mis take no
// light samples at a glass surface (its smooth lobes are Dirac-like peaks that light samples
// could not find); so the emission that a path finds right after a vertex without light
// samples counts in full, for nee and mis alike: BSDF sampling is the only estimator of that
// light, which keeps both unbiased (light behind glass, caustics). Delta lobes (roughness 0,
// BSDF_LOBE_DELTA) likewise: a light sample never finds their peak, so the emission that a
// path finds after a delta pick counts in full (MIS weight 1), for nee and mis alike,
// whatever the vertex's light samples found through its other lobes. Every integrator
// samples the BSDF at transmissive surfaces and at surfaces with a delta lobe (a cosine or
// uniform hemisphere cannot find a refraction's or a mirror's peak); a ray that leaves a refracting volume
// loses what the volume absorbed (get_volume_transmittance()); Russian roulette weighs the
// throughput with the refractions' eta^2 divided out (as pbrt does), so that a path inside
// glass, whose radiance is scaled by 1 / eta^2, is not killed for it.
//
// Random numbers: cosine, nee and mis draw each at a fixed dimension pair
// (glsl/sample_dimensions.glsl, the table): the pixel jitter at CAMERA_PAIR_PIXEL (main(),
// box filter); at vertex i (0: the camera ray's hit) that is not the last, in the block that
// starts at get_vertex_dimension_pair(i): nee's and mis's light samples (glsl/lights.glsl
// names their rows), the direction at VERTEX_PAIR_DIRECTION and a layered material's lobe
// choice at VERTEX_PAIR_LOBE (has_layers()), the guide's pairs (glsl/path_guiding.glsl), and
// past RUSSIAN_ROULETTE_START the survival number at VERTEX_PAIR_RUSSIAN_ROULETTE. So no
// number depends on which others were drawn or in which order: the loop takes the light
// samples before or after the direction as suits the registers (SAMPLES_DIRECTION_FIRST). The
// workshop's Exercises 6 and 7 draw the workshop's PCG2D stream from `seed` in their order
// (main()'s get_sample_tex_coord(), then at each vertex the direction, and at a layered or
// transmissive surface sampled by its BSDF the direction's and the lobe's pairs): keep that
// order, which decides their every output bit. Alpha coverage (ALPHA_MODE_BLEND) hashes
// g_path.alpha_seed with the ray count instead and draws nothing, so the rays traced, and
// their order, must stay as they are.
//
// The global medium (render --medium, glsl/medium.glsl; compiled out without one,
// SCENE_HAS_MEDIUM): it fills the space outside closed refracting volumes (the path leaves it
// where it refracts into a volume's front and comes back where it refracts out of its back).
// On each segment in it, cosine, nee and mis sample a distance (sample_medium_distance(), at
// VERTEX_PAIR_MEDIUM_DISTANCE of the segment's vertex): short of the hit, the path scatters
// there (step_into_medium()) and that point is the path's vertex i instead of the hit, with
// the light samples of nee and mis (the phase function in place of the BSDF, MIS against the
// phase function's density), the phase function's direction (its own density, weight 1) and
// Russian roulette; else the path goes on to the hit, weighted by get_medium_passing_weight().
// A medium vertex counts towards MAX_PATH_LENGTH as a hit does, and takes no guide cell.
//
// Rust twin: src/cpu/path_loop.rs (Lambert, without media). Needs MAX_PATH_LENGTH, INTEGRATOR,
// RUSSIAN_ROULETTE_START, SAMPLER and LIGHT_SAMPLING defined by the includer.
#ifndef VKPATH_PATH_LOOP_GLSL
#define VKPATH_PATH_LOOP_GLSL

#include "integrators.glsl"
#include "scattering_vertex.glsl"
#include "path_guiding.glsl"
#include "lights.glsl"

// Step 1 at a hit: throughput times the emission the path found, weighted as the integrator
// says: all of it for the camera ray and integrators without light samples; none for nee
// (its light samples account for it); MIS-weighted against light sampling for mis.
// \param vertex Index of the hit on the path (0: the camera ray's)
// \param previous_position Origin of the ray that found it
// \param direction_density Density of the direction sample that found it
// \param light_sampled Whether the previous vertex took light samples that could find this
//        emission (false after a delta pick)
// \param light_origin, light_normal Its light sample's origin and the light tree's normal
vec3 get_found_emission(int vertex, vec3 throughput_weight, surface_t surface, uint triangle_index, triangle_t triangle, vec3 previous_position, vec3 ray_direction, float t, float direction_density, bool light_sampled, vec3 light_origin, vec3 light_normal) {
    if (vertex == 0)
        return throughput_weight * get_camera_emission(surface);
    if (!light_sampled)
        return throughput_weight * surface.emission;
    if (weighs_by_mis() && surface.emission != vec3(0.0)) {
        float light_density = get_emissive_triangle_density(triangle_index, triangle, previous_position, ray_direction, t, light_origin, light_normal);
        return throughput_weight * surface.emission * get_power_heuristic_weight(direction_density, light_density);
    }
    return vec3(0.0);
}

#ifdef USE_MATERIALS
// Step 1 where a ray leaves the scene: throughput times the environment's radiance, weighted
// as get_found_emission() weighs emission; in full where light samples never come from the
// environment (a constant one: SCENE_SAMPLES_ENVIRONMENT).
vec3 get_found_environment(int vertex, vec3 throughput_weight, vec3 ray_direction, float direction_density, bool light_sampled) {
    if (vertex == 0 || !light_sampled || !SCENE_SAMPLES_ENVIRONMENT)
        return throughput_weight * get_environment_radiance(ray_direction);
    if (weighs_by_mis() && get_environment_kind() != ENVIRONMENT_NONE)
        return throughput_weight * get_environment_radiance(ray_direction) * get_power_heuristic_weight(direction_density, get_environment_density(ray_direction));
    return vec3(0.0);
}
#endif

// Whether the path loop samples a vertex's direction before its light samples (glTF
// materials, whose surface is larger than a direction sample) or after (Lambert).
#ifdef USE_MATERIALS
const bool SAMPLES_DIRECTION_FIRST = true;
#else
const bool SAMPLES_DIRECTION_FIRST = false;
#endif

// The numbers of a direction sample: dimension pair `dimension_pair` for the
// importance-sampled integrators; the workshop's next PCG2D pair for Exercises 6 and 7,
// which draw in their order.
vec2 get_direction_random_numbers(uint dimension_pair, inout uvec2 seed) {
    return is_importance_sampled() ? get_path_random_numbers(dimension_pair) : get_random_numbers(seed);
}

// Step 3: the direction the path continues in, as the integrator samples it (by the BSDF
// at transmissive surfaces and at delta lobes whatever the integrator).
// \param vertex_pairs The vertex's first dimension pair (get_vertex_dimension_pair())
// \param seed The workshop's PCG2D state (Exercises 6 and 7 only)
bsdf_sample_t sample_path_direction(scattering_vertex_t vertex, uint vertex_pairs, inout uvec2 seed) {
    surface_t surface = vertex.surface;
    vec3 view = vertex.view;
    bool transmissive = is_transmissive(surface) || has_delta_lobe(surface);
    if (samples_uniform_directions() && !transmissive)
        return sample_uniform_direction(surface, view, get_random_numbers(seed));
    vec2 random_numbers = get_direction_random_numbers(vertex_pairs + VERTEX_PAIR_DIRECTION, seed);
    if (samples_cosine_directions() && !transmissive)
        return sample_cosine_direction(surface, view, random_numbers);
    float lobe_random = has_layers(surface) ? get_direction_random_numbers(vertex_pairs + VERTEX_PAIR_LOBE, seed)[0] : 0.0;
    return sample_bsdf(surface, view, random_numbers, lobe_random);
}

// Step 3 with path guiding (glsl/path_guiding.glsl): at a vertex that the guide guides (cell
// `guide_cell`), one number chooses between sample_path_direction() and the guide; elsewhere
// (GUIDE_NO_CELL, always without guiding) sample_path_direction() alone. One function for
// both, so that sample_path_direction() appears once: on lavapipe both sides of a branch
// run, and a guided and an unguided call would each pay for the BSDF's sampling.
// Only nee and mis guide (at vertices with light samples), so the guide's numbers are always
// at their dimension pairs.
bsdf_sample_t sample_guided_path_direction(scattering_vertex_t vertex, uint guide_cell, uint vertex_pairs, inout uvec2 seed) {
    bool guided = guide_cell != GUIDE_NO_CELL;
    bool bsdf_chosen = !guided || get_path_random_numbers(vertex_pairs + VERTEX_PAIR_GUIDE_CHOICE)[0] < GUIDE_BSDF_FRACTION;
    bsdf_sample_t bsdf_sample;
    vec2 guide_random_numbers = vec2(0.0);
    if (bsdf_chosen)
        bsdf_sample = sample_path_direction(vertex, vertex_pairs, seed);
    else
        guide_random_numbers = get_path_random_numbers(vertex_pairs + VERTEX_PAIR_GUIDE_DIRECTION);
    if (!guided)
        return bsdf_sample;
    return get_guided_direction(vertex, guide_cell, bsdf_sample, bsdf_chosen, guide_random_numbers);
}

// Russian roulette after vertex `vertex` (past RUSSIAN_ROULETTE_START, importance-sampled
// integrators only): the path continues with probability q = min(1, max throughput component
// times eta_scale), and its throughput is divided by q, which keeps the estimate unbiased.
// \return Whether the path continues
bool survives_russian_roulette(int vertex, uint vertex_pairs, inout vec3 throughput_weight, float eta_scale) {
    if (is_importance_sampled() && RUSSIAN_ROULETTE_START > 0 && vertex + 1 >= RUSSIAN_ROULETTE_START) {
        float survival = min(1.0, max(throughput_weight.r, max(throughput_weight.g, throughput_weight.b)) * eta_scale);
        if (get_path_random_numbers(vertex_pairs + VERTEX_PAIR_RUSSIAN_ROULETTE)[0] >= survival)
            return false;
        throughput_weight /= survival;
    }
    return true;
}

// What the camera ray's hit shows (ray tracing: the base colour; normal: the shading
// normal; depth: the ray parameter t; material: (metallic, roughness, 0) after texture
// lookups, (0, 1, 0) for the Lambertian triangles of kernels without USE_MATERIALS, which
// leave them unset; triangle: (triangle_index + 1, b_1, b_2), the barycentrics of `position`).
// The path loop returns it at its first hit (0 where the ray hits
// nothing): one intersection and one get_surface() in the kernel serve every integrator,
// which lavapipe translates and optimises once instead of twice.
vec3 get_first_hit_view(surface_t surface, float t, uint triangle_index, triangle_t triangle, vec3 position) {
    if (INTEGRATOR == INTEGRATOR_TRIANGLE)
        return vec3(float(triangle_index + 1u), get_barycentrics(position, triangle).yz);
    if (INTEGRATOR == INTEGRATOR_RAY_TRACING)
        return surface.material.base_color;
    if (INTEGRATOR == INTEGRATOR_NORMAL)
        return surface.shading_normal;
    if (INTEGRATOR == INTEGRATOR_MATERIAL) {
#ifdef USE_MATERIALS
        return vec3(surface.material.metallic, surface.material.roughness, 0.0);
#else
        return vec3(0.0, 1.0, 0.0);
#endif
    }
    return vec3(t);
}

// A Monte Carlo estimate of the radiance arriving along a ray: the loop of the file's
// comment. L_{j+1} = L_j + T_j (found emission + light samples), T_{j+1} = T_j weight_j.
// \param ray_origin, ray_direction The camera ray, world space
// \param seed The sample's PCG2D state: the workshop's Exercises 6 and 7 draw from it (the
//        others at fixed dimension pairs, get_path_random_numbers())
vec3 get_path_radiance(vec3 ray_origin, vec3 ray_direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    vec3 throughput_weight = vec3(1.0);
    // Density of the direction sample that produced ray_direction (0: the camera ray, a
    // delta pick), and whether its vertex took light samples that could find what it finds
    // (not after a delta pick).
    float direction_density = 0.0;
    bool light_sampled = false;
    // The product of the refractions' eta^2 along the path (Russian roulette's correction).
    float eta_scale = 1.0;
    // Origin of the current ray: where MIS weights see a light found by it.
    vec3 previous_position = ray_origin;
    // Where the previous vertex took its light sample, and the light tree's normal there.
    vec3 light_origin = vec3(0.0);
    vec3 light_normal = vec3(0.0);
    int vertex_count = is_direct_illumination() ? 2 : MAX_PATH_LENGTH;
    // Whether the ray travels through the global medium (not inside a refracting volume)
    bool in_medium = true;
    // The scattering medium of the refracting volume the ray travels in
    // (KHR_materials_volume_scatter, SCENE_HAS_VOLUME_SCATTER), one slot: set where the path
    // refracts into a scattering volume's front, cleared where it refracts out of a back. It
    // holds the volume's sigma_s and g only (absorption 0): the volume's absorption stays
    // Beer-Lambert, applied per segment.
    bool in_volume_medium = false;
    medium_t volume_medium = medium_t(vec3(0.0), vec3(0.0), 0.0);
    // That volume's absorption coefficient sigma_a (its material's attenuation)
    vec3 volume_absorption = vec3(0.0);
    for (int i = 0; i != vertex_count; ++i) {
        float t;
        triangle_t triangle;
        bool hit = ray_mesh_intersection(t, triangle, ray_origin, ray_direction);
        // The global medium before the hit: a scattering event there is vertex i
        if (SCENE_HAS_MEDIUM && in_medium && is_importance_sampled()) {
            medium_t medium = get_global_medium();
            uint vertex_pairs = get_vertex_dimension_pair(i);
            float segment = hit ? t : NO_HIT_T;
            float distance = sample_medium_distance(medium, get_path_random_numbers(vertex_pairs + VERTEX_PAIR_MEDIUM_DISTANCE));
            if (distance < segment) {
                throughput_weight *= get_medium_scattering_weight(medium, distance);
                ray_origin += distance * ray_direction;
                scattering_vertex_t vertex = get_medium_vertex(ray_origin, -ray_direction, medium.anisotropy);
                if (i + 1 == vertex_count)
                    break;
                // 2. Light samples, weighed by MIS against the phase function's directions
                light_sampled = takes_light_samples();
                g_path.guide_cell = GUIDE_NO_CELL;
                if (light_sampled) {
                    light_origin = vertex.light_sample_origin;
                    light_normal = vertex.light_selection_normal;
                    radiance += throughput_weight * sample_direct_light(vertex, vertex_pairs);
                }
                // 3. The phase function's direction: weight p / p = 1
                ray_direction = sample_phase_function(get_path_random_numbers(vertex_pairs + VERTEX_PAIR_DIRECTION), vertex.view, medium.anisotropy);
                direction_density = get_phase_function_density(vertex.view, ray_direction, medium.anisotropy);
                previous_position = ray_origin;
                if (!survives_russian_roulette(i, vertex_pairs, throughput_weight, eta_scale))
                    break;
                continue;
            }
            throughput_weight *= get_medium_passing_weight(medium, segment);
        }
        // The scattering medium inside a refracting volume before the hit: the same distance
        // sampler on its sigma_s alone (absorption 0, so the weights are those of a medium of
        // albedo 1), times the volume's Beer-Lambert absorption exp(-sigma_a t) up to the
        // scattering point; a segment that reaches the volume's back takes its absorption
        // there (get_volume_transmittance()). Together: sigma_s exp(-sigma_t t) / p(t) where it
        // scatters, exp(-sigma_t d) / P(passing) where it passes, unbiased. No light samples
        // at such a vertex (shadow rays see glass as opaque, as at a glass surface): the phase
        // function's direction alone finds the light, which then counts in full.
        else if (SCENE_HAS_VOLUME_SCATTER && in_volume_medium && is_importance_sampled()) {
            uint vertex_pairs = get_vertex_dimension_pair(i);
            float segment = hit ? t : NO_HIT_T;
            float distance = sample_medium_distance(volume_medium, get_path_random_numbers(vertex_pairs + VERTEX_PAIR_MEDIUM_DISTANCE));
            if (distance < segment) {
                throughput_weight *= get_medium_scattering_weight(volume_medium, distance) * exp(-volume_absorption * distance);
                ray_origin += distance * ray_direction;
                if (i + 1 == vertex_count)
                    break;
                light_sampled = false;
                g_path.guide_cell = GUIDE_NO_CELL;
                vec3 view = -ray_direction;
                ray_direction = sample_phase_function(get_path_random_numbers(vertex_pairs + VERTEX_PAIR_DIRECTION), view, volume_medium.anisotropy);
                direction_density = get_phase_function_density(view, ray_direction, volume_medium.anisotropy);
                previous_position = ray_origin;
                if (!survives_russian_roulette(i, vertex_pairs, throughput_weight, eta_scale))
                    break;
                continue;
            }
            throughput_weight *= get_medium_passing_weight(volume_medium, segment);
        }
        if (!hit) {
#ifdef USE_MATERIALS
            if (!shows_first_hit())
                radiance += get_found_environment(i, throughput_weight, ray_direction, direction_density, light_sampled);
#endif
            break;
        }
        uint triangle_index = g_path.hit_triangle_index;
        ray_origin += t * ray_direction;
        surface_t surface = get_surface(triangle_index, triangle, ray_origin, ray_direction);
        // Ray tracing, normal, depth and material: what the camera ray's hit shows, no path
        if (shows_first_hit())
            return get_first_hit_view(surface, t, triangle_index, triangle, ray_origin);
        scattering_vertex_t vertex = get_surface_vertex(surface, ray_origin, -ray_direction);
        throughput_weight *= get_volume_transmittance(surface, t);
        // 1. The emission found
        radiance += get_found_emission(i, throughput_weight, surface, triangle_index, triangle, previous_position, ray_direction, t, direction_density, light_sampled, light_origin, light_normal);
        if (i + 1 == vertex_count)
            break;
        // 2. Light samples (none at glass), weighed by MIS against the direction sampling of
        // step 3, guided where the guide knows the vertex's cell
        light_sampled = takes_light_samples() && !is_transmissive(surface);
        uint guide_grid_cell = get_path_guide_grid_cell(vertex, light_sampled);
        g_path.guide_cell = get_path_guide_cell(guide_grid_cell, vertex);
        // 3. Continue the path: with glTF materials (SAMPLES_DIRECTION_FIRST), the direction
        // is sampled before the light samples, so that the shadow rays hold the direction
        // sample, not the material (RDNA3, nee and mis on materials.gltf: 192 -> 144 VGPRs, 8
        // -> 10 subgroups per SIMD); the Lambertian kernels take the light samples first,
        // where the other order would hold more (constant-triangle mis: 96 -> 108). Each draws
        // at its own dimension pairs, so the order changes no number.
        uint vertex_pairs = get_vertex_dimension_pair(i);
        bsdf_sample_t direction;
        if (SAMPLES_DIRECTION_FIRST)
            direction = sample_guided_path_direction(vertex, g_path.guide_cell, vertex_pairs, seed);
        if (light_sampled) {
            light_origin = vertex.light_sample_origin;
            light_normal = vertex.light_selection_normal;
            radiance += throughput_weight * sample_direct_light(vertex, vertex_pairs);
        }
        if (!SAMPLES_DIRECTION_FIRST)
            direction = sample_guided_path_direction(vertex, g_path.guide_cell, vertex_pairs, seed);
        vec3 departure_origin = get_vertex_departure_origin(vertex, direction.lobes);
        if (direction.weight == vec3(0.0))
            break;
        ray_direction = direction.direction;
        direction_density = direction.density;
        // A delta pick: no light sample finds what it finds, which counts in full
        if ((direction.lobes & BSDF_LOBE_DELTA) != 0u)
            light_sampled = false;
        eta_scale *= direction.eta * direction.eta;
        throughput_weight *= direction.weight;
        ray_origin = departure_origin;
        previous_position = ray_origin;
#ifdef USE_MATERIALS
        // A refraction into a volume's front leaves the global medium, one out of its back
        // returns to it
        if (SCENE_HAS_MEDIUM && (direction.lobes & BSDF_LOBE_TRANSMIT) != 0u && is_refracting(surface.material))
            in_medium = surface.back_face;
        // A refraction into a scattering volume's front makes its medium the path's, one out
        // of a back leaves it (nested volumes: the inner one's exit forgets the outer medium)
        if (SCENE_HAS_VOLUME_SCATTER && (direction.lobes & BSDF_LOBE_TRANSMIT) != 0u && is_refracting(surface.material)) {
            vec4 scattering = get_material_volume_scattering(get_material_index(triangle_index));
            in_volume_medium = !surface.back_face && any(greaterThan(scattering.rgb, vec3(0.0)));
            volume_medium = medium_t(vec3(0.0), scattering.rgb, scattering.a);
            volume_absorption = surface.material.attenuation;
        }
#endif
        if (!survives_russian_roulette(i, vertex_pairs, throughput_weight, eta_scale))
            break;
        // Training frames: where this vertex's light came from (glsl/path_guiding.glsl)
        record_guide_vertex(guide_grid_cell, vertex, ray_direction, direction_density, throughput_weight, radiance);
    }
    if (is_guide_training())
        splat_guide_records(radiance);
    return radiance;
}

#endif
