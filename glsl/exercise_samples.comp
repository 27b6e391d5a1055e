#version 460
// The sample display of the workshop's ShaderToy framework for Exercises 4 and 5 ("The
// framework displays 512 samples"), for `vkpath exercise sample-sphere|sample-hemisphere|
// spherical-coords|brdf-samples`: a dimly shaded unit sphere, seen from a fixed orthographic
// camera, with a dot wherever one of EXERCISE_SAMPLE_COUNT sample directions lands. Dots on
// the visible hemisphere are bright; those on the far side show through the sphere, fainter.
// Every pixel draws the same sample directions from the same seed, so the dots are the
// samples, not noise. For sample_brdf() (normal +z), a blue disk marks the view direction
// and a green ring the mirror direction on the sphere's visible side: above the faint dots
// behind the sphere, beneath the bright ones. Rust twins of the view and the
// samples: src/exercise/view.rs.

#include "shared.h"

layout(local_size_x = WORKGROUP_SIZE_X, local_size_y = WORKGROUP_SIZE_Y, local_size_z = 1) in;

// Unused here; declared so that the included scene files (and a user's functions that call
// them) compile exactly as in path_tracer.comp.
layout(constant_id = SPEC_MAX_PATH_LENGTH) const int MAX_PATH_LENGTH = DEFAULT_MAX_PATH_LENGTH;

#include "integrator.glsl"
#include "exercise_samplers.glsl"
#include "brdf.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

// One linear RGB colour per pixel (alpha 1), rows top-down.
layout(std430, set = 0, binding = BINDING_EXERCISE_PIXELS) writeonly buffer exercise_pixels {
    vec4 g_pixels[];
};

// The directions EXERCISE_SAMPLER_DIRECTIONS draws (xyz, unit length).
layout(std430, set = 0, binding = BINDING_EXERCISE_DIRECTIONS) readonly buffer exercise_directions {
    vec4 g_directions[];
};

// What the display shows. Mirrors `vkpath::exercise::view::SampleDisplayPushConstants`.
// All but the first member only matter for EXERCISE_SAMPLER_BRDF.
layout(push_constant) uniform exercise_push_constants {
    // x, y: image size in pixels; z: EXERCISE_SAMPLER_*; w: seed of the sample sequence
    uvec4 g_resolution_sampler_seed;
    // xyz: the material's base colour, linear RGB; w: its metallic factor
    vec4 g_base_color_metallic;
    // xyz: the material's specular colour, linear RGB; w: its specular factor
    vec4 g_specular_color_specular;
    // xyz: unit view direction, from the surface towards the viewer (normal +z, z > 0)
    vec4 g_view_direction;
    // x: the material's perceptual roughness; y: its index of refraction
    vec4 g_roughness_ior;
};

// The camera looks at the sphere from 30 degrees above its equator with +z up in the image,
// so that the pole where spherical coordinates crowd their samples faces the viewer. The
// image plane is spanned by SAMPLE_VIEW_RIGHT and SAMPLE_VIEW_UP (orthonormal); the viewer
// is in direction SAMPLE_VIEW_TOWARD_VIEWER = cross(right, up). Rust twins: SAMPLE_VIEW_*.
const vec3 SAMPLE_VIEW_RIGHT = vec3(1.0, 0.0, 0.0);
// (0, sin 30deg, cos 30deg)
const vec3 SAMPLE_VIEW_UP = vec3(0.0, SAMPLE_VIEW_ELEVATION_SIN, SAMPLE_VIEW_ELEVATION_COS);
// (0, -cos 30deg, sin 30deg)
const vec3 SAMPLE_VIEW_TOWARD_VIEWER = vec3(0.0, -SAMPLE_VIEW_ELEVATION_COS, SAMPLE_VIEW_ELEVATION_SIN);
// SAMPLE_VIEW_HALF_HEIGHT (glsl/shared.h): half the image height in sphere radii.
// Unit direction to the light that shades the sphere dimly (from the upper left front).
const vec3 SAMPLE_VIEW_LIGHT = vec3(-0.48507125007266594, -0.48507125007266594, 0.7276068751089989);
// Colour of a dot on the visible hemisphere, linear RGB; dots behind the sphere blend
// BACK_DOT_OPACITY of it over the sphere. The dots are orange and the sphere grey, so a
// reader (or a test) tells them apart by hue.
const vec3 DOT_COLOR = vec3(1.0, 0.45, 0.05);
const float BACK_DOT_OPACITY = 0.35;
// Markers of the BRDF display, linear RGB, told apart from the dots and the grey sphere by
// hue: the view direction is a blue disk of MARKER_RADIUS dot radii, the mirror direction a
// green ring of that radius, MARKER_RING_WIDTH dot radii wide, so that the samples that
// cluster at the mirror direction stay visible inside it.
const vec3 VIEW_MARKER_COLOR = vec3(0.1, 0.3, 1.0);
const vec3 MIRROR_MARKER_COLOR = vec3(0.1, 0.9, 0.15);
const float MARKER_RADIUS = 3.0;
const float MARKER_RING_WIDTH = 1.0;

// The point of the view's image plane that a pixel centre shows, in sphere radii: x to the
// right, y up, (0, 0) at the sphere's centre.
// \param pixel Pixel index, counted from the bottom-left as ShaderToy does
// \param resolution Image size in pixels
vec2 get_sample_view_point(uvec2 pixel, uvec2 resolution) {
    vec2 centered = (vec2(pixel) + 0.5) - 0.5 * vec2(resolution);
    return centered * (2.0 * SAMPLE_VIEW_HALF_HEIGHT / float(resolution.y));
}

