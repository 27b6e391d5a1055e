// The surface seam: what the path loop (glsl/path_loop.glsl) and the light estimators
// (glsl/lights.glsl) know of a surface. A hit becomes a surface_t (get_surface()), and
// everything else goes through one BSDF interface over it: sample_bsdf() (direction,
// density, weight, lobes), get_bsdf() and get_bsdf_density(), plus the side and offset rules
// (get_light_sample_origin(), get_departure_origin()). A new lobe or material model is added
// here and behind it, never in the integrators.
//
// Two material models, chosen when the kernel is built:
// - Lambert, the workshop's (kernels without USE_MATERIALS): albedo / pi, cosine sampled;
// - glTF 2.0 metallic-roughness (USE_MATERIALS): glsl/brdf.glsl's BRDF with the textures,
//   normal maps and emission of glsl/materials.glsl, and where a material has them (and
//   SCENE_HAS_LAYERS), the transmission and clear coat of glsl/layered_bsdf.glsl; in scenes
//   whose materials are all Lambertian (not SCENE_HAS_SPECULAR) its Lambertian special case
//   (get_lambert_brdf() and its sampling), the same bits without the GGX maths.
//
// Side rule: the BSDF is evaluated with the shading normal (interpolated vertex normals,
// perturbed by a normal map), but light never crosses the geometric surface: a direction
// counts only where it leaves on the side the ray came from (geometric normal n_g . l > 0);
// get_bsdf() is 0 elsewhere. The shading normal is flipped with the geometric one when a ray
// hits the back, and where the view lies below it (a vertex normal bent away from the viewer)
// the geometric normal is used instead, so that get_brdf() always sees the view above its
// normal. Rays leave (and light samples start) just off the surface on the geometric
// normal's side (offset_ray_origin()). Transmissive materials let light through to the other
// side too: a direction below the geometric surface counts where it is below the shading
// normal too. Shadow rays see glass as opaque, and the path loop takes no light samples at
// glass (glsl/path_loop.glsl).
//
// Rust twins: src/cpu/surface.rs (the Lambert model), src/cpu/gltf_surface.rs (the glTF
// model's get_surface() and get_bsdf(), reading the same words), src/cpu/brdf.rs. Needs
// MAX_PATH_LENGTH and LIGHT_SAMPLING (of the files it includes) defined by the includer.
#ifndef VKPATH_SURFACE_GLSL
#define VKPATH_SURFACE_GLSL

#include "integrator.glsl"
#include "importance_sampling.glsl"
#include "brdf.glsl"
#ifdef USE_MATERIALS
#include "materials.glsl"
#include "layered_bsdf.glsl"
#endif

// Lobe flags of a bsdf_sample_t: a reflection (the direction leaves on the view's side), a
// transmission (it crosses the surface), a delta lobe (a Dirac peak: no density to weigh by
// MIS). Lambert and metallic-roughness reflect only.
#define BSDF_LOBE_REFLECT 1u
#define BSDF_LOBE_TRANSMIT 2u
#define BSDF_LOBE_DELTA 4u

// A hit point as the integrators shade it.
struct surface_t {
    // Unit geometric normal, on the side the ray came from
    vec3 geometric_normal;
    // Unit shading normal, on the same side, with the view direction above it (Lambert: the
    // geometric normal)
    vec3 shading_normal;
    // The material after texture lookups (Lambert: only base_color, the albedo, is set)
    material_t material;
    // Emitted radiance towards the ray's origin (0 from the back of one-sided emitters)
    vec3 emission;
    // glTF only (left unset by Lambert):
    // The clear coat's unit normal, on the view's side (the geometric normal where the view
    // lies below it)
    vec3 clearcoat_normal;
    // Relative index of refraction across the surface, the far side's over the ray's: ior
    // where the ray hit the front, 1 / ior where it comes from inside
    float eta;
    // Whether the ray hit the triangle's back (from inside a closed mesh)
    bool back_face;
    // KHR_materials_unlit: the base colour, what camera rays see (0 for lit materials)
    vec3 unlit_color;
};

