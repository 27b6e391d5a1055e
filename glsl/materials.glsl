// Materials, textures and shading normals of glTF assets (kernels built with USE_MATERIALS):
// the packed words a hit triangle's material and shading data are read from, and what they
// unpack to (material_t of glsl/brdf.glsl, the shading normal, emission, alpha coverage).
// The surface seam's glTF model (glsl/gltf_surface.glsl) builds its surface_t from these.
// Host side: src/render/gpu_materials.rs; Rust twins of the functions: src/cpu/materials.rs.
#ifndef VKPATH_MATERIALS_GLSL
#define VKPATH_MATERIALS_GLSL

#include "brdf.glsl"
#include "textures.glsl"
#include "scene.glsl"

layout(set = 0, binding = BINDING_SHADING) uniform utextureBuffer g_shading_texels;
layout(set = 0, binding = BINDING_MATERIALS) uniform utextureBuffer g_material_texels;


// The vertex attributes that some triangle of the scene has beyond the usual ones
// (VERTEX_ATTRIBUTE_* bits, glsl/shared.h); 0 compiles their reading out and keeps the
// shading data's layout of scenes without them.
layout(constant_id = SPEC_SCENE_VERTEX_ATTRIBUTES) const uint SCENE_VERTEX_ATTRIBUTES = 0u;
// Texels of shading data per triangle: SHADING_TEXEL_COUNT, and EXTRA_SHADING_TEXEL_COUNT
// more where the scene has extra vertex attributes.
const uint SHADING_TEXEL_STRIDE = uint(SHADING_TEXEL_COUNT) + uint(EXTRA_SHADING_TEXEL_COUNT) * uint(SCENE_VERTEX_ATTRIBUTES != 0u);

// Texel j of triangle i's shading data.
uvec4 get_shading_texel(uint triangle_index, int texel) {
    return texelFetch(g_shading_texels, int(SHADING_TEXEL_STRIDE * triangle_index) + texel);
}

// Texel j of material i.
uvec4 get_material_texel(uint material_index, int texel) {
    return texelFetch(g_material_texels, int(uint(MATERIAL_TEXEL_COUNT) * material_index) + texel);
}

// The material's words: MATERIAL_TEXEL_COUNT texels laid out by the MATERIAL_TEXEL_* of
// glsl/shared.h (`GpuMaterial` on the host).

// ALPHA_MODE_OPAQUE, _MASK or _BLEND of material i.
uint get_material_alpha_mode(uint material_index) {
    return get_material_texel(material_index, MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK).x;
}

// alphaCutoff of material i (ALPHA_MODE_MASK).
float get_material_alpha_cutoff(uint material_index) {
    return uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF).w);
}

// normalTexture.scale of material i.
float get_material_normal_scale(uint material_index) {
    return uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE).w);
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

// glTF's TEXCOORD_1 at a point with the given barycentrics: 0 where the scene has no second
// texture coordinates (the interpolation as get_tex_coord()'s).
vec2 get_tex_coord_1(uint triangle_index, vec3 barycentrics) {
    if ((SCENE_VERTEX_ATTRIBUTES & uint(VERTEX_ATTRIBUTE_TEX_COORD_1)) == 0u)
        return vec2(0.0);
    uvec4 second = get_shading_texel(triangle_index, SHADING_TEXEL_COUNT + 1);
    uvec4 third = get_shading_texel(triangle_index, SHADING_TEXEL_COUNT + 2);
    return barycentrics[0] * uintBitsToFloat(second.zw) + barycentrics[1] * uintBitsToFloat(third.xy) + barycentrics[2] * uintBitsToFloat(third.zw);
}

// The texture coordinates a texture slot reads: tex_coord_1 (TEXCOORD_1) where its texCoord
// is 1, else tex_coord (TEXCOORD_0). Scenes that read no TEXCOORD_1 compile the choice out.
vec2 select_tex_coord(texture_slot_t texture, vec2 tex_coord, vec2 tex_coord_1) {
    if ((SCENE_VERTEX_ATTRIBUTES & uint(VERTEX_ATTRIBUTE_TEX_COORD_1)) != 0u && (texture.flags & uint(TEXTURE_FLAG_TEX_COORD_1)) != 0u)
        return tex_coord_1;
    return tex_coord;
}

