// Light from infinitely far away (kernels built with USE_MATERIALS): an equirectangular
// environment map, importance-sampled with an alias table, or a constant background.
// Convention (src/scene/environment.rs): +Y is up; direction d looks up
// u = 0.5 + atan2(x, -z) / (2 pi), v = acos(y) / pi, (0, 0) the image's top-left, so the
// image's centre is -Z; the map turns about +Y by the rotation (90 degrees: what was seen
// down -Z is seen down -X). Texels are constant over their patch (no filtering), which the
// density describes exactly. Rust twins: src/cpu/environment.rs.
#ifndef VKPATH_ENVIRONMENT_GLSL
#define VKPATH_ENVIRONMENT_GLSL

#include "shared.h"
#include "workshop.glsl"

// Texel 0: uvec4(width, height, ENVIRONMENT_*, 0); texel 1: (strength, cos rotation,
// sin rotation, 0) as float bits; texel 2: (background rgb, 0); then per map texel i (rows
// top-down) texel 3 + 2 i: (radiance rgb times strength, probability of choosing it) and
// texel 4 + 2 i: (alias threshold, alias index, 0, 0). GpuEnvironment on the host.
layout(set = 0, binding = BINDING_ENVIRONMENT) uniform usamplerBuffer g_environment_texels;

// ENVIRONMENT_NONE (black: nothing to sample), ENVIRONMENT_CONSTANT or ENVIRONMENT_MAP.
uint get_environment_kind() {
    return texelFetch(g_environment_texels, 0).z;
}

// Turns a direction about +Y by the angle with the given cosine and sine (right-handed).
vec3 rotate_about_y(vec3 direction, float cosine, float sine) {
    return vec3(cosine * direction.x + sine * direction.z, direction.y, -sine * direction.x + cosine * direction.z);
}

// (u, v) of a unit direction in the map's own frame.
vec2 get_environment_uv(vec3 map_direction) {
    return vec2(0.5 + atan(map_direction.x, -map_direction.z) / (2.0 * M_PI), acos(clamp(map_direction.y, -1.0, 1.0)) / M_PI);
}

// Index of the map texel that a unit direction (world space) looks up.
uint get_environment_texel_index(vec3 direction) {
    uvec4 header = texelFetch(g_environment_texels, 0);
    vec4 rotation = uintBitsToFloat(texelFetch(g_environment_texels, 1));
    vec2 uv = get_environment_uv(rotate_about_y(direction, rotation.y, -rotation.z));
    uint x = min(uint(max(uv.x * float(header.x), 0.0)), header.x - 1u);
    uint y = min(uint(max(uv.y * float(header.y), 0.0)), header.y - 1u);
    return y * header.x + x;
}

// Radiance arriving from infinitely far along a unit direction (world space).
vec3 get_environment_radiance(vec3 direction) {
    uint kind = get_environment_kind();
    if (kind == ENVIRONMENT_MAP)
        return uintBitsToFloat(texelFetch(g_environment_texels, 3 + 2 * int(get_environment_texel_index(direction))).rgb);
    return uintBitsToFloat(texelFetch(g_environment_texels, 2).rgb);
}

// A direction with density get_environment_density(): a texel from the alias table (u_0
// picks a bucket and, by its fraction, the bucket's texel or its alias; that fraction,
// stretched back to [0, 1), and u_1 place the point uniformly in the texel's (u, v)
// rectangle), turned into world space; uniform on the sphere for a constant colour.
vec3 sample_environment(vec2 random_numbers) {
    uvec4 header = texelFetch(g_environment_texels, 0);
    if (header.z != ENVIRONMENT_MAP)
        return sample_sphere(random_numbers);
    uint count = header.x * header.y;
    float scaled = random_numbers[0] * float(count);
    uint bucket = min(uint(scaled), count - 1u);
    float fraction = scaled - float(bucket);
    uvec4 alias = texelFetch(g_environment_texels, 4 + 2 * int(bucket));
    float threshold = uintBitsToFloat(alias.x);
    uint texel = bucket;
    if (fraction < threshold) {
        fraction = fraction / threshold;
    } else {
        texel = alias.y;
        fraction = (fraction - threshold) / (1.0 - threshold);
    }
    float u = (float(texel % header.x) + min(fraction, 0.99999994)) / float(header.x);
    float v = (float(texel / header.x) + random_numbers[1]) / float(header.y);
    float theta = v * M_PI;
    float phi = (u - 0.5) * 2.0 * M_PI;
    vec3 map_direction = vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    vec4 rotation = uintBitsToFloat(texelFetch(g_environment_texels, 1));
    return rotate_about_y(map_direction, rotation.y, rotation.z);
}

// Density of sample_environment() w.r.t. solid angle: the texel's probability times its
// texel count, over the (u, v) -> sphere Jacobian 2 pi^2 sin theta; 1 / (4 pi) for a
// constant colour.
float get_environment_density(vec3 direction) {
    uvec4 header = texelFetch(g_environment_texels, 0);
    if (header.z != ENVIRONMENT_MAP)
        return 1.0 / (4.0 * M_PI);
    float probability = uintBitsToFloat(texelFetch(g_environment_texels, 3 + 2 * int(get_environment_texel_index(direction))).w);
    float sin_theta = sqrt(max(0.0, 1.0 - direction.y * direction.y));
    return (sin_theta > 0.0) ? probability * float(header.x * header.y) / (2.0 * M_PI * M_PI * sin_theta) : 0.0;
}

#endif
