//! Rust twins of `glsl/punctual_lights.glsl`: KHR_lights_punctual's point, spot and
//! directional lights, read from the same words the GPU reads
//! (`crate::lights::gpu_punctual::gpu_punctual_light_words`), with the same maths.

use glam::Vec3;

use crate::contract::{
    NO_HIT_T, PUNCTUAL_LIGHT_DIRECTIONAL, PUNCTUAL_LIGHT_SPOT, PUNCTUAL_LIGHT_TEXEL_COUNT,
};
use crate::cpu::texels::{fetch_float_texel, fetch_texel};

/// The words of `g_punctual_light_texels` as the twins read them.
pub struct PunctualLightTexels<'a> {
    /// RGBA32_UINT texels, four words each.
    pub words: &'a [u32],
}

impl PunctualLightTexels<'_> {
    /// Twin of `texelFetch(g_punctual_light_texels, index)`.
    fn texel(&self, index: usize) -> [u32; 4] {
        fetch_texel(self.words, index).to_array()
    }

    /// Texel `index` as `uintBitsToFloat` reads it.
    fn float_texel(&self, index: usize) -> [f32; 4] {
        fetch_float_texel(self.words, index).to_array()
    }
}

/// Twin of `punctual_light_t`: a punctual light as the integrators use it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PunctualLightT {
    /// `PUNCTUAL_LIGHT_POINT`, `_SPOT` or `_DIRECTIONAL`.
    pub kind: u32,
    /// Position (point, spot), world space.
    pub position: Vec3,
    /// Unit direction the light shines along (spot, directional), world space.
    pub direction: Vec3,
    /// Radiant intensity (point, spot) or irradiance (directional), linear RGB.
    pub intensity: Vec3,
    /// Spot cone: attenuation = clamp(cos * scale + offset, 0, 1)^2.
    pub cone_scale: f32,
    /// See `cone_scale`.
    pub cone_offset: f32,
}

/// Twin of `get_punctual_light_count`.
pub fn get_punctual_light_count(texels: &PunctualLightTexels) -> u32 {
    texels.texel(0)[0]
}

/// Twin of `get_punctual_light`.
pub fn get_punctual_light(texels: &PunctualLightTexels, index: u32) -> PunctualLightT {
    let first = 1 + PUNCTUAL_LIGHT_TEXEL_COUNT as usize * index as usize;
    let position = texels.float_texel(first);
    let xyz = |texel: [f32; 4]| Vec3::new(texel[0], texel[1], texel[2]);
    let cone = texels.float_texel(first + 3);
    PunctualLightT {
        kind: position[3].to_bits(),
        position: xyz(position),
        direction: xyz(texels.float_texel(first + 1)),
        intensity: xyz(texels.float_texel(first + 2)),
        cone_scale: cone[1],
        cone_offset: cone[2],
    }
}

