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

// Smith's masking function G_1 of GGX for a direction whose cosine with the normal is
// `cos_theta` (> 0): 2 cos / (cos + sqrt(alpha^2 + (1 - alpha^2) cos^2)).
float get_smith_masking(float alpha, float cos_theta) {
    float alpha_squared = alpha * alpha;
    return 2.0 * cos_theta / (cos_theta + sqrt(alpha_squared + (1.0 - alpha_squared) * cos_theta * cos_theta));
}

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
// under total internal reflection F = 1 and it always reflects.
vec3 sample_rough_dielectric(vec2 random_numbers, float lobe_random, float alpha, float eta, vec3 local_view) {
    vec3 local_half = sample_ggx_visible_normal(random_numbers, alpha, local_view);
    float fresnel = get_dielectric_fresnel(dot(local_view, local_half), eta);
    vec3 refracted = refract(-local_view, local_half, 1.0 / eta);
    // refract() may see total internal reflection where rounding left F just below 1
    if (lobe_random < fresnel || refracted == vec3(0.0))
        return reflect(-local_view, local_half);
    return refracted;
}

// A direction mirrored through the surface's plane: a thin wall's transmission is its GGX
// reflection lobe mirrored to the other side.
vec3 mirror_through_surface(vec3 local_direction) {
    return vec3(local_direction.xy, -local_direction.z);
}

// Schlick's Fresnel of a material's dielectric (get_dielectric_f0(), F90 = specular) at v.h.
vec3 get_thin_wall_fresnel(material_t material, float view_dot_half) {
    return get_schlick_fresnel(get_dielectric_f0(material), vec3(material.specular), view_dot_half);
}