// A direction sampled at a surface, as sample_bsdf() and the loop's other direction
// samplers return it.
struct bsdf_sample_t {
    // Unit direction, world space, away from the surface
    vec3 direction;
    // Density w.r.t. solid angle
    float density;
    // get_bsdf() / density: what the path's throughput is multiplied by; 0 ends the path
    vec3 weight;
    // BSDF_LOBE_* of the lobe sampled
    uint lobes;
    // The relative index of refraction the direction crossed (surface_t.eta), 1 for
    // reflections and thin walls: refraction scales radiance by 1 / eta^2, which Russian
    // roulette divides out
    float eta;
};

// Whether the surface's material has layers (transmission, a clear coat) that
// glsl/layered_bsdf.glsl evaluates; never for Lambert or where SCENE_HAS_LAYERS is false.
bool has_layers(surface_t surface) {
#ifdef USE_MATERIALS
    return SCENE_HAS_LAYERS && is_layered(surface.material);
#else
    return false;
#endif
}

// Whether light may pass through the surface (transmission).
bool is_transmissive(surface_t surface) {
#ifdef USE_MATERIALS
    return SCENE_HAS_LAYERS && surface.material.transmission > 0.0;
#else
    return false;
#endif
}

// Everything the integrators need at a hit: normals, the material after textures, emission.
// \param triangle_index The hit triangle (g_hit_triangle_index)
// \param triangle The hit triangle as ray_mesh_intersection() returned it (not oriented)
// \param position The hit point, world space
// \param ray_direction Direction of the ray that hit it
surface_t get_surface(uint triangle_index, triangle_t triangle, vec3 position, vec3 ray_direction) {
    surface_t surface;
#ifdef USE_MATERIALS
    uint material_index = get_material_index(triangle_index);
    vec3 barycentrics = get_barycentrics(position, triangle);
    vec2 tex_coord = get_tex_coord(triangle_index, barycentrics);
    bool front = dot(triangle.normal, ray_direction) <= 0.0;
    vec3 view = -ray_direction;
    surface.geometric_normal = front ? triangle.normal : -triangle.normal;
    material_textures_t textures = sample_material_textures(material_index, tex_coord);
    vec3 shading_normal = get_front_shading_normal(triangle_index, material_index, barycentrics, textures, triangle.normal);
    shading_normal = front ? shading_normal : -shading_normal;
    surface.shading_normal = (dot(shading_normal, view) > 0.0) ? shading_normal : surface.geometric_normal;
    vec4 base_color = get_base_color(material_index, textures.slots[MATERIAL_TEXTURE_BASE_COLOR]);
    surface.material = get_material(material_index, textures, base_color);
    bool double_sided = is_double_sided(triangle_index);
    surface.emission = (front || double_sided) ? get_material_emission(material_index, textures.slots[MATERIAL_TEXTURE_EMISSIVE]) : vec3(0.0);
    surface.eta = front ? surface.material.ior : 1.0 / surface.material.ior;
    surface.back_face = !front;
    surface.clearcoat_normal = surface.geometric_normal;
    surface.unlit_color = vec3(0.0);
    if (SCENE_HAS_LAYERS) {
        if (surface.material.clearcoat > 0.0) {
            vec3 clearcoat_normal = get_front_clearcoat_normal(triangle_index, material_index, barycentrics, textures, triangle.normal);
            clearcoat_normal = front ? clearcoat_normal : -clearcoat_normal;
            surface.clearcoat_normal = (dot(clearcoat_normal, view) > 0.0) ? clearcoat_normal : surface.geometric_normal;
        }
        if (is_unlit_material(material_index)) {
            surface.unlit_color = base_color.rgb;
            // Nothing reflects: black, no specular lobe, no layers
            surface.material.base_color = vec3(0.0);
            surface.material.metallic = 0.0;
            surface.material.specular = 0.0;
            surface.material.transmission = 0.0;
            surface.material.clearcoat = 0.0;
            surface.material.sheen_color = vec3(0.0);
        }
    }
#else
    // Lambert: the workshop's triangle, its normal facing the ray (orient_towards_ray())
    orient_towards_ray(triangle, ray_direction, is_double_sided(triangle_index));
    surface.geometric_normal = triangle.normal;
    surface.shading_normal = triangle.normal;
    surface.material.base_color = triangle.color;
    surface.emission = triangle.emission;
#endif
    return surface;
}

