//! The environment as `glsl/environment.glsl` reads it (an RGBA32_UINT texel buffer), word
//! for word.

use super::alias_table::AliasTable;
use super::environment::Environment;
use crate::contract::{ENVIRONMENT_CONSTANT, ENVIRONMENT_MAP, ENVIRONMENT_NONE};

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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

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
