// The clear-coat lobe of KHR_materials_clearcoat (fresnel_coat): a GGX coat of ior
// CLEARCOAT_IOR (F0 = 0.04) with its own normal, over the rest. Its quartet:
// - value:   get_clearcoat_brdf();
// - density: get_clearcoat_density();
// - sample:  sample_clearcoat();
// - weight:  get_clearcoat_weight() (clearcoat F(N_c . V)).
// A smooth coat (clearcoat_roughness 0, GGX alpha 0) is a delta lobe: value and density 0 for
// any direction, sample_clearcoat() returns the mirror direction about the coat's normal,
// and sample_layered_bsdf() gives that pick the weight 1 (its peak carries w_c, the
// probability of picking it).
// Included by glsl/layered_bsdf.glsl. Rust twin: src/cpu/lobe_clearcoat.rs (same names, same
// maths).
#ifndef VKPATH_LOBE_CLEARCOAT_GLSL
#define VKPATH_LOBE_CLEARCOAT_GLSL

// fresnel_coat's weight: clearcoat times Schlick's F (F0 = 0.04 of CLEARCOAT_IOR, F90 = 1)
// at the coat's normal and the view (N_c . V, not V . H, as the extension specifies).
float get_clearcoat_weight(material_t material, float clearcoat_normal_dot_view) {
    float reflectance = (CLEARCOAT_IOR - 1.0) / (CLEARCOAT_IOR + 1.0);
    return material.clearcoat * get_schlick_fresnel(vec3(reflectance * reflectance), vec3(1.0), clearcoat_normal_dot_view).x;
}

// The clear coat's GGX lobe D V with its own roughness, around its normal; 0 where the view
// or the light is below it.
float get_clearcoat_brdf(material_t material, vec3 clearcoat_normal, vec3 view, vec3 light) {
    float normal_dot_view = dot(clearcoat_normal, view);
    float normal_dot_light = dot(clearcoat_normal, light);
    if (normal_dot_view <= 0.0 || normal_dot_light <= 0.0)
        return 0.0;
    mat3 basis = get_shading_basis(clearcoat_normal);
    vec3 local_half = normalize((view + light) * basis);
    float alpha = get_ggx_alpha(material.clearcoat_roughness);
    return get_ggx_distribution(alpha, local_half) * get_smith_visibility(alpha, normal_dot_view, normal_dot_light);
}

// Density of sample_clearcoat(): the reflected visible normal's, G_1(v) D(h) / (4 n_c.v).
float get_clearcoat_density(material_t material, vec3 clearcoat_normal, vec3 view, vec3 light) {
    vec3 half_sum = view + light;
    if (dot(clearcoat_normal, view) <= 0.0 || !(dot(half_sum, half_sum) > 0.0))
        return 0.0;
    mat3 basis = get_shading_basis(clearcoat_normal);
    return get_ggx_reflection_density(get_ggx_alpha(material.clearcoat_roughness), view * basis, normalize(half_sum * basis));
}

// Samples the clear coat: the view reflected at a visible GGX normal of the coat.
vec3 sample_clearcoat(vec2 random_numbers, material_t material, vec3 clearcoat_normal, vec3 view) {
    mat3 basis = get_shading_basis(clearcoat_normal);
    vec3 local_view = view * basis;
    vec3 local_half = sample_ggx_visible_normal(random_numbers, get_ggx_alpha(material.clearcoat_roughness), local_view);
    return normalize(basis * reflect(-local_view, local_half));
}

#endif
