//! Rust twins of `glsl/exercise_samples.comp`: the fixed view of the unit sphere on which the
//! sample display draws its dots, and the sequence of sample directions it draws. Same
//! names and maths as the shader, so that a test can predict where every dot lands.

use bytemuck::{Pod, Zeroable};
use glam::{UVec2, Vec2, Vec3};

use crate::contract::{
    EXERCISE_SAMPLER_HEMISPHERE, EXERCISE_SAMPLER_SPHERE, EXERCISE_SAMPLER_SPHERICAL_COORDINATES,
    EXERCISE_SAMPLE_COUNT, SAMPLE_VIEW_ELEVATION_COS, SAMPLE_VIEW_ELEVATION_SIN,
};
use crate::cpu::workshop::{
    get_random_numbers, sample_hemisphere, sample_sphere, sample_sphere_spherical_coordinates,
};

/// The image plane's right vector (world space, unit length), twin of GLSL
/// `SAMPLE_VIEW_RIGHT`.
pub const SAMPLE_VIEW_RIGHT: Vec3 = Vec3::new(1.0, 0.0, 0.0);
/// The image plane's up vector, (0, sin 30°, cos 30°): the camera looks from 30° above the
/// equator and +z points up in the image. Twin of GLSL `SAMPLE_VIEW_UP`.
pub const SAMPLE_VIEW_UP: Vec3 =
    Vec3::new(0.0, SAMPLE_VIEW_ELEVATION_SIN, SAMPLE_VIEW_ELEVATION_COS);
/// Unit direction from the sphere's centre to the viewer, cross(right, up) =
/// (0, -cos 30°, sin 30°). Twin of GLSL `SAMPLE_VIEW_TOWARD_VIEWER`.
pub const SAMPLE_VIEW_TOWARD_VIEWER: Vec3 =
    Vec3::new(0.0, -SAMPLE_VIEW_ELEVATION_COS, SAMPLE_VIEW_ELEVATION_SIN);
/// Half the image height in sphere radii (a 15% margin around the sphere), shared with GLSL
/// (`glsl/shared.h`).
pub use crate::contract::SAMPLE_VIEW_HALF_HEIGHT;

/// `exercise_push_constants` of `glsl/exercise_samples.comp` (16 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct SampleDisplayPushConstants {
    /// Image width and height in pixels, `EXERCISE_SAMPLER_*`, seed of the sample sequence.
    pub resolution_sampler_seed: [u32; 4],
}

/// The samplers the display can show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExerciseSampler {
    /// Exercise 4: `sample_sphere`, uniform on the sphere.
    Sphere,
    /// Exercise 5: `sample_hemisphere` around the normal +z.
    Hemisphere,
    /// The slides' naive `sample_sphere_spherical_coordinates`, crowded at the poles.
    SphericalCoordinates,
}

impl ExerciseSampler {
    /// The `EXERCISE_SAMPLER_*` value of `glsl/shared.h`.
    pub fn contract_value(self) -> u32 {
        match self {
            ExerciseSampler::Sphere => EXERCISE_SAMPLER_SPHERE,
            ExerciseSampler::Hemisphere => EXERCISE_SAMPLER_HEMISPHERE,
            ExerciseSampler::SphericalCoordinates => EXERCISE_SAMPLER_SPHERICAL_COORDINATES,
        }
    }
}

/// The point of the view's image plane that a pixel centre shows, in sphere radii (x right,
/// y up, the sphere's centre at 0), twin of GLSL `get_sample_view_point`.
/// \param pixel Pixel index, counted from the bottom-left
/// \param resolution Image size in pixels
pub fn get_sample_view_point(pixel: UVec2, resolution: UVec2) -> Vec2 {
    let centered = (pixel.as_vec2() + 0.5) - 0.5 * resolution.as_vec2();
    centered * (2.0 * SAMPLE_VIEW_HALF_HEIGHT / resolution.y as f32)
}

/// Where a point of the view's image plane lies in the image: continuous texel coordinates
/// (x right, y down from the top edge, pixel centres at +0.5), the inverse of
/// `get_sample_view_point`.
pub fn sample_view_point_to_texel(view_point: Vec2, resolution: UVec2) -> Vec2 {
    let from_bottom = view_point / (2.0 * SAMPLE_VIEW_HALF_HEIGHT / resolution.y as f32)
        + 0.5 * resolution.as_vec2();
    Vec2::new(from_bottom.x, resolution.y as f32 - from_bottom.y)
}

/// Where a direction (a point of the unit sphere) appears in the view, in sphere radii:
/// its orthographic projection onto the image plane, twin of GLSL `project_to_sample_view`.
pub fn project_to_sample_view(direction: Vec3) -> Vec2 {
    Vec2::new(
        direction.dot(SAMPLE_VIEW_RIGHT),
        direction.dot(SAMPLE_VIEW_UP),
    )
}

