// The Fresnel room: every lobe's reflectance at an interface comes from here. Rust twins:
// src/cpu/fresnel.rs (same names, same maths); change both together.
// - get_schlick_fresnel(): Schlick's approximation, the glTF specification's Fresnel;
// - get_dielectric_fresnel(): the exact reflectance of a smooth dielectric interface (the
//   refracting lobes of glsl/lobe_dielectric.glsl and glsl/layered_bsdf.glsl);
// - get_dielectric_f0(), get_dielectric_schlick_fresnel(), get_metal_schlick_fresnel(): the
//   base layer's two Fresnel terms (KHR_materials_specular, KHR_materials_ior), which
//   get_brdf(), the lobe choice, the mirror lobe, the thin wall and the transmissive mix
//   all read through these two functions.
// The seam for a Fresnel modifier (thin-film iridescence, dispersion): it changes the base's
// reflectance in get_dielectric_schlick_fresnel() and get_metal_schlick_fresnel() (and the
// refracting lobes' in get_dielectric_fresnel()), and every lobe follows.
//
// Included by glsl/brdf.glsl after material_t.
#ifndef VKPATH_FRESNEL_GLSL
#define VKPATH_FRESNEL_GLSL

// Schlick's Fresnel approximation F = f0 + (f90 - f0) (1 - |v.h|)^5.
vec3 get_schlick_fresnel(vec3 f0, vec3 f90, float view_dot_half) {
    // max(): |v.h| may round above 1
    float weight = max(0.0, 1.0 - abs(view_dot_half));
    float weight_squared = weight * weight;
    return f0 + (f90 - f0) * (weight_squared * weight_squared * weight);
}

// The exact Fresnel reflectance of a smooth dielectric interface for unpolarised light,
// the mean of the s- and p-polarised reflectances; 1 under total internal reflection.
// \param cos_theta_i Cosine of the angle between the incident direction and the normal on
//        its side (a negative one comes from the other side: eta is inverted)
// \param eta Index of refraction of the far side over that of the incident side
float get_dielectric_fresnel(float cos_theta_i, float eta) {
    cos_theta_i = clamp(cos_theta_i, -1.0, 1.0);
    if (cos_theta_i < 0.0) {
        eta = 1.0 / eta;
        cos_theta_i = -cos_theta_i;
    }
    float sin2_theta_t = (1.0 - cos_theta_i * cos_theta_i) / (eta * eta);
    if (sin2_theta_t >= 1.0)
        return 1.0;
    float cos_theta_t = sqrt(max(0.0, 1.0 - sin2_theta_t));
    float r_parallel = (eta * cos_theta_i - cos_theta_t) / (eta * cos_theta_i + cos_theta_t);
    float r_perpendicular = (cos_theta_i - eta * cos_theta_t) / (cos_theta_i + eta * cos_theta_t);
    return 0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

// The dielectric's reflectance at normal incidence F0 = min(((ior - 1)/(ior + 1))^2
// specular_color, 1) specular and at grazing incidence F90 = specular
// (KHR_materials_specular with KHR_materials_ior); glTF's defaults give 0.04 and 1.
vec3 get_dielectric_f0(material_t material) {
    float reflectance = (material.ior - 1.0) / (material.ior + 1.0);
    return min(reflectance * reflectance * material.specular_color, vec3(1.0)) * material.specular;
}

// The base dielectric's Fresnel F_d: Schlick's with F0 = get_dielectric_f0() and
// F90 = specular, at the cosine v.h (n.v for a delta lobe's peak).
vec3 get_dielectric_schlick_fresnel(material_t material, float view_dot_half) {
    return get_schlick_fresnel(get_dielectric_f0(material), vec3(material.specular), view_dot_half);
}

// The base metal's Fresnel F_m: Schlick's with F0 = base_color and F90 = 1, at the cosine
// v.h (n.v for a delta lobe's peak).
vec3 get_metal_schlick_fresnel(material_t material, float view_dot_half) {
    return get_schlick_fresnel(material.base_color, vec3(1.0), view_dot_half);
}

#endif