// Where a direction (a point on the unit sphere) appears in the view: its coordinates in the
// image plane (orthographic projection), in sphere radii.
vec2 project_to_sample_view(vec3 direction) {
    return vec2(dot(direction, SAMPLE_VIEW_RIGHT), dot(direction, SAMPLE_VIEW_UP));
}

// Sample i of the displayed sequence uses the random numbers of the i-th call of
// get_random_numbers() from this state. Seed 0 starts PCG2D at (0, 0); other seeds are
// spread over both words by the odd multipliers of get_sample_seed().
uvec2 get_sample_display_seed(uint user_seed) {
    return uvec2(2654435769u, 2246822507u) * user_seed;
}

// The material of the BRDF display, from the push constants.
material_t get_display_material() {
    return get_base_material(g_base_color_metallic.xyz, g_base_color_metallic.w, g_roughness_ior.x, g_specular_color_specular.w, g_specular_color_specular.xyz, g_roughness_ior.y);
}

// The sampler the display shows, by EXERCISE_SAMPLER_* value.
// \param sampler_id EXERCISE_SAMPLER_SPHERE, _HEMISPHERE (normal +z), _SPHERICAL_COORDINATES
//        or _BRDF
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \param material, view What EXERCISE_SAMPLER_BRDF samples: the normal is +z, view a unit
//        vector above it
// \return A unit vector
vec3 get_exercise_sample_direction(uint sampler_id, vec2 random_numbers, material_t material, vec3 view) {
    if (sampler_id == EXERCISE_SAMPLER_BRDF)
        return sample_brdf(random_numbers, material, vec3(0.0, 0.0, 1.0), view);
    if (sampler_id == EXERCISE_SAMPLER_HEMISPHERE)
        return sample_hemisphere(random_numbers, vec3(0.0, 0.0, 1.0));
    if (sampler_id == EXERCISE_SAMPLER_SPHERICAL_COORDINATES)
        return sample_sphere_spherical_coordinates(random_numbers);
    return sample_sphere(random_numbers);
}

void main() {
    uvec2 resolution = g_resolution_sampler_seed.xy;
    uvec2 texel = gl_GlobalInvocationID.xy;
    if (texel.x >= resolution.x || texel.y >= resolution.y)
        return;
    // Image rows run top-down; ShaderToy counts pixels from the bottom-left.
    uvec2 pixel = uvec2(texel.x, resolution.y - 1u - texel.y);
    vec2 view_point = get_sample_view_point(pixel, resolution);

    // Ray-cast the unit sphere with the view's parallel ray through this pixel: the ray
    // o + t d with d = -toward_viewer hits |x| = 1 where t^2 + 2 t (o.d) + o.o - 1 = 0.
    vec3 origin = view_point.x * SAMPLE_VIEW_RIGHT + view_point.y * SAMPLE_VIEW_UP + 3.0 * SAMPLE_VIEW_TOWARD_VIEWER;
    vec3 direction = -SAMPLE_VIEW_TOWARD_VIEWER;
    float half_b = dot(origin, direction);
    float discriminant = half_b * half_b - (dot(origin, origin) - 1.0);
    vec3 color = vec3(0.0);
    if (discriminant >= 0.0) {
        vec3 normal = normalize(origin + (-half_b - sqrt(discriminant)) * direction);
        // Dim Lambertian shading plus ambient, so that the dots stand out.
        color = vec3(0.03 + 0.12 * max(0.0, dot(normal, SAMPLE_VIEW_LIGHT)));
    }

    // A dot is a disk of radius max(1.5, height / 128) pixels around a sample's projection.
    float dot_radius = max(1.5, float(resolution.y) / 128.0) * (2.0 * SAMPLE_VIEW_HALF_HEIGHT / float(resolution.y));
    uint sampler_id = g_resolution_sampler_seed.z;
    material_t material = get_display_material();
    vec3 view = g_view_direction.xyz;
    bool view_marker = false;
    bool mirror_marker = false;
    if (sampler_id == EXERCISE_SAMPLER_BRDF) {
        // The view and its mirror image reflect(-view, +z) face the camera (both have y = 0).
        float view_distance = length(project_to_sample_view(view) - view_point);
        vec3 mirror = reflect(-view, vec3(0.0, 0.0, 1.0));
        float mirror_distance = length(project_to_sample_view(mirror) - view_point);
        view_marker = view_distance <= MARKER_RADIUS * dot_radius;
        mirror_marker = abs(mirror_distance - MARKER_RADIUS * dot_radius) <= 0.5 * MARKER_RING_WIDTH * dot_radius;
    }
    bool front_dot = false;
    bool back_dot = false;
    uvec2 seed = get_sample_display_seed(g_resolution_sampler_seed.w);
    for (int i = 0; i != EXERCISE_SAMPLE_COUNT; ++i) {
        vec3 sample_direction = get_exercise_sample_direction(sampler_id, get_random_numbers(seed), material, view);
        if (sampler_id == EXERCISE_SAMPLER_DIRECTIONS)
            sample_direction = g_directions[i].xyz;
        vec2 offset = project_to_sample_view(sample_direction) - view_point;
        if (dot(offset, offset) <= dot_radius * dot_radius) {
            if (dot(sample_direction, SAMPLE_VIEW_TOWARD_VIEWER) >= 0.0)
                front_dot = true;
            else
                back_dot = true;
        }
    }
    // Back to front: dots behind the sphere, markers on it, dots in front.
    if (back_dot)
        color = mix(color, DOT_COLOR, BACK_DOT_OPACITY);
    if (view_marker)
        color = VIEW_MARKER_COLOR;
    else if (mirror_marker)
        color = MIRROR_MARKER_COLOR;
    if (front_dot)
        color = DOT_COLOR;
    g_pixels[texel.y * resolution.x + texel.x] = vec4(color, 1.0);
}
