//! Rust twins of `glsl/exercise_samples.comp`: the fixed view of the unit sphere on which the
//! sample display draws its dots, and the sequence of sample directions it draws (for
//! `sample_brdf`, with the material and view direction of a `BrdfDisplaySetup`). Same names
//! and maths as the shader, so that a test can predict where every dot lands.

use glam::{UVec2, Vec2, Vec3};

use crate::contract::{
    EXERCISE_SAMPLER_BRDF, EXERCISE_SAMPLER_HEMISPHERE, EXERCISE_SAMPLER_SPHERE,
    EXERCISE_SAMPLER_SPHERICAL_COORDINATES, EXERCISE_SAMPLE_COUNT, SAMPLE_VIEW_ELEVATION_COS,
    SAMPLE_VIEW_ELEVATION_SIN,
};
use crate::cpu::brdf::{sample_brdf, MaterialSample};
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

/// The sample display's push constants, declared beside the kernels.
pub use crate::kernels::push_constants::SampleDisplayPushConstants;

impl SampleDisplayPushConstants {
    /// The constants that draw `sampler` (its samples drawn from `seed`) at `width` x
    /// `height` pixels; `brdf` says what `ExerciseSampler::Brdf` samples.
    pub fn new(
        sampler: ExerciseSampler,
        width: u32,
        height: u32,
        seed: u32,
        brdf: &BrdfDisplaySetup,
    ) -> SampleDisplayPushConstants {
        let material = &brdf.material;
        SampleDisplayPushConstants {
            resolution_sampler_seed: [width, height, sampler.contract_value(), seed],
            base_color_metallic: material.base_color.extend(material.metallic).to_array(),
            specular_color_specular: material.specular_color.extend(material.specular).to_array(),
            view_direction: brdf.view.extend(0.0).to_array(),
            roughness_ior: [material.roughness, material.ior, 0.0, 0.0],
        }
    }
}

/// What the BRDF display (`vkpath exercise brdf-samples`) samples: `sample_brdf` for a
/// material at a surface with normal +z, seen from `view`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrdfDisplaySetup {
    /// The material, as glTF describes it.
    pub material: MaterialSample,
    /// Unit view direction, world space, z > 0 (above the surface).
    pub view: Vec3,
}

impl BrdfDisplaySetup {
    /// The view `view_angle_degrees` (in [0, 90)) away from the normal +z, towards -x: the
    /// viewer sits on the left of the display's sphere and the mirror direction on its
    /// right, both on the hemisphere that faces the display's camera.
    pub fn new(material: MaterialSample, view_angle_degrees: f32) -> BrdfDisplaySetup {
        let (sin, cos) = view_angle_degrees.to_radians().sin_cos();
        BrdfDisplaySetup {
            material,
            view: Vec3::new(-sin, 0.0, cos),
        }
    }

    /// The view reflected about the normal +z: where a perfect mirror sends it, the centre of
    /// the specular lobe of a smooth material. Twin of the shader's `reflect(-view, +z)`.
    pub fn mirror(&self) -> Vec3 {
        Vec3::new(-self.view.x, -self.view.y, self.view.z)
    }
}

impl Default for BrdfDisplaySetup {
    /// A white dielectric with glTF's defaults otherwise (roughness 1, specular 1, ior 1.5),
    /// seen from 45 degrees.
    fn default() -> BrdfDisplaySetup {
        BrdfDisplaySetup::new(MaterialSample::gltf(Vec3::ONE, 0.0, 1.0), 45.0)
    }
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
    /// `sample_brdf` (`glsl/brdf.glsl`) for a `BrdfDisplaySetup`'s material and view.
    Brdf,
}

