// The thin-wall lobe of KHR_materials_transmission (thickness 0, or ior 1): the extension's
// fresnel_mix with Schlick's Fresnel; light passes straight through, the GGX lobe mirrored to
// the other side (mirror_through_surface()). Its quartet:
// - value:   get_thin_wall_btdf();
// - density: get_thin_wall_density();
// - sample:  sample_thin_wall();
// - weight:  get_thin_wall_reflection_probability() splits reflection from transmission
//            (Fresnel get_dielectric_schlick_fresnel(), glsl/fresnel.glsl); the layered
//            mix picks the lobe itself with get_transmission_probability() and
//            is_refracting() (glsl/layered_bsdf.glsl).
// Smooth (roughness 0, GGX alpha 0): a delta lobe. Its value and density are 0 for any
// direction (get_ggx_distribution() is), sample_thin_wall() returns the mirror direction or
// -v itself, and what the two peaks carry is get_dielectric_schlick_fresnel() at n.v
// (reflection) and get_smooth_thin_wall_transmittance() (transmission), which
// get_transmissive_delta_weight() (glsl/layered_bsdf.glsl) turns into a pick's weight.
// Included by glsl/layered_bsdf.glsl. Rust twin: src/cpu/lobe_thin_wall.rs (same names,
// same maths).
#ifndef VKPATH_LOBE_THIN_WALL_GLSL
#define VKPATH_LOBE_THIN_WALL_GLSL

// A direction mirrored through the surface's plane: a thin wall's transmission is its GGX
// reflection lobe mirrored to the other side.
vec3 mirror_through_surface(vec3 local_direction) {
    return vec3(local_direction.xy, -local_direction.z);
}

// The probability that sample_thin_wall() reflects at a microfacet h: the reflection's
// share of luminance, F against (1 - F) times the base colour; 1 where neither has any.
float get_thin_wall_reflection_probability(material_t material, float view_dot_half) {
    vec3 fresnel = get_dielectric_schlick_fresnel(material, view_dot_half);
    float reflected = get_luminance(fresnel);
    float transmitted = get_luminance((1.0 - fresnel) * material.base_color);
    return (reflected + transmitted > 0.0) ? reflected / (reflected + transmitted) : 1.0;
}

// The thin wall's transmission (light below): (1 - F) base_color D V at the light mirrored
// back above the surface; 0 for light above (the reflection belongs to the dielectric's
// specular lobe, get_brdf()).
vec3 get_thin_wall_btdf(material_t material, float alpha, vec3 local_view, vec3 local_light) {
    if (!(local_light.z < 0.0))
        return vec3(0.0);
    vec3 mirrored = mirror_through_surface(local_light);
    vec3 local_half = normalize(local_view + mirrored);
    vec3 fresnel = get_dielectric_schlick_fresnel(material, dot(local_view, local_half));
    return (1.0 - fresnel) * material.base_color * get_ggx_distribution(alpha, local_half) * get_smith_visibility(alpha, local_view.z, mirrored.z);
}

// What a smooth thin wall's straight-through peak carries (f |n.l| integrated over it):
// (1 - F) base_color, F get_dielectric_schlick_fresnel() at v.h = n.v.
vec3 get_smooth_thin_wall_transmittance(material_t material, float normal_dot_view) {
    return (1.0 - get_dielectric_schlick_fresnel(material, normal_dot_view)) * material.base_color;
}

// Density of sample_thin_wall(), whichever side the light is on: the visible-normal
// reflection density at h_r = normalize(v + l) times the reflection probability, plus that at
// the mirrored light's half vector times its complement.
float get_thin_wall_density(material_t material, float alpha, vec3 local_view, vec3 local_light) {
    float density = 0.0;
    vec3 reflected_sum = local_view + local_light;
    if (dot(reflected_sum, reflected_sum) > 0.0) {
        vec3 local_half = normalize(reflected_sum);
        density = get_thin_wall_reflection_probability(material, dot(local_view, local_half)) * get_ggx_reflection_density(alpha, local_view, local_half);
    }
    vec3 mirrored_sum = local_view + mirror_through_surface(local_light);
    if (dot(mirrored_sum, mirrored_sum) > 0.0) {
        vec3 local_half = normalize(mirrored_sum);
        density += (1.0 - get_thin_wall_reflection_probability(material, dot(local_view, local_half))) * get_ggx_reflection_density(alpha, local_view, local_half);
    }
    return density;
}

// Samples the thin wall: a visible GGX normal, the view reflected at it, and that mirrored
// through the surface where lobe_random >= the reflection probability. For alpha 0 the
// normal is the surface's: the mirror direction, or -v straight through.
vec3 sample_thin_wall(vec2 random_numbers, float lobe_random, material_t material, float alpha, vec3 local_view) {
    vec3 local_half = sample_ggx_visible_normal(random_numbers, alpha, local_view);
    vec3 reflected = reflect(-local_view, local_half);
    if (lobe_random < get_thin_wall_reflection_probability(material, dot(local_view, local_half)))
        return reflected;
    return mirror_through_surface(reflected);
}

#endif
