//! `vkpath exercise` through the binary: every exercise renders; the sample displays put
//! their dots where the Rust twins of the samplers say, spread over the sphere for
//! `sample_sphere` and crowded at the top for spherical coordinates, and cluster at the
//! mirror direction for a smooth metal's `sample_brdf`; the ray tracer shows the Cornell box's
//! red wall on the left and green wall on the right; `guide-cell` draws a trained guide's
//! samples and the BSDF's where the twins put them.

use crate::common;

use std::path::Path;

use glam::{UVec2, Vec2, Vec3};
use vkpath::cpu::brdf::MaterialSample;
use vkpath::cpu::workshop::{get_random_numbers, sample_sphere};
use vkpath::exercise::view::{
    dot_radius_pixels, get_sample_view_point, project_to_sample_view, sample_display_directions,
    sample_display_directions_with, sample_view_point_to_texel, SAMPLE_VIEW_TOWARD_VIEWER,
};
use vkpath::exercise::{BrdfDisplaySetup, ExerciseSampler};

/// Runs `vkpath exercise ARGS` in `dir` with validation on and expects success.
fn exercise(dir: &Path, args: &[&str]) {
    let mut full = vec!["exercise"];
    full.extend_from_slice(args);
    full.push("--validate");
    let output = common::vkpath(dir, &full);
    assert!(
        output.status.success(),
        "vkpath {full:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// What a pixel of a sample display shows, from its sRGB colour: the sphere and background
/// are grey (r = g = b), front dots the full dot colour (linear (1, 0.45, 0.05): sRGB 255,
/// 178, 63), back dots 35% of it over the sphere (red well above green, but below 230); the
/// BRDF display's markers are blue or green (linear (0.1, 0.3, 1) and (0.1, 0.9, 0.15): red
/// more than 100 below blue or green).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Shown {
    Grey,
    FrontDot,
    BackDot,
    Marker,
}

impl Shown {
    fn is_dot(self) -> bool {
        matches!(self, Shown::FrontDot | Shown::BackDot)
    }
}

fn classify(pixel: &image::Rgb<u8>) -> Shown {
    let [r, g, b] = pixel.0.map(i32::from);
    if g.max(b) > r + 100 {
        Shown::Marker
    } else if r >= 230 && r - g > 40 {
        Shown::FrontDot
    } else if r - g > 20 {
        Shown::BackDot
    } else {
        Shown::Grey
    }
}

/// Renders a sample display at 256x256 and returns its pixels.
fn sample_display(dir: &Path, name: &str) -> image::RgbImage {
    sample_display_with(dir, name, &[], name)
}

/// `sample_display` with extra arguments, saved as `file_stem`.png.
fn sample_display_with(dir: &Path, name: &str, extra: &[&str], file_stem: &str) -> image::RgbImage {
    let file = format!("{file_stem}.png");
    let mut args = vec![name, "-o", &file];
    args.extend_from_slice(extra);
    exercise(dir, &args);
    let image = image::open(dir.join(&file)).unwrap().to_rgb8();
    assert_eq!(image.dimensions(), (256, 256));
    image
}

/// Every dot the Rust twins predict is in the GPU's image: the pixel under each sample's
/// projection shows a dot (front dots and markers hide back dots, so a back sample may show
/// either of those too).
fn assert_dots_where_the_twins_say(image: &image::RgbImage, sampler: ExerciseSampler) {
    assert_dots_at(image, sampler, &sample_display_directions(sampler, 0));
}

/// `assert_dots_where_the_twins_say` for the twins' `directions` of `sampler`.
fn assert_dots_at(image: &image::RgbImage, sampler: ExerciseSampler, directions: &[Vec3]) {
    let resolution = UVec2::new(image.width(), image.height());
    for (index, direction) in directions.iter().enumerate() {
        let texel = sample_view_point_to_texel(project_to_sample_view(*direction), resolution);
        let shown = classify(image.get_pixel(texel.x as u32, texel.y as u32));
        let front = direction.dot(SAMPLE_VIEW_TOWARD_VIEWER) >= 0.0;
        assert!(
            shown == Shown::FrontDot || (!front && shown != Shown::Grey),
            "{sampler:?} sample {index} ({direction}, front {front}) lands on texel {texel} which shows {shown:?}"
        );
    }
}

/// The view point (sphere radii) of every pixel, with what it shows.
fn shown_points(image: &image::RgbImage) -> Vec<(Vec2, Shown)> {
    let resolution = UVec2::new(image.width(), image.height());
    image
        .enumerate_pixels()
        .map(|(x, y, pixel)| {
            let from_bottom = UVec2::new(x, resolution.y - 1 - y);
            (
                get_sample_view_point(from_bottom, resolution),
                classify(pixel),
            )
        })
        .collect()
}

/// The image of the sphere's top (the pole z = +1) and the radius around it that counts as
/// "the top", in sphere radii.
const POLE_RADIUS: f32 = 0.25;

/// Of all dot pixels, the fraction that shows the front within `POLE_RADIUS` of the pole.
fn pole_fraction(image: &image::RgbImage) -> f64 {
    let pole = project_to_sample_view(Vec3::Z);
    let points = shown_points(image);
    let dots = points.iter().filter(|(_, s)| s.is_dot()).count();
    let at_pole = points
        .iter()
        .filter(|(p, s)| *s == Shown::FrontDot && p.distance(pole) <= POLE_RADIUS)
        .count();
    at_pole as f64 / dots as f64
}

/// The same fraction for uniformly distributed directions: the probability that a uniform
/// direction faces the viewer and projects within `POLE_RADIUS` of the pole, by Monte Carlo
/// with 2^18 samples (standard error 3.4e-4 at the ~3% it comes to).
fn uniform_pole_probability() -> f64 {
    let pole = project_to_sample_view(Vec3::Z);
    let mut seed = UVec2::new(12345, 678);
    let count = 1 << 18;
    let hits = (0..count)
        .filter(|_| {
            let direction = sample_sphere(get_random_numbers(&mut seed));
            direction.dot(SAMPLE_VIEW_TOWARD_VIEWER) >= 0.0
                && project_to_sample_view(direction).distance(pole) <= POLE_RADIUS
        })
        .count();
    hits as f64 / count as f64
}

#[test]
fn spherical_coordinates_crowd_the_top_and_sample_sphere_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let uniform = sample_display(dir.path(), "sample-sphere");
    let naive = sample_display(dir.path(), "spherical-coords");
    assert_dots_where_the_twins_say(&uniform, ExerciseSampler::Sphere);
    assert_dots_where_the_twins_say(&naive, ExerciseSampler::SphericalCoordinates);
    let expected = uniform_pole_probability();
    let (uniform_fraction, naive_fraction) = (pole_fraction(&uniform), pole_fraction(&naive));
    let pole = project_to_sample_view(Vec3::Z);
    let samples_at_top = |sampler| {
        sample_display_directions(sampler, 0)
            .iter()
            .filter(|d| {
                d.dot(SAMPLE_VIEW_TOWARD_VIEWER) >= 0.0
                    && project_to_sample_view(**d).distance(pole) <= POLE_RADIUS
            })
            .count()
    };
    println!(
        "dot pixels at the top: sample-sphere {uniform_fraction:.4}, spherical-coords \
         {naive_fraction:.4}; uniform expectation {expected:.4}; samples at the top: {} and {} \
         of 512",
        samples_at_top(ExerciseSampler::Sphere),
        samples_at_top(ExerciseSampler::SphericalCoordinates)
    );
    // 512 uniform samples put 512 * 3.2% = 16 +- 4 (binomial SD) dots at the top; twice the
    // expectation is 4 SD away, and the dot pixels track the dots. Spherical coordinates put
    // about 11% there (density 1 / sin(theta) near the pole), 3.5x the expectation.
    assert!(
        uniform_fraction < 2.0 * expected,
        "sample-sphere crowds the top: {uniform_fraction} vs {expected}"
    );
    assert!(
        naive_fraction > 2.0 * expected,
        "spherical-coords does not crowd the top: {naive_fraction} vs {expected}"
    );
}

