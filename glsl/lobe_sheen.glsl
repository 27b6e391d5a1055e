// The sheen lobe of KHR_materials_sheen: the Charlie lobe (the extension's reference,
// Estevez & Kulla 2017: their distribution and visibility), sampled by the cosine. Its
// quartet:
// - value:   get_sheen_brdf() (its helpers get_sheen_alpha(), get_charlie_distribution(),
//            get_sheen_lambda_fit(), get_sheen_lambda(), get_sheen_visibility());
// - density: none of its own: the cosine's (sample_hemisphere_cosine()), mixed in by
//            get_layered_density() (glsl/layered_bsdf.glsl);
// - sample:  the cosine sampler, sample_hemisphere_cosine(), in sample_layered_bsdf();
// - weight:  get_sheen_weight() (max(sheen colour) E(n.v), E tabulated: get_sheen_albedo(),
//            get_sheen_albedo_entry()); has_sheen() says whether it is there at all.
// Included by glsl/layered_bsdf.glsl. Rust twin: src/cpu/lobe_sheen.rs (same names, same
// maths).
#ifndef VKPATH_LOBE_SHEEN_GLSL
#define VKPATH_LOBE_SHEEN_GLSL

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

#endif
