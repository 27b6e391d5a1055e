// The layers of glTF materials beyond metallic-roughness, behind the surface seam
// (glsl/surface.glsl routes a material here when it has one, SCENE_HAS_LAYERS):
// - KHR_materials_transmission with KHR_materials_ior and KHR_materials_volume: a fraction
//   `transmission` of the dielectric lets light through. Refracting (thickness > 0): a rough
//   dielectric BSDF (Walter et al. 2007, "Microfacet Models for Refraction through Rough
//   Surfaces") with the exact Fresnel reflectance, GGX with the surface's roughness, light
//   transmitted tinted by the base colour at each crossing, absorbed inside by Beer-Lambert
//   (get_volume_transmittance()). Thin-walled (thickness 0, or ior 1): the extension's
//   fresnel_mix with Schlick's Fresnel; light passes straight through, the GGX lobe mirrored
//   to the other side, weighted by (1 - F) and the base colour.
// - KHR_materials_clearcoat: fresnel_coat(), a GGX coat (ior 1.5, F0 = 0.04) over the rest,
//   weighted by clearcoat * F(N_c . V) with the coat's own normal, as the extension's text
//   specifies: f = (1 - clearcoat F_c) f_base + clearcoat F_c D_c V_c.
// - KHR_materials_sheen, below the coat: the Charlie sheen lobe (the extension's reference,
//   Estevez & Kulla 2017: their distribution and visibility) over the base, which it scales
//   by 1 - max(sheen colour) E(n.v) with E the lobe's tabulated directional albedo
//   (get_sheen_albedo()): f = sheen_color D V + (1 - max(sheen_color) E) f_base.
// The BSDFs are without the cosine; directions in the shading frame (local_, z the normal,
// the view above it) unless said otherwise. `eta` is the relative index of refraction
// across the surface: the other side's over the view's (entering glass: ior; leaving: 1/ior).
// Each lobe's functions (its quartet: value, density, sample, weight) live in its own file,
// included below where they stood: glsl/lobe_dielectric.glsl, glsl/lobe_thin_wall.glsl,
// glsl/lobe_sheen.glsl, glsl/lobe_clearcoat.glsl. Their Fresnel terms come from
// glsl/fresnel.glsl and their GGX terms from glsl/brdf.glsl; this file keeps the layered mix
// (is_layered(), get_transmissive_*(), get_layered_*(), sample_layered_bsdf()).
// Rust twins: src/cpu/layered_bsdf.rs (same names, same maths).
#ifndef VKPATH_LAYERED_BSDF_GLSL
#define VKPATH_LAYERED_BSDF_GLSL
// textureSize() of a texel buffer declared as a texture (utextureBuffer: the texel buffers
// carry no sampler, which SPIR-V validation asks of buffer images).
#extension GL_EXT_samplerless_texture_functions : require

#include "brdf.glsl"
// sample_hemisphere_cosine() (glsl/importance_sampling.glsl) and g_material_texels
// (glsl/materials.glsl) come from the includer (glsl/gltf_surface.glsl), which includes
// them first.

#include "lobe_dielectric.glsl"

#include "lobe_thin_wall.glsl"

#include "lobe_sheen.glsl"

// Whether the material has layers beyond metallic-roughness (at this point, after its
// textures): transmission, a clear coat or sheen.
bool is_layered(material_t material) {
    return material.transmission > 0.0 || material.clearcoat > 0.0 || has_sheen(material);
}

// Whether light refracts through the material (a volume of another index) rather than
// passing a thin wall straight.
bool is_refracting(material_t material) {
    return material.thickness > 0.0 && material.ior != 1.0;
}

// The probability of sampling the transmissive dielectric's lobes (rather than
// sample_brdf()'s): their weight (1 - metallic) transmission.
float get_transmission_probability(material_t material) {
    return (1.0 - material.metallic) * material.transmission;
}