#[test]
fn sample_hemisphere_stays_above_the_equator() {
    let dir = tempfile::tempdir().unwrap();
    let hemisphere = sample_display(dir.path(), "sample-hemisphere");
    assert_dots_where_the_twins_say(&hemisphere, ExerciseSampler::Hemisphere);
    // Directions with z >= 0 project to y = 0.5 d_y + 0.866 d_z >= -0.5; dots reach 2 pixels
    // (0.018 radii) beyond their centres. The lowest half of the sphere's image stays bare.
    let low_dots = shown_points(&hemisphere)
        .iter()
        .filter(|(p, s)| s.is_dot() && p.y < -0.55)
        .count();
    assert_eq!(low_dots, 0, "hemisphere samples below the equator");
}

/// The texel (x right, y down) where a direction lands in a 256x256 display.
fn texel_of(direction: Vec3) -> Vec2 {
    sample_view_point_to_texel(project_to_sample_view(direction), UVec2::splat(256))
}

/// The BRDF display of a metal at view angle 45° with this roughness, and its setup.
fn metal_display(dir: &Path, roughness: &str) -> (image::RgbImage, BrdfDisplaySetup) {
    let args = [
        "--metallic",
        "1",
        "--roughness",
        roughness,
        "--view-angle",
        "45",
    ];
    let image = sample_display_with(dir, "brdf-samples", &args, &format!("metal-{roughness}"));
    let material = MaterialSample::gltf(Vec3::ONE, 1.0, roughness.parse().unwrap());
    (image, BrdfDisplaySetup::new(material, 45.0))
}