impl ExerciseSampler {
    /// The `EXERCISE_SAMPLER_*` value of `glsl/shared.h`.
    pub fn contract_value(self) -> u32 {
        match self {
            ExerciseSampler::Sphere => EXERCISE_SAMPLER_SPHERE,
            ExerciseSampler::Hemisphere => EXERCISE_SAMPLER_HEMISPHERE,
            ExerciseSampler::SphericalCoordinates => EXERCISE_SAMPLER_SPHERICAL_COORDINATES,
            ExerciseSampler::Brdf => EXERCISE_SAMPLER_BRDF,
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
/// \param material, view What `EXERCISE_SAMPLER_BRDF` samples (normal +z, view above it)
/// \return A unit vector
pub fn get_exercise_sample_direction(
    sampler: u32,
    random_numbers: Vec2,
    material: &MaterialSample,
    view: Vec3,
) -> Vec3 {
    if sampler == EXERCISE_SAMPLER_BRDF {
        return sample_brdf(random_numbers, material, Vec3::Z, view);
    }
    if sampler == EXERCISE_SAMPLER_HEMISPHERE {
        return sample_hemisphere(random_numbers, Vec3::Z);
    }
    if sampler == EXERCISE_SAMPLER_SPHERICAL_COORDINATES {
        return sample_sphere_spherical_coordinates(random_numbers);
    }
    sample_sphere(random_numbers)
}

/// The `EXERCISE_SAMPLE_COUNT` directions the display draws for a sampler and seed, in the
/// shader's order (`ExerciseSampler::Brdf` with `BrdfDisplaySetup::default()`).
pub fn sample_display_directions(sampler: ExerciseSampler, user_seed: u32) -> Vec<Vec3> {
    sample_display_directions_with(sampler, user_seed, &BrdfDisplaySetup::default())
}

/// `sample_display_directions` with `brdf` saying what `ExerciseSampler::Brdf` samples.
pub fn sample_display_directions_with(
    sampler: ExerciseSampler,
    user_seed: u32,
    brdf: &BrdfDisplaySetup,
) -> Vec<Vec3> {
    let mut seed = get_sample_display_seed(user_seed);
    (0..EXERCISE_SAMPLE_COUNT)
        .map(|_| {
            get_exercise_sample_direction(
                sampler.contract_value(),
                get_random_numbers(&mut seed),
                &brdf.material,
                brdf.view,
            )
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
    use crate::cpu::brdf::get_base_material;

    #[test]
    fn push_constants_carry_the_material_and_view() {
        let setup = BrdfDisplaySetup::new(
            get_base_material(
                Vec3::new(0.1, 0.2, 0.3),
                0.4,
                0.5,
                0.6,
                Vec3::new(0.7, 0.8, 0.9),
                1.7,
            ),
            30.0,
        );
        let constants = SampleDisplayPushConstants::new(ExerciseSampler::Brdf, 64, 32, 7, &setup);
        assert_eq!(
            constants.resolution_sampler_seed,
            [64, 32, EXERCISE_SAMPLER_BRDF, 7]
        );
        assert_eq!(constants.base_color_metallic, [0.1, 0.2, 0.3, 0.4]);
        assert_eq!(constants.specular_color_specular, [0.7, 0.8, 0.9, 0.6]);
        assert_eq!(constants.roughness_ior, [0.5, 1.7, 0.0, 0.0]);
        assert_eq!(constants.view_direction, setup.view.extend(0.0).to_array());
    }

    #[test]
    fn brdf_view_and_mirror_face_the_camera_on_either_side_of_the_normal() {
        let setup = BrdfDisplaySetup::new(MaterialSample::gltf(Vec3::ONE, 1.0, 0.3), 45.0);
        // sin 45° = cos 45° = 0.7071; 1e-6 covers the f32 roundings.
        assert!(setup
            .view
            .abs_diff_eq(Vec3::new(-0.70710677, 0.0, 0.70710677), 1e-6));
        let mirror = setup.mirror();
        // The mirror reflects the view about the normal: v + r = 2 (n.v) n.
        assert!((setup.view + mirror).abs_diff_eq(2.0 * setup.view.z * Vec3::Z, 1e-6));
        for direction in [setup.view, mirror] {
            assert!(direction.dot(SAMPLE_VIEW_TOWARD_VIEWER) > 0.0);
        }
        assert!(
            project_to_sample_view(setup.view).x < 0.0 && project_to_sample_view(mirror).x > 0.0
        );
        // A near-mirror metal (GGX alpha 0.0025) sends almost every sample within 2.6° of the
        // mirror direction (cos > 0.999): half vectors stray more than 1.3° from the normal
        // with probability about alpha^2 / (0.0223^2 + alpha^2) = 1.2%, 6.4 +- 2.5 of 512.
        // The rough white dielectric (mostly diffuse, alpha 1) spreads its samples over the
        // hemisphere: a cap of 2.6° holds 0.1% of the cosine-weighted ones.
        let sharp = BrdfDisplaySetup::new(MaterialSample::gltf(Vec3::ONE, 1.0, 0.05), 45.0);
        let near_mirror = |directions: Vec<Vec3>, mirror: Vec3| {
            directions.iter().filter(|d| d.dot(mirror) > 0.999).count()
        };
        let sharp_count = near_mirror(
            sample_display_directions_with(ExerciseSampler::Brdf, 0, &sharp),
            sharp.mirror(),
        );
        let rough_count = near_mirror(
            sample_display_directions(ExerciseSampler::Brdf, 0),
            BrdfDisplaySetup::default().mirror(),
        );
        println!(
            "samples near the mirror direction: sharp metal {sharp_count}, default {rough_count}"
        );
        assert!(
            sharp_count >= 490 && rough_count < 50,
            "{sharp_count} {rough_count}"
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
