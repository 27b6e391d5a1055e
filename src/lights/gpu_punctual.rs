//! KHR_lights_punctual's lights as `glsl/punctual_lights.glsl` reads them (an RGBA32_UINT
//! texel buffer), word for word; `crate::cpu::punctual_lights` reads the same words.

use super::punctual::{PunctualKind, PunctualLight};
use crate::contract::{PUNCTUAL_LIGHT_DIRECTIONAL, PUNCTUAL_LIGHT_POINT, PUNCTUAL_LIGHT_SPOT};

/// The words of `g_punctual_light_texels`: the count, then per light (position, kind),
/// (direction, 0), (intensity, 0), (0, cone scale, cone offset, 0).
pub fn gpu_punctual_light_words(lights: &[PunctualLight]) -> Vec<u32> {
    let f = f32::to_bits;
    let mut words = vec![lights.len() as u32, 0, 0, 0];
    for light in lights {
        let kind = match light.kind {
            PunctualKind::Point => PUNCTUAL_LIGHT_POINT,
            PunctualKind::Spot { .. } => PUNCTUAL_LIGHT_SPOT,
            PunctualKind::Directional => PUNCTUAL_LIGHT_DIRECTIONAL,
        };
        let (scale, offset) = light.cone_scale_offset();
        let (p, d, i) = (light.position, light.direction, light.intensity);
        words.extend_from_slice(&[f(p.x), f(p.y), f(p.z), kind]);
        words.extend_from_slice(&[f(d.x), f(d.y), f(d.z), 0]);
        words.extend_from_slice(&[f(i.x), f(i.y), f(i.z), 0]);
        words.extend_from_slice(&[0, f(scale), f(offset), 0]);
    }
    words
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contract::PUNCTUAL_LIGHT_TEXEL_COUNT;
    use glam::{Mat4, Vec3};

    #[test]
    fn punctual_lights_fill_their_texels() {
        let light = PunctualLight::new(
            PunctualKind::Point,
            Vec3::ONE,
            2.0,
            Mat4::from_translation(Vec3::Y),
        )
        .unwrap();
        let words = gpu_punctual_light_words(&[light, light]);
        assert_eq!(words.len(), 4 + 2 * 4 * PUNCTUAL_LIGHT_TEXEL_COUNT as usize);
        assert_eq!(words[0], 2);
        assert_eq!(f32::from_bits(words[5]), 1.0);
        assert_eq!(words[7], PUNCTUAL_LIGHT_POINT);
        assert_eq!(f32::from_bits(words[12]), 2.0);
    }
}