/// The dot pixels of `image` and how many of them lie within `radius` pixels of `texel`.
fn dot_pixels_near(image: &image::RgbImage, texel: Vec2, radius: f32) -> (usize, usize) {
    let dots: Vec<Vec2> = image
        .enumerate_pixels()
        .filter(|(_, _, p)| classify(p).is_dot())
        .map(|(x, y, _)| Vec2::new(x as f32 + 0.5, y as f32 + 0.5))
        .collect();
    let near = dots.iter().filter(|p| p.distance(texel) <= radius).count();
    (dots.len(), near)
}

#[test]
fn brdf_samples_of_a_smooth_metal_cluster_at_the_mirror_direction() {
    let dir = tempfile::tempdir().unwrap();
    let (sharp, sharp_setup) = metal_display(dir.path(), "0.05");
    let (rough, rough_setup) = metal_display(dir.path(), "1.0");
    // The GPU's sample_brdf puts its dots where the Rust twin's samples project.
    for (image, setup) in [(&sharp, &sharp_setup), (&rough, &rough_setup)] {
        let directions = sample_display_directions_with(ExerciseSampler::Brdf, 0, setup);
        assert_dots_at(image, ExerciseSampler::Brdf, &directions);
    }
    let mirror = texel_of(sharp_setup.mirror());
    // 8 dot radii (16 pixels, 0.14 sphere radii, about 8° around the mirror direction at
    // this view): GGX alpha 0.0025 puts all but ~1% of the samples within 2.6° of it (see
    // the unit test in src/exercise/view.rs), so nearly every dot pixel lies inside, while
    // roughness 1 (alpha 1) spreads the lobe over the hemisphere.
    let radius = 8.0 * dot_radius_pixels(256);
    let (sharp_dots, sharp_near) = dot_pixels_near(&sharp, mirror, radius);
    let (rough_dots, rough_near) = dot_pixels_near(&rough, mirror, radius);
    println!(
        "mirror texel {mirror}: roughness 0.05 {sharp_near} of {sharp_dots} dot pixels near it, \
         roughness 1 {rough_near} of {rough_dots}"
    );
    assert!(sharp_dots > 0 && rough_dots > 0);
    assert_eq!(
        classify(sharp.get_pixel(mirror.x as u32, mirror.y as u32)),
        Shown::FrontDot,
        "no sample at the mirror direction"
    );
    assert!(
        sharp_near as f64 >= 0.9 * sharp_dots as f64,
        "roughness 0.05: only {sharp_near} of {sharp_dots} dot pixels near the mirror direction"
    );
    assert!(
        (rough_near as f64) < 0.25 * rough_dots as f64 && rough_dots > 5 * sharp_dots,
        "roughness 1 is not spread out: {rough_near} of {rough_dots} near, sharp {sharp_dots}"
    );
    assert_ne!(sharp.as_raw(), rough.as_raw());
    // The markers: a blue disk at the view direction (a metal samples nothing there), a
    // green ring 3 dot radii (6 pixels) around the mirror direction.
    let view = texel_of(sharp_setup.view);
    let [r, g, b] = sharp
        .get_pixel(view.x as u32, view.y as u32)
        .0
        .map(i32::from);
    assert!(
        b > r + 100 && b > g + 50,
        "view marker is not blue: {r} {g} {b}"
    );
    let ring = mirror + Vec2::new(0.0, 3.0 * dot_radius_pixels(256));
    let [r, g, b] = sharp
        .get_pixel(ring.x as u32, ring.y as u32)
        .0
        .map(i32::from);
    assert!(
        g > r + 100 && g > b + 100,
        "mirror ring is not green: {r} {g} {b}"
    );
}

