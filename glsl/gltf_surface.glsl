// The surface seam's glTF 2.0 model (kernels built with USE_MATERIALS): the interface of
// glsl/surface.glsl over glsl/brdf.glsl's metallic-roughness BRDF, the textures, normal maps
// and emission of glsl/materials.glsl and, where a material has them (and SCENE_HAS_LAYERS),
// the transmission, clear coat and sheen of glsl/layered_bsdf.glsl; in scenes whose
// materials are all Lambertian (not SCENE_HAS_SPECULAR) its Lambertian special case
// (get_lambert_brdf() and its sampling), the same bits without the GGX maths.
// Included by glsl/surface.glsl only, after its types. Rust twin: src/cpu/gltf_surface.rs
// (reading the same words), over src/cpu/brdf.rs and src/cpu/layered_bsdf.rs.
#ifndef VKPATH_GLTF_SURFACE_GLSL
#define VKPATH_GLTF_SURFACE_GLSL

#include "materials.glsl"
#include "layered_bsdf.glsl"

// Whether the surface's material has layers (transmission, a clear coat) that
// glsl/layered_bsdf.glsl evaluates; never for Lambert or where SCENE_HAS_LAYERS is false.
bool has_layers(surface_t surface) {
    return SCENE_HAS_LAYERS && is_layered(surface.material);
}

// Whether light may pass through the surface (transmission).
bool is_transmissive(surface_t surface) {
    return SCENE_HAS_LAYERS && surface.material.transmission > 0.0;
}

// Whether the surface's BSDF has a delta (perfectly specular) lobe: a specular lobe (metal,
// or specular above 0) or a transmission of roughness 0, or a smooth clear coat. Directions
// that no BSDF sampling chose (cosine, uniform hemisphere) never find its peak, so every
// integrator samples the BSDF there (glsl/path_loop.glsl).
bool has_delta_lobe(surface_t surface) {
    if (!SCENE_HAS_SPECULAR)
        return false;
    material_t material = surface.material;
    if (get_ggx_alpha(material.roughness) == 0.0 && (material.metallic > 0.0 || material.specular > 0.0 || is_transmissive(surface)))
        return true;
    return has_layers(surface) && material.clearcoat > 0.0 && get_ggx_alpha(material.clearcoat_roughness) == 0.0;
}

// Whether every lobe of the surface's BSDF is delta, so that get_bsdf() is 0 for every
// direction and no light sample can reflect off it: a smooth (roughness 0) full metal
// without layers (get_brdf()'s dielectric weighs 1 - metallic = 0, its GGX lobe has no value).
// Transmissive surfaces take no light samples at all (glsl/path_loop.glsl).
bool has_only_delta_lobes(surface_t surface) {
    if (!SCENE_HAS_SPECULAR)
        return false;
    material_t material = surface.material;
    return get_ggx_alpha(material.roughness) == 0.0 && material.metallic == 1.0 && !has_layers(surface);
}

// Everything the integrators need at a hit: normals, the material after textures, emission.
// \param triangle_index The hit triangle (g_hit_triangle_index)
// \param triangle The hit triangle as ray_mesh_intersection() returned it (not oriented)
// \param position The hit point, world space
// \param ray_direction Direction of the ray that hit it
surface_t get_surface(uint triangle_index, triangle_t triangle, vec3 position, vec3 ray_direction) {
    surface_t surface;
    uint material_index = get_material_index(triangle_index);
    vec3 barycentrics = get_barycentrics(position, triangle);
    vec2 tex_coord = get_tex_coord(triangle_index, barycentrics);
    vec2 tex_coord_1 = get_tex_coord_1(triangle_index, barycentrics);
    bool front = dot(triangle.normal, ray_direction) <= 0.0;
    vec3 view = -ray_direction;
    surface.geometric_normal = front ? triangle.normal : -triangle.normal;
    material_textures_t textures = sample_material_textures(material_index, tex_coord, tex_coord_1);
    vec3 shading_normal = get_front_shading_normal(triangle_index, material_index, barycentrics, textures, triangle.normal);
    shading_normal = front ? shading_normal : -shading_normal;
    surface.shading_normal = (dot(shading_normal, view) > 0.0) ? shading_normal : surface.geometric_normal;
    vec4 base_color = get_surface_base_color(triangle_index, material_index, barycentrics, textures.slots[MATERIAL_TEXTURE_BASE_COLOR]);
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
    return surface;
}

// Radiance that triangle i emits from its front at a point of it (a light sample's end).
vec3 get_front_emission(uint triangle_index, triangle_t triangle, vec3 position) {
    uint material_index = get_material_index(triangle_index);
    vec3 barycentrics = get_barycentrics(position, triangle);
    vec2 tex_coord = get_tex_coord(triangle_index, barycentrics);
    vec2 tex_coord_1 = get_tex_coord_1(triangle_index, barycentrics);
    return get_material_emission(material_index, sample_material_texture(material_index, MATERIAL_TEXTURE_EMISSIVE, tex_coord, tex_coord_1));
}

// The BSDF times the cosine, as the rendering equation's integrand needs it:
// f(view, light) max(0, n_s . light), and 0 for light from below the geometric surface
// (layered materials: get_layered_bsdf(), which transmits light there).
vec3 get_bsdf(surface_t surface, vec3 view, vec3 light) {
    if (has_layers(surface))
        return get_layered_bsdf(surface.material, surface.eta, surface.geometric_normal, surface.shading_normal, surface.clearcoat_normal, view, light);
    if (dot(surface.geometric_normal, light) <= 0.0)
        return vec3(0.0);
    if (!SCENE_HAS_SPECULAR)
        return get_lambert_brdf(surface.material, surface.shading_normal, view, light) * max(0.0, dot(surface.shading_normal, light));
    return get_brdf(surface.material, surface.shading_normal, view, light) * max(0.0, dot(surface.shading_normal, light));
}

