#version 460
// Probe of the surface seam's glTF model (glsl/surface.glsl over glsl/materials.glsl): for
// each input, is_opaque_hit() of a candidate hit, get_surface() at that hit, get_bsdf() and
// get_bsdf_density() towards a light direction, and sample_bsdf() with the input's random
// numbers (the layers of glsl/layered_bsdf.glsl where SCENE_HAS_LAYERS). Host side: vkpath::probe::surface_probe (SurfaceProbeInput, SurfaceProbeOutput),
// tests/surface_twins.rs; Rust twins: src/cpu/gltf_surface.rs.
//
// Descriptor set 0: the scene's BINDING_TRIANGLES, BINDING_RENDER_UNIFORMS (declared by
// scene.glsl), BINDING_TEXTURE_TEXELS, BINDING_SHADING and BINDING_MATERIALS as the path
// tracer binds them, then PROBE_BINDING_INPUTS and PROBE_BINDING_OUTPUTS.

#include "shared.h"
// The glTF model, as the path tracer's material builds have it; the constants that the
// files surface.glsl includes need (unused by the functions probed).
#define USE_MATERIALS 1
const int MAX_PATH_LENGTH = 1;
const int LIGHT_SAMPLING = LIGHT_SAMPLING_SOLID_ANGLE;
#include "surface.glsl"

layout(local_size_x = PROBE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

// Which inputs this dispatch covers. Mirrors `vkpath::probe::ProbePushConstants`.
layout(push_constant) uniform probe_push_constants {
    // Index of the input that invocation 0 of this dispatch evaluates.
    uint g_probe_first;
    // Number of inputs in the buffer: invocations past it do nothing.
    uint g_probe_count;
};

struct probe_input_t {
    vec4 ray_origin;     // xyz: the ray's origin, world space; w: the hit's ray parameter t
    vec4 ray_direction;  // xyz: the ray's direction (unit); w: unused
    vec4 light;          // xyz: the light direction of get_bsdf() (unit);
                         // w: unused
    uvec4 triangle_seed; // x: the hit triangle; yz: g_path.alpha_seed; w: g_path.ray_count
    vec4 randoms;        // xy: sample_bsdf()'s random_numbers; z: its lobe_random; w: unused
};

struct probe_output_t {
    vec4 geometric_normal; // xyz: surface.geometric_normal; w: is_opaque_hit() as 0 or 1
    vec4 shading_normal;   // xyz: surface.shading_normal; w: 0
    vec4 base_color;       // rgb: surface.material.base_color; a: metallic
    vec4 factors;          // roughness, specular, ior, has_delta_lobe() as 0 or 1
    vec4 specular_color;   // rgb: surface.material.specular_color; a: 0
    vec4 emission;         // rgb: surface.emission; a: 0
    vec4 reflection;       // rgb: get_bsdf(surface, -direction, light);
                           // a: get_bsdf_density(surface, -direction, light)
    vec4 layers;           // the material's transmission, thickness, clearcoat, clearcoat_roughness
    vec4 clearcoat_normal; // xyz: surface.clearcoat_normal; w: surface.eta
    vec4 sampled;          // xyz: sample_bsdf()'s direction; w: its density
    vec4 sample_weight;    // rgb: sample_bsdf()'s weight; a: its lobes (as a float)
    vec4 extras;           // rgb: surface.unlit_color; a: the sample's eta
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
    uint triangle_index = probe_input.triangle_seed.x;
    g_path.alpha_seed = probe_input.triangle_seed.yz;
    g_path.ray_count = probe_input.triangle_seed.w;
    vec3 origin = probe_input.ray_origin.xyz;
    vec3 direction = probe_input.ray_direction.xyz;
    float t = probe_input.ray_origin.w;
    bool opaque = is_opaque_hit(triangle_index, origin, direction, t);
    surface_t surface = get_surface(triangle_index, get_triangle(triangle_index), origin + t * direction, direction);
    probe_output_t result;
    result.geometric_normal = vec4(surface.geometric_normal, opaque ? 1.0 : 0.0);
    result.shading_normal = vec4(surface.shading_normal, 0.0);
    result.base_color = vec4(surface.material.base_color, surface.material.metallic);
    result.factors = vec4(surface.material.roughness, surface.material.specular, surface.material.ior, has_delta_lobe(surface) ? 1.0 : 0.0);
    result.specular_color = vec4(surface.material.specular_color, 0.0);
    result.emission = vec4(surface.emission, 0.0);
    vec3 light = probe_input.light.xyz;
    result.reflection = vec4(get_bsdf(surface, -direction, light), get_bsdf_density(surface, -direction, light));
    result.layers = vec4(surface.material.transmission, surface.material.thickness, surface.material.clearcoat, surface.material.clearcoat_roughness);
    result.clearcoat_normal = vec4(surface.clearcoat_normal, surface.eta);
    bsdf_sample_t bsdf_sample = sample_bsdf(surface, -direction, probe_input.randoms.xy, probe_input.randoms.z);
    result.sampled = vec4(bsdf_sample.direction, bsdf_sample.density);
    result.sample_weight = vec4(bsdf_sample.weight, float(bsdf_sample.lobes));
    result.extras = vec4(surface.unlit_color, bsdf_sample.eta);
    g_outputs[index] = result;
}
