//! The environment and the punctual lights as `glsl/environment.glsl` and
//! `glsl/punctual_lights.glsl` read them (RGBA32_UINT texel buffers), word for word.

use crate::contract::{
    ENVIRONMENT_CONSTANT, ENVIRONMENT_MAP, ENVIRONMENT_NONE, PUNCTUAL_LIGHT_DIRECTIONAL,
    PUNCTUAL_LIGHT_POINT, PUNCTUAL_LIGHT_SPOT,
};
use crate::scene::environment::{AliasTable, Environment};
use crate::scene::punctual::{PunctualKind, PunctualLight};

/// The words of `g_environment_texels`: the header, rotation, background, then per map texel
/// (radiance times strength, the sampler's density over the texel w.r.t. solid angle) and
/// (alias threshold, alias index, 0, 0).
pub fn gpu_environment_words(environment: Option<&Environment>) -> Vec<u32> {
    let f = f32::to_bits;
    let Some(environment) = environment.filter(|e| e.emits_light()) else {
        return vec![
            1,
            1,
            ENVIRONMENT_NONE,
            0,
            f(1.0),
            f(1.0),
            f(0.0),
            0,
            0,
            0,
            0,
            0,
        ];
    };
    let radians = environment.rotation_degrees.to_radians();
    let (width, height, kind) = match &environment.map {
        Some(map) => (map.width, map.height, ENVIRONMENT_MAP),
        None => (1, 1, ENVIRONMENT_CONSTANT),
    };
    let background = environment.background;
    let mut words = vec![
        width,
        height,
        kind,
        0,
        f(environment.strength),
        f(radians.cos()),
        f(radians.sin()),
        0,
        f(background.x),
        f(background.y),
        f(background.z),
        0,
    ];
    if let Some(map) = &environment.map {
        let table = AliasTable::new(map);
        words.reserve(8 * map.texels.len());
        for (i, radiance) in map.texels.iter().enumerate() {
            let scaled = *radiance * environment.strength;
            words.extend_from_slice(&[
                f(scaled.x),
                f(scaled.y),
                f(scaled.z),
                f(table.densities[i]),
            ]);
            words.extend_from_slice(&[f(table.thresholds[i]), table.aliases[i], 0, 0]);
        }
    }
    words
}

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

    #[test]
    fn a_black_environment_is_none() {
        let words = gpu_environment_words(Some(&Environment::constant(Vec3::ZERO)));
        assert_eq!(words[2], ENVIRONMENT_NONE);
        let words = gpu_environment_words(Some(&Environment::constant(Vec3::ONE)));
        assert_eq!(
            (words[2], f32::from_bits(words[8])),
            (ENVIRONMENT_CONSTANT, 1.0)
        );
    }
}