// The metallic-roughness BSDF with transmission, without the clear coat and the cosine:
// mix(dielectric, metal, metallic) as get_brdf() for light above, where the dielectric is
// F_s D V + (1 - transmission) (1 - F_s) base_color / pi for a thin wall (its diffuse part
// replaced by transmission, KHR_materials_transmission) and
// (1 - transmission) (get_brdf()'s dielectric) + transmission F D V (the rough dielectric's
// exact-Fresnel reflection) for a refracting one; for light below, (1 - metallic)
// transmission times the thin wall's or the rough dielectric's transmission tinted by the
// base colour.
// \param eta The relative index of refraction (surface_t.eta)
// \param local_view, local_light The directions in the shading frame (local_view.z > 0)
vec3 get_transmissive_bsdf(material_t material, float eta, vec3 local_view, vec3 local_light) {
    float alpha = get_ggx_alpha(material.roughness);
    if (local_light.z > 0.0) {
        vec3 local_half = normalize(local_view + local_light);
        float view_dot_half = dot(local_view, local_half);
        float specular = get_ggx_distribution(alpha, local_half) * get_smith_visibility(alpha, local_view.z, local_light.z);
        vec3 dielectric_fresnel = get_dielectric_schlick_fresnel(material, view_dot_half);
        vec3 diffuse = (1.0 - dielectric_fresnel) * material.base_color / M_PI;
        vec3 dielectric;
        if (is_refracting(material))
            dielectric = (1.0 - material.transmission) * (diffuse + dielectric_fresnel * specular) + material.transmission * get_dielectric_fresnel(view_dot_half, eta) * specular;
        else
            dielectric = dielectric_fresnel * specular + (1.0 - material.transmission) * diffuse;
        vec3 metal = get_metal_schlick_fresnel(material, view_dot_half) * specular;
        return mix(dielectric, metal, material.metallic);
    }
    vec3 transmitted = is_refracting(material)
        ? get_rough_dielectric_bsdf(alpha, eta, local_view, local_light).y * material.base_color
        : get_thin_wall_btdf(material, alpha, local_view, local_light);
    return (1.0 - material.metallic) * material.transmission * transmitted;
}

// Density of sample_transmissive_bsdf(): the transmissive dielectric's lobes with
// probability get_transmission_probability(), sample_brdf()'s otherwise.
float get_transmissive_density(material_t material, float eta, vec3 shading_normal, vec3 view, vec3 light) {
    float transmission_probability = get_transmission_probability(material);
    float density = (1.0 - transmission_probability) * get_brdf_density(material, shading_normal, view, light);
    if (transmission_probability > 0.0) {
        mat3 basis = get_shading_basis(shading_normal);
        float alpha = get_ggx_alpha(material.roughness);
        float lobe = is_refracting(material)
            ? get_rough_dielectric_density(alpha, eta, view * basis, light * basis)
            : get_thin_wall_density(material, alpha, view * basis, light * basis);
        density += transmission_probability * lobe;
    }
    return density;
}

// The weight f / p of a delta pick of sample_transmissive_bsdf() (roughness 0, GGX alpha 0),
// f the peak's coefficient in get_transmissive_bsdf() (f |n.l| integrated over the peak), p
// the probability of that pick alone (no continuous lobe's density enters):
// - transmission (`transmitted`): (1 - metallic) T times the thin wall's
//   get_smooth_thin_wall_transmittance() or the refraction's
//   get_smooth_dielectric_transmittance() base_color, over P_t (1 - P_r), with
//   P_t = get_transmission_probability() = (1 - metallic) T, which cancels, and P_r the thin
//   wall's reflection probability or the exact Fresnel F at n.v;
// - reflection: mix(F_s, F_m, metallic) for a thin wall, mix((1 - T) F_s + T F, F_m,
//   metallic) for a refracting one (F_s, F_m Schlick's, as get_transmissive_bsdf()), over
//   P_t P_r + (1 - P_t) p_s: two routes reach the mirror direction (the transmissive lobe's
//   reflection and sample_brdf()'s specular lobe, p_s = get_specular_probability()), so its
//   probability is their sum (the balance heuristic over the routes).
// \param local_view The view in the shading frame (z > 0)
vec3 get_transmissive_delta_weight(material_t material, float eta, vec3 local_view, bool transmitted) {
    float normal_dot_view = local_view.z;
    bool refracting = is_refracting(material);
    float reflection_probability = refracting ? get_dielectric_fresnel(normal_dot_view, eta) : get_thin_wall_reflection_probability(material, normal_dot_view);
    if (transmitted) {
        vec3 transmittance = refracting ? get_smooth_dielectric_transmittance(eta, normal_dot_view) * material.base_color : get_smooth_thin_wall_transmittance(material, normal_dot_view);
        return transmittance / (1.0 - reflection_probability);
    }
    vec3 schlick_fresnel = get_dielectric_schlick_fresnel(material, normal_dot_view);
    vec3 dielectric = refracting ? (1.0 - material.transmission) * schlick_fresnel + material.transmission * get_dielectric_fresnel(normal_dot_view, eta) : schlick_fresnel;
    vec3 reflectance = mix(dielectric, get_metal_schlick_fresnel(material, normal_dot_view), material.metallic);
    float transmission_probability = get_transmission_probability(material);
    return reflectance / (transmission_probability * reflection_probability + (1.0 - transmission_probability) * get_specular_probability(material, normal_dot_view));
}

