// Textures of glTF materials: texel lookup with wrap modes, sRGB decoding, KHR_texture_transform
// and bilinear (or nearest) filtering. Host side: src/render/gpu_textures.rs packs the texels
// and slots; the Rust twins are src/cpu/textures.rs (same names, parameters and maths; change
// both together; tests/texture_twins.rs compares them).
//
// Texture coordinates follow glTF: (0, 0) is the image's top-left corner, u grows to the right,
// v downwards; texel (x, y) covers [x, x + 1] / width x [y, y + 1] / height, row y = 0 is the
// image's top row. Every value returned is linear: sRGB textures are decoded per texel, before
// filtering, as the glTF specification requires.
//
// Numerics: the arithmetic that decides which texels are read (the transform, u * width - 0.5,
// floor) is `precise`, so that no fused multiply-add makes it differ from the CPU twin, whose
// operations are rounded one by one; then GPU and CPU read the same texels with the same
// weights. Only pow() in srgb_to_linear() is approximate on GPUs.
#ifndef VKPATH_TEXTURES_GLSL
#define VKPATH_TEXTURES_GLSL

#include "shared.h"

// How a material reads one texture. Packed as TEXTURE_SLOT_TEXEL_COUNT uvec4s (host side
// GpuTextureSlot), see unpack_texture_slot().
struct texture_slot_t {
    // Index of the texture's texel (0, 0) in g_texture_texels.
    uint first_texel;
    // Size in texels, at least 1 (a slot of zeros reads texel 0 of the buffer).
    uint width;
    uint height;
    // TEXTURE_FLAG_SRGB, TEXTURE_FLAG_NEAREST and the WRAP_* modes at TEXTURE_WRAP_S_SHIFT
    // and TEXTURE_WRAP_T_SHIFT.
    uint flags;
    // The rows of KHR_texture_transform's affine map: uv' = (dot(row0, (u, v, 1)),
    // dot(row1, (u, v, 1))).
    vec3 transform_row0;
    vec3 transform_row1;
};

// Every texture's RGBA8 texels, concatenated (R8G8B8A8_UINT: each channel 0..255).
layout(set = 0, binding = BINDING_TEXTURE_TEXELS) uniform utextureBuffer g_texture_texels;

// Unpacks a texture slot from its three texels: a = (first_texel, width, height, flags),
// b.xyz and c.xyz the bits of the transform's rows (their w is unused).
texture_slot_t unpack_texture_slot(uvec4 a, uvec4 b, uvec4 c) {
    texture_slot_t slot;
    slot.first_texel = a.x;
    slot.width = a.y;
    slot.height = a.z;
    slot.flags = a.w;
    slot.transform_row0 = uintBitsToFloat(b.xyz);
    slot.transform_row1 = uintBitsToFloat(c.xyz);
    return slot;
}