// Radiance that triangle i emits from its front at a point of it (a light sample's end).
vec3 get_front_emission(uint triangle_index, triangle_t triangle, vec3 position) {
#ifdef USE_MATERIALS
    uint material_index = get_material_index(triangle_index);
    vec2 tex_coord = get_tex_coord(triangle_index, get_barycentrics(position, triangle));
    return get_material_emission(material_index, sample_material_texture(material_index, MATERIAL_TEXTURE_EMISSIVE, tex_coord));
#else
    return triangle.emission;
#endif
}

// The BSDF times the cosine, as the rendering equation's integrand needs it:
// f(view, light) max(0, n_s . light), and 0 for light from below the geometric surface
// (layered materials: get_layered_bsdf(), which transmits light there).
vec3 get_bsdf(surface_t surface, vec3 view, vec3 light) {
#ifdef USE_MATERIALS
    if (has_layers(surface))
        return get_layered_bsdf(surface.material, surface.eta, surface.geometric_normal, surface.shading_normal, surface.clearcoat_normal, view, light);
#endif
    if (dot(surface.geometric_normal, light) <= 0.0)
        return vec3(0.0);
#ifdef USE_MATERIALS
    if (!SCENE_HAS_SPECULAR)
        return get_lambert_brdf(surface.material, surface.shading_normal, view, light) * max(0.0, dot(surface.shading_normal, light));
    return get_brdf(surface.material, surface.shading_normal, view, light) * max(0.0, dot(surface.shading_normal, light));
#else
    return surface.material.base_color / M_PI * max(0.0, dot(surface.shading_normal, light));
#endif
}

// The radiance the surface reflects towards `view` from `radiance` arriving along `light`:
// get_bsdf() times the radiance. `bsdf` is get_bsdf(surface, view, light), which the caller
// has (it skips shadow rays where it is 0). Lambert multiplies in the order of the
// workshop's formula, a / pi * L * (n . l), so that its images keep every bit.
vec3 get_reflected_radiance(surface_t surface, vec3 light, vec3 bsdf, vec3 radiance) {
#ifdef USE_MATERIALS
    return bsdf * radiance;
#else
    return surface.material.base_color / M_PI * radiance * dot(surface.shading_normal, light);
#endif
}

// Density of sample_bsdf() w.r.t. solid angle.
float get_bsdf_density(surface_t surface, vec3 view, vec3 light) {
#ifdef USE_MATERIALS
    if (has_layers(surface))
        return get_layered_density(surface.material, surface.eta, surface.shading_normal, surface.clearcoat_normal, view, light);
    if (!SCENE_HAS_SPECULAR)
        return get_lambert_brdf_density(surface.shading_normal, view, light);
    return get_brdf_density(surface.material, surface.shading_normal, view, light);
#else
    return get_hemisphere_cosine_density(surface.geometric_normal, light);
#endif
}

