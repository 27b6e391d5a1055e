// A scattering vertex: a point where a path scatters, as the light estimator
// (glsl/lights.glsl), MIS, path guiding (glsl/path_guiding.glsl) and the path loop
// (glsl/path_loop.glsl) see it: a surface point (SCATTERING_VERTEX_SURFACE: a surface_t of
// the surface seam, glsl/surface.glsl) or a point in the render's global medium
// (SCATTERING_VERTEX_MEDIUM, glsl/medium.glsl), whose scattering is the Henyey-Greenstein
// phase function (glsl/phase_function.glsl) instead of a BSDF.
//
// The estimators ask a vertex four things, each a function here that dispatches on its kind:
// the scattering function towards a direction (get_vertex_scattering(): the BSDF f, or the
// phase function p), its density (get_vertex_scattering_density(): the BSDF sampler's, w.r.t.
// solid angle, or p itself), the light it scatters towards the view
// (get_vertex_scattered_radiance(): f (n_s . l) L, or p L: no cosine), and whether it
// scatters only into Dirac peaks (has_only_delta_scattering(); never in a medium); and they
// read where its shadow rays start (light_sample_origin: just off a surface, the point
// itself in a medium) and the light tree's bound (light_selection_normal: 0, no bound, in a
// medium). Path guiding guides surface vertices only: the path loop gives a medium vertex no
// guide cell. Shadow rays return the medium's transmittance (get_shadow_transmittance(),
// glsl/lights.glsl).
//
// SCENE_HAS_MEDIUM (SPEC_MEDIUM) is false in every render without --medium: the medium's
// branches below fold away, and the kernels are those without media.
//
// Rust twin: src/cpu/scattering_vertex.rs (ScatteringVertex, over the Lambert surface).
#ifndef VKPATH_SCATTERING_VERTEX_GLSL
#define VKPATH_SCATTERING_VERTEX_GLSL

#include "surface.glsl"
#include "medium.glsl"

// The kinds of scattering_vertex_t: a surface point, a point in a medium.
#define SCATTERING_VERTEX_SURFACE 0u
#define SCATTERING_VERTEX_MEDIUM 1u

// The render's global medium (glsl/shared.h's SPEC_MEDIUM): whether there is one, and its
// coefficients (src/medium.rs writes them).
layout(constant_id = SPEC_MEDIUM) const bool SCENE_HAS_MEDIUM = false;
layout(constant_id = SPEC_MEDIUM_COEFFICIENTS + 0) const float MEDIUM_ABSORPTION_R = 0.0;
layout(constant_id = SPEC_MEDIUM_COEFFICIENTS + 1) const float MEDIUM_ABSORPTION_G = 0.0;
layout(constant_id = SPEC_MEDIUM_COEFFICIENTS + 2) const float MEDIUM_ABSORPTION_B = 0.0;
layout(constant_id = SPEC_MEDIUM_COEFFICIENTS + 3) const float MEDIUM_SCATTERING_R = 0.0;
layout(constant_id = SPEC_MEDIUM_COEFFICIENTS + 4) const float MEDIUM_SCATTERING_G = 0.0;
layout(constant_id = SPEC_MEDIUM_COEFFICIENTS + 5) const float MEDIUM_SCATTERING_B = 0.0;
layout(constant_id = SPEC_MEDIUM_COEFFICIENTS + 6) const float MEDIUM_ANISOTROPY = 0.0;

// Whether some material encloses a scattering volume (glsl/shared.h's
// SPEC_SCENE_HAS_VOLUME_SCATTER): false compiles the volume's medium out of the path loop.
layout(constant_id = SPEC_SCENE_HAS_VOLUME_SCATTER) const bool SCENE_HAS_VOLUME_SCATTER = false;

// The global medium that fills the space outside closed refracting volumes (render --medium).
medium_t get_global_medium() {
    return medium_t(vec3(MEDIUM_ABSORPTION_R, MEDIUM_ABSORPTION_G, MEDIUM_ABSORPTION_B), vec3(MEDIUM_SCATTERING_R, MEDIUM_SCATTERING_G, MEDIUM_SCATTERING_B), MEDIUM_ANISOTROPY);
}

