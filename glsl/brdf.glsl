// The glTF 2.0 metallic-roughness BRDF (the specification's Appendix B), with
// KHR_materials_specular and KHR_materials_ior, and its importance sampling: the workshop's
// closing slide's "BRDF importance sampling" for real materials. Functions come in pairs
// sample_x / get_x_density as in Peters' renderers. Rust twins: src/cpu/brdf.rs (same names,
// same maths); change both together. Its Fresnel terms come from glsl/fresnel.glsl (the
// Fresnel room, included after material_t).
//
// Conventions: every direction is a unit vector, world space unless named local_; `view`
// points from the surface towards the viewer (the reverse of the incoming ray), `light`
// from the surface towards where light comes from. The BRDF is evaluated in the shading
// frame (the shading normal, see glsl/materials.glsl), without the cosine factor.
#ifndef VKPATH_BRDF_GLSL
#define VKPATH_BRDF_GLSL

#include "shared.h"
#include "workshop.glsl"
#include "shading_basis.glsl"

// A surface point's material after texture lookups: what get_brdf() and sample_brdf() read.
struct material_t {
    // Base colour (glTF baseColorFactor times baseColorTexture), linear RGB in [0, 1]
    vec3 base_color;
    // 0: dielectric, 1: metal; in between a linear mix of the two BRDFs
    float metallic;
    // Perceptual roughness in [0, 1]; the GGX alpha is its square (get_ggx_alpha())
    float roughness;
    // KHR_materials_specular's specularFactor: scales the dielectric's Fresnel (0: Lambertian)
    float specular;
    // KHR_materials_specular's specularColorFactor: tints the dielectric's F0, linear RGB
    vec3 specular_color;
    // KHR_materials_ior's index of refraction (glTF's default 1.5, F0 = 0.04)
    float ior;
    // The layers of glsl/layered_bsdf.glsl, all 0 for a material without them (and left
    // unset by the Lambert model):
    // KHR_materials_transmission's transmission in [0, 1]
    float transmission;
    // KHR_materials_volume's thickness: 0 thin-walled, above 0 a refracting volume
    float thickness;
    // The volume's absorption coefficient per unit length (Beer-Lambert)
    vec3 attenuation;
    // KHR_materials_clearcoat's clearcoat in [0, 1] and its perceptual roughness
    float clearcoat;
    float clearcoat_roughness;
    // KHR_materials_sheen's colour (linear RGB) and perceptual roughness
    vec3 sheen_color;
    float sheen_roughness;
};

#include "fresnel.glsl"

// The one constructor of a material_t: the metallic-roughness model's factors, every layer
// of glsl/layered_bsdf.glsl off (0). A new field of material_t gets its "off" value here and
// nowhere else; whoever has the layer sets it after.
// \param base_color Linear RGB in [0, 1]; \param metallic 0: dielectric, 1: metal
// \param roughness Perceptual roughness in [0, 1]; \param specular specularFactor
// \param specular_color specularColorFactor, linear RGB; \param ior Index of refraction
material_t get_base_material(vec3 base_color, float metallic, float roughness, float specular, vec3 specular_color, float ior) {
    material_t material;
    material.base_color = base_color;
    material.metallic = metallic;
    material.roughness = roughness;
    material.specular = specular;
    material.specular_color = specular_color;
    material.ior = ior;
    material.transmission = 0.0;
    material.thickness = 0.0;
    material.attenuation = vec3(0.0);
    material.clearcoat = 0.0;
    material.clearcoat_roughness = 0.0;
    material.sheen_color = vec3(0.0);
    material.sheen_roughness = 0.0;
    return material;
}

// The GGX alpha of a perceptual roughness: roughness^2 as glTF defines it, but at least
// MIN_GGX_ALPHA, so that a roughness just above 0 gives a lobe about 10^-4 rad wide whose
// peak density (3e7) and squared MIS weights stay far inside float range. Roughness 0
// exactly gives alpha 0: a delta (perfectly specular) lobe, a Dirac peak that no value or
// density describes. get_ggx_distribution() is 0 for it, so every GGX lobe's value and
// density vanish for any direction (light samples find nothing), and
// sample_ggx_visible_normal() returns the normal itself, so the samplers return the lobe's
// peak (the mirror direction, the thin wall's straight-through one, the refraction); the
// samplers' callers weigh such a pick by its own f / p (get_brdf_mirror_weight(),
// get_transmissive_delta_weight()) and mark it BSDF_LOBE_DELTA (glsl/surface.glsl).
float get_ggx_alpha(float roughness) {
    return (roughness == 0.0) ? 0.0 : max(roughness * roughness, MIN_GGX_ALPHA);
}