#[test]
fn ray_tracing_shows_red_left_and_green_right() {
    let dir = tempfile::tempdir().unwrap();
    exercise(
        dir.path(),
        &[
            "ray-tracing",
            "-o",
            "rt.png",
            "--width",
            "64",
            "--height",
            "64",
        ],
    );
    let image = image::open(dir.path().join("rt.png")).unwrap().to_rgb8();
    // At mid-height, the outer tenth of the image is the side walls (workshop camera).
    let wall = |x: u32| image.get_pixel(x, 32).0.map(i32::from);
    for x in 1..6 {
        let [r, g, b] = wall(x);
        assert!(
            r > g + 40 && r > b + 40,
            "left wall at x={x} is not red: {r} {g} {b}"
        );
        let [r, g, b] = wall(63 - x);
        assert!(
            g > r + 40 && g > b + 40,
            "right wall at x={} is not green: {r} {g} {b}",
            63 - x
        );
    }
    let [r, g, b] = wall(32);
    assert!(
        r > 180 && (r - g).abs() < 10 && (r - b).abs() < 10,
        "the back wall is not white: {r} {g} {b}"
    );
}

#[test]
fn every_exercise_renders_and_sample_count_sets_the_frame() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "ray-tracing",
        "sample-sphere",
        "sample-hemisphere",
        "spherical-coords",
        "direct-illumination",
        "path-tracing",
        "brdf-samples",
    ] {
        let file = format!("{name}.png");
        exercise(
            dir.path(),
            &[name, "-o", &file, "--width", "40", "--height", "24"],
        );
        let image = image::open(dir.path().join(&file)).unwrap();
        assert_eq!((image.width(), image.height()), (40, 24), "{name}");
    }
    // One frame of SAMPLE_COUNT samples, as the slides' pictures; or progressive --spp.
    for (extra, expected_count) in [
        (&["--sample-count", "8"][..], 8.0),
        (&["--sample-count", "8", "--spp", "24"][..], 24.0),
    ] {
        let mut args = vec![
            "direct-illumination",
            "-o",
            "di.exr",
            "--width",
            "16",
            "--height",
            "16",
            "--moments",
        ];
        args.extend_from_slice(extra);
        exercise(dir.path(), &args);
        let image = vkpath::image_io::exr_input::read_exr(&dir.path().join("di.exr")).unwrap();
        assert!(image.has_moments);
        assert!(
            image
                .image
                .sample_count
                .iter()
                .all(|&n| n == expected_count),
            "{extra:?}"
        );
    }
}

