#version 460
// Probe of the glTF BRDF and its sampling (glsl/brdf.glsl): for each input, get_brdf(),
// get_brdf_density(), sample_brdf() and the density at the sampled direction,
// sample_ggx_visible_normal(), get_specular_probability() and the Fresnel room's terms
// (glsl/fresnel.glsl) on the input's material,
// normal, view, light and random numbers. Host side: vkpath::probe::brdf_probe
// (BrdfProbeInput, BrdfProbeOutput), tests/brdf_twins.rs.
//
// Descriptor set 0: PROBE_BINDING_INPUTS and PROBE_BINDING_OUTPUTS only. Self-contained:
// unlike probe_common.glsl it binds no scene.

#include "shared.h"
#include "brdf.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

// Which inputs this dispatch covers. Mirrors `vkpath::probe::ProbePushConstants`.
layout(push_constant) uniform probe_push_constants {
    // Index of the input that invocation 0 of this dispatch evaluates.
    uint g_probe_first;
    // Number of inputs in the buffer: invocations past it do nothing.
    uint g_probe_count;
};

struct probe_input_t {
    vec4 base_color_metallic;     // rgb: material_t.base_color; a: metallic
    vec4 specular_color_specular; // rgb: material_t.specular_color; a: specular
    vec4 roughness_ior_randoms;   // x: roughness; y: ior; zw: the random numbers (u_0, u_1)
                                  // of sample_brdf() and sample_ggx_visible_normal()
    vec4 normal;                  // xyz: unit shading normal, world space; w: unused
    vec4 view;                    // xyz: unit view direction, world space; w: unused
    vec4 light;                   // xyz: unit light direction, world space; w: unused
};

struct probe_output_t {
    vec4 brdf;           // rgb: get_brdf(material, normal, view, light);
                         // a: get_brdf_density(material, normal, view, light)
    vec4 sampled;        // xyz: sample_brdf(randoms, material, normal, view);
                         // w: get_brdf_density() at that direction
    vec4 visible_normal; // xyz: sample_ggx_visible_normal(randoms, alpha, local_view) with
                         // alpha = get_ggx_alpha(roughness) and local_view = (view.xy,
                         // |view.z|), the view read as a shading-frame vector above the
                         // surface; w: get_specular_probability(material, dot(normal, view))
    vec4 mirror;         // rgb: get_brdf_mirror_weight(material, normal, view) where the
                         // mirror probability is above 0, else 0;
                         // a: get_brdf_mirror_probability(material, normal, view)
    vec4 fresnel;        // rgb: get_dielectric_schlick_fresnel(material, dot(normal, view));
                         // a: get_dielectric_fresnel(dot(normal, view), material.ior)
    vec4 metal_fresnel;  // rgb: get_metal_schlick_fresnel(material, dot(normal, view)); a: 0
};

layout(std430, set = 0, binding = PROBE_BINDING_INPUTS) readonly buffer probe_inputs {
    probe_input_t g_inputs[];
};
layout(std430, set = 0, binding = PROBE_BINDING_OUTPUTS) writeonly buffer probe_outputs {
    probe_output_t g_outputs[];
};

void main() {
    uint index = g_probe_first + gl_GlobalInvocationID.x;
    if (index >= g_probe_count)
        return;
    probe_input_t probe_input = g_inputs[index];
    material_t material;
    material.base_color = probe_input.base_color_metallic.rgb;
    material.metallic = probe_input.base_color_metallic.a;
    material.roughness = probe_input.roughness_ior_randoms.x;
    material.specular = probe_input.specular_color_specular.a;
    material.specular_color = probe_input.specular_color_specular.rgb;
    material.ior = probe_input.roughness_ior_randoms.y;
    vec2 random_numbers = probe_input.roughness_ior_randoms.zw;
    vec3 normal = probe_input.normal.xyz;
    vec3 view = probe_input.view.xyz;
    vec3 light = probe_input.light.xyz;

    probe_output_t result;
    result.brdf = vec4(get_brdf(material, normal, view, light),
                       get_brdf_density(material, normal, view, light));
    vec3 sampled = sample_brdf(random_numbers, material, normal, view);
    result.sampled = vec4(sampled, get_brdf_density(material, normal, view, sampled));
    vec3 local_view = vec3(view.xy, abs(view.z));
    result.visible_normal = vec4(
        sample_ggx_visible_normal(random_numbers, get_ggx_alpha(material.roughness), local_view),
        get_specular_probability(material, dot(normal, view)));
    float mirror_probability = get_brdf_mirror_probability(material, normal, view);
    result.mirror = vec4((mirror_probability > 0.0) ? get_brdf_mirror_weight(material, normal, view) : vec3(0.0), mirror_probability);
    float normal_dot_view = dot(normal, view);
    result.fresnel = vec4(get_dielectric_schlick_fresnel(material, normal_dot_view),
                          get_dielectric_fresnel(normal_dot_view, material.ior));
    result.metal_fresnel = vec4(get_metal_schlick_fresnel(material, normal_dot_view), 0.0);
    g_outputs[index] = result;
}