// The radiance the surface reflects towards `view` from `radiance` arriving along `light`:
// get_bsdf() times the radiance. `bsdf` is get_bsdf(surface, view, light), which the caller
// has (it skips shadow rays where it is 0). Lambert multiplies in the order of the
// workshop's formula, a / pi * L * (n . l), so that its images keep every bit.
vec3 get_reflected_radiance(surface_t surface, vec3 light, vec3 bsdf, vec3 radiance) {
    return bsdf * radiance;
}

// Density of sample_bsdf() w.r.t. solid angle.
float get_bsdf_density(surface_t surface, vec3 view, vec3 light) {
    if (has_layers(surface))
        return get_layered_density(surface.material, surface.eta, surface.shading_normal, surface.clearcoat_normal, view, light);
    if (!SCENE_HAS_SPECULAR)
        return get_lambert_brdf_density(surface.shading_normal, view, light);
    return get_brdf_density(surface.material, surface.shading_normal, view, light);
}

// BSDF importance sampling: a direction with density get_bsdf_density() and the weight
// get_bsdf() / density (0 where the density is 0). A pick of a delta lobe (roughness 0, a
// smooth coat: has_delta_lobe()) is marked BSDF_LOBE_DELTA, has density 0 (MIS has nothing
// to weigh it against: the emission it finds counts in full) and the weight f / p of that
// pick alone (get_brdf_mirror_weight(), sample_layered_bsdf()'s out_delta_weight), 0 where
// the geometric and the shading normal disagree about the side it leaves to (the side rule
// of glsl/surface.glsl; for a smooth coat under a normal map that also drops the rare
// reflection between the two horizons, which get_bsdf() would count).
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \param lobe_random Uniform in [0,1): chooses the lobe of layered materials (has_layers();
//        unused otherwise)
bsdf_sample_t sample_bsdf(surface_t surface, vec3 view, vec2 random_numbers, float lobe_random) {
    bsdf_sample_t bsdf_sample;
    bsdf_sample.lobes = BSDF_LOBE_REFLECT;
    bsdf_sample.eta = 1.0;
    bool delta = false;
    vec3 delta_weight = vec3(0.0);
    if (has_layers(surface)) {
        bsdf_sample.direction = sample_layered_bsdf(random_numbers, lobe_random, surface.material, surface.eta, surface.shading_normal, surface.clearcoat_normal, view, delta, delta_weight);
        if (dot(surface.geometric_normal, bsdf_sample.direction) < 0.0) {
            bsdf_sample.lobes = BSDF_LOBE_TRANSMIT;
            bsdf_sample.eta = is_refracting(surface.material) ? surface.eta : 1.0;
        }
    } else if (!SCENE_HAS_SPECULAR)
        bsdf_sample.direction = sample_lambert_brdf(random_numbers, surface.shading_normal);
    else {
        bsdf_sample.direction = sample_brdf(random_numbers, surface.material, surface.shading_normal, view);
        delta = random_numbers[0] < get_brdf_mirror_probability(surface.material, surface.shading_normal, view);
        delta_weight = delta ? get_brdf_mirror_weight(surface.material, surface.shading_normal, view) : vec3(0.0);
    }
    // One density and one BSDF evaluation after both branches: the kernel holds them once
    // (lavapipe translates every inlined copy at each start).
    bsdf_sample.density = get_bsdf_density(surface, view, bsdf_sample.direction);
    bsdf_sample.weight = (bsdf_sample.density > 0.0) ? get_bsdf(surface, view, bsdf_sample.direction) / bsdf_sample.density : vec3(0.0);
    if (delta) {
        bool sides_agree = (dot(surface.geometric_normal, bsdf_sample.direction) > 0.0) == (dot(surface.shading_normal, bsdf_sample.direction) > 0.0);
        bsdf_sample.lobes |= BSDF_LOBE_DELTA;
        bsdf_sample.density = 0.0;
        bsdf_sample.weight = sides_agree ? delta_weight : vec3(0.0);
    }
    return bsdf_sample;
}

// A cosine-weighted direction around the geometric normal (the cosine integrator, whatever
// the BSDF), weight get_bsdf() / density.
bsdf_sample_t sample_cosine_direction(surface_t surface, vec3 view, vec2 random_numbers) {
    bsdf_sample_t bsdf_sample;
    bsdf_sample.lobes = BSDF_LOBE_REFLECT;
    bsdf_sample.eta = 1.0;
    bsdf_sample.direction = sample_hemisphere_cosine(random_numbers, surface.geometric_normal);
    bsdf_sample.density = get_hemisphere_cosine_density(surface.geometric_normal, bsdf_sample.direction);
    bsdf_sample.weight = (bsdf_sample.density > 0.0) ? get_bsdf(surface, view, bsdf_sample.direction) / bsdf_sample.density : vec3(0.0);
    return bsdf_sample;
}

// What a camera ray sees the surface emit: its emission, and an unlit material's colour.
vec3 get_camera_emission(surface_t surface) {
    return surface.emission + surface.unlit_color;
}

// The fraction of its light a ray keeps over `distance` before it hit the surface: inside a
// refracting volume (the ray hit its back), KHR_materials_volume's absorption (Beer-Lambert,
// exp(-sigma distance)); 1 elsewhere. Absorption is applied where a ray leaves the volume, so
// volumes must be closed and not nested.
vec3 get_volume_transmittance(surface_t surface, float distance) {
    if (is_transmissive(surface) && surface.back_face && is_refracting(surface.material))
        return get_absorption(surface.material, distance);
    return vec3(1.0);
}

#endif
