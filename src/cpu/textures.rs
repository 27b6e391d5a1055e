//! Rust twins of `glsl/textures.glsl`: texel lookup with wrap modes, sRGB decoding,
//! KHR_texture_transform and bilinear (or nearest) filtering. Each function has the name,
//! parameters and maths of its GLSL twin, operation for operation; the texel buffer
//! `g_texture_texels` is the `texels` parameter here (`TextureAtlas::texels`). The shader
//! marks the arithmetic that chooses texels `precise` and every operation here is rounded on
//! its own, so both read the same texels with the same weights; only `powf` in
//! `srgb_to_linear` differs from a GPU's `pow` by a few ulps. Change both together.

use glam::{IVec2, UVec4, Vec2, Vec3, Vec4};

use crate::contract::{
    TEXEL_UNORM_SCALE, TEXTURE_COORDINATE_LIMIT, TEXTURE_FLAG_NEAREST, TEXTURE_FLAG_SRGB,
    TEXTURE_WRAP_MASK, TEXTURE_WRAP_S_SHIFT, TEXTURE_WRAP_T_SHIFT, WRAP_MIRRORED_REPEAT,
    WRAP_REPEAT,
};

/// GLSL `texture_slot_t`: how a material reads one texture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureSlot {
    /// Index of the texture's texel (0, 0) in the texel buffer.
    pub first_texel: u32,
    /// Width in texels, at least 1 (0 counts as 1).
    pub width: u32,
    /// Height in texels, at least 1 (0 counts as 1).
    pub height: u32,
    /// `TEXTURE_FLAG_SRGB`, `TEXTURE_FLAG_NEAREST` and the wrap modes.
    pub flags: u32,
    /// Row 0 of the texture transform: u' = row 0 · (u, v, 1).
    pub transform_row0: Vec3,
    /// Row 1 of the texture transform: v' = row 1 · (u, v, 1).
    pub transform_row1: Vec3,
}

/// Twin of GLSL `unpack_texture_slot`: a slot from its three packed texels
/// (`GpuTextureSlot::to_texels`).
pub fn unpack_texture_slot(a: UVec4, b: UVec4, c: UVec4) -> TextureSlot {
    let floats = |t: UVec4| {
        Vec3::new(
            f32::from_bits(t.x),
            f32::from_bits(t.y),
            f32::from_bits(t.z),
        )
    };
    TextureSlot {
        first_texel: a.x,
        width: a.y,
        height: a.z,
        flags: a.w,
        transform_row0: floats(b),
        transform_row1: floats(c),
    }
}

/// Twin of GLSL `srgb_to_linear`: the sRGB electro-optical transfer function (IEC
/// 61966-2-1), an sRGB-encoded value in [0, 1] to linear [0, 1].
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Twin of GLSL `transform_tex_coord`: the slot's KHR_texture_transform applied to texture
/// coordinates (each product and sum rounded on its own, as the shader's `precise`).
pub fn transform_tex_coord(slot: &TextureSlot, tex_coord: Vec2) -> Vec2 {
    let (row0, row1) = (slot.transform_row0, slot.transform_row1);
    let u = row0.x * tex_coord.x + row0.y * tex_coord.y + row0.z;
    let v = row1.x * tex_coord.x + row1.y * tex_coord.y + row1.z;
    Vec2::new(u, v)
}

/// Twin of GLSL `wrap_texel_coordinate`: an integer texel coordinate mapped to
/// [0, size − 1] by a wrap mode (OpenGL 4.6, table 8.20).
/// \param coordinate Any i32 in ±`TEXTURE_COORDINATE_LIMIT`.
/// \param size The size along this axis; below 1 counts as 1.
/// \param wrap_mode `WRAP_REPEAT`, `WRAP_CLAMP_TO_EDGE` or `WRAP_MIRRORED_REPEAT` (others
///        clamp).
pub fn wrap_texel_coordinate(coordinate: i32, size: i32, wrap_mode: u32) -> i32 {
    let size = size.max(1);
    if wrap_mode == WRAP_REPEAT || wrap_mode == WRAP_MIRRORED_REPEAT {
        let period = if wrap_mode == WRAP_REPEAT {
            size
        } else {
            2 * size
        };
        // Euclidean modulo, written as the shader must (GLSL's % of negatives is undefined),
        // with one % for both signs.
        let negative = coordinate < 0;
        let remainder = if negative {
            -coordinate - 1
        } else {
            coordinate
        } % period;
        let wrapped = if negative {
            period - 1 - remainder
        } else {
            remainder
        };
        if wrap_mode == WRAP_REPEAT {
            return wrapped;
        }
        // (size - 1) - mirror(wrapped - size) with mirror(a) = a >= 0 ? a : -(1 + a).
        let a = wrapped - size;
        return (size - 1) - if a >= 0 { a } else { -(1 + a) };
    }
    coordinate.max(0).min(size - 1)
}

