// Light from infinitely far away (kernels built with USE_MATERIALS): an equirectangular
// environment map, importance-sampled with an alias table, or a constant background.
// Convention (src/lights/environment.rs): +Y is up; direction d looks up
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
// top-down) texel 3 + 2 i: (radiance rgb times strength, the density of sample_environment()
// w.r.t. solid angle over the texel) and texel 4 + 2 i: (alias threshold, alias index, 0, 0).
// gpu_environment_words() on the host.
layout(set = 0, binding = BINDING_ENVIRONMENT) uniform utextureBuffer g_environment_texels;

// Whether the scene has an environment that emits light (the host specializes it; false
// makes the kind a constant ENVIRONMENT_NONE, which compiles the environment's light samples,
// lookups and MIS weights out).
layout(constant_id = SPEC_SCENE_HAS_ENVIRONMENT) const bool SCENE_HAS_ENVIRONMENT = true;

// Whether light samples are drawn from the environment (the host specializes it: true for a
// map, false for a constant environment, which only BSDF-sampled rays find; glsl/shared.h).
// The lean builds (WITHOUT_ENVIRONMENT_MAP), for scenes without a map, hold constants
// instead, so that their SPIR-V carries none of the map's sampling and lookups.
#ifdef WITHOUT_ENVIRONMENT_MAP
const bool SCENE_SAMPLES_ENVIRONMENT = false;
const bool SCENE_HAS_ENVIRONMENT_MAP = false;
#else
layout(constant_id = SPEC_SCENE_SAMPLES_ENVIRONMENT) const bool SCENE_SAMPLES_ENVIRONMENT = true;
const bool SCENE_HAS_ENVIRONMENT_MAP = true;
#endif

// ENVIRONMENT_NONE (black: nothing to sample), ENVIRONMENT_CONSTANT or ENVIRONMENT_MAP.
uint get_environment_kind() {
    if (!SCENE_HAS_ENVIRONMENT)
        return ENVIRONMENT_NONE;
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
    // ENVIRONMENT_NONE's background texel is black (gpu_environment_words() on the host)
    if (!SCENE_HAS_ENVIRONMENT)
        return vec3(0.0);
    if (SCENE_HAS_ENVIRONMENT_MAP && kind == ENVIRONMENT_MAP)
        return uintBitsToFloat(texelFetch(g_environment_texels, 3 + 2 * int(get_environment_texel_index(direction))).rgb);
    return uintBitsToFloat(texelFetch(g_environment_texels, 2).rgb);
}

// A direction with density get_environment_density(): a texel from the alias table, then a
// point uniformly distributed in solid angle over the texel's patch (phi uniform, cos theta
// uniform between the row's edges), turned into world space; uniform on the sphere for a
// constant colour.
// Issue 18: this used to take the texel and the point from one pair, the texel's own-or-alias
// choice from the bucket's fraction of u_0, which with 2^17 texels keeps 7 of its bits: the
// choice was off by up to 1/128 per bucket (texels with aliases were chosen too often, their
// aliases, the bright ones, too rarely) and the point sat on the texel's left edge in 1 of
// 128 samples, where the lookup can round into the neighbour. Each draw now has its own 24
// bits, and the density is constant over a texel, so it is the sampled texel's wherever
// the direction lands inside it.
// \param texel_randoms Uniform (u_0, u_1): u_0 picks an alias bucket, u_1 the bucket's texel
//        or its alias; for a constant colour, the direction on the sphere
// \param point_randoms Uniform (u_2, u_3): the point in the texel (phi, cos theta); unused
//        for a constant colour
vec3 sample_environment(vec2 texel_randoms, vec2 point_randoms) {
    uvec4 header = texelFetch(g_environment_texels, 0);
    if (header.z != ENVIRONMENT_MAP)
        return sample_sphere(texel_randoms);
    uint count = header.x * header.y;
    uint bucket = min(uint(texel_randoms[0] * float(count)), count - 1u);
    uvec4 alias = texelFetch(g_environment_texels, 4 + 2 * int(bucket));
    uint texel = (texel_randoms[1] < uintBitsToFloat(alias.x)) ? bucket : alias.y;
    float row = float(texel / header.x);
    float phi = ((float(texel % header.x) + point_randoms[0]) / float(header.x) - 0.5) * 2.0 * M_PI;
    float cos_top = cos(M_PI * row / float(header.y));
    float cos_bottom = cos(M_PI * (row + 1.0) / float(header.y));
    float cos_theta = cos_top + point_randoms[1] * (cos_bottom - cos_top);
    float sin_theta = sqrt(max(0.0, (1.0 - cos_theta) * (1.0 + cos_theta)));
    vec3 map_direction = vec3(sin_theta * sin(phi), cos_theta, -sin_theta * cos(phi));
    vec4 rotation = uintBitsToFloat(texelFetch(g_environment_texels, 1));
    return rotate_about_y(map_direction, rotation.y, rotation.z);
}

// Density of sample_environment() w.r.t. solid angle: the texel's probability over its solid
// angle, constant over the texel (the host stores it); 1 / (4 pi) for a constant colour.
float get_environment_density(vec3 direction) {
    if (get_environment_kind() != ENVIRONMENT_MAP)
        return 1.0 / (4.0 * M_PI);
    return uintBitsToFloat(texelFetch(g_environment_texels, 3 + 2 * int(get_environment_texel_index(direction))).w);
}

#endif
