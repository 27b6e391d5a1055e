//! The light tree (`--light-selection tree`): `glsl/light_tree.glsl` on the GPU
//! (`glsl/probe_light_tree.comp`) against its Rust twins (`vkpath::cpu::light_tree`) on the
//! same words; the probability a sample returns is the one a walk from the root recomputes
//! and sums to one over the lights; far from a cluster the choice follows power; lights
//! behind the surface are never chosen; and a corridor of 1000 lights renders consistently
//! with the power CDF's image. Each test asserts that the validation layer stayed silent.

use crate::common;

use glam::Vec3;
use vkpath::cpu::light_tree::{
    get_light_bounds_importance, get_light_tree_first_child_probability, get_light_tree_node,
    get_light_tree_probability, sample_light_tree, LightTexels, NO_LIGHT,
};
use vkpath::lights::emissive::{triangle_power, EmissiveTriangles};
use vkpath::lights::gpu_emissive::gpu_light_bytes_with_tree;
use vkpath::lights::light_tree::LightTree;
use vkpath::probe::inputs::InputRng;
use vkpath::probe::light_tree_probe::{LightTreeProbeInput, LightTreeProbeRunner};
use vkpath::scene::Triangle;

/// `count` small emitters of widely varying power (10^-2 to 10^2 in emission, 0.02 to 0.2
/// in size) around `center` within `spread`, facing random directions, every third
/// two-sided.
fn lights(count: usize, center: Vec3, spread: f32, rng: &mut InputRng) -> Vec<Triangle> {
    (0..count)
        .map(|i| {
            let p = center + rng.in_box(Vec3::splat(-spread), Vec3::splat(spread));
            let normal = rng.unit_vector();
            let tangent = normal.any_orthonormal_vector();
            let bitangent = normal.cross(tangent);
            let size = rng.range(0.02, 0.2);
            Triangle::new(
                [p, p + size * tangent, p + size * bitangent],
                Vec3::ONE,
                Vec3::splat(10f32.powf(rng.range(-2.0, 2.0))),
                i % 3 == 0,
            )
            .unwrap()
        })
        .collect()
}

/// The lights' texel buffer with a tree over `triangles`, as bytes and as words.
fn texel_bytes(triangles: &[Triangle]) -> (EmissiveTriangles, Vec<u8>, Vec<u32>) {
    let table = EmissiveTriangles::new(triangles);
    let tree = LightTree::build(triangles, &table);
    let bytes = gpu_light_bytes_with_tree(&table, &tree);
    let words = bytemuck::pod_collect_to_vec(&bytes);
    (table, bytes, words)
}

/// Relative tolerance of a probability between the GPU and the CPU, and between a sample's
/// probability and the walk's: 1e-4. Each is a product of at most ~15 levels' ratios of
/// importances, each importance a dozen float operations with a sqrt and a division (a few
/// ulps each on the GPU, Vulkan's sqrt being 1 / inversesqrt), so about 15 * 12 * 3 ulps =
/// 6e-5 in the worst case.
const PROBABILITY_TOLERANCE: f32 = 1e-4;

/// The probability that `sample_light_tree` at `position` ends in a dead end, a node both of
/// whose children the bounds prove unreachable (pbrt-v4's BVHLightSampler returns no light
/// there too): a node's bound can admit a point that neither child's admits (its box is
/// larger, so it subtends a wider angle), and no light below it can then contribute. The
/// lights' probabilities sum to 1 minus this; computed with the walk's own numbers.
fn dead_end_probability(texels: LightTexels, node_index: u32, position: Vec3, normal: Vec3) -> f64 {
    let node = get_light_tree_node(texels, node_index);
    if node.is_leaf {
        let unreachable =
            node_index == 0 && get_light_bounds_importance(&node, position, normal) <= 0.0;
        return if unreachable { 1.0 } else { 0.0 };
    }
    let first = get_light_tree_first_child_probability(texels, &node, node_index, position, normal);
    if first < 0.0 {
        return 1.0;
    }
    let mut dead = 0.0;
    if first > 0.0 {
        dead += f64::from(first) * dead_end_probability(texels, node_index + 1, position, normal);
    }
    if first < 1.0 {
        dead += f64::from(1.0 - first) * dead_end_probability(texels, node.index, position, normal);
    }
    dead
}

