//! Furnace tests of the CPU integrators: the camera inside a closed box whose walls all have
//! albedo a and emission L_e. Every path hits a wall at every bounce, so path tracing with
//! paths of n hits has the expectation
//! E[L] = sum_{j<n} L_e a^j E[prod 2 cos] = L_e (1 - a^n) / (1 - a),
//! because 2 n.omega has expectation 1 under uniform hemisphere sampling (density 1/(2 pi)).
//! With a constant albedo, all variance comes from the factors 2 cos (cos is uniform in
//! [0, 1] for uniform hemisphere samples), never from what the rays hit.

use glam::{Vec3, Vec4Swizzles};

use crate::camera::Camera;
use crate::contract::{
    INTEGRATOR_COSINE, INTEGRATOR_DIRECT_ILLUMINATION, INTEGRATOR_MIS, INTEGRATOR_NEE,
    INTEGRATOR_PATH_TRACING, INTEGRATOR_RAY_TRACING, LIGHT_SAMPLING_AREA,
    LIGHT_SAMPLING_SOLID_ANGLE, PIXEL_FILTER_BOX, PIXEL_FILTER_CENTER,
};
use crate::cpu::{add_cpu_samples, render_cpu, CpuImage, CpuRenderSettings};
use crate::scene::Triangle;

/// The 12 triangles of the cube [-1, 1]^3, ordered so that every normal points inwards.
fn furnace_box(albedo: Vec3, emission: Vec3) -> Vec<Triangle> {
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            // The face's corners in cyclic order around the face.
            let corner = |u: f32, v: f32| {
                let mut p = Vec3::ZERO;
                p[axis] = side;
                p[(axis + 1) % 3] = u;
                p[(axis + 2) % 3] = v;
                p
            };
            let quad = [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ];
            for mut positions in [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]] {
                let centroid = (positions[0] + positions[1] + positions[2]) / 3.0;
                let outward = (positions[1] - positions[0])
                    .cross(positions[2] - positions[0])
                    .dot(centroid)
                    > 0.0;
                if outward {
                    positions.swap(1, 2);
                }
                triangles.push(
                    Triangle::new(positions, albedo, emission, false)
                        .expect("cube faces are not degenerate"),
                );
            }
        }
    }
    triangles
}

fn settings(integrator: u32, max_path_length: u32) -> CpuRenderSettings {
    CpuRenderSettings {
        width: 16,
        height: 16,
        spp: 64,
        max_path_length,
        seed: 1,
        pixel_filter: PIXEL_FILTER_BOX,
        integrator,
        russian_roulette_start: 0,
        // Independent samples: the z-tests below assume them (docs: Sobol's are not)
        sampler: crate::contract::SAMPLER_PCG,
        light_sampling: LIGHT_SAMPLING_SOLID_ANGLE,
        light_selection: crate::contract::LIGHT_SELECTION_POWER,
    }
}

fn camera_inside() -> crate::camera::ImagePlane {
    Camera::look_at(
        Vec3::new(0.1, 0.2, -0.3),
        Vec3::new(1.0, 0.5, 0.0),
        Vec3::Y,
        1.2,
    )
    .image_plane(1.0)
}

/// The mean over all samples of all pixels, and its standard error from the sample variance
/// of all those samples (f64 sums of the per-pixel f32 sums).
fn pooled_mean_and_standard_error(image: &CpuImage) -> (Vec3, Vec3) {
    let mut sum = [0.0f64; 3];
    let mut sum_of_squares = [0.0f64; 3];
    let mut count = 0.0f64;
    for pixel in &image.pixels {
        for channel in 0..3 {
            sum[channel] += pixel.sum[channel] as f64 - pixel.compensation[channel] as f64;
            sum_of_squares[channel] += pixel.sum_of_squares[channel] as f64;
        }
        count += pixel.sample_count as f64;
    }
    let mean = sum.map(|s| s / count);
    let standard_error = std::array::from_fn(|c| {
        ((sum_of_squares[c] / count - mean[c] * mean[c]).max(0.0) * count / (count - 1.0) / count)
            .sqrt()
    });
    (
        Vec3::from_array(mean.map(|m| m as f32)),
        Vec3::from_array(standard_error.map(|s: f64| s as f32)),
    )
}

