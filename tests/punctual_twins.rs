//! The punctual lights of `glsl/punctual_lights.glsl` on the GPU
//! (`glsl/probe_punctual_lights.comp`) against their Rust twins
//! (`vkpath::cpu::punctual_lights`), reading the same words (`gpu_punctual_light_words`):
//! point lights, spots with wide, narrow and nearly equal cones, pointing along and across
//! the axes, and tilted directional lights, each at fixed origins (a grid and points of a
//! fixed seed around the lights, inside, between and outside the spots' cones). The lights
//! read back must match bit for bit, the irradiance, direction and distance within the
//! bounds justified below; the test prints its measured errors and asserts that the
//! validation layer stayed silent.

use crate::common;

use glam::{EulerRot, Mat4, Quat, Vec3};
use vkpath::contract::NO_HIT_T;
use vkpath::cpu::punctual_lights::{
    get_punctual_irradiance, get_punctual_light, get_punctual_light_count, PunctualLightTexels,
};
use vkpath::lights::gpu_punctual::gpu_punctual_light_words;
use vkpath::lights::{PunctualKind, PunctualLight};
use vkpath::probe::inputs::InputRng;
use vkpath::probe::punctual_probe::{PunctualProbeInput, PunctualProbeRunner};

/// One ulp of a float in [1, 2).
const ULP: f32 = f32::EPSILON;

/// Largest relative error of the unattenuated irradiance intensity / d^2, the distance and
/// each component of the direction (relative to 1, it is a unit vector): 16 ulps. The GPU
/// computes d^2 as a dot product (which it may fuse into multiply-adds: about 2 ulps), its
/// sqrt (Vulkan: as 1 / inversesqrt, about 3 ulps) and two divisions (2.5 ulps each), so
/// each result carries at most about 10 ulps; 16 leaves a margin.
const RELATIVE_TOLERANCE: f32 = 16.0 * ULP;

/// A spot's attenuation is clamp(cos * scale + offset, 0, 1)^2: the cosine carries the
/// direction's error (above), which the cone scale magnifies, and the square doubles it;
/// so a spot's irradiance may differ by (16 ulps) * (1 + 2 * 2 * scale) of the unattenuated
/// irradiance. With the scales below (up to 1000, the extension's floor of 0.001 on the
/// difference of cosines) that is up to 7e-3 of it on the cone's edge; far from the edges
/// the attenuation is exactly 0 or 1 on both sides.
fn irradiance_tolerance(unattenuated: f32, cone_scale: f32) -> f32 {
    RELATIVE_TOLERANCE * unattenuated * (1.0 + 4.0 * cone_scale.abs())
}

/// The lights: a point light, spots (wide, narrow, nearly equal cones, pointing along and
/// across the axes, coloured), and directional lights tilted off the axes.
fn test_lights() -> Vec<PunctualLight> {
    let at = |position: Vec3, yaw: f32, pitch: f32| {
        Mat4::from_rotation_translation(
            Quat::from_euler(EulerRot::YXZ, yaw.to_radians(), pitch.to_radians(), 0.0),
            position,
        )
    };
    let spot = |inner: f32, outer: f32| PunctualKind::Spot {
        inner_cone_angle: inner.to_radians(),
        outer_cone_angle: outer.to_radians(),
    };
    let light = |kind, color, intensity, transform| {
        PunctualLight::new(kind, color, intensity, transform).expect("a valid light")
    };
    vec![
        light(
            PunctualKind::Point,
            Vec3::ONE,
            10.0,
            at(Vec3::new(0.0, 3.0, 0.0), 0.0, 0.0),
        ),
        light(
            PunctualKind::Point,
            Vec3::new(0.2, 0.5, 1.0),
            0.75,
            at(Vec3::new(-1.5, 0.25, 2.0), 30.0, 10.0),
        ),
        light(
            spot(0.0, 45.0),
            Vec3::ONE,
            20.0,
            at(Vec3::new(0.0, 3.0, 0.0), 0.0, -90.0),
        ),
        light(
            spot(15.0, 25.0),
            Vec3::new(1.0, 0.8, 0.5),
            5.0,
            at(Vec3::new(2.0, 1.0, -1.0), 60.0, -30.0),
        ),
        light(
            spot(29.95, 30.0),
            Vec3::ONE,
            3.0,
            at(Vec3::new(-2.0, 2.0, 2.0), -135.0, -45.0),
        ),
        light(
            PunctualKind::Directional,
            Vec3::ONE,
            3.0,
            at(Vec3::ZERO, 20.0, -70.0),
        ),
        light(
            PunctualKind::Directional,
            Vec3::new(1.0, 0.9, 0.7),
            1.5,
            at(Vec3::ZERO, -100.0, -15.0),
        ),
    ]
}