/// Twin of GLSL `get_wrapped_texel`: the texel at column `x`, row `y` (both already wrapped
/// into the texture), as linear floats in [0, 1] (rgb decoded from sRGB when the slot says
/// so, alpha as stored). An index past `texels` (a slot that does not fit the buffer) reads
/// zeros, as a robust texel fetch does.
pub fn get_wrapped_texel(texels: &[[u8; 4]], slot: &TextureSlot, x: i32, y: i32) -> Vec4 {
    let index = slot
        .first_texel
        .wrapping_add((y as u32).wrapping_mul(slot.width.max(1)))
        .wrapping_add(x as u32);
    let raw = texels.get(index as usize).copied().unwrap_or([0; 4]);
    let mut value = Vec4::from_array(raw.map(f32::from)) * TEXEL_UNORM_SCALE;
    if slot.flags & TEXTURE_FLAG_SRGB != 0 {
        value.x = srgb_to_linear(value.x);
        value.y = srgb_to_linear(value.y);
        value.z = srgb_to_linear(value.z);
    }
    value
}

/// Twin of GLSL `get_wrap_s`: the slot's wrap mode along s (x), `WRAP_*`.
pub fn get_wrap_s(slot: &TextureSlot) -> u32 {
    (slot.flags >> TEXTURE_WRAP_S_SHIFT) & TEXTURE_WRAP_MASK
}

/// Twin of GLSL `get_wrap_t`: the slot's wrap mode along t (y), `WRAP_*`.
pub fn get_wrap_t(slot: &TextureSlot) -> u32 {
    (slot.flags >> TEXTURE_WRAP_T_SHIFT) & TEXTURE_WRAP_MASK
}

/// Twin of GLSL `get_texel`: one texel, wrapped with the slot's wrap modes
/// (`get_wrapped_texel`).
pub fn get_texel(texels: &[[u8; 4]], slot: &TextureSlot, texel: IVec2) -> Vec4 {
    let x = wrap_texel_coordinate(texel.x, slot.width as i32, get_wrap_s(slot));
    let y = wrap_texel_coordinate(texel.y, slot.height as i32, get_wrap_t(slot));
    get_wrapped_texel(texels, slot, x, y)
}

/// Twin of GLSL `limit_texel_coordinate`: NaN becomes 0, anything else is clamped to
/// ±`TEXTURE_COORDINATE_LIMIT`, so that the conversion to i32 is exact.
pub fn limit_texel_coordinate(x: f32) -> f32 {
    if x.is_nan() {
        0.0
    } else {
        // GLSL clamp(): min(max(x, lo), hi), the same for any x but NaN.
        x.clamp(-TEXTURE_COORDINATE_LIMIT, TEXTURE_COORDINATE_LIMIT)
    }
}

/// Twin of GLSL `sample_texture`: the texture at texture coordinates (before the slot's
/// transform), linear RGBA; bilinear over the four texels around (u · width − 0.5,
/// v · height − 0.5), each decoded before the weighting, or the nearest texel
/// (floor(u · width), floor(v · height)) with `TEXTURE_FLAG_NEAREST`: the same sum with an
/// offset and weights of 0. NaN coordinates count as texel coordinate 0, infinite and huge
/// ones as ±`TEXTURE_COORDINATE_LIMIT`.
pub fn sample_texture(texels: &[[u8; 4]], slot: &TextureSlot, tex_coord: Vec2) -> Vec4 {
    let uv = transform_tex_coord(slot, tex_coord);
    let size = Vec2::new(slot.width.max(1) as f32, slot.height.max(1) as f32);
    let nearest = slot.flags & TEXTURE_FLAG_NEAREST != 0;
    let offset = if nearest { 0.0 } else { 0.5 };
    let x = limit_texel_coordinate(uv.x * size.x - offset);
    let y = limit_texel_coordinate(uv.y * size.y - offset);
    let (x0, y0) = (x.floor(), y.floor());
    // The weights of the texels at x0 + 1 and y0 + 1, in [0, 1).
    let (weight_x, weight_y) = if nearest {
        (0.0, 0.0)
    } else {
        (x - x0, y - y0)
    };
    let (width, height) = (slot.width as i32, slot.height as i32);
    let left = wrap_texel_coordinate(x0 as i32, width, get_wrap_s(slot));
    let right = wrap_texel_coordinate(x0 as i32 + 1, width, get_wrap_s(slot));
    let top_row = wrap_texel_coordinate(y0 as i32, height, get_wrap_t(slot));
    let bottom_row = wrap_texel_coordinate(y0 as i32 + 1, height, get_wrap_t(slot));
    let top_left = get_wrapped_texel(texels, slot, left, top_row);
    let top_right = get_wrapped_texel(texels, slot, right, top_row);
    let bottom_left = get_wrapped_texel(texels, slot, left, bottom_row);
    let bottom_right = get_wrapped_texel(texels, slot, right, bottom_row);
    let top = (1.0 - weight_x) * top_left + weight_x * top_right;
    let bottom = (1.0 - weight_x) * bottom_left + weight_x * bottom_right;
    (1.0 - weight_y) * top + weight_y * bottom
}

#[cfg(test)]
#[path = "textures_tests.rs"]
mod tests;