/// L_e (1 - a^n) / (1 - a) per channel, n L_e where a = 1.
fn furnace_expectation(albedo: Vec3, emission: Vec3, path_length: u32) -> Vec3 {
    Vec3::from_array(std::array::from_fn(|c| {
        let a = albedo[c];
        let geometric_sum = if a == 1.0 {
            path_length as f32
        } else {
            (1.0 - a.powi(path_length as i32)) / (1.0 - a)
        };
        emission[c] * geometric_sum
    }))
}

/// Checks |mean - expected| <= 5 standard errors per channel. The pooled mean of
/// 16 x 16 x 64 = 16384 samples is close to normal (CLT, bounded samples), so a correct
/// integrator misses this bound with probability 5.7e-7 per channel; the seeds are fixed, so
/// the test is deterministic anyway. The bound still has teeth: a lost bounce lowers the
/// red channel's expectation by L_e a^(n-1) = 0.25 (a = 0.5, n = 3) or 0.33 (a = 0.8,
/// n = 6), i.e. 69 and 18 of its standard errors (0.0036 and 0.018, measured), and dropping
/// the factor 2 of 2 cos halves every bounce's contribution.
fn assert_within_five_standard_errors(label: &str, image: &CpuImage, expected: Vec3) {
    let (mean, standard_error) = pooled_mean_and_standard_error(image);
    println!("{label}: mean {mean}, expected {expected}, standard error {standard_error}");
    // 1e-5 relative covers the f32 rounding of the sums where the standard error is 0.
    let tolerance = 5.0 * standard_error + 1e-5 * expected;
    assert!(
        (mean - expected).abs().cmple(tolerance).all(),
        "{label}: mean {mean} vs expected {expected} (tolerance {tolerance})"
    );
    assert!(image.pixels.iter().all(|pixel| pixel.sample_count == 64));
}

#[test]
fn furnace_box_normals_point_inwards() {
    for triangle in furnace_box(Vec3::ONE, Vec3::ONE) {
        let centroid =
            (triangle.positions[0] + triangle.positions[1] + triangle.positions[2]) / 3.0;
        assert!(triangle.normal.dot(centroid) < 0.0);
    }
}

#[test]
fn path_tracing_furnace() {
    let emission = Vec3::new(1.0, 2.0, 0.5);
    for (a, path_length) in [(0.5f32, 3u32), (0.8, 6)] {
        // A third channel with albedo 1 checks the limit n L_e.
        let albedo = Vec3::new(a, 0.5 * a, 1.0);
        let triangles = furnace_box(albedo, emission);
        let image = render_cpu(
            &triangles,
            &camera_inside(),
            &settings(INTEGRATOR_PATH_TRACING, path_length),
        );
        let expected = furnace_expectation(albedo, emission, path_length);
        assert_within_five_standard_errors(
            &format!("path tracing a = {albedo}, n = {path_length}"),
            &image,
            expected,
        );
    }
}

#[test]
fn importance_sampled_furnace_with_both_light_samplings() {
    // The box's 12 emitters seen from points on its walls: solid angles from 0 (the point's
    // own face) to nearly 2 pi, so both sides of use_spherical_sampling()'s thresholds.
    let emission = Vec3::new(1.0, 2.0, 0.5);
    let albedo = Vec3::new(0.5, 0.25, 1.0);
    let path_length = 3;
    let triangles = furnace_box(albedo, emission);
    let expected = furnace_expectation(albedo, emission, path_length);
    for integrator in [INTEGRATOR_COSINE, INTEGRATOR_NEE, INTEGRATOR_MIS] {
        for light_sampling in [LIGHT_SAMPLING_AREA, LIGHT_SAMPLING_SOLID_ANGLE] {
            let image = render_cpu(
                &triangles,
                &camera_inside(),
                &CpuRenderSettings {
                    light_sampling,
                    ..settings(integrator, path_length)
                },
            );
            assert_within_five_standard_errors(
                &format!("integrator {integrator}, light sampling {light_sampling}"),
                &image,
                expected,
            );
        }
    }
}