// Samples get_transmissive_bsdf(): lobe_random < get_transmission_probability() samples
// the rough dielectric or the thin wall (lobe_random, stretched back to [0, 1), chooses
// between reflection and transmission), else sample_brdf(). Where the roughness is 0 every
// pick but sample_brdf()'s diffuse one is a delta lobe's peak (out_delta), with the weight
// get_transmissive_delta_weight() (out_delta_weight; 0 for other picks).
// \return A unit direction, world space (either side of the surface)
vec3 sample_transmissive_bsdf(vec2 random_numbers, float lobe_random, material_t material, float eta, vec3 shading_normal, vec3 view, out bool out_delta, out vec3 out_delta_weight) {
    float transmission_probability = get_transmission_probability(material);
    mat3 basis = get_shading_basis(shading_normal);
    vec3 local_view = view * basis;
    float alpha = get_ggx_alpha(material.roughness);
    if (lobe_random < transmission_probability) {
        float reflection_random = lobe_random / transmission_probability;
        vec3 local_light = is_refracting(material)
            ? sample_rough_dielectric(random_numbers, reflection_random, alpha, eta, local_view)
            : sample_thin_wall(random_numbers, reflection_random, material, alpha, local_view);
        out_delta = alpha == 0.0;
        out_delta_weight = out_delta ? get_transmissive_delta_weight(material, eta, local_view, local_light.z < 0.0) : vec3(0.0);
        return normalize(basis * local_light);
    }
    out_delta = random_numbers[0] < get_brdf_mirror_probability(material, shading_normal, view);
    out_delta_weight = out_delta ? get_transmissive_delta_weight(material, eta, local_view, false) : vec3(0.0);
    return sample_brdf(random_numbers, material, shading_normal, view);
}

#include "lobe_clearcoat.glsl"

// The cosine of the base's lobes: |n_s . l| where the shading and the geometric normal put
// the light on the same side (light crosses the surface only where it crosses the geometric
// one too), 0 where they disagree.
float get_layered_base_cosine(vec3 geometric_normal, vec3 shading_normal, vec3 light) {
    float geometric_cosine = dot(geometric_normal, light);
    float shading_cosine = dot(shading_normal, light);
    return ((geometric_cosine > 0.0 && shading_cosine > 0.0) || (geometric_cosine < 0.0 && shading_cosine < 0.0)) ? abs(shading_cosine) : 0.0;
}