// BSDF importance sampling: a direction with density get_bsdf_density() and the weight
// get_bsdf() / density (0 where the density is 0).
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \param lobe_random Uniform in [0,1): chooses the lobe of layered materials (has_layers();
//        unused otherwise)
bsdf_sample_t sample_bsdf(surface_t surface, vec3 view, vec2 random_numbers, float lobe_random) {
    bsdf_sample_t bsdf_sample;
    bsdf_sample.lobes = BSDF_LOBE_REFLECT;
    bsdf_sample.eta = 1.0;
#ifdef USE_MATERIALS
    if (has_layers(surface)) {
        bsdf_sample.direction = sample_layered_bsdf(random_numbers, lobe_random, surface.material, surface.eta, surface.shading_normal, surface.clearcoat_normal, view);
        if (dot(surface.geometric_normal, bsdf_sample.direction) < 0.0) {
            bsdf_sample.lobes = BSDF_LOBE_TRANSMIT;
            bsdf_sample.eta = is_refracting(surface.material) ? surface.eta : 1.0;
        }
    } else if (!SCENE_HAS_SPECULAR)
        bsdf_sample.direction = sample_lambert_brdf(random_numbers, surface.shading_normal);
    else
        bsdf_sample.direction = sample_brdf(random_numbers, surface.material, surface.shading_normal, view);
    // One density and one BSDF evaluation after both branches: the kernel holds them once
    // (lavapipe translates every inlined copy at each start).
    bsdf_sample.density = get_bsdf_density(surface, view, bsdf_sample.direction);
    bsdf_sample.weight = (bsdf_sample.density > 0.0) ? get_bsdf(surface, view, bsdf_sample.direction) / bsdf_sample.density : vec3(0.0);
#else
    // Lambert: cosine sampling, whose weight a (n.l) / pi / p(l) is exactly the albedo a.
    bsdf_sample.direction = sample_hemisphere_cosine(random_numbers, surface.geometric_normal);
    bsdf_sample.density = get_hemisphere_cosine_density(surface.geometric_normal, bsdf_sample.direction);
    bsdf_sample.weight = (bsdf_sample.density > 0.0) ? surface.material.base_color : vec3(0.0);
#endif
    return bsdf_sample;
}

// A cosine-weighted direction around the geometric normal (the cosine integrator, whatever
// the BSDF), weight get_bsdf() / density.
bsdf_sample_t sample_cosine_direction(surface_t surface, vec3 view, vec2 random_numbers) {
#ifdef USE_MATERIALS
    bsdf_sample_t bsdf_sample;
    bsdf_sample.lobes = BSDF_LOBE_REFLECT;
    bsdf_sample.eta = 1.0;
    bsdf_sample.direction = sample_hemisphere_cosine(random_numbers, surface.geometric_normal);
    bsdf_sample.density = get_hemisphere_cosine_density(surface.geometric_normal, bsdf_sample.direction);
    bsdf_sample.weight = (bsdf_sample.density > 0.0) ? get_bsdf(surface, view, bsdf_sample.direction) / bsdf_sample.density : vec3(0.0);
    return bsdf_sample;
#else
    // Lambert's BSDF sampling is this very distribution, with the exact weight.
    return sample_bsdf(surface, view, random_numbers, 0.0);
#endif
}

// The workshop's uniform hemisphere direction around the geometric normal (Exercises 6 and
// 7 on glTF materials): density 1 / (2 pi), weight get_bsdf() 2 pi.
bsdf_sample_t sample_uniform_direction(surface_t surface, vec3 view, vec2 random_numbers) {
    bsdf_sample_t bsdf_sample;
    bsdf_sample.lobes = BSDF_LOBE_REFLECT;
    bsdf_sample.eta = 1.0;
    bsdf_sample.direction = sample_hemisphere(random_numbers, surface.geometric_normal);
    bsdf_sample.density = 0.5 / M_PI;
    bsdf_sample.weight = get_bsdf(surface, view, bsdf_sample.direction) * 2.0 * M_PI;
    return bsdf_sample;
}

// What a camera ray sees the surface emit: its emission, and an unlit material's colour.
vec3 get_camera_emission(surface_t surface) {
#ifdef USE_MATERIALS
    return surface.emission + surface.unlit_color;
#else
    return surface.emission;
#endif
}

// The fraction of its light a ray keeps over `distance` before it hit the surface: inside a
// refracting volume (the ray hit its back), KHR_materials_volume's absorption (Beer-Lambert,
// exp(-sigma distance)); 1 elsewhere. Absorption is applied where a ray leaves the volume, so
// volumes must be closed and not nested.
vec3 get_volume_transmittance(surface_t surface, float distance) {
#ifdef USE_MATERIALS
    if (is_transmissive(surface) && surface.back_face && is_refracting(surface.material))
        return get_absorption(surface.material, distance);
#endif
    return vec3(1.0);
}

// Where a light sample's shadow ray starts: just off the surface on the side light may come
// from (the geometric normal's).
vec3 get_light_sample_origin(surface_t surface, vec3 position) {
    return offset_ray_origin(position, surface.geometric_normal);
}

// Where a path continues from after sampling `direction` with `lobes`: just off the surface
// on the side the direction leaves to (reflections: the geometric normal's).
vec3 get_departure_origin(surface_t surface, vec3 position, uint lobes) {
    return offset_ray_origin(position, ((lobes & BSDF_LOBE_TRANSMIT) != 0u) ? -surface.geometric_normal : surface.geometric_normal);
}

#endif
