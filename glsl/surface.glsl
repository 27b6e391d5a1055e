// The surface seam: what the path loop (glsl/path_loop.glsl) and the light estimators
// (glsl/lights.glsl) know of a surface. A hit becomes a surface_t (get_surface()), and
// everything else goes through one BSDF interface over it: sample_bsdf() (direction,
// density, weight, lobes), get_bsdf() and get_bsdf_density(), plus the side and offset rules
// (get_light_sample_origin(), get_departure_origin()). A new lobe or material model is added
// behind this interface, never in the integrators.
//
// This file holds the interface: the types, and the rules every model shares. The model is
// chosen once, when the kernel is built, and lives in a file of its own that defines the
// interface's functions (has_layers, is_transmissive, has_delta_lobe, has_only_delta_lobes,
// get_surface, get_front_emission,
// get_bsdf, get_reflected_radiance, get_bsdf_density, sample_bsdf, sample_cosine_direction,
// get_camera_emission, get_volume_transmittance):
// - glsl/lambert_surface.glsl, the workshop's (kernels without USE_MATERIALS): albedo / pi,
//   cosine sampled; Rust twin src/cpu/surface.rs;
// - glsl/gltf_surface.glsl, glTF 2.0 metallic-roughness (USE_MATERIALS): glsl/brdf.glsl's
//   BRDF with the textures, normal maps and emission of glsl/materials.glsl, and where a
//   material has them (and SCENE_HAS_LAYERS), the layers of glsl/layered_bsdf.glsl; Rust
//   twin src/cpu/gltf_surface.rs.
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
// Needs MAX_PATH_LENGTH and LIGHT_SAMPLING (of the files it includes) defined by the
// includer.
#ifndef VKPATH_SURFACE_GLSL
#define VKPATH_SURFACE_GLSL

#include "integrator.glsl"
#include "importance_sampling.glsl"
#include "brdf.glsl"

// Lobe flags of a bsdf_sample_t: a reflection (the direction leaves on the view's side), a
// transmission (it crosses the surface), a delta lobe (a Dirac peak, roughness 0: no density
// to weigh by MIS, density 0, and what the path finds next counts in full). Lambert and
// metallic-roughness reflect only.
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
    // Density w.r.t. solid angle (0 for a delta lobe's pick, BSDF_LOBE_DELTA)
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

// The material model, chosen once.
#ifdef USE_MATERIALS
#include "gltf_surface.glsl"
#else
#include "lambert_surface.glsl"
#endif

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