// The layered BSDF times the cosine: fresnel_coat over the sheen over
// get_transmissive_bsdf(), (1 - w_c) (f_sheen max(0, n_s . l) + (1 - w_s) f_base cos_base)
// + w_c f_coat max(0, n_c . l) with w_c = get_clearcoat_weight(), w_s = get_sheen_weight()
// and cos_base = get_layered_base_cosine(); the coat and the sheen, reflections, are 0 below
// the geometric surface.
// \param geometric_normal, shading_normal, clearcoat_normal Unit normals on the view's side
vec3 get_layered_bsdf(material_t material, float eta, vec3 geometric_normal, vec3 shading_normal, vec3 clearcoat_normal, vec3 view, vec3 light) {
    vec3 bsdf = vec3(0.0);
    float base_cosine = get_layered_base_cosine(geometric_normal, shading_normal, light);
    if (base_cosine > 0.0) {
        mat3 basis = get_shading_basis(shading_normal);
        bsdf = get_transmissive_bsdf(material, eta, view * basis, light * basis) * base_cosine;
    }
    if (has_sheen(material)) {
        bsdf *= 1.0 - get_sheen_weight(material, dot(shading_normal, view));
        if (dot(geometric_normal, light) > 0.0)
            bsdf += get_sheen_brdf(material, shading_normal, view, light) * max(0.0, dot(shading_normal, light));
    }
    if (material.clearcoat > 0.0) {
        float coat_weight = get_clearcoat_weight(material, dot(clearcoat_normal, view));
        bsdf *= 1.0 - coat_weight;
        if (dot(geometric_normal, light) > 0.0)
            bsdf += coat_weight * get_clearcoat_brdf(material, clearcoat_normal, view, light) * max(0.0, dot(clearcoat_normal, light));
    }
    return bsdf;
}

// Density of sample_layered_bsdf(): the coat with probability w_c, then the sheen (cosine
// directions around the shading normal) with probability get_sheen_weight(), the rest
// otherwise.
float get_layered_density(material_t material, float eta, vec3 shading_normal, vec3 clearcoat_normal, vec3 view, vec3 light) {
    float density = get_transmissive_density(material, eta, shading_normal, view, light);
    if (has_sheen(material)) {
        float sheen_weight = get_sheen_weight(material, dot(shading_normal, view));
        density = (1.0 - sheen_weight) * density + sheen_weight * max(0.0, dot(shading_normal, light)) / M_PI;
    }
    if (material.clearcoat > 0.0) {
        float coat_weight = get_clearcoat_weight(material, dot(clearcoat_normal, view));
        density = (1.0 - coat_weight) * density + coat_weight * get_clearcoat_density(material, clearcoat_normal, view, light);
    }
    return density;
}

// Samples the layered BSDF, its lobes by weight: lobe_random < w_c samples the coat, else
// (stretched back to [0, 1)) the sheen by its weight (a cosine direction), else (stretched
// again) sample_transmissive_bsdf(). A pick of a delta lobe (a smooth coat, or the base's
// as sample_transmissive_bsdf() says) sets out_delta and its weight f / p out_delta_weight:
// the layers' factors of get_layered_bsdf(), (1 - w_c) (1 - w_s) for the base and w_c for
// the coat, are the probabilities of picking them, so they cancel (a smooth coat's peak
// carries w_c, its weight is 1).
vec3 sample_layered_bsdf(vec2 random_numbers, float lobe_random, material_t material, float eta, vec3 shading_normal, vec3 clearcoat_normal, vec3 view, out bool out_delta, out vec3 out_delta_weight) {
    out_delta = false;
    out_delta_weight = vec3(0.0);
    if (material.clearcoat > 0.0) {
        float coat_weight = get_clearcoat_weight(material, dot(clearcoat_normal, view));
        if (lobe_random < coat_weight) {
            out_delta = get_ggx_alpha(material.clearcoat_roughness) == 0.0;
            out_delta_weight = out_delta ? vec3(1.0) : vec3(0.0);
            return sample_clearcoat(random_numbers, material, clearcoat_normal, view);
        }
        lobe_random = (lobe_random - coat_weight) / (1.0 - coat_weight);
    }
    if (has_sheen(material)) {
        float sheen_weight = get_sheen_weight(material, dot(shading_normal, view));
        if (lobe_random < sheen_weight)
            return sample_hemisphere_cosine(random_numbers, shading_normal);
        lobe_random = (lobe_random - sheen_weight) / (1.0 - sheen_weight);
    }
    return sample_transmissive_bsdf(random_numbers, lobe_random, material, eta, shading_normal, view, out_delta, out_delta_weight);
}

// The fraction of light a ray keeps over `distance` inside the material's volume
// (Beer-Lambert, exp(-sigma d)).
vec3 get_absorption(material_t material, float distance) {
    return exp(-material.attenuation * distance);
}

#endif
