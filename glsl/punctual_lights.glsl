// KHR_lights_punctual's point, spot and directional lights (kernels built with
// USE_MATERIALS). Units: a point or spot light's intensity is its radiant intensity in the
// units in which emissive surfaces give radiance, so a surface facing it at distance d
// receives irradiance intensity / d^2; a directional light's intensity is the irradiance it
// gives a surface facing it; `range` is ignored. They are delta lights: only light samples
// (nee, mis) can find them. Rust twins: src/cpu/punctual_lights.rs.
#ifndef VKPATH_PUNCTUAL_LIGHTS_GLSL
#define VKPATH_PUNCTUAL_LIGHTS_GLSL

#include "shared.h"

// Texel 0: uvec4(count, 0, 0, 0); light i at texel 1 + PUNCTUAL_LIGHT_TEXEL_COUNT i:
// (position xyz, PUNCTUAL_LIGHT_* bits), (the direction it shines xyz, 0),
// (intensity rgb, 0), (0, cone scale, cone offset, 0). gpu_punctual_light_words() of
// src/lights/gpu_punctual.rs on the host.
layout(set = 0, binding = BINDING_PUNCTUAL_LIGHTS) uniform utextureBuffer g_punctual_light_texels;

// A punctual light as the integrators use it.
struct punctual_light_t {
    // PUNCTUAL_LIGHT_POINT, _SPOT or _DIRECTIONAL
    uint kind;
    // Position (point, spot), world space
    vec3 position;
    // Unit direction the light shines along (spot, directional), world space
    vec3 direction;
    // Radiant intensity (point, spot) or irradiance (directional), linear RGB
    vec3 intensity;
    // Spot cone: attenuation = clamp(cos * scale + offset, 0, 1)^2 (the extension's formula)
    float cone_scale;
    float cone_offset;
};

uint get_punctual_light_count() {
    return texelFetch(g_punctual_light_texels, 0).x;
}

punctual_light_t get_punctual_light(uint index) {
    int first = 1 + PUNCTUAL_LIGHT_TEXEL_COUNT * int(index);
    vec4 position = uintBitsToFloat(texelFetch(g_punctual_light_texels, first));
    punctual_light_t light;
    light.kind = floatBitsToUint(position.w);
    light.position = position.xyz;
    light.direction = uintBitsToFloat(texelFetch(g_punctual_light_texels, first + 1).xyz);
    light.intensity = uintBitsToFloat(texelFetch(g_punctual_light_texels, first + 2).rgb);
    vec4 cone = uintBitsToFloat(texelFetch(g_punctual_light_texels, first + 3));
    light.cone_scale = cone.y;
    light.cone_offset = cone.z;
    return light;
}

// Irradiance that a punctual light gives a surface facing it at `origin`, the unit direction
// towards the light and the distance to it (NO_HIT_T for directional lights).
vec3 get_punctual_irradiance(punctual_light_t light, vec3 origin, out vec3 out_direction, out float out_distance) {
    if (light.kind == PUNCTUAL_LIGHT_DIRECTIONAL) {
        out_direction = -light.direction;
        out_distance = NO_HIT_T;
        return light.intensity;
    }
    vec3 to_light = light.position - origin;
    float squared_distance = dot(to_light, to_light);
    out_distance = sqrt(squared_distance);
    out_direction = to_light / out_distance;
    vec3 irradiance = light.intensity / squared_distance;
    if (light.kind == PUNCTUAL_LIGHT_SPOT) {
        float attenuation = clamp(dot(light.direction, -out_direction) * light.cone_scale + light.cone_offset, 0.0, 1.0);
        irradiance *= attenuation * attenuation;
    }
    return irradiance;
}

#endif