#[test]
fn gpu_and_cpu_choose_the_same_light_with_the_probability_the_walk_recomputes() {
    let mut rng = InputRng::new(2201);
    let mut triangles = lights(120, Vec3::ZERO, 1.0, &mut rng);
    triangles.extend(lights(80, Vec3::new(6.0, 1.0, -3.0), 3.0, &mut rng));
    let (table, bytes, words) = texel_bytes(&triangles);
    let light_count = table.triangle_indices.len() as u32;
    let texels = LightTexels { words: &words };
    // 40 shading points inside and around the lights, each with every light (for the sums)
    // and a random number.
    let mut inputs = Vec::new();
    for _ in 0..40 {
        let position = rng.in_box(Vec3::new(-3.0, -3.0, -6.0), Vec3::new(9.0, 4.0, 3.0));
        let normal = if rng.uniform() < 0.2 {
            Vec3::ZERO
        } else {
            rng.unit_vector()
        };
        for light in 0..light_count {
            inputs.push(LightTreeProbeInput::new(
                position,
                normal,
                rng.uniform(),
                light,
            ));
        }
    }
    let context = common::validated_context();
    let runner = LightTreeProbeRunner::new(&context, &bytes).expect("the probe runs");
    let outputs = runner.run(&inputs).expect("the probe runs");
    // Built once: building it per input took most of this test's 33 s of CPU.
    let depth = LightTree::build(&triangles, &table).depth;
    let (mut same_light, mut chosen, mut worst) = (0usize, 0usize, 0f32);
    let (mut worst_sum, mut points_with_dead_ends) = (0f64, 0usize);
    for (point, (point_inputs, point_outputs)) in inputs
        .chunks(light_count as usize)
        .zip(outputs.chunks(light_count as usize))
        .enumerate()
    {
        let position = Vec3::from_slice(&point_inputs[0].position_random[..3]);
        let normal = Vec3::from_slice(&point_inputs[0].normal[..3]);
        let gpu_sum: f64 = point_outputs
            .iter()
            .map(|o| f64::from(o.probabilities[2]))
            .sum();
        let cpu_sum: f64 = (0..light_count)
            .map(|i| f64::from(get_light_tree_probability(texels, i, position, normal)))
            .sum();
        // The probabilities and the dead ends' sum to 1 (to 1e-5: a few hundred f32
        // products of ~1e-7 relative error each, summed in f64).
        let dead = dead_end_probability(texels, 0, position, normal);
        if dead > 0.0 {
            points_with_dead_ends += 1;
        }
        for sum in [gpu_sum, cpu_sum] {
            worst_sum = worst_sum.max((sum + dead - 1.0).abs());
            assert!(
                (sum + dead - 1.0).abs() < 1e-5,
                "point {point}: probabilities sum to {sum}, dead ends {dead}"
            );
        }
        for (input, output) in point_inputs.iter().zip(point_outputs) {
            let light = input.light_index[0];
            let cpu_given = get_light_tree_probability(texels, light, position, normal);
            let gpu_given = output.probabilities[2];
            assert!(
                (cpu_given - gpu_given).abs() <= PROBABILITY_TOLERANCE * cpu_given.max(1e-30),
                "point {point}, light {light}: walk {gpu_given} on the GPU, {cpu_given} on the CPU"
            );
            let (cpu_light, cpu_p) =
                sample_light_tree(texels, input.position_random[3], position, normal);
            let (gpu_light, gpu_p) = (output.light[0], output.probabilities[0]);
            assert_eq!(output.light[1], depth);
            if gpu_light == NO_LIGHT {
                assert!(gpu_p == 0.0 && dead > 0.0, "no light only in a dead end");
            } else {
                chosen += 1;
                // The probability returned with the sample is the walk's for that light.
                let walked = output.probabilities[1];
                let error = (gpu_p - walked).abs() / walked;
                worst = worst.max(error);
                assert!(
                    error <= PROBABILITY_TOLERANCE,
                    "sampled {gpu_p} vs walked {walked}"
                );
            }
            if cpu_light == gpu_light {
                same_light += 1;
                if cpu_light != NO_LIGHT {
                    assert!((cpu_p - gpu_p).abs() <= PROBABILITY_TOLERANCE * cpu_p);
                }
            }
        }
    }
    println!(
        "{chosen} lights chosen of {} inputs; GPU = CPU for {same_light}; worst sample/walk error {worst:.2e}; \
         worst |sum + dead ends - 1| {worst_sum:.2e}; {points_with_dead_ends} of 40 points with dead ends",
        inputs.len()
    );
    // The same light but where the random number falls within a few ulps of a boundary
    // between two children (their probabilities differ by ~1e-6 between GPU and CPU, so
    // about 1e-6 * depth of the inputs): at most one in a thousand.
    assert!(
        inputs.len() - same_light <= inputs.len() / 1000,
        "GPU and CPU chose different lights for {} of {} inputs",
        inputs.len() - same_light,
        inputs.len()
    );
    common::assert_validation_silent(&context);
}