// The Trowbridge-Reitz (GGX) normal distribution D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1)
// + 1)^2), written with the local half vector's components as
// 1 / (pi alpha^2 ((h_x^2 + h_y^2) / alpha^2 + h_z^2)^2), which keeps its digits near the
// peak where the textbook form subtracts nearly equal numbers. 0 below the surface, and 0
// for alpha 0 (a delta lobe, get_ggx_alpha(): its Dirac peak has no value at any half vector).
// \param local_half Unit half vector in the shading frame (z = normal)
float get_ggx_distribution(float alpha, vec3 local_half) {
    if (local_half.z <= 0.0 || alpha == 0.0)
        return 0.0;
    float stretched = (local_half.x * local_half.x + local_half.y * local_half.y) / (alpha * alpha) + local_half.z * local_half.z;
    return 1.0 / (M_PI * alpha * alpha * stretched * stretched);
}

// The height-correlated Smith visibility term V = G_2 / (4 |n.l| |n.v|) of GGX (Heitz 2014):
// 0.5 / (n.l sqrt(alpha^2 + (1 - alpha^2) (n.v)^2) + n.v sqrt(alpha^2 + (1 - alpha^2) (n.l)^2)).
// Both cosines must be positive.
float get_smith_visibility(float alpha, float normal_dot_view, float normal_dot_light) {
    float alpha_squared = alpha * alpha;
    float view_term = normal_dot_light * sqrt(alpha_squared + (1.0 - alpha_squared) * normal_dot_view * normal_dot_view);
    float light_term = normal_dot_view * sqrt(alpha_squared + (1.0 - alpha_squared) * normal_dot_light * normal_dot_light);
    return 0.5 / (view_term + light_term);
}

// Smith's masking function G_1 of GGX for a direction whose cosine with the normal is
// `cos_theta` (> 0): 2 cos / (cos + sqrt(alpha^2 + (1 - alpha^2) cos^2)).
float get_smith_masking(float alpha, float cos_theta) {
    float alpha_squared = alpha * alpha;
    return 2.0 * cos_theta / (cos_theta + sqrt(alpha_squared + (1.0 - alpha_squared) * cos_theta * cos_theta));
}

// The glTF BRDF (Appendix B), without the cosine:
// mix(dielectric, metal, metallic) with
// dielectric = (1 - F_d) base_color / pi + F_d D V  (F_d: the dielectric's Fresnel),
// metal = F_m D V  (F_m: Schlick with F0 = base_color, F90 = 1).
// 0 where the view or the light is below the shading normal's horizon.
// \param normal Unit shading normal, world space
// \return f(view, light), linear RGB, per steradian
vec3 get_brdf(material_t material, vec3 normal, vec3 view, vec3 light) {
    float normal_dot_view = dot(normal, view);
    float normal_dot_light = dot(normal, light);
    if (normal_dot_view <= 0.0 || normal_dot_light <= 0.0)
        return vec3(0.0);
    mat3 basis = get_shading_basis(normal);
    vec3 local_half = normalize((view + light) * basis);
    float view_dot_half = dot(view, basis * local_half);
    float alpha = get_ggx_alpha(material.roughness);
    float specular = get_ggx_distribution(alpha, local_half) * get_smith_visibility(alpha, normal_dot_view, normal_dot_light);
    vec3 dielectric_fresnel = get_dielectric_schlick_fresnel(material, view_dot_half);
    vec3 dielectric = (1.0 - dielectric_fresnel) * material.base_color / M_PI + dielectric_fresnel * specular;
    vec3 metal = get_metal_schlick_fresnel(material, view_dot_half) * specular;
    return mix(dielectric, metal, material.metallic);
}

// Relative luminance of linear RGB (Rec. 709 weights), for choosing lobes.
float get_luminance(vec3 color) {
    return dot(color, vec3(0.2126, 0.7152, 0.0722));
}