#[test]
fn guided_furnace_with_a_guide_the_cpu_trained() {
    // The twins of path guiding (crate::cpu::path_guiding): a guide trained by the CPU's
    // own training iterations, then nee and mis sampling with it. The walls are all
    // emitters, so every vertex takes light samples and every direction's MIS weight
    // involves the guide's density; the closed form holds only if the mixture and its
    // weights are right: a guide sample weighted as a BSDF sample (f / p_bsdf) read 1.793
    // for 1.75 in red with nee, 8 standard errors off.
    let emission = Vec3::new(1.0, 2.0, 0.5);
    let albedo = Vec3::new(0.5, 0.25, 1.0);
    let path_length = 3;
    let triangles = furnace_box(albedo, emission);
    let expected = furnace_expectation(albedo, emission, path_length);
    let grid = crate::guiding::GuideGrid::around_triangles(triangles.iter().map(|t| t.positions));
    for integrator in [INTEGRATOR_NEE, INTEGRATOR_MIS] {
        let settings = settings(integrator, path_length);
        let guide = crate::cpu::train_cpu_guide(
            &triangles,
            &camera_inside(),
            &settings,
            grid.clone(),
            crate::guiding::training::GuideTraining { samples: 16 },
        )
        .unwrap();
        // The camera sees only part of the walls, and only cells with enough splats learn.
        assert!(guide.guided_cell_count() > 0);
        let mut image = CpuImage::new(settings.width, settings.height);
        crate::cpu::add_cpu_guided_samples(
            &triangles,
            &camera_inside(),
            &settings,
            crate::cpu::CpuGuiding {
                guide: Some(guide.texels()),
                splats: None,
            },
            0..settings.spp,
            &mut image,
        );
        assert_within_five_standard_errors(
            &format!(
                "guided integrator {integrator}, {} cells guided",
                guide.guided_cell_count()
            ),
            &image,
            expected,
        );
    }
}

#[test]
fn direct_illumination_and_ray_tracing_furnace() {
    let emission = Vec3::new(1.0, 2.0, 0.5);
    let albedo = Vec3::new(0.5, 0.8, 1.0);
    let triangles = furnace_box(albedo, emission);
    // Exercise 6 is L_e + one bounce: the path-tracing expectation for n = 2.
    let image = render_cpu(
        &triangles,
        &camera_inside(),
        &settings(INTEGRATOR_DIRECT_ILLUMINATION, 5),
    );
    assert_within_five_standard_errors(
        "direct illumination",
        &image,
        furnace_expectation(albedo, emission, 2),
    );
    // Ray tracing shows the albedo of the first hit, exactly.
    let image = render_cpu(
        &triangles,
        &camera_inside(),
        &settings(INTEGRATOR_RAY_TRACING, 5),
    );
    assert!(image
        .mean()
        .iter()
        .all(|rgba| Vec3::from_slice(rgba) == albedo));
}

#[test]
fn progressive_frames_are_bit_identical_to_one_render() {
    let triangles = furnace_box(Vec3::splat(0.7), Vec3::ONE);
    let plane = camera_inside();
    for pixel_filter in [PIXEL_FILTER_BOX, PIXEL_FILTER_CENTER] {
        let settings = CpuRenderSettings {
            pixel_filter,
            spp: 10,
            ..settings(INTEGRATOR_PATH_TRACING, 4)
        };
        let whole = render_cpu(&triangles, &plane, &settings);
        let mut frames = CpuImage::new(settings.width, settings.height);
        for first in (0..settings.spp).step_by(3) {
            add_cpu_samples(
                &triangles,
                &plane,
                &settings,
                first,
                (first + 3).min(settings.spp),
                &mut frames,
            );
        }
        assert_eq!(whole, frames);
        // Another user seed gives other paths.
        let reseeded = render_cpu(
            &triangles,
            &plane,
            &CpuRenderSettings {
                seed: 2,
                ..settings
            },
        );
        assert_ne!(whole.mean(), reseeded.mean());
    }
    // A camera outside the box sees only back faces, whose emission is one-sided: black.
    let outside =
        Camera::look_at(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y, 0.5).image_plane(1.0);
    let image = render_cpu(&triangles, &outside, &settings(INTEGRATOR_PATH_TRACING, 3));
    assert!(image
        .mean()
        .iter()
        .all(|rgba| glam::Vec4::from_array(*rgba).xyz() == Vec3::ZERO));
}