/// The 1 - 10^-6 quantile of chi^2 with `dof` degrees of freedom, by Wilson and Hilferty's
/// approximation (accurate to a fraction of a percent for dof > 30).
fn chi_squared_threshold(dof: f64) -> f64 {
    // z of the standard normal's 1 - 10^-6 quantile
    let z = 4.753;
    let a = 2.0 / (9.0 * dof);
    dof * (1.0 - a + z * a.sqrt()).powi(3)
}

#[test]
fn far_from_a_cluster_the_choice_follows_power() {
    // 64 lights in a 1 m cube, all facing +y (one-sided), seen from 1 km above: every
    // light's importance is phi cos / d^2 with cos and d equal to within 1e-3, so the
    // tree's choice must follow power alone.
    let mut rng = InputRng::new(2202);
    let triangles: Vec<Triangle> = (0..64)
        .map(|_| {
            let p = rng.in_box(Vec3::splat(-0.5), Vec3::splat(0.5));
            let size = rng.range(0.02, 0.2);
            Triangle::new(
                [
                    p,
                    p + Vec3::new(0.0, 0.0, size),
                    p + Vec3::new(size, 0.0, 0.0),
                ],
                Vec3::ONE,
                Vec3::splat(10f32.powf(rng.range(-1.0, 1.0))),
                false,
            )
            .unwrap()
        })
        .collect();
    let (table, _, words) = texel_bytes(&triangles);
    let texels = LightTexels { words: &words };
    let powers: Vec<f64> = table
        .triangle_indices
        .iter()
        .map(|&t| f64::from(triangle_power(&triangles[t as usize])))
        .collect();
    let total: f64 = powers.iter().sum();
    let samples = 200_000usize;
    let mut counts = vec![0usize; powers.len()];
    for _ in 0..samples {
        let position = Vec3::new(rng.range(-1.0, 1.0), 1000.0, rng.range(-1.0, 1.0));
        let (light, p) = sample_light_tree(texels, rng.uniform(), position, -Vec3::Y);
        assert_ne!(light, NO_LIGHT);
        let expected = powers[light as usize] / total;
        // The returned probability is power's to 1% (the lights' cosines and distances
        // differ by at most ~1e-3 at this distance).
        assert!(
            (f64::from(p) - expected).abs() < 0.01 * expected,
            "{p} vs {expected}"
        );
        counts[light as usize] += 1;
    }
    // Pearson's chi^2 against power-proportional frequencies. Lights expected fewer than 5
    // times are pooled (a few of the smallest, dimmest ones), as the test requires.
    let (mut chi2, mut bins, mut pooled_count, mut pooled_expected) = (0.0, 0usize, 0.0, 0.0);
    for (count, power) in counts.iter().zip(&powers) {
        let expected = samples as f64 * power / total;
        if expected < 5.0 {
            pooled_count += *count as f64;
            pooled_expected += expected;
            continue;
        }
        chi2 += (*count as f64 - expected).powi(2) / expected;
        bins += 1;
    }
    if pooled_expected > 0.0 {
        chi2 += (pooled_count - pooled_expected).powi(2) / pooled_expected;
        bins += 1;
    }
    // A false alarm at one in a million (the seed is fixed, so this run either passes or
    // not; the threshold says how unlikely a failure of a correct tree would have been).
    let threshold = chi_squared_threshold((bins - 1) as f64);
    println!("chi^2 = {chi2:.1} over {bins} bins (threshold {threshold:.1})");
    assert!(chi2 < threshold, "chi^2 {chi2} >= {threshold}");
}