// The probability with which sample_brdf() samples the specular (GGX) lobe rather than the
// diffuse one: the specular lobe's share of the reflected energy estimated at the view
// angle (Fresnel at v.h = n.v). 0 where the specular lobe vanishes (specular 0 and not
// metallic), 1 where the diffuse one does (metals, black base colours).
float get_specular_probability(material_t material, float normal_dot_view) {
    vec3 dielectric_fresnel = get_dielectric_schlick_fresnel(material, normal_dot_view);
    vec3 metal_fresnel = get_metal_schlick_fresnel(material, normal_dot_view);
    float specular = get_luminance(mix(dielectric_fresnel, metal_fresnel, material.metallic));
    float diffuse = (1.0 - material.metallic) * get_luminance((1.0 - dielectric_fresnel) * material.base_color);
    return (specular + diffuse > 0.0) ? specular / (specular + diffuse) : 0.5;
}

// The reflectance of the glTF BRDF's delta specular lobe (roughness 0) towards the mirror
// direction: what its Dirac peak carries, f (n.l) integrated over the peak,
// mix(F_d, F_m, metallic) with the dielectric's and the metal's Schlick Fresnel at
// v.h = n.v (the specular terms of get_brdf() with D V replaced by delta(l - r) / (n.l)).
vec3 get_mirror_reflectance(material_t material, float normal_dot_view) {
    vec3 dielectric_fresnel = get_dielectric_schlick_fresnel(material, normal_dot_view);
    vec3 metal_fresnel = get_metal_schlick_fresnel(material, normal_dot_view);
    return mix(dielectric_fresnel, metal_fresnel, material.metallic);
}

// The probability that sample_brdf() returns the mirror direction of a delta specular lobe:
// its specular probability where the roughness is 0 (get_ggx_alpha() 0), 0 elsewhere.
// sample_brdf() picks the mirror exactly where random_numbers[0] is below it (the same
// expression of the same inputs as its own choice).
// \param normal Unit shading normal, world space; the view must be above it
float get_brdf_mirror_probability(material_t material, vec3 normal, vec3 view) {
    if (get_ggx_alpha(material.roughness) != 0.0)
        return 0.0;
    mat3 basis = get_shading_basis(normal);
    vec3 local_view = view * basis;
    return get_specular_probability(material, local_view.z);
}

// The weight f / p of sample_brdf()'s mirror pick (get_brdf_mirror_probability() > 0):
// get_mirror_reflectance() over the probability of that pick alone; the continuous diffuse
// lobe plays no part (its density is get_brdf_density(), which has no delta part).
vec3 get_brdf_mirror_weight(material_t material, vec3 normal, vec3 view) {
    mat3 basis = get_shading_basis(normal);
    vec3 local_view = view * basis;
    return get_mirror_reflectance(material, local_view.z) / get_specular_probability(material, local_view.z);
}

// Samples a GGX microfacet normal visible from the view direction (the distribution of
// visible normals, Heitz 2018) with Dupuy and Benyoub's spherical caps (2023): in the
// configuration stretched to alpha = 1, a visible normal is the view direction plus a
// uniform point on the spherical cap below it.
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \param local_view Unit view direction in the shading frame, z > 0
// \return A unit half vector in the shading frame, density
//         G_1(v) max(0, v.h) D(h) / v_z w.r.t. solid angle
vec3 sample_ggx_visible_normal(vec2 random_numbers, float alpha, vec3 local_view) {
    vec3 stretched_view = normalize(vec3(alpha * local_view.xy, local_view.z));
    float phi = 2.0 * M_PI * random_numbers[0];
    float z = (1.0 - random_numbers[1]) * (1.0 + stretched_view.z) - stretched_view.z;
    float sin_theta = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
    vec3 cap_point = vec3(sin_theta * cos(phi), sin_theta * sin(phi), z);
    vec3 stretched_half = cap_point + stretched_view;
    return normalize(vec3(alpha * stretched_half.xy, stretched_half.z));
}

// Density w.r.t. solid angle of the light direction that reflecting the view direction at a
// sampled visible normal gives: G_1(v) D(h) / (4 n.v), with Smith's
// G_1(v) = 2 n.v / (n.v + sqrt(alpha^2 + (1 - alpha^2) (n.v)^2)), so
// D(h) / (2 (n.v + sqrt(alpha^2 + (1 - alpha^2) (n.v)^2))).
float get_ggx_reflection_density(float alpha, vec3 local_view, vec3 local_half) {
    float alpha_squared = alpha * alpha;
    float root = sqrt(alpha_squared + (1.0 - alpha_squared) * local_view.z * local_view.z);
    return get_ggx_distribution(alpha, local_half) / (2.0 * (local_view.z + root));
}