// The probability that sample_thin_wall() reflects at a microfacet h: the reflection's
// share of luminance, F against (1 - F) times the base colour; 1 where neither has any.
float get_thin_wall_reflection_probability(material_t material, float view_dot_half) {
    vec3 fresnel = get_thin_wall_fresnel(material, view_dot_half);
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
    vec3 fresnel = get_thin_wall_fresnel(material, dot(local_view, local_half));
    return (1.0 - fresnel) * material.base_color * get_ggx_distribution(alpha, local_half) * get_smith_visibility(alpha, local_view.z, mirrored.z);
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
// through the surface where lobe_random >= the reflection probability.
vec3 sample_thin_wall(vec2 random_numbers, float lobe_random, material_t material, float alpha, vec3 local_view) {
    vec3 local_half = sample_ggx_visible_normal(random_numbers, alpha, local_view);
    vec3 reflected = reflect(-local_view, local_half);
    if (lobe_random < get_thin_wall_reflection_probability(material, dot(local_view, local_half)))
        return reflected;
    return mirror_through_surface(reflected);
}

// Whether the material has sheen (a sheen colour above 0).
bool has_sheen(material_t material) {
    return max(material.sheen_color.r, max(material.sheen_color.g, material.sheen_color.b)) > 0.0;
}

// The Charlie sheen lobe's alpha: sheen roughness^2, at least SHEEN_MIN_ALPHA.
float get_sheen_alpha(float sheen_roughness) {
    return max(sheen_roughness * sheen_roughness, SHEEN_MIN_ALPHA);
}

// The Charlie distribution D(h) = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi).
float get_charlie_distribution(float alpha, float normal_dot_half) {
    float sin_squared = max(0.0, 1.0 - normal_dot_half * normal_dot_half);
    return (2.0 + 1.0 / alpha) * pow(sin_squared, 0.5 / alpha) / (2.0 * M_PI);
}

// Estevez & Kulla's fit L(x) of the sheen's Lambda: a / (1 + b x^c) + d x + e, each
// coefficient between their alpha-1 and alpha-0 values by (1 - alpha)^2.
float get_sheen_lambda_fit(float x, float alpha) {
    float t = (1.0 - alpha) * (1.0 - alpha);
    float a = mix(21.5473, 25.3245, t);
    float b = mix(3.82987, 3.32435, t);
    float c = mix(0.19823, 0.16801, t);
    float d = mix(-1.97760, -1.27393, t);
    float e = mix(-4.32054, -4.85967, t);
    return a / (1.0 + b * pow(x, c)) + d * x + e;
}

// The sheen's Lambda at a cosine: exp(L(c)) below 0.5, exp(2 L(0.5) - L(1 - c)) above.
float get_sheen_lambda(float cos_theta, float alpha) {
    float c = abs(cos_theta);
    return (c < 0.5) ? exp(get_sheen_lambda_fit(c, alpha)) : exp(2.0 * get_sheen_lambda_fit(0.5, alpha) - get_sheen_lambda_fit(1.0 - c, alpha));
}

// The Charlie visibility 1 / ((1 + Lambda(n.v) + Lambda(n.l)) 4 (n.v)(n.l)), at most 1.
float get_sheen_visibility(float alpha, float normal_dot_view, float normal_dot_light) {
    return clamp(1.0 / ((1.0 + get_sheen_lambda(normal_dot_view, alpha) + get_sheen_lambda(normal_dot_light, alpha)) * 4.0 * normal_dot_view * normal_dot_light), 0.0, 1.0);
}

// The sheen lobe sheen_color D V; 0 where the view or the light is below the normal.
vec3 get_sheen_brdf(material_t material, vec3 normal, vec3 view, vec3 light) {
    float normal_dot_view = dot(normal, view);
    float normal_dot_light = dot(normal, light);
    if (normal_dot_view <= 0.0 || normal_dot_light <= 0.0)
        return vec3(0.0);
    float alpha = get_sheen_alpha(material.sheen_roughness);
    float normal_dot_half = dot(normal, normalize(view + light));
    return material.sheen_color * get_charlie_distribution(alpha, normal_dot_half) * get_sheen_visibility(alpha, normal_dot_view, normal_dot_light);
}

// Entry k of the sheen's albedo table (row-major, SHEEN_ALBEDO_SIZE^2 floats, four to a
// texel): the last SHEEN_ALBEDO_TEXEL_COUNT texels of g_material_texels, after the materials
// (host: material_texel_words(); the numbers: src/cpu/sheen_albedo_table.rs). A table in a
// buffer, not a GLSL constant array: llvmpipe did not finish compiling the 1024-entry array.
float get_sheen_albedo_entry(int k) {
    int first = textureSize(g_material_texels) - SHEEN_ALBEDO_TEXEL_COUNT;
    return uintBitsToFloat(texelFetch(g_material_texels, first + k / 4)[k % 4]);
}

// The lobe's directional albedo E(n.v, sheen roughness) (sheen colour 1), bilinear in the
// table.
float get_sheen_albedo(float normal_dot_view, float sheen_roughness) {
    float last = float(SHEEN_ALBEDO_SIZE - 1);
    vec2 position = clamp(vec2(normal_dot_view, sheen_roughness), 0.0, 1.0) * last;
    ivec2 low = min(ivec2(position), ivec2(SHEEN_ALBEDO_SIZE - 2));
    vec2 weight = position - vec2(low);
    int row = low.x * SHEEN_ALBEDO_SIZE + low.y;
    float below = mix(get_sheen_albedo_entry(row), get_sheen_albedo_entry(row + 1), weight.y);
    float above = mix(get_sheen_albedo_entry(row + SHEEN_ALBEDO_SIZE), get_sheen_albedo_entry(row + SHEEN_ALBEDO_SIZE + 1), weight.y);
    return mix(below, above, weight.x);
}

// The share of the light the sheen takes from the base, max(sheen colour) E(n.v), at most 1
// (the Charlie lobe's albedo passes 1 at grazing views of smooth sheen): the base is scaled
// by 1 minus it, and sample_layered_bsdf() samples the sheen with this probability.
float get_sheen_weight(material_t material, float normal_dot_view) {
    float strongest = max(material.sheen_color.r, max(material.sheen_color.g, material.sheen_color.b));
    return clamp(strongest * get_sheen_albedo(normal_dot_view, material.sheen_roughness), 0.0, 1.0);
}

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
        vec3 dielectric_fresnel = get_schlick_fresnel(get_dielectric_f0(material), vec3(material.specular), view_dot_half);
        vec3 diffuse = (1.0 - dielectric_fresnel) * material.base_color / M_PI;
        vec3 dielectric;
        if (is_refracting(material))
            dielectric = (1.0 - material.transmission) * (diffuse + dielectric_fresnel * specular) + material.transmission * get_dielectric_fresnel(view_dot_half, eta) * specular;
        else
            dielectric = dielectric_fresnel * specular + (1.0 - material.transmission) * diffuse;
        vec3 metal = get_schlick_fresnel(material.base_color, vec3(1.0), view_dot_half) * specular;
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

// Samples get_transmissive_bsdf(): lobe_random < get_transmission_probability() samples
// the rough dielectric or the thin wall (lobe_random, stretched back to [0, 1), chooses
// between reflection and transmission), else sample_brdf().
// \return A unit direction, world space (either side of the surface)
vec3 sample_transmissive_bsdf(vec2 random_numbers, float lobe_random, material_t material, float eta, vec3 shading_normal, vec3 view) {
    float transmission_probability = get_transmission_probability(material);
    if (lobe_random < transmission_probability) {
        float reflection_random = lobe_random / transmission_probability;
        mat3 basis = get_shading_basis(shading_normal);
        vec3 local_view = view * basis;
        float alpha = get_ggx_alpha(material.roughness);
        vec3 local_light = is_refracting(material)
            ? sample_rough_dielectric(random_numbers, reflection_random, alpha, eta, local_view)
            : sample_thin_wall(random_numbers, reflection_random, material, alpha, local_view);
        return normalize(basis * local_light);
    }
    return sample_brdf(random_numbers, material, shading_normal, view);
}

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
// again) sample_transmissive_bsdf().
vec3 sample_layered_bsdf(vec2 random_numbers, float lobe_random, material_t material, float eta, vec3 shading_normal, vec3 clearcoat_normal, vec3 view) {
    if (material.clearcoat > 0.0) {
        float coat_weight = get_clearcoat_weight(material, dot(clearcoat_normal, view));
        if (lobe_random < coat_weight)
            return sample_clearcoat(random_numbers, material, clearcoat_normal, view);
        lobe_random = (lobe_random - coat_weight) / (1.0 - coat_weight);
    }
    if (has_sheen(material)) {
        float sheen_weight = get_sheen_weight(material, dot(shading_normal, view));
        if (lobe_random < sheen_weight)
            return sample_hemisphere_cosine(random_numbers, shading_normal);
        lobe_random = (lobe_random - sheen_weight) / (1.0 - sheen_weight);
    }
    return sample_transmissive_bsdf(random_numbers, lobe_random, material, eta, shading_normal, view);
}

// The fraction of light a ray keeps over `distance` inside the material's volume
// (Beer-Lambert, exp(-sigma d)).
vec3 get_absorption(material_t material, float distance) {
    return exp(-material.attenuation * distance);
}

#endif