#[test]
fn bad_exercise_arguments_fail_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let unknown = common::vkpath(dir.path(), &["exercise", "sample-cube", "-o", "x.png"]);
    assert_eq!(unknown.status.code(), Some(2), "clap's usage error");
    let bad_format = common::vkpath(dir.path(), &["exercise", "sample-sphere", "-o", "x.jpg"]);
    let stderr = String::from_utf8_lossy(&bad_format.stderr);
    assert_eq!(bad_format.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("x.jpg") && !stderr.contains("panicked"),
        "{stderr}"
    );
    let zero = common::vkpath(
        dir.path(),
        &["exercise", "sample-sphere", "-o", "x.png", "--width", "0"],
    );
    let stderr = String::from_utf8_lossy(&zero.stderr);
    assert_eq!(zero.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("0x256"), "{stderr}");
    for bad in [
        &["--roughness", "1.5"][..],
        &["--view-angle", "90"],
        &["--base-color", "1,2,1"],
    ] {
        let mut args = vec!["exercise", "brdf-samples", "-o", "x.png"];
        args.extend_from_slice(bad);
        let output = common::vkpath(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{bad:?}: {stderr}");
        assert!(stderr.contains(bad[0]), "{bad:?}: {stderr}");
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "files left behind"
    );
}

#[test]
fn guide_cell_draws_the_guides_samples_left_and_the_bsdfs_right() {
    // The library's view of the Cornell box's centre pixel: every front-facing sample the
    // twins drew (the guide's cell on the left, the cosine lobe on the right) is a dot where
    // the twins project it, in its half; the point lies on the surface the camera sees.
    let context = common::validated_context();
    let scene = vkpath::scene::Scene::builtin_cornell_box().unwrap();
    let setup = vkpath::exercise::GuideCellSetup {
        width: 64,
        height: 64,
        training: vkpath::guiding::training::GuideTraining { samples: 64 },
        pixel: UVec2::new(32, 32),
        seed: 0,
    };
    let view = vkpath::exercise::render_guide_cell_display(
        &context,
        &scene,
        &scene.camera.unwrap(),
        &setup,
        256,
        256,
    )
    .unwrap();
    assert_eq!((view.image.width, view.image.height), (512, 256));
    assert!((view.normal.length() - 1.0).abs() < 1e-5);
    let resolution = UVec2::new(256, 256);
    for (offset, directions) in [(0, &view.guide_directions), (256, &view.bsdf_directions)] {
        assert_eq!(directions.len(), 512);
        for direction in directions.iter() {
            if direction.dot(SAMPLE_VIEW_TOWARD_VIEWER) < 0.0 {
                continue;
            }
            let texel = sample_view_point_to_texel(project_to_sample_view(*direction), resolution);
            let index = texel.y as usize * 512 + offset + texel.x as usize;
            let color = view.image.mean[index];
            assert!(
                (color[0] - 1.0).abs() < 1e-6 && (color[1] - 0.45).abs() < 1e-6,
                "sample {direction} at texel {texel} (+{offset}) shows {color:?}"
            );
        }
    }
    // The BSDF's samples lie above the surface; the guide's need not.
    assert!(view
        .bsdf_directions
        .iter()
        .all(|d| d.dot(view.normal) >= 0.0));
    common::assert_validation_silent(&context);
    // The command line writes it, and a pixel that sees nothing is a one-line error.
    let dir = tempfile::tempdir().unwrap();
    exercise(
        dir.path(),
        &[
            "guide-cell",
            "-o",
            "cell.png",
            "--width",
            "64",
            "--height",
            "64",
        ],
    );
    let image = image::open(dir.path().join("cell.png")).unwrap();
    assert_eq!((image.width(), image.height()), (128, 64));
    let output = common::vkpath(
        dir.path(),
        &["exercise", "guide-cell", "-o", "bad.png", "--pixel", "64,0"],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("outside the 64x64 view"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
}
