// Materials, textures and shading normals at a ray's hit (kernels built with USE_MATERIALS):
// what turns a hit triangle of a glTF asset into a material_t for glsl/brdf.glsl.
// Host side: src/render/gpu_materials.rs; Rust twins of the functions: src/cpu/materials.rs.
//
// Shading-normal convention: the BRDF is evaluated with the shading normal (interpolated
// vertex normals, perturbed by the normal map), but light never crosses the geometric
// surface: a direction counts only where it leaves on the side the ray came from
// (geometric normal n_g . l > 0); get_surface_reflection() is 0 elsewhere. The shading
// normal is flipped with the geometric one when a ray hits the back, and where the view
// lies below it (a vertex normal bent away from the viewer) the geometric normal is used
// instead, so that get_brdf() always sees the view above its normal.
#ifndef VKPATH_MATERIALS_GLSL
#define VKPATH_MATERIALS_GLSL

#include "brdf.glsl"
#include "textures.glsl"
#include "scene.glsl"

layout(set = 0, binding = BINDING_SHADING) uniform usamplerBuffer g_shading_texels;
layout(set = 0, binding = BINDING_MATERIALS) uniform usamplerBuffer g_material_texels;

// Random state for stochastic alpha (ALPHA_MODE_BLEND), set once per sample by the kernel:
// a hit's coverage decision hashes it with the ray count and the triangle index.
uvec2 g_alpha_seed = uvec2(0u);

// A hit point as the integrators shade it.
struct surface_t {
    // Unit geometric normal, on the side the ray came from
    vec3 geometric_normal;
    // Unit shading normal, on the same side, with the view direction above it
    vec3 shading_normal;
    // The material after texture lookups
    material_t material;
    // Emitted radiance towards the ray's origin (0 from the back of one-sided emitters)
    vec3 emission;
};

// Barycentric coordinates (b_0, b_1, b_2) of a point in a triangle's plane.
vec3 get_barycentrics(vec3 position, triangle_t triangle) {
    vec3 edge_1 = triangle.positions[1] - triangle.positions[0];
    vec3 edge_2 = triangle.positions[2] - triangle.positions[0];
    vec3 offset = position - triangle.positions[0];
    vec3 normal = cross(edge_1, edge_2);
    float inverse_squared_area = 1.0 / dot(normal, normal);
    float b_1 = dot(cross(offset, edge_2), normal) * inverse_squared_area;
    float b_2 = dot(cross(edge_1, offset), normal) * inverse_squared_area;
    return vec3(1.0 - b_1 - b_2, b_1, b_2);
}

// Texel j of triangle i's shading data.
uvec4 get_shading_texel(uint triangle_index, int texel) {
    return texelFetch(g_shading_texels, int(uint(SHADING_TEXEL_COUNT) * triangle_index) + texel);
}

// Texel j of material i.
uvec4 get_material_texel(uint material_index, int texel) {
    return texelFetch(g_material_texels, int(uint(MATERIAL_TEXEL_COUNT) * material_index) + texel);
}

// Index of triangle i's material.
uint get_material_index(uint triangle_index) {
    return get_shading_texel(triangle_index, 0).w;
}

// TEXCOORD_0 at a point with the given barycentrics.
vec2 get_tex_coord(uint triangle_index, vec3 barycentrics) {
    uvec4 first = get_shading_texel(triangle_index, 3);
    uvec4 second = get_shading_texel(triangle_index, 4);
    return barycentrics[0] * uintBitsToFloat(first.xy) + barycentrics[1] * uintBitsToFloat(first.zw) + barycentrics[2] * uintBitsToFloat(second.xy);
}

// Whether material i has a texture in slot MATERIAL_TEXTURE_*.
bool has_material_texture(uint material_index, uint slot) {
    return (get_material_texel(material_index, 4).y & (1u << slot)) != 0u;
}

// Whether the scene has any texture (the host specializes it; false compiles lookups out).
layout(constant_id = SPEC_SCENE_HAS_TEXTURES) const bool SCENE_HAS_TEXTURES = true;

// A texture slot MATERIAL_TEXTURE_* of material i, sampled at tex_coord (1 without texture).
vec4 sample_material_texture(uint material_index, uint slot, vec2 tex_coord) {
    if (!SCENE_HAS_TEXTURES || !has_material_texture(material_index, slot))
        return vec4(1.0);
    int first = MATERIAL_FACTOR_TEXEL_COUNT + 3 * int(slot);
    texture_slot_t texture = unpack_texture_slot(get_material_texel(material_index, first), get_material_texel(material_index, first + 1), get_material_texel(material_index, first + 2));
    return sample_texture(texture, tex_coord);
}

// Base colour and alpha: factor times texture.
vec4 get_base_color(uint material_index, vec2 tex_coord) {
    return uintBitsToFloat(get_material_texel(material_index, 0)) * sample_material_texture(material_index, MATERIAL_TEXTURE_BASE_COLOR, tex_coord);
}

// Emitted radiance (front side): factor times texture.
vec3 get_material_emission(uint material_index, vec2 tex_coord) {
    return uintBitsToFloat(get_material_texel(material_index, 1).rgb) * sample_material_texture(material_index, MATERIAL_TEXTURE_EMISSIVE, tex_coord).rgb;
}