// A point where a path scatters, with what the light estimator needs of it.
struct scattering_vertex_t {
    // SCATTERING_VERTEX_*: what scatters here
    uint kind;
    // The point, world space (on the surface, or in the medium)
    vec3 position;
    // Unit direction towards where the path came from (minus the ray's direction), world
    // space
    vec3 view;
    // Where shadow rays from this vertex start, world space: just off the surface on the
    // side light may come from (get_light_sample_origin())
    vec3 light_sample_origin;
    // The normal with which the light tree bounds what the vertex receives, unit or 0 (no
    // bound): get_light_selection_normal()
    vec3 light_selection_normal;
    // The phase function's g, in (-1, 1) (kind SCATTERING_VERTEX_MEDIUM; 0 at a surface)
    float anisotropy;
    // The surface hit (kind SCATTERING_VERTEX_SURFACE; undefined in a medium)
    surface_t surface;
};

// The normal with which the light tree bounds what a surface receives (glsl/light_tree.glsl): the geometric
// normal on the ray's side (get_bsdf() is 0 below it); 0 (no bound) for layered materials.
vec3 get_light_selection_normal(surface_t surface) {
    return has_layers(surface) ? vec3(0.0) : surface.geometric_normal;
}

// The vertex of a surface hit at `position`, seen along `view` (unit, towards the ray's
// origin).
scattering_vertex_t get_surface_vertex(surface_t surface, vec3 position, vec3 view) {
    scattering_vertex_t vertex;
    vertex.kind = SCATTERING_VERTEX_SURFACE;
    vertex.position = position;
    vertex.view = view;
    vertex.light_sample_origin = get_light_sample_origin(surface, position);
    vertex.light_selection_normal = get_light_selection_normal(surface);
    vertex.anisotropy = 0.0;
    vertex.surface = surface;
    return vertex;
}

// The vertex of a scattering event at `position` in a medium of phase function g =
// `anisotropy`, seen along `view` (unit, towards the ray's origin): shadow rays start at the
// point itself, the light tree has no bound, and the surface is left undefined.
scattering_vertex_t get_medium_vertex(vec3 position, vec3 view, float anisotropy) {
    scattering_vertex_t vertex;
    vertex.kind = SCATTERING_VERTEX_MEDIUM;
    vertex.position = position;
    vertex.view = view;
    vertex.light_sample_origin = position;
    vertex.light_selection_normal = vec3(0.0);
    vertex.anisotropy = anisotropy;
    return vertex;
}

// Whether the vertex lies in a medium: false in every kernel without one (SCENE_HAS_MEDIUM),
// which folds the medium's branches away.
bool is_medium_vertex(scattering_vertex_t vertex) {
    return SCENE_HAS_MEDIUM && vertex.kind == SCATTERING_VERTEX_MEDIUM;
}

// The vertex's scattering function for light arriving from `direction` (unit, world space,
// away from the vertex) and leaving towards its view: the BSDF f, or the phase function p
// (1/sr).
vec3 get_vertex_scattering(scattering_vertex_t vertex, vec3 direction) {
    if (is_medium_vertex(vertex))
        return vec3(get_phase_function(vertex.view, direction, vertex.anisotropy));
    return get_bsdf(vertex.surface, vertex.view, direction);
}

// Density w.r.t. solid angle with which the vertex's own sampler (sample_bsdf()) finds
// `direction` (in a medium sample_phase_function()'s, the phase function itself).
float get_vertex_scattering_density(scattering_vertex_t vertex, vec3 direction) {
    if (is_medium_vertex(vertex))
        return get_phase_function_density(vertex.view, direction, vertex.anisotropy);
    return get_bsdf_density(vertex.surface, vertex.view, direction);
}

// The radiance scattered towards the view of radiance `radiance` arriving from `direction`,
// given `scattering` = get_vertex_scattering(vertex, direction): f (n_s . l) L for a surface,
// p L in a medium (no cosine: a phase function is a density over the sphere).
vec3 get_vertex_scattered_radiance(scattering_vertex_t vertex, vec3 direction, vec3 scattering, vec3 radiance) {
    if (is_medium_vertex(vertex))
        return scattering * radiance;
    return get_reflected_radiance(vertex.surface, direction, scattering, radiance);
}

// Whether the vertex scatters only into Dirac peaks (a smooth metal), where no light
// sample can contribute (never in a medium).
bool has_only_delta_scattering(scattering_vertex_t vertex) {
    if (is_medium_vertex(vertex))
        return false;
    return has_only_delta_lobes(vertex.surface);
}

// Where a path continues from after sampling a direction with `lobes` (BSDF_LOBE_*): just
// off the surface on the side the direction leaves to (get_departure_origin()); the point
// itself in a medium.
vec3 get_vertex_departure_origin(scattering_vertex_t vertex, uint lobes) {
    if (is_medium_vertex(vertex))
        return vertex.position;
    return get_departure_origin(vertex.surface, vertex.position, lobes);
}

#endif
