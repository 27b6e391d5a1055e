//! RGBA32_UINT texel buffers as the twins read them: `texelFetch` of a `utextureBuffer`
//! (four words a texel) and `uintBitsToFloat` of the result.

use glam::{UVec4, Vec4};

/// Twin of `texelFetch(buffer, index)` on an RGBA32_UINT texel buffer of `words`.
pub fn fetch_texel(words: &[u32], index: usize) -> UVec4 {
    UVec4::from_slice(&words[4 * index..4 * index + 4])
}

/// Twin of `uintBitsToFloat` of a texel.
pub fn uint_bits_to_float(texel: UVec4) -> Vec4 {
    Vec4::from_array(texel.to_array().map(f32::from_bits))
}

/// Twin of `uintBitsToFloat(texelFetch(buffer, index))`.
pub fn fetch_float_texel(words: &[u32], index: usize) -> Vec4 {
    uint_bits_to_float(fetch_texel(words, index))
}