// glTF's COLOR_0 (linear RGBA) at a point with the given barycentrics: 1 where the scene has
// no vertex colours (the interpolation as get_tex_coord()'s).
vec4 get_vertex_color(uint triangle_index, vec3 barycentrics) {
    if ((SCENE_VERTEX_ATTRIBUTES & uint(VERTEX_ATTRIBUTE_COLOR)) == 0u)
        return vec4(1.0);
    uvec4 first = get_shading_texel(triangle_index, SHADING_TEXEL_COUNT);
    uvec4 second = get_shading_texel(triangle_index, SHADING_TEXEL_COUNT + 1);
    vec4 color_0 = vec4(unpackUnorm2x16(first.x), unpackUnorm2x16(first.y));
    vec4 color_1 = vec4(unpackUnorm2x16(first.z), unpackUnorm2x16(first.w));
    vec4 color_2 = vec4(unpackUnorm2x16(second.x), unpackUnorm2x16(second.y));
    return barycentrics[0] * color_0 + barycentrics[1] * color_1 + barycentrics[2] * color_2;
}

// The texture slots (bit 1 << MATERIAL_TEXTURE_*) in which some material of the scene has a
// texture: the host specializes it, and a slot outside it compiles that slot's lookups out.
layout(constant_id = SPEC_SCENE_TEXTURE_SLOTS) const uint SCENE_TEXTURE_SLOTS = 0xFFFFFFFFu;

// Whether material i has a texture in slot MATERIAL_TEXTURE_* (never in a slot outside
// SCENE_TEXTURE_SLOTS).
bool has_material_texture(uint material_index, uint slot) {
    return (SCENE_TEXTURE_SLOTS & (1u << slot)) != 0u && (get_material_texel(material_index, MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK).y & (1u << slot)) != 0u;
}
// Whether any material has transmission or a clear coat (false compiles their lobes out).
// The build for scenes without them (WITHOUT_LAYERS) holds a constant false instead, so
// that its SPIR-V carries none of glsl/layered_bsdf.glsl: lavapipe translates and optimises
// a kernel's whole SPIR-V at every start, dead code too (docs/performance.md, "Start-up").
#ifdef WITHOUT_LAYERS
const bool SCENE_HAS_LAYERS = false;
#else
layout(constant_id = SPEC_SCENE_HAS_LAYERS) const bool SCENE_HAS_LAYERS = true;
#endif

// Whether any material has a specular (GGX) lobe: metallic or KHR_materials_specular's
// specularFactor above 0, or layers. False where every material is Lambertian (the workshop's
// box under an environment, most converted scenes): the surface seam then evaluates and
// samples albedo / pi directly (glsl/surface.glsl), the same bits without the GGX maths that
// lavapipe would otherwise run at every vertex.
layout(constant_id = SPEC_SCENE_HAS_SPECULAR) const bool SCENE_HAS_SPECULAR = true;

// KHR_materials_volume_scatter of material i: the volume's scattering coefficient sigma_s per
// unit length (rgb, 0 without the extension) and its Henyey-Greenstein g (a). Read where a
// path refracts into the volume (glsl/path_loop.glsl, SCENE_HAS_VOLUME_SCATTER), not by
// get_material().
vec4 get_material_volume_scattering(uint material_index) {
    uvec4 flags = get_material_texel(material_index, MATERIAL_TEXEL_FLAGS);
    uvec4 alpha = get_material_texel(material_index, MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK);
    return vec4(uintBitsToFloat(flags.yzw), uintBitsToFloat(alpha.z));
}

// clearcoatNormalTexture.scale of material i.
float get_material_clearcoat_normal_scale(uint material_index) {
    return uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE).w);
}

// Whether material i is KHR_materials_unlit.
bool is_unlit_material(uint material_index) {
    return (get_material_texel(material_index, MATERIAL_TEXEL_FLAGS).x & uint(MATERIAL_FLAG_UNLIT)) != 0u;
}

// A texture slot MATERIAL_TEXTURE_* of material i, sampled at tex_coord or tex_coord_1 (the
// point's TEXCOORD_0 and TEXCOORD_1, as the slot's texCoord says; 1 without texture).
vec4 sample_material_texture(uint material_index, uint slot, vec2 tex_coord, vec2 tex_coord_1) {
    if (!has_material_texture(material_index, slot))
        return vec4(1.0);
    int first = MATERIAL_FACTOR_TEXEL_COUNT + 3 * int(slot);
    texture_slot_t texture = unpack_texture_slot(get_material_texel(material_index, first), get_material_texel(material_index, first + 1), get_material_texel(material_index, first + 2));
    return sample_texture(texture, select_tex_coord(texture, tex_coord, tex_coord_1));
}

// The texture slots of material i at a point: each slot's sample_material_texture() (1 where
// the material has no texture there; the slots past MATERIAL_TEXTURE_EMISSIVE stay 1 in
// scenes without layered materials, which never read them).
struct material_textures_t {
    vec4 slots[MATERIAL_TEXTURE_SLOT_COUNT];
};