/// Twin of `get_punctual_irradiance`: the irradiance that `light` gives a surface facing it
/// at `origin`, with the unit direction towards the light and the distance to it (`NO_HIT_T`
/// for directional lights), returned as (irradiance, direction, distance).
pub fn get_punctual_irradiance(light: &PunctualLightT, origin: Vec3) -> (Vec3, Vec3, f32) {
    if light.kind == PUNCTUAL_LIGHT_DIRECTIONAL {
        return (light.intensity, -light.direction, NO_HIT_T);
    }
    let to_light = light.position - origin;
    let squared_distance = to_light.dot(to_light);
    let distance = squared_distance.sqrt();
    let direction = to_light / distance;
    let mut irradiance = light.intensity / squared_distance;
    if light.kind == PUNCTUAL_LIGHT_SPOT {
        let attenuation = (light.direction.dot(-direction) * light.cone_scale + light.cone_offset)
            .clamp(0.0, 1.0);
        irradiance *= attenuation * attenuation;
    }
    (irradiance, direction, distance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::gpu_punctual::gpu_punctual_light_words;
    use crate::lights::{PunctualKind, PunctualLight};
    use glam::{Mat4, Quat};

    /// A point light of intensity 4 at (0, 0, 2); a spot at (0, 0, 2) shining down -Z with
    /// cones of 20 and 40 degrees; a sun of irradiance 3 shining down -Z.
    fn lights() -> Vec<PunctualLight> {
        let above = Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0));
        let spot = PunctualKind::Spot {
            inner_cone_angle: 20f32.to_radians(),
            outer_cone_angle: 40f32.to_radians(),
        };
        vec![
            PunctualLight::new(PunctualKind::Point, Vec3::ONE, 4.0, above).unwrap(),
            PunctualLight::new(spot, Vec3::new(1.0, 0.5, 0.25), 4.0, above).unwrap(),
            PunctualLight::new(PunctualKind::Directional, Vec3::ONE, 3.0, Mat4::IDENTITY).unwrap(),
        ]
    }

    #[test]
    fn the_twins_read_back_what_the_host_wrote() {
        let lights = lights();
        let words = gpu_punctual_light_words(&lights);
        let texels = PunctualLightTexels { words: &words };
        assert_eq!(get_punctual_light_count(&texels), 3);
        for (index, light) in lights.iter().enumerate() {
            let read = get_punctual_light(&texels, index as u32);
            assert_eq!(read.position, light.position);
            assert_eq!(read.direction, light.direction);
            assert_eq!(read.intensity, light.intensity);
            assert_eq!(
                (read.cone_scale, read.cone_offset),
                light.cone_scale_offset()
            );
        }
    }

    #[test]
    fn irradiance_follows_the_inverse_square_law_and_the_cone() {
        let lights = lights();
        let words = gpu_punctual_light_words(&lights);
        let texels = PunctualLightTexels { words: &words };
        let point = get_punctual_light(&texels, 0);
        // Distance 2 below the light: intensity / d^2 = 4 / 4.
        let (irradiance, direction, distance) = get_punctual_irradiance(&point, Vec3::ZERO);
        assert!((irradiance - Vec3::ONE).abs().max_element() < 1e-6);
        assert!((direction - Vec3::Z).length() < 1e-6 && (distance - 2.0).abs() < 1e-6);

        let spot = get_punctual_light(&texels, 1);
        // On the axis: full intensity; 30 degrees off (between the cones): the extension's
        // smooth falloff ((cos 30 - cos 40) / (cos 20 - cos 40))^2; 50 degrees off: dark.
        let on_axis = get_punctual_irradiance(&spot, Vec3::ZERO).0;
        assert!((on_axis - Vec3::new(1.0, 0.5, 0.25)).abs().max_element() < 1e-6);
        let at = |degrees: f32| {
            let offset = Quat::from_rotation_y(degrees.to_radians()) * Vec3::NEG_Z;
            Vec3::new(0.0, 0.0, 2.0) + offset
        };
        let (c20, c30, c40) = (
            20f32.to_radians().cos(),
            30f32.to_radians().cos(),
            40f32.to_radians().cos(),
        );
        let falloff = ((c30 - c40) / (c20 - c40)).powi(2);
        // At distance 1 from the light: intensity (4 in red) * falloff.
        let between = get_punctual_irradiance(&spot, at(30.0)).0;
        assert!(
            (between.x - 4.0 * falloff).abs() < 1e-5,
            "{between} vs {falloff}"
        );
        assert_eq!(get_punctual_irradiance(&spot, at(50.0)).0, Vec3::ZERO);

        let sun = get_punctual_light(&texels, 2);
        let (irradiance, direction, distance) =
            get_punctual_irradiance(&sun, Vec3::new(5.0, -3.0, 1.0));
        assert_eq!(
            (irradiance, direction, distance),
            (Vec3::splat(3.0), Vec3::Z, NO_HIT_T)
        );
    }
}