#[test]
fn lights_behind_the_surface_are_never_chosen_on_the_gpu() {
    // One-sided lights facing up under a floor at y = 0 and lights above at y = 3 facing
    // down: a point on the floor with the normal up sees only the ones above; with the
    // normal down only the ones below (and those face it).
    let mut rng = InputRng::new(2203);
    let facing = |center: Vec3, normal_y: f32, rng: &mut InputRng| -> Vec<Triangle> {
        (0..24)
            .map(|_| {
                let p = center + rng.in_box(Vec3::new(-2.0, 0.0, -2.0), Vec3::new(2.0, 0.0, 2.0));
                let s = rng.range(0.05, 0.2);
                let (b, c) = if normal_y > 0.0 {
                    (Vec3::new(0.0, 0.0, s), Vec3::new(s, 0.0, 0.0))
                } else {
                    (Vec3::new(s, 0.0, 0.0), Vec3::new(0.0, 0.0, s))
                };
                Triangle::new(
                    [p, p + b, p + c],
                    Vec3::ONE,
                    Vec3::splat(rng.range(0.1, 10.0)),
                    false,
                )
                .unwrap()
            })
            .collect()
    };
    let mut triangles = facing(Vec3::new(0.0, -1.0, 0.0), 1.0, &mut rng);
    triangles.extend(facing(Vec3::new(0.0, 3.0, 0.0), -1.0, &mut rng));
    let (table, bytes, words) = texel_bytes(&triangles);
    let texels = LightTexels { words: &words };
    let light_count = table.triangle_indices.len() as u32;
    let below = |light: u32| light < 24;
    let mut inputs = Vec::new();
    for i in 0..400 {
        let position = Vec3::new(rng.range(-1.0, 1.0), 0.0, rng.range(-1.0, 1.0));
        let normal = if i % 2 == 0 { Vec3::Y } else { -Vec3::Y };
        inputs.push(LightTreeProbeInput::new(
            position,
            normal,
            rng.uniform(),
            i % light_count,
        ));
    }
    let context = common::validated_context();
    let runner = LightTreeProbeRunner::new(&context, &bytes).expect("the probe runs");
    let outputs = runner.run(&inputs).expect("the probe runs");
    let mut found = [0usize; 2];
    for (input, output) in inputs.iter().zip(&outputs) {
        let up = input.normal[1] > 0.0;
        let light = output.light[0];
        // No light at all is allowed (a dead end, see dead_end_probability), a light on the
        // wrong side never.
        if light != NO_LIGHT {
            assert!(below(light) != up, "light {light} for normal up {up}");
            found[usize::from(up)] += 1;
        }
        let given = input.light_index[0];
        let position = Vec3::from_slice(&input.position_random[..3]);
        let normal = Vec3::from_slice(&input.normal[..3]);
        if below(given) == up {
            // Behind the surface: probability 0 on both sides.
            assert_eq!(output.probabilities[2], 0.0);
            assert_eq!(
                get_light_tree_probability(texels, given, position, normal),
                0.0
            );
        } else {
            assert!(output.probabilities[2] > 0.0);
        }
    }
    println!(
        "lights found: {} of 200 with the normal down, {} of 200 up",
        found[0], found[1]
    );
    assert!(
        found[0] > 150 && found[1] > 150,
        "too many dead ends: {found:?}"
    );
    common::assert_validation_silent(&context);
}

#[test]
fn a_thousand_lights_render_consistently_with_the_power_cdf() {
    // scenes/many_lights.gltf (scripts/make_many_lights_scene.py): 1000 emissive triangles
    // along a corridor, none in view. Each integrator that samples lights, with the tree and
    // with power, at 32 x 24 and 64 spp with moments; `vkpath compare` (block z-tests with
    // both images' moments, family-wise alpha 0.01) must find them consistent.
    let scene = format!("{}/scenes/many_lights.gltf", env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    for integrator in ["nee", "mis"] {
        let mut images = Vec::new();
        for selection in ["tree", "power"] {
            let name = format!("{integrator}-{selection}.exr");
            let output = common::vkpath(
                dir.path(),
                &[
                    "render",
                    &scene,
                    "--integrator",
                    integrator,
                    "--light-selection",
                    selection,
                    "--width",
                    "32",
                    "--height",
                    "24",
                    "--spp",
                    "64",
                    "--moments",
                    "--validate",
                    "--json",
                    "-o",
                    &name,
                ],
            );
            assert!(
                output.status.success(),
                "render {name}: {}",
                String::from_utf8_lossy(&output.stderr)
            );
            let report: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
            assert_eq!(report["light_selection"], selection);
            images.push(name);
        }
        let output = common::vkpath(dir.path(), &["compare", &images[0], &images[1]]);
        assert!(
            output.status.success(),
            "{integrator}: tree and power differ: {}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

#[test]
fn the_default_is_the_tree_only_for_many_lights_and_bad_names_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let many = format!("{}/scenes/many_lights.gltf", env!("CARGO_MANIFEST_DIR"));
    let few = common::fixture("emissive_quad.gltf");
    for (scene, expected) in [(&many, "tree"), (&few, "power")] {
        let output = common::vkpath(
            dir.path(),
            &[
                "render",
                scene,
                "--integrator",
                "mis",
                "--width",
                "8",
                "--height",
                "8",
                "--spp",
                "1",
                "--json",
                "-o",
                "a.exr",
            ],
        );
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let report: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
        assert_eq!(report["light_selection"], expected, "{scene}");
    }
    let output = common::vkpath(
        dir.path(),
        &["render", "--light-selection", "cdf", "-o", "a.exr"],
    );
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("invalid value 'cdf' for '--light-selection"),
        "{stderr}"
    );
}