// The diffuse lobe's direction by Malley's method: a uniform point on the unit disk (radius
// sqrt(u), angle 2 pi phi_random), projected up to the hemisphere around the basis's third
// axis; density max(0, n.l) / pi.
// \param u, phi_random Uniform in [0,1)
// \param basis get_shading_basis() of the normal
vec3 sample_diffuse_lobe(float u, float phi_random, mat3 basis) {
    float radius = sqrt(u);
    float phi = 2.0 * M_PI * phi_random;
    return basis * vec3(radius * cos(phi), radius * sin(phi), sqrt(max(0.0, 1.0 - u)));
}

// Samples a light direction for the glTF BRDF: the specular lobe (a reflected visible GGX
// normal) with probability get_specular_probability(), else the diffuse lobe (cosine
// weighted). u_0 chooses the lobe and is stretched back to [0, 1) for the lobe's sampler.
// The direction may lie below the surface (a GGX reflection can); get_brdf() is 0 there.
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \param normal Unit shading normal, world space; the view must be above it
// \return A unit light direction, world space, density get_brdf_density()
vec3 sample_brdf(vec2 random_numbers, material_t material, vec3 normal, vec3 view) {
    mat3 basis = get_shading_basis(normal);
    vec3 local_view = view * basis;
    float specular_probability = get_specular_probability(material, local_view.z);
    if (random_numbers[0] < specular_probability) {
        vec2 lobe_randoms = vec2(random_numbers[0] / specular_probability, random_numbers[1]);
        vec3 local_half = sample_ggx_visible_normal(lobe_randoms, get_ggx_alpha(material.roughness), local_view);
        return normalize(basis * reflect(-local_view, local_half));
    }
    float u = (random_numbers[0] - specular_probability) / (1.0 - specular_probability);
    return sample_diffuse_lobe(u, random_numbers[1], basis);
}

// Density of sample_brdf() w.r.t. solid angle: p_s G_1(v) D(h) / (4 n.v) + (1 - p_s)
// max(0, n.l) / pi with p_s = get_specular_probability(). It integrates to 1 over the sphere
// (part of the specular lobe may fall below the horizon). 0 when the view is below.
float get_brdf_density(material_t material, vec3 normal, vec3 view, vec3 light) {
    float normal_dot_view = dot(normal, view);
    if (normal_dot_view <= 0.0)
        return 0.0;
    mat3 basis = get_shading_basis(normal);
    vec3 local_view = view * basis;
    float specular_probability = get_specular_probability(material, normal_dot_view);
    // light = -view has no half vector; no reflection reaches it.
    vec3 half_sum = view + light;
    float specular = 0.0;
    if (dot(half_sum, half_sum) > 0.0)
        specular = get_ggx_reflection_density(get_ggx_alpha(material.roughness), local_view, normalize(half_sum * basis));
    float diffuse = max(0.0, dot(normal, light)) / M_PI;
    return specular_probability * specular + (1.0 - specular_probability) * diffuse;
}

// The glTF BRDF of a Lambertian material (metallic and specular 0, KHR_materials_specular's
// specularFactor 0), where get_brdf()'s Fresnel terms are exact zeros: base_color / pi, 0
// where the view or the light is below the normal. The same bits as get_brdf() for such a
// material, without the GGX maths (kernels whose scene has no specular lobe,
// SCENE_HAS_SPECULAR).
vec3 get_lambert_brdf(material_t material, vec3 normal, vec3 view, vec3 light) {
    if (dot(normal, view) <= 0.0 || dot(normal, light) <= 0.0)
        return vec3(0.0);
    return material.base_color / M_PI;
}

// sample_brdf() of a Lambertian material: its specular probability is 0, so the diffuse
// lobe alone, with u_0 as it is (the same bits where the base colour is not black; a black
// one reflects nothing whichever lobe is sampled).
vec3 sample_lambert_brdf(vec2 random_numbers, vec3 normal) {
    return sample_diffuse_lobe(random_numbers[0], random_numbers[1], get_shading_basis(normal));
}

// Density of sample_lambert_brdf(): max(0, n.l) / pi, 0 when the view is below (what
// get_brdf_density() gives a Lambertian material whose base colour is not black).
float get_lambert_brdf_density(vec3 normal, vec3 view, vec3 light) {
    if (dot(normal, view) <= 0.0)
        return 0.0;
    return max(0.0, dot(normal, light)) / M_PI;
}

#endif