/// The random state from which the display draws its samples, twin of GLSL
/// `get_sample_display_seed`: (0, 0) for seed 0, otherwise the seed spread over both words
/// by `get_sample_seed`'s odd multipliers.
pub fn get_sample_display_seed(user_seed: u32) -> UVec2 {
    UVec2::new(2654435769, 2246822507).wrapping_mul(UVec2::splat(user_seed))
}

/// The displayed sampler by its `EXERCISE_SAMPLER_*` value, twin of GLSL
/// `get_exercise_sample_direction` (unknown values fall back to `sample_sphere`, as there).
/// \param sampler `EXERCISE_SAMPLER_*`
/// \param random_numbers Uniform (u_0, u_1) in [0, 1)^2
/// \return A unit vector
pub fn get_exercise_sample_direction(sampler: u32, random_numbers: Vec2) -> Vec3 {
    if sampler == EXERCISE_SAMPLER_HEMISPHERE {
        return sample_hemisphere(random_numbers, Vec3::Z);
    }
    if sampler == EXERCISE_SAMPLER_SPHERICAL_COORDINATES {
        return sample_sphere_spherical_coordinates(random_numbers);
    }
    sample_sphere(random_numbers)
}

/// The `EXERCISE_SAMPLE_COUNT` directions the display draws for a sampler and seed, in the
/// shader's order.
pub fn sample_display_directions(sampler: ExerciseSampler, user_seed: u32) -> Vec<Vec3> {
    let mut seed = get_sample_display_seed(user_seed);
    (0..EXERCISE_SAMPLE_COUNT)
        .map(|_| {
            get_exercise_sample_direction(sampler.contract_value(), get_random_numbers(&mut seed))
        })
        .collect()
}

/// Radius of a dot in pixels for an image `height` pixels high, as the shader draws it:
/// max(1.5, height / 128), i.e. 2 pixels at the default 256.
pub fn dot_radius_pixels(height: u32) -> f32 {
    (height as f32 / 128.0).max(1.5)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn push_constants_match_the_shader_block() {
        // uniform exercise_push_constants { uvec4 g_resolution_sampler_seed; }
        assert_eq!(size_of::<SampleDisplayPushConstants>(), 16);
        assert_eq!(
            offset_of!(SampleDisplayPushConstants, resolution_sampler_seed),
            0
        );
    }

    #[test]
    fn view_is_orthonormal_and_right_handed() {
        // 1e-6: the literals are f32 roundings of sin/cos 30°, a few 1e-8 off.
        assert!((SAMPLE_VIEW_UP.length() - 1.0).abs() < 1e-6);
        assert!(SAMPLE_VIEW_RIGHT.dot(SAMPLE_VIEW_UP).abs() < 1e-6);
        assert!(SAMPLE_VIEW_RIGHT
            .cross(SAMPLE_VIEW_UP)
            .abs_diff_eq(SAMPLE_VIEW_TOWARD_VIEWER, 1e-6));
    }

    #[test]
    fn texel_of_a_view_point_inverts_the_pixel_mapping() {
        let resolution = UVec2::new(300, 200);
        let pixel = UVec2::new(17, 150);
        let texel =
            sample_view_point_to_texel(get_sample_view_point(pixel, resolution), resolution);
        // Pixel 150 from the bottom is texel row 200 - 1 - 150 = 49, centre at 49.5.
        assert!(texel.abs_diff_eq(Vec2::new(17.5, 49.5), 1e-3), "{texel}");
        // The sphere's top (z = +1) shows above the centre by cos 30° radii.
        assert!((project_to_sample_view(Vec3::Z).y - 0.8660254).abs() < 1e-6);
    }

    #[test]
    fn displayed_samples_follow_their_samplers() {
        let hemisphere = sample_display_directions(ExerciseSampler::Hemisphere, 0);
        assert_eq!(hemisphere.len(), EXERCISE_SAMPLE_COUNT as usize);
        assert!(hemisphere.iter().all(|d| d.z >= -1e-6));
        // "Too many samples at the top": the cap z >= 0.9 holds (1 - 0.9) / 2 = 5% of
        // uniform samples but acos(0.9) / pi = 14.4% of spherical-coordinates samples. With
        // 512 samples, 5% is 25.6 +- 4.9 (binomial SD), so "< 45" fails for a uniform
        // sampler with probability < 1e-4, and 14.4% is 73.7 +- 8.
        let cap = |sampler| {
            sample_display_directions(sampler, 0)
                .iter()
                .filter(|d| d.z >= 0.9)
                .count()
        };
        let (uniform, naive) = (
            cap(ExerciseSampler::Sphere),
            cap(ExerciseSampler::SphericalCoordinates),
        );
        assert!(
            uniform < 45 && naive > 45,
            "uniform {uniform}, naive {naive}"
        );
        assert_ne!(
            sample_display_directions(ExerciseSampler::Sphere, 1),
            sample_display_directions(ExerciseSampler::Sphere, 0)
        );
    }
}