// Every texture slot of material i at tex_coord (or tex_coord_1, TEXCOORD_1, for the slots
// whose texCoord is 1): a loop over the slots that have a texture
// (the layered materials' only in scenes with them), so that the kernel holds a single copy
// of sample_texture() for all the lookups of a surface instead of one per slot. lavapipe
// translates and optimises a kernel's whole code at every start, and those copies were 43 %
// of the material kernel's instructions (docs/performance.md, "Start-up").
#extension GL_EXT_control_flow_attributes : enable
material_textures_t sample_material_textures(uint material_index, vec2 tex_coord, vec2 tex_coord_1) {
    material_textures_t textures;
    textures.slots = vec4[MATERIAL_TEXTURE_SLOT_COUNT](vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0));
    if (SCENE_TEXTURE_SLOTS == 0u)
        return textures;
    uint slot_count = SCENE_HAS_LAYERS ? MATERIAL_TEXTURE_SLOT_COUNT : MATERIAL_TEXTURE_EMISSIVE + 1;
    uint scene_slots = SCENE_TEXTURE_SLOTS & ((1u << slot_count) - 1u);
    uint slots = get_material_texel(material_index, MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK).y & scene_slots;
    // Where the scene's materials use one slot only (commonly the base colour), its index is
    // a constant once specialized and the loop runs once, which the driver folds away.
    bool one_slot = bitCount(scene_slots) == 1;
    do {
        int slot = one_slot ? findLSB(scene_slots) : findLSB(slots);
        if (slots != 0u) {
            int first = MATERIAL_FACTOR_TEXEL_COUNT + 3 * slot;
            texture_slot_t texture = unpack_texture_slot(get_material_texel(material_index, first), get_material_texel(material_index, first + 1), get_material_texel(material_index, first + 2));
            vec4 value = sample_texture(texture, select_tex_coord(texture, tex_coord, tex_coord_1));
            // Stored at constant indices: an array written at a variable index is kept in
            // memory for every lane on lavapipe, which made the textured box's samples twice
            // as slow (docs/performance.md, "Stop 25"); so each slot the scene uses selects.
            [[unroll]] for (int k = 0; k != MATERIAL_TEXTURE_SLOT_COUNT; ++k)
                if ((scene_slots & (1u << k)) != 0u && k == slot)
                    textures.slots[k] = value;
        }
        slots &= slots - 1u;
    } while (!one_slot && slots != 0u);
    return textures;
}

// Base colour and alpha: factor times `texture`, the base colour slot's value
// (sample_material_texture() of MATERIAL_TEXTURE_BASE_COLOR).
vec4 get_base_color(uint material_index, vec4 texture) {
    return uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_BASE_COLOR)) * texture;
}

// Base colour and alpha at a point of triangle i: get_base_color() times the vertex colour
// (glTF 2.0, 3.9.2: COLOR_0 multiplies the base colour and its alpha); exactly
// get_base_color() where the scene has no vertex colours.
vec4 get_surface_base_color(uint triangle_index, uint material_index, vec3 barycentrics, vec4 texture) {
    vec4 base_color = get_base_color(material_index, texture);
    if ((SCENE_VERTEX_ATTRIBUTES & uint(VERTEX_ATTRIBUTE_COLOR)) != 0u)
        base_color *= get_vertex_color(triangle_index, barycentrics);
    return base_color;
}

// Emitted radiance (front side): factor times `texture`, the emissive slot's value.
vec3 get_material_emission(uint material_index, vec4 texture) {
    return uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_EMISSIVE_METALLIC).rgb) * texture.rgb;
}