/// Fixed origins: a 5 x 5 x 5 grid over [-4, 4]^3 and 200 points of a fixed seed in
/// [-5, 5]^3, without those within 0.05 of a light (where 1 / d^2 is far from any surface
/// the integrators shade).
fn test_origins(lights: &[PunctualLight]) -> Vec<Vec3> {
    let mut origins: Vec<Vec3> = (0..125)
        .map(|i| Vec3::new((i % 5) as f32, (i / 5 % 5) as f32, (i / 25) as f32) * 2.0 - 4.0)
        .collect();
    let mut rng = InputRng::new(18);
    origins.extend((0..200).map(|_| rng.in_box(Vec3::splat(-5.0), Vec3::splat(5.0))));
    origins.retain(|origin| {
        lights
            .iter()
            .all(|l| l.kind == PunctualKind::Directional || l.position.distance(*origin) > 0.05)
    });
    origins
}

#[test]
fn punctual_lights_match_their_twins_on_the_gpu() {
    let lights = test_lights();
    let words = gpu_punctual_light_words(&lights);
    let texels = PunctualLightTexels { words: &words };
    let origins = test_origins(&lights);
    let inputs: Vec<PunctualProbeInput> = (0..lights.len() as u32)
        .flat_map(|light| {
            origins
                .iter()
                .map(move |&origin| PunctualProbeInput::new(light, origin))
        })
        .collect();
    let context = common::validated_context();
    let runner = PunctualProbeRunner::new(&context, &words).expect("the probe runs");
    let outputs = runner.run(&inputs).expect("the probe runs");
    assert_eq!(outputs.len(), inputs.len());

    let (mut worst_irradiance, mut worst_direction, mut worst_distance) = (0f32, 0f32, 0f32);
    let (mut lit, mut dark, mut between_cones) = (0, 0, 0);
    for (input, output) in inputs.iter().zip(&outputs) {
        let light = get_punctual_light(&texels, input.light_index[0]);
        // The light as read: the same words, so bit for bit.
        assert_eq!(
            output.kind_count,
            [light.kind, get_punctual_light_count(&texels), 0, 0]
        );
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        let gpu = |v: &[f32; 4]| Vec3::from_slice(&v[..3]);
        assert_eq!(bits(gpu(&output.position)), bits(light.position));
        assert_eq!(bits(gpu(&output.light_direction)), bits(light.direction));
        assert_eq!(bits(gpu(&output.intensity)), bits(light.intensity));
        assert_eq!(
            [output.cone[0].to_bits(), output.cone[1].to_bits()],
            [light.cone_scale.to_bits(), light.cone_offset.to_bits()]
        );

        let (irradiance, direction, distance) = get_punctual_irradiance(&light, input.origin());
        let (gpu_irradiance, gpu_direction, gpu_distance) = output.irradiance();
        let context = format!("light {} at {}", input.light_index[0], input.origin());
        if distance == NO_HIT_T {
            // Directional: the intensity and the negated direction, no arithmetic.
            assert_eq!(
                (bits(gpu_irradiance), bits(gpu_direction), gpu_distance),
                (bits(irradiance), bits(direction), NO_HIT_T),
                "{context}"
            );
            continue;
        }
        let unattenuated = light.intensity.max_element() / (distance * distance);
        let irradiance_error = (gpu_irradiance - irradiance).abs().max_element();
        let tolerance = irradiance_tolerance(unattenuated, light.cone_scale);
        assert!(
            irradiance_error <= tolerance,
            "{context}: irradiance {gpu_irradiance} on the GPU, {irradiance} on the CPU"
        );
        let direction_error = (gpu_direction - direction).abs().max_element();
        assert!(
            direction_error <= RELATIVE_TOLERANCE,
            "{context}: direction {gpu_direction} on the GPU, {direction} on the CPU"
        );
        let distance_error = (gpu_distance - distance).abs() / distance;
        assert!(
            distance_error <= RELATIVE_TOLERANCE,
            "{context}: distance {gpu_distance} on the GPU, {distance} on the CPU"
        );
        worst_irradiance = worst_irradiance.max(irradiance_error / unattenuated);
        worst_direction = worst_direction.max(direction_error);
        worst_distance = worst_distance.max(distance_error);
        lit += usize::from(irradiance.max_element() > 0.0);
        dark += usize::from(irradiance.max_element() == 0.0);
        let fraction = irradiance.max_element() / unattenuated;
        between_cones += usize::from(fraction > 0.0 && fraction < 0.999);
    }
    // The inputs reach every regime: lit points, points outside the spots' cones, and points
    // on their falloff.
    assert!(
        lit >= 2 * origins.len() && dark >= 10 && between_cones >= 10,
        "{lit} lit, {dark} dark, {between_cones} in a cone's falloff"
    );
    println!(
        "{} inputs, {lit} lit, {dark} dark, {between_cones} in a cone's falloff; largest GPU-CPU differences: \
         irradiance {worst_irradiance:.2e} of intensity / d^2, direction {worst_direction:.2e}, \
         distance {worst_distance:.2e} relative",
        inputs.len()
    );
    common::assert_validation_silent(&context);
}
