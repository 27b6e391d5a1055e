// The rough dielectric lobe of KHR_materials_transmission where light refracts (thickness > 0,
// ior != 1): Walter et al. 2007 with the exact Fresnel reflectance, GGX with the surface's
// roughness. Its quartet:
// - value:   get_rough_dielectric_bsdf() (reflection and transmission, without the cosine);
// - density: get_rough_dielectric_density();
// - sample:  sample_rough_dielectric();
// - weight:  none of its own: the layered mix picks it with get_transmission_probability()
//            and is_refracting() (glsl/layered_bsdf.glsl); get_refraction_half() is its helper.
// Smooth (roughness 0, GGX alpha 0): a delta lobe. Its value and density are 0 for any
// direction (get_ggx_distribution() is), sample_rough_dielectric() returns the mirror or the
// refracted direction itself, and what the two peaks carry is get_dielectric_fresnel() at n.v
// (reflection) and get_smooth_dielectric_transmittance() (refraction), which
// get_transmissive_delta_weight() (glsl/layered_bsdf.glsl) turns into a pick's weight.
// Included by glsl/layered_bsdf.glsl; get_dielectric_fresnel() comes from glsl/fresnel.glsl
// and get_smith_masking() from glsl/brdf.glsl. Rust twin: src/cpu/lobe_dielectric.rs (same names, same maths).
#ifndef VKPATH_LOBE_DIELECTRIC_GLSL
#define VKPATH_LOBE_DIELECTRIC_GLSL

// The generalised half vector of a refraction from local_view (above) into local_light
// (below): normalize(eta l + v), turned to face the normal; 0 where it does not exist.
vec3 get_refraction_half(float eta, vec3 local_view, vec3 local_light) {
    vec3 half_sum = eta * local_light + local_view;
    if (!(dot(half_sum, half_sum) > 0.0))
        return vec3(0.0);
    vec3 local_half = normalize(half_sum);
    return (local_half.z < 0.0) ? -local_half : local_half;
}

// The rough dielectric BSDF (Walter et al. 2007, height-correlated Smith visibility V):
// reflection (light above) F D V, transmission (light below) 4 D V (1 - F) |l.h| (v.h) /
// (eta l.h + v.h)^2 with h the refraction half vector, for radiance (the 1 / eta^2 of
// crossing into a denser medium included); F = get_dielectric_fresnel(v.h, eta). 0 where
// the half vector faces away from either direction.
// \return x: the reflection, y: the transmission (one of them 0)
vec2 get_rough_dielectric_bsdf(float alpha, float eta, vec3 local_view, vec3 local_light) {
    if (local_light.z > 0.0) {
        vec3 local_half = normalize(local_view + local_light);
        float fresnel = get_dielectric_fresnel(dot(local_view, local_half), eta);
        return vec2(fresnel * get_ggx_distribution(alpha, local_half) * get_smith_visibility(alpha, local_view.z, local_light.z), 0.0);
    }
    if (!(local_light.z < 0.0))
        return vec2(0.0);
    vec3 local_half = get_refraction_half(eta, local_view, local_light);
    float view_dot_half = dot(local_view, local_half);
    float light_dot_half = dot(local_light, local_half);
    if (!(view_dot_half > 0.0) || !(light_dot_half < 0.0))
        return vec2(0.0);
    float fresnel = get_dielectric_fresnel(view_dot_half, eta);
    float denominator = eta * light_dot_half + view_dot_half;
    float visibility = get_smith_visibility(alpha, local_view.z, -local_light.z);
    return vec2(0.0, 4.0 * get_ggx_distribution(alpha, local_half) * visibility * (1.0 - fresnel) * -light_dot_half * view_dot_half / (denominator * denominator));
}

// What a smooth dielectric's refracted peak carries for radiance (f |n.l| integrated over
// it): (1 - F) / eta^2 with F = get_dielectric_fresnel(n.v, eta), the 1 / eta^2 of
// crossing into a denser medium included as in get_rough_dielectric_bsdf(); 0 under total
// internal reflection.
float get_smooth_dielectric_transmittance(float eta, float normal_dot_view) {
    return (1.0 - get_dielectric_fresnel(normal_dot_view, eta)) / (eta * eta);
}

// Density w.r.t. solid angle of sample_rough_dielectric(), whichever side the light is on
// (a reflection at a steep microfacet may land below the surface, a refraction above): the
// reflection's F G_1(v) D(h_r) / (4 v_z) at h_r = normalize(v + l), plus the refraction's
// (1 - F) G_1(v) D(h_t) (v.h_t) / v_z |dh_t/dl| with |dh_t/dl| = eta^2 |l.h_t| /
// (eta l.h_t + v.h_t)^2 where h_t = get_refraction_half() faces both directions rightly.
float get_rough_dielectric_density(float alpha, float eta, vec3 local_view, vec3 local_light) {
    float density = 0.0;
    vec3 half_sum = local_view + local_light;
    if (dot(half_sum, half_sum) > 0.0) {
        vec3 reflection_half = normalize(half_sum);
        density = get_dielectric_fresnel(dot(local_view, reflection_half), eta) * get_ggx_reflection_density(alpha, local_view, reflection_half);
    }
    vec3 local_half = get_refraction_half(eta, local_view, local_light);
    float view_dot_half = dot(local_view, local_half);
    float light_dot_half = dot(local_light, local_half);
    if (view_dot_half > 0.0 && light_dot_half < 0.0) {
        float fresnel = get_dielectric_fresnel(view_dot_half, eta);
        float denominator = eta * light_dot_half + view_dot_half;
        float jacobian = eta * eta * -light_dot_half / (denominator * denominator);
        density += (1.0 - fresnel) * get_smith_masking(alpha, local_view.z) * get_ggx_distribution(alpha, local_half) * view_dot_half / local_view.z * jacobian;
    }
    return density;
}

// Samples the rough dielectric: a visible GGX normal h from (u_0, u_1), then the reflection
// of the view at h where lobe_random < F(v.h), else its refraction (GLSL's refract() with
// 1 / eta). The direction may lie on the wrong side of the surface (the BSDF is 0 there);
// under total internal reflection F = 1 and it always reflects. For alpha 0 the normal is
// the surface's: the mirror or the refracted direction.
vec3 sample_rough_dielectric(vec2 random_numbers, float lobe_random, float alpha, float eta, vec3 local_view) {
    vec3 local_half = sample_ggx_visible_normal(random_numbers, alpha, local_view);
    float fresnel = get_dielectric_fresnel(dot(local_view, local_half), eta);
    vec3 refracted = refract(-local_view, local_half, 1.0 / eta);
    // refract() may see total internal reflection where rounding left F just below 1
    if (lobe_random < fresnel || refracted == vec3(0.0))
        return reflect(-local_view, local_half);
    return refracted;
}

#endif