// Whether a candidate hit at ray parameter t on triangle i counts: always for opaque
// materials; where alpha >= alphaCutoff for ALPHA_MODE_MASK; with probability alpha for
// ALPHA_MODE_BLEND (stochastic coverage, decided by a hash of the sample's alpha seed, the
// ray and the triangle, so that a ray sees the same coverage in every test of it).
bool is_opaque_hit(uint triangle_index, vec3 ray_origin, vec3 ray_direction, float t) {
    uint material_index = get_material_index(triangle_index);
    uint alpha_mode = get_material_texel(material_index, 4).x;
    if (alpha_mode == ALPHA_MODE_OPAQUE)
        return true;
    vec3 barycentrics = get_barycentrics(ray_origin + t * ray_direction, get_triangle(triangle_index));
    float alpha = get_base_color(material_index, get_tex_coord(triangle_index, barycentrics)).a;
    if (alpha_mode == ALPHA_MODE_MASK)
        return alpha >= uintBitsToFloat(get_material_texel(material_index, 3).w);
    uvec2 hash_state = g_alpha_seed ^ uvec2(g_ray_count * 2654435769u, triangle_index);
    return get_random_numbers(hash_state)[0] < alpha;
}

// A normal perturbed by a tangent-space normal map (glTF 2.0, 3.9.3): the tangent is made
// orthogonal to the normal (Gram-Schmidt), B = cross(N, T) w, and the texel's
// (2 rgb - 1) * (scale, scale, 1) is taken in (T, B, N). The unperturbed normal where the
// tangent or the result vanishes.
// \param normal Unit normal; \param tangent xyz: tangent (any length), w: bitangent sign
// \param texel The normal texture's rgb in [0, 1]; \param scale normalTexture.scale
vec3 apply_normal_map(vec3 normal, vec4 tangent, vec3 texel, float scale) {
    vec3 orthogonal = tangent.xyz - dot(tangent.xyz, normal) * normal;
    if (!(dot(orthogonal, orthogonal) > 1.0e-12))
        return normal;
    orthogonal = normalize(orthogonal);
    vec3 bitangent = cross(normal, orthogonal) * ((tangent.w < 0.0) ? -1.0 : 1.0);
    vec3 direction = 2.0 * texel - 1.0;
    vec3 mapped = direction.x * scale * orthogonal + direction.y * scale * bitangent + direction.z * normal;
    return (dot(mapped, mapped) > 1.0e-12) ? normalize(mapped) : normal;
}

// The interpolated shading normal of triangle i (front side), perturbed by the material's
// normal map in the interpolated MikkTSpace frame (glTF: n = normalize(T x + B y + N z) with
// (x, y, z) = (2 rgb - 1) * (scale, scale, 1) and B = cross(N, T) w). The face normal where
// the interpolation vanishes.
vec3 get_front_shading_normal(uint triangle_index, uint material_index, vec3 barycentrics, vec2 tex_coord, vec3 face_normal) {
    vec3 normal = barycentrics[0] * uintBitsToFloat(get_shading_texel(triangle_index, 0).xyz) + barycentrics[1] * uintBitsToFloat(get_shading_texel(triangle_index, 1).xyz) + barycentrics[2] * uintBitsToFloat(get_shading_texel(triangle_index, 2).xyz);
    if (!(dot(normal, normal) > 1.0e-12))
        return face_normal;
    normal = normalize(normal);
    if (SCENE_HAS_TEXTURES && has_material_texture(material_index, MATERIAL_TEXTURE_NORMAL)) {
        vec4 tangent_0 = uintBitsToFloat(get_shading_texel(triangle_index, 5));
        vec3 tangent = barycentrics[0] * tangent_0.xyz + barycentrics[1] * uintBitsToFloat(get_shading_texel(triangle_index, 6).xyz) + barycentrics[2] * uintBitsToFloat(get_shading_texel(triangle_index, 7).xyz);
        float scale = uintBitsToFloat(get_material_texel(material_index, 2).w);
        vec3 texel = sample_material_texture(material_index, MATERIAL_TEXTURE_NORMAL, tex_coord).rgb;
        normal = apply_normal_map(normal, vec4(tangent, tangent_0.w), texel, scale);
    }
    return normal;
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
    bool front = dot(triangle.normal, ray_direction) <= 0.0;
    vec3 view = -ray_direction;
    surface.geometric_normal = front ? triangle.normal : -triangle.normal;
    vec3 shading_normal = get_front_shading_normal(triangle_index, material_index, barycentrics, tex_coord, triangle.normal);
    shading_normal = front ? shading_normal : -shading_normal;
    surface.shading_normal = (dot(shading_normal, view) > 0.0) ? shading_normal : surface.geometric_normal;
    vec4 base_color = get_base_color(material_index, tex_coord);
    vec4 factors = uintBitsToFloat(get_material_texel(material_index, 2));
    // glTF: roughness in G, metallic in B of the metallic-roughness texture
    vec4 metallic_roughness = sample_material_texture(material_index, MATERIAL_TEXTURE_METALLIC_ROUGHNESS, tex_coord);
    surface.material.base_color = base_color.rgb;
    surface.material.metallic = uintBitsToFloat(get_material_texel(material_index, 1).w) * metallic_roughness.b;
    surface.material.roughness = factors.x * metallic_roughness.g;
    surface.material.specular = factors.y;
    surface.material.ior = factors.z;
    surface.material.specular_color = uintBitsToFloat(get_material_texel(material_index, 3).rgb);
    bool double_sided = is_double_sided(triangle_index);
    surface.emission = (front || double_sided) ? get_material_emission(material_index, tex_coord) : vec3(0.0);
    return surface;
}

// The reflected part of the rendering equation's integrand without the incoming radiance:
// f(view, light) max(0, n_s . light), and 0 for light from below the geometric surface.
vec3 get_surface_reflection(surface_t surface, vec3 view, vec3 light) {
    if (dot(surface.geometric_normal, light) <= 0.0)
        return vec3(0.0);
    return get_brdf(surface.material, surface.shading_normal, view, light) * max(0.0, dot(surface.shading_normal, light));
}

#endif