// Whether a candidate hit at ray parameter t on triangle i counts: always for opaque
// materials; where alpha >= alphaCutoff for ALPHA_MODE_MASK; with probability alpha for
// ALPHA_MODE_BLEND (stochastic coverage, decided by a hash of the sample's alpha seed, the
// ray and the triangle, so that a ray sees the same coverage in every test of it).
bool is_opaque_hit(uint triangle_index, vec3 ray_origin, vec3 ray_direction, float t) {
    uint material_index = get_material_index(triangle_index);
    uint alpha_mode = get_material_alpha_mode(material_index);
    if (alpha_mode == ALPHA_MODE_OPAQUE)
        return true;
    vec3 barycentrics = get_barycentrics(ray_origin + t * ray_direction, get_triangle(triangle_index));
    vec2 tex_coord = get_tex_coord(triangle_index, barycentrics);
    vec2 tex_coord_1 = get_tex_coord_1(triangle_index, barycentrics);
    float alpha = get_surface_base_color(triangle_index, material_index, barycentrics, sample_material_texture(material_index, MATERIAL_TEXTURE_BASE_COLOR, tex_coord, tex_coord_1)).a;
    if (alpha_mode == ALPHA_MODE_MASK)
        return alpha >= get_material_alpha_cutoff(material_index);
    uvec2 hash_state = g_path.alpha_seed ^ uvec2(g_path.ray_count * 2654435769u, triangle_index);
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

// The interpolated vertex normal of triangle i (front side), perturbed by the normal map in
// texture slot `slot` (MATERIAL_TEXTURE_NORMAL or _CLEARCOAT_NORMAL), whose value at the
// point is `texture`, with `scale`, in the
// interpolated MikkTSpace frame (glTF: n = normalize(T x + B y + N z) with (x, y, z) =
// (2 rgb - 1) * (scale, scale, 1) and B = cross(N, T) w). The face normal where the
// interpolation vanishes.
vec3 get_front_mapped_normal(uint triangle_index, uint material_index, vec3 barycentrics, vec4 texture, vec3 face_normal, uint slot, float scale) {
    vec3 normal = barycentrics[0] * uintBitsToFloat(get_shading_texel(triangle_index, 0).xyz) + barycentrics[1] * uintBitsToFloat(get_shading_texel(triangle_index, 1).xyz) + barycentrics[2] * uintBitsToFloat(get_shading_texel(triangle_index, 2).xyz);
    if (!(dot(normal, normal) > 1.0e-12))
        return face_normal;
    normal = normalize(normal);
    if (has_material_texture(material_index, slot)) {
        vec4 tangent_0 = uintBitsToFloat(get_shading_texel(triangle_index, 5));
        vec3 tangent = barycentrics[0] * tangent_0.xyz + barycentrics[1] * uintBitsToFloat(get_shading_texel(triangle_index, 6).xyz) + barycentrics[2] * uintBitsToFloat(get_shading_texel(triangle_index, 7).xyz);
        normal = apply_normal_map(normal, vec4(tangent, tangent_0.w), texture.rgb, scale);
    }
    return normal;
}

// The shading normal of triangle i (front side): the vertex normals and the material's
// normalTexture (get_front_mapped_normal()).
vec3 get_front_shading_normal(uint triangle_index, uint material_index, vec3 barycentrics, material_textures_t textures, vec3 face_normal) {
    return get_front_mapped_normal(triangle_index, material_index, barycentrics, textures.slots[MATERIAL_TEXTURE_NORMAL], face_normal, MATERIAL_TEXTURE_NORMAL, get_material_normal_scale(material_index));
}

// The clear coat's normal of triangle i (front side): the vertex normals and the material's
// clearcoatNormalTexture, not its normalTexture (KHR_materials_clearcoat).
vec3 get_front_clearcoat_normal(uint triangle_index, uint material_index, vec3 barycentrics, material_textures_t textures, vec3 face_normal) {
    return get_front_mapped_normal(triangle_index, material_index, barycentrics, textures.slots[MATERIAL_TEXTURE_CLEARCOAT_NORMAL], face_normal, MATERIAL_TEXTURE_CLEARCOAT_NORMAL, get_material_clearcoat_normal_scale(material_index));
}

// Material i at a point whose texture slots have the values `textures`: the factors times
// their textures (glTF: roughness in G, metallic in B of the metallic-roughness texture).
// \param base_color get_base_color() at the point (alpha tests read it too)
material_t get_material(uint material_index, material_textures_t textures, vec4 base_color) {
    vec4 factors = uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE));
    vec4 metallic_roughness = textures.slots[MATERIAL_TEXTURE_METALLIC_ROUGHNESS];
    float metallic = uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_EMISSIVE_METALLIC).w) * metallic_roughness.b;
    vec3 specular_color = uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF).rgb);
    material_t material = get_base_material(base_color.rgb, metallic, factors.x * metallic_roughness.g, factors.y, specular_color, factors.z);
    if (SCENE_HAS_LAYERS) {
        // KHR_materials_specular's textures (A: specular, RGB sRGB: specular colour)
        material.specular *= textures.slots[MATERIAL_TEXTURE_SPECULAR].a;
        material.specular_color *= textures.slots[MATERIAL_TEXTURE_SPECULAR_COLOR].rgb;
        vec4 layers = uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT));
        material.transmission = layers.x * textures.slots[MATERIAL_TEXTURE_TRANSMISSION].r;
        material.thickness = layers.y * textures.slots[MATERIAL_TEXTURE_THICKNESS].g;
        material.attenuation = uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE).rgb);
        material.clearcoat = layers.z * textures.slots[MATERIAL_TEXTURE_CLEARCOAT].r;
        material.clearcoat_roughness = layers.w * textures.slots[MATERIAL_TEXTURE_CLEARCOAT_ROUGHNESS].g;
        vec4 sheen = uintBitsToFloat(get_material_texel(material_index, MATERIAL_TEXEL_SHEEN));
        material.sheen_color = sheen.rgb * textures.slots[MATERIAL_TEXTURE_SHEEN_COLOR].rgb;
        material.sheen_roughness = sheen.a * textures.slots[MATERIAL_TEXTURE_SHEEN_ROUGHNESS].a;
    }
    return material;
}

#endif