// The sRGB electro-optical transfer function (IEC 61966-2-1): an sRGB-encoded value in [0, 1]
// to linear [0, 1]. Exact formula, no approximation (pow() itself is approximate on GPUs:
// Vulkan allows about 3 ulps plus the error of exp2(y * log2(x))).
float srgb_to_linear(float c) {
    return (c <= 0.04045) ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

// Applies the slot's KHR_texture_transform to texture coordinates.
vec2 transform_tex_coord(texture_slot_t slot, vec2 tex_coord) {
    precise float u = slot.transform_row0.x * tex_coord.x + slot.transform_row0.y * tex_coord.y
        + slot.transform_row0.z;
    precise float v = slot.transform_row1.x * tex_coord.x + slot.transform_row1.y * tex_coord.y
        + slot.transform_row1.z;
    return vec2(u, v);
}

// Maps an integer texel coordinate to [0, size - 1] with a wrap mode (OpenGL 4.6, table
// 8.20, which glTF's samplers follow).
// \param coordinate Any int in [-TEXTURE_COORDINATE_LIMIT, TEXTURE_COORDINATE_LIMIT].
// \param size The texture's size along this axis; values below 1 count as 1.
// \param wrap_mode WRAP_REPEAT, WRAP_CLAMP_TO_EDGE or WRAP_MIRRORED_REPEAT (others clamp).
int wrap_texel_coordinate(int coordinate, int size, uint wrap_mode) {
    size = max(size, 1);
    if (wrap_mode == WRAP_REPEAT || wrap_mode == WRAP_MIRRORED_REPEAT) {
        int period = (wrap_mode == WRAP_REPEAT) ? size : 2 * size;
        // Euclidean modulo; GLSL's % is undefined for negative operands, so negative
        // coordinates use -coordinate - 1 >= 0. One % for both signs: an integer division is
        // a scalar loop over the SIMD lanes on lavapipe, and both sides of a ?: run.
        bool negative = coordinate < 0;
        int remainder = (negative ? -coordinate - 1 : coordinate) % period;
        int wrapped = negative ? period - 1 - remainder : remainder;
        if (wrap_mode == WRAP_REPEAT)
            return wrapped;
        // (size - 1) - mirror(wrapped - size) with mirror(a) = a >= 0 ? a : -(1 + a).
        int a = wrapped - size;
        return (size - 1) - ((a >= 0) ? a : -(1 + a));
    }
    return clamp(coordinate, 0, size - 1);
}

// The value of the texel at column x, row y of the texture (both already wrapped into it,
// wrap_texel_coordinate()), as linear floats in [0, 1] (rgb decoded from sRGB when the slot
// says so; alpha always as stored).
vec4 get_wrapped_texel(texture_slot_t slot, int x, int y) {
    uint index = slot.first_texel + uint(y) * max(slot.width, 1u) + uint(x);
    // A multiplication by the rounded 1/255 is correctly rounded on every device (a division
    // only to 2.5 ulps), so that the CPU twin gets the same bits.
    vec4 value = vec4(texelFetch(g_texture_texels, int(index))) * TEXEL_UNORM_SCALE;
    if ((slot.flags & TEXTURE_FLAG_SRGB) != 0u) {
        value.r = srgb_to_linear(value.r);
        value.g = srgb_to_linear(value.g);
        value.b = srgb_to_linear(value.b);
    }
    return value;
}

// The wrap mode of a slot along s (x) or t (y): WRAP_*.
uint get_wrap_s(texture_slot_t slot) {
    return (slot.flags >> TEXTURE_WRAP_S_SHIFT) & TEXTURE_WRAP_MASK;
}
uint get_wrap_t(texture_slot_t slot) {
    return (slot.flags >> TEXTURE_WRAP_T_SHIFT) & TEXTURE_WRAP_MASK;
}

// The value of one texel, wrapped with the slot's wrap modes, as linear floats in [0, 1]
// (get_wrapped_texel()).
vec4 get_texel(texture_slot_t slot, ivec2 texel) {
    int x = wrap_texel_coordinate(texel.x, int(slot.width), get_wrap_s(slot));
    int y = wrap_texel_coordinate(texel.y, int(slot.height), get_wrap_t(slot));
    return get_wrapped_texel(slot, x, y);
}

// A texel coordinate that int() can convert: NaN becomes 0, anything else is clamped to
// +-TEXTURE_COORDINATE_LIMIT (int() of a float out of range is undefined in GLSL).
float limit_texel_coordinate(float x) {
    return isnan(x) ? 0.0 : clamp(x, -TEXTURE_COORDINATE_LIMIT, TEXTURE_COORDINATE_LIMIT);
}

// Samples a texture at texture coordinates (before the slot's transform), linear RGBA.
// Bilinear: the four texels around (u * width - 0.5, v * height - 0.5), weighted by the
// fractional parts, each wrapped and decoded to linear before the weighting; at a texel's
// centre exactly that texel's value. Nearest (TEXTURE_FLAG_NEAREST): texel
// (floor(u * width), floor(v * height)), which is the same sum with an offset and weights of
// 0 (1 * texel + 0 * neighbour is the texel's value exactly), so one path serves both: on
// lavapipe both sides of a branch run, and a separate nearest lookup cost a fifth texel.
// Coordinates of any size read a defined texel: NaN counts as texel coordinate 0 (texel
// (0, 0)'s value where both are NaN), infinities and huge values as
// +-TEXTURE_COORDINATE_LIMIT.
vec4 sample_texture(texture_slot_t slot, vec2 tex_coord) {
    vec2 uv = transform_tex_coord(slot, tex_coord);
    vec2 size = vec2(float(max(slot.width, 1u)), float(max(slot.height, 1u)));
    bool nearest = (slot.flags & TEXTURE_FLAG_NEAREST) != 0u;
    float offset = nearest ? 0.0 : 0.5;
    precise float x = limit_texel_coordinate(uv.x * size.x - offset);
    precise float y = limit_texel_coordinate(uv.y * size.y - offset);
    precise float x0 = floor(x);
    precise float y0 = floor(y);
    // The weights of the texels at x0 + 1 and y0 + 1, in [0, 1).
    precise float weight_x = nearest ? 0.0 : x - x0;
    precise float weight_y = nearest ? 0.0 : y - y0;
    // Each column and row wrapped once, not once per texel
    int left = wrap_texel_coordinate(int(x0), int(slot.width), get_wrap_s(slot));
    int right = wrap_texel_coordinate(int(x0) + 1, int(slot.width), get_wrap_s(slot));
    int top_row = wrap_texel_coordinate(int(y0), int(slot.height), get_wrap_t(slot));
    int bottom_row = wrap_texel_coordinate(int(y0) + 1, int(slot.height), get_wrap_t(slot));
    vec4 top_left = get_wrapped_texel(slot, left, top_row);
    vec4 top_right = get_wrapped_texel(slot, right, top_row);
    vec4 bottom_left = get_wrapped_texel(slot, left, bottom_row);
    vec4 bottom_right = get_wrapped_texel(slot, right, bottom_row);
    precise vec4 top = (1.0 - weight_x) * top_left + weight_x * top_right;
    precise vec4 bottom = (1.0 - weight_x) * bottom_left + weight_x * bottom_right;
    precise vec4 value = (1.0 - weight_y) * top + weight_y * bottom;
    return value;
}

#endif
