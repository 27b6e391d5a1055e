// A scattering vertex: a point where a path scatters, as the light estimator
// (glsl/lights.glsl), MIS, path guiding (glsl/path_guiding.glsl) and the path loop
// (glsl/path_loop.glsl) see it. Today every vertex is a surface point
// (SCATTERING_VERTEX_SURFACE: a surface_t of the surface seam, glsl/surface.glsl); the kind
// word leaves room for a point in a participating medium, whose scattering is a phase
// function instead of a BSDF.
//
// The estimators ask a vertex four things, each a function here that dispatches on its kind:
// the scattering function towards a direction (get_vertex_scattering(): the BSDF f), its
// density (get_vertex_scattering_density(): the BSDF sampler's, w.r.t. solid angle), the
// light it scatters towards the view (get_vertex_scattered_radiance(): f (n_s . l) L), and
// whether it scatters only into Dirac peaks (has_only_delta_scattering()); and they read
// where its shadow rays start (light_sample_origin) and the light tree's bound
// (light_selection_normal). A medium's vertex would add: a phase function (value = density,
// no cosine, no side rule), light_sample_origin = position (no offset), light_selection_normal
// 0 (no bound), a guide cell without a facing (glsl/guiding.glsl), its distance sample at the
// VERTEX_PAIR row the table reserves for it, and shadow rays that return the medium's
// transmittance (get_shadow_transmittance(), glsl/lights.glsl). None of that exists yet:
// each function below has one kind.
//
// Rust twin: src/cpu/scattering_vertex.rs (ScatteringVertex, over the Lambert surface).
#ifndef VKPATH_SCATTERING_VERTEX_GLSL
#define VKPATH_SCATTERING_VERTEX_GLSL

#include "surface.glsl"

// The kinds of scattering_vertex_t: a surface point. (A point in a medium would be the next.)
#define SCATTERING_VERTEX_SURFACE 0u

// A point where a path scatters, with what the light estimator needs of it.
struct scattering_vertex_t {
    // SCATTERING_VERTEX_*: what scatters here (today always SCATTERING_VERTEX_SURFACE)
    uint kind;
    // The point, world space (on the surface)
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
    // The surface hit (kind SCATTERING_VERTEX_SURFACE)
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
    vertex.surface = surface;
    return vertex;
}

// The vertex's scattering function for light arriving from `direction` (unit, world space,
// away from the vertex) and leaving towards its view: the BSDF f (1/sr).
vec3 get_vertex_scattering(scattering_vertex_t vertex, vec3 direction) {
    return get_bsdf(vertex.surface, vertex.view, direction);
}

// Density w.r.t. solid angle with which the vertex's own sampler (sample_bsdf()) finds
// `direction`.
float get_vertex_scattering_density(scattering_vertex_t vertex, vec3 direction) {
    return get_bsdf_density(vertex.surface, vertex.view, direction);
}

// The radiance scattered towards the view of radiance `radiance` arriving from `direction`,
// given `scattering` = get_vertex_scattering(vertex, direction): f (n_s . l) L for a surface.
vec3 get_vertex_scattered_radiance(scattering_vertex_t vertex, vec3 direction, vec3 scattering, vec3 radiance) {
    return get_reflected_radiance(vertex.surface, direction, scattering, radiance);
}

// Whether the vertex scatters only into Dirac peaks (a smooth metal), where no light
// sample can contribute.
bool has_only_delta_scattering(scattering_vertex_t vertex) {
    return has_only_delta_lobes(vertex.surface);
}

// Where a path continues from after sampling a direction with `lobes` (BSDF_LOBE_*): just
// off the surface on the side the direction leaves to (get_departure_origin()).
vec3 get_vertex_departure_origin(scattering_vertex_t vertex, uint lobes) {
    return get_departure_origin(vertex.surface, vertex.position, lobes);
}

#endif
