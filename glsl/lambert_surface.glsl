// The surface seam's Lambert model, the workshop's (kernels built without USE_MATERIALS):
// the interface of glsl/surface.glsl for diffuse triangles, albedo / pi, cosine sampled, no
// layers, no volumes. Included by glsl/surface.glsl only, after its types.
// Rust twin: src/cpu/surface.rs.
#ifndef VKPATH_LAMBERT_SURFACE_GLSL
#define VKPATH_LAMBERT_SURFACE_GLSL

// Whether the surface's material has layers (transmission, a clear coat) that
// glsl/layered_bsdf.glsl evaluates; never for Lambert or where SCENE_HAS_LAYERS is false.
bool has_layers(surface_t surface) {
    return false;
}

// Whether light may pass through the surface (transmission).
bool is_transmissive(surface_t surface) {
    return false;
}

// Whether the surface's BSDF has a delta (perfectly specular) lobe: never for Lambert.
bool has_delta_lobe(surface_t surface) {
    return false;
}

// Whether every lobe of the surface's BSDF is delta: never for Lambert.
bool has_only_delta_lobes(surface_t surface) {
    return false;
}

// Everything the integrators need at a hit: normals, the material after textures, emission.
// \param triangle_index The hit triangle (g_hit_triangle_index)
// \param triangle The hit triangle as ray_mesh_intersection() returned it (not oriented)
// \param position The hit point, world space
// \param ray_direction Direction of the ray that hit it
surface_t get_surface(uint triangle_index, triangle_t triangle, vec3 position, vec3 ray_direction) {
    surface_t surface;
    // Lambert: the workshop's triangle, its normal facing the ray (orient_towards_ray())
    orient_towards_ray(triangle, ray_direction, is_double_sided(triangle_index));
    surface.geometric_normal = triangle.normal;
    surface.shading_normal = triangle.normal;
    surface.material.base_color = triangle.color;
    surface.emission = triangle.emission;
    return surface;
}

// Radiance that triangle i emits from its front at a point of it (a light sample's end).
vec3 get_front_emission(uint triangle_index, triangle_t triangle, vec3 position) {
    return triangle.emission;
}

// The BSDF times the cosine, as the rendering equation's integrand needs it:
// f(view, light) max(0, n_s . light), and 0 for light from below the geometric surface
// (layered materials: get_layered_bsdf(), which transmits light there).
vec3 get_bsdf(surface_t surface, vec3 view, vec3 light) {
    if (dot(surface.geometric_normal, light) <= 0.0)
        return vec3(0.0);
    return surface.material.base_color / M_PI * max(0.0, dot(surface.shading_normal, light));
}

// The radiance the surface reflects towards `view` from `radiance` arriving along `light`:
// get_bsdf() times the radiance. `bsdf` is get_bsdf(surface, view, light), which the caller
// has (it skips shadow rays where it is 0). Lambert multiplies in the order of the
// workshop's formula, a / pi * L * (n . l), so that its images keep every bit.
vec3 get_reflected_radiance(surface_t surface, vec3 light, vec3 bsdf, vec3 radiance) {
    return surface.material.base_color / M_PI * radiance * dot(surface.shading_normal, light);
}

// Density of sample_bsdf() w.r.t. solid angle.
float get_bsdf_density(surface_t surface, vec3 view, vec3 light) {
    return get_hemisphere_cosine_density(surface.geometric_normal, light);
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
    // Lambert: cosine sampling, whose weight a (n.l) / pi / p(l) is exactly the albedo a.
    bsdf_sample.direction = sample_hemisphere_cosine(random_numbers, surface.geometric_normal);
    bsdf_sample.density = get_hemisphere_cosine_density(surface.geometric_normal, bsdf_sample.direction);
    bsdf_sample.weight = (bsdf_sample.density > 0.0) ? surface.material.base_color : vec3(0.0);
    return bsdf_sample;
}

// A cosine-weighted direction around the geometric normal (the cosine integrator, whatever
// the BSDF), weight get_bsdf() / density.
bsdf_sample_t sample_cosine_direction(surface_t surface, vec3 view, vec2 random_numbers) {
    // Lambert's BSDF sampling is this very distribution, with the exact weight.
    return sample_bsdf(surface, view, random_numbers, 0.0);
}

// What a camera ray sees the surface emit: its emission, and an unlit material's colour.
vec3 get_camera_emission(surface_t surface) {
    return surface.emission;
}

// The fraction of its light a ray keeps over `distance` before it hit the surface: inside a
// refracting volume (the ray hit its back), KHR_materials_volume's absorption (Beer-Lambert,
// exp(-sigma distance)); 1 elsewhere. Absorption is applied where a ray leaves the volume, so
// volumes must be closed and not nested.
vec3 get_volume_transmittance(surface_t surface, float distance) {
    return vec3(1.0);
}

#endif
