//! The surface functions of `glsl/materials.glsl` (`is_opaque_hit`, `get_surface`,
//! `get_bsdf`) on the GPU (`glsl/probe_surface.comp`) against their Rust twins
//! (`vkpath::cpu::gltf_surface`), reading the same words (the packed triangles, shading data,
//! materials and texture atlas of `scenes/materials.gltf`: base-colour, metallic-roughness,
//! normal and emissive textures with texture transforms, alpha-masked and alpha-blended
//! materials, one- and double-sided emitters). Fixed inputs: points at barycentrics of a
//! fixed seed on every triangle, hit from random directions (front and back) and lit from
//! random directions. Decisions (opacity, which side) must agree exactly, the values within
//! the bounds justified below; the test prints its measured errors and asserts that the
//! validation layer stayed silent.

use crate::common;

use glam::{UVec2, Vec2, Vec3};
use vkpath::cpu::gltf_surface::{
    get_bsdf, get_bsdf_density, get_surface, get_triangle, has_delta_lobe, is_opaque_hit,
    sample_bsdf,
};
use vkpath::cpu::surface::{BSDF_LOBE_DELTA, BSDF_LOBE_TRANSMIT};
use vkpath::probe::inputs::InputRng;
use vkpath::probe::surface_probe::{
    SurfaceProbeInput, SurfaceProbeOutput, SurfaceProbeRunner, SurfaceWords,
};
use vkpath::scene::materials::AlphaMode;
use vkpath::scene::Scene;

/// Largest difference between the GPU's and the CPU's normals and material values (in
/// units of the value's magnitude, at least 1), from the normalisations (Vulkan: about 3
/// ulps each), the interpolations and, for textured values, the bilinear weights (which
/// the textures' twins match bit for bit, `tests/texture_twins.rs`). Measured on lavapipe
/// (9 892 inputs): 1.8e-7, 1.5 ulps; 64 ulps leave room for a driver with coarser
/// normalize().
const VALUE_TOLERANCE: f32 = 64.0 * f32::EPSILON;

/// Largest relative difference of `get_bsdf` (relative to the larger of the
/// two and to the base colour / pi, the diffuse lobe's size): the BRDF twins agree to 8
/// error units of `tests/brdf_twins.rs` (ulps times the half vector's condition, which
/// near a polished metal's mirror direction reaches 1e3), and the shading normal's few ulps
/// enter it with the same condition. Measured on lavapipe: 8.4e-6; 1e-4 is 12 times that.
const REFLECTION_TOLERANCE: f32 = 1.0e-4;

/// Inputs per triangle, and per triangle of an alpha-masked or alpha-blended material (few
/// triangles, where is_opaque_hit() has its branches).
const INPUTS_PER_TRIANGLE: usize = 2;
const INPUTS_PER_ALPHA_TRIANGLE: usize = 64;

fn unit(rng: &mut InputRng) -> Vec3 {
    rng.unit_vector()
}

/// Fixed inputs: on each triangle (more on those with alpha), points at random barycentrics (inside), hit from a random
/// direction at distance t in [0.5, 2] and lit from a random direction, with random alpha
/// seeds and ray counts.
fn inputs(scene: &Scene) -> Vec<SurfaceProbeInput> {
    let mut rng = InputRng::new(1804);
    let mut inputs = Vec::new();
    let materials = scene.materials.as_ref().expect("the scene has materials");
    for (index, triangle) in scene.triangles.iter().enumerate() {
        let material = &materials.materials[materials.triangles[index].material as usize];
        let count = match material.alpha_mode {
            AlphaMode::Opaque => INPUTS_PER_TRIANGLE,
            _ => INPUTS_PER_ALPHA_TRIANGLE,
        };
        for _ in 0..count {
            let (mut b_1, mut b_2) = (rng.uniform(), rng.uniform());
            if b_1 + b_2 > 1.0 {
                (b_1, b_2) = (1.0 - b_1, 1.0 - b_2);
            }
            let [p_0, p_1, p_2] = triangle.positions;
            let point = p_0 + b_1 * (p_1 - p_0) + b_2 * (p_2 - p_0);
            let direction = unit(&mut rng);
            let t = rng.range(0.5, 2.0);
            let light = unit(&mut rng);
            let seed = UVec2::new(rng.next_u32(), rng.next_u32());
            inputs.push(SurfaceProbeInput::new(
                index as u32,
                point - t * direction,
                direction,
                t,
                light,
                seed,
                rng.next_u32(),
            ));
        }
    }
    inputs
}

/// The largest difference between two vectors' components, in units of their magnitude
/// (at least 1).
fn difference(gpu: &[f32], cpu: Vec3) -> f32 {
    let gpu = Vec3::from_slice(&gpu[..3]);
    (gpu - cpu).abs().max_element() / cpu.abs().max_element().max(1.0)
}

#[test]
fn surface_functions_match_their_twins_on_the_gpu() {
    let scene = Scene::load(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/materials.gltf"),
    )
    .expect("the showcase scene loads");
    let words = SurfaceWords::new(&scene).expect("the scene packs");
    let texels = words.texels();
    let inputs = inputs(&scene);
    let context = common::validated_context();
    let runner = SurfaceProbeRunner::new(&context, &words).expect("the probe runs");
    let outputs: Vec<SurfaceProbeOutput> = runner.run(&inputs).expect("the probe runs");
    assert_eq!(outputs.len(), inputs.len());

    let (mut worst_value, mut worst_reflection) = (0f32, 0f32);
    let (mut transparent, mut back, mut reflecting, mut bent_normals) = (0, 0, 0, 0);
    for (input, gpu) in inputs.iter().zip(&outputs) {
        let triangle_index = input.triangle_seed[0];
        let origin = Vec3::from_slice(&input.ray_origin[..3]);
        let direction = Vec3::from_slice(&input.ray_direction[..3]);
        let t = input.ray_origin[3];
        let light = Vec3::from_slice(&input.light[..3]);
        let seed = UVec2::new(input.triangle_seed[1], input.triangle_seed[2]);
        let context = format!("triangle {triangle_index}, ray {origin} + t {direction}, t {t}");

        let opaque = is_opaque_hit(
            &texels,
            triangle_index,
            origin,
            direction,
            t,
            seed,
            input.triangle_seed[3],
        );
        assert_eq!(
            gpu.geometric_normal[3] == 1.0,
            opaque,
            "{context}: is_opaque_hit"
        );
        transparent += usize::from(!opaque);

        let triangle = get_triangle(&texels, triangle_index);
        let surface = get_surface(
            &texels,
            triangle_index,
            &triangle,
            origin + t * direction,
            direction,
        );
        // Which side: a sign decision on the same words, so exact.
        assert_eq!(
            Vec3::from_slice(&gpu.geometric_normal[..3]),
            surface.geometric_normal,
            "{context}: geometric normal"
        );
        back += usize::from(surface.geometric_normal != triangle.normal);
        bent_normals += usize::from(surface.shading_normal != surface.geometric_normal);
        let material = &surface.material;
        let values = [
            difference(&gpu.shading_normal, surface.shading_normal),
            difference(&gpu.base_color, material.base_color),
            difference(&gpu.specular_color, material.specular_color),
            difference(&gpu.emission, surface.emission),
            difference(
                &gpu.factors,
                Vec3::new(material.roughness, material.specular, material.ior),
            ),
            (gpu.base_color[3] - material.metallic).abs(),
        ];
        let value = values.into_iter().fold(0.0, f32::max);
        assert!(
            value <= VALUE_TOLERANCE,
            "{context}: {values:?}\n{gpu:?}\n{surface:?}"
        );
        worst_value = worst_value.max(value);

        let reflection = get_bsdf(&surface, -direction, light);
        let gpu_reflection = Vec3::from_slice(&gpu.reflection[..3]);
        let scale = reflection
            .abs()
            .max_element()
            .max(gpu_reflection.abs().max_element())
            .max(material.base_color.max_element() / std::f32::consts::PI);
        let error =
            (gpu_reflection - reflection).abs().max_element() / scale.max(f32::MIN_POSITIVE);
        assert!(
            error <= REFLECTION_TOLERANCE,
            "{context}: reflection {gpu_reflection} on the GPU, {reflection} on the CPU"
        );
        worst_reflection = worst_reflection.max(error);
        reflecting += usize::from(reflection.max_element() > 0.0);
    }
    // The inputs reach every branch: see-through hits, back faces, bent shading normals and
    // light on both sides.
    assert!(
        transparent >= 10 && back >= inputs.len() / 4 && bent_normals >= 10 && reflecting >= inputs.len() / 8,
        "{transparent} transparent, {back} from the back, {bent_normals} bent normals, {reflecting} reflecting"
    );
    println!(
        "{} inputs ({transparent} transparent, {back} from the back, {bent_normals} bent normals, \
         {reflecting} reflecting); largest GPU-CPU differences: values {worst_value:.2e}, \
         reflection {worst_reflection:.2e} relative",
        inputs.len()
    );
    common::assert_validation_silent(&context);
}

/// Inputs per triangle of a layered material (transmission, clear coat, unlit) in
/// `scenes/glass.gltf`, and per other triangle.
const INPUTS_PER_LAYERED_TRIANGLE: usize = 24;

/// Largest angle (radians) between the GPU's and the CPU's sampled directions where both
/// chose the same lobe; smooth glass maps the random numbers through a lobe 10^-4 wide and
/// refraction, each a few ulps: measured below.
const SAMPLED_DIRECTION_TOLERANCE: f32 = 1.0e-3;

/// Relative difference of densities, BSDF values and sample weights of the layered lobes
/// where both sides took the same lobe: a smooth lobe's peak (density ~3e7) amplifies the
/// half vector's ulps by its width 10^-4 (measured below).
const LAYERED_TOLERANCE: f32 = 2.0e-2;

#[test]
fn layered_surfaces_match_their_twins_on_the_gpu() {
    let scene =
        Scene::load(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glass.gltf"))
            .expect("the glass scene loads");
    let materials = scene.materials.as_ref().expect("the scene has materials");
    let words = SurfaceWords::new(&scene).expect("the scene packs");
    assert!(words.has_layers, "scenes/glass.gltf has layered materials");
    let texels = words.texels();
    let mut rng = InputRng::new(2718);
    let mut inputs = Vec::new();
    for (index, triangle) in scene.triangles.iter().enumerate() {
        let material = &materials.materials[materials.triangles[index].material as usize];
        let count = if material.is_layered() || material.unlit {
            INPUTS_PER_LAYERED_TRIANGLE
        } else {
            1
        };
        for _ in 0..count {
            let (mut b_1, mut b_2) = (rng.uniform(), rng.uniform());
            if b_1 + b_2 > 1.0 {
                (b_1, b_2) = (1.0 - b_1, 1.0 - b_2);
            }
            let [p_0, p_1, p_2] = triangle.positions;
            let point = p_0 + b_1 * (p_1 - p_0) + b_2 * (p_2 - p_0);
            let direction = rng.unit_vector();
            let t = rng.range(0.5, 2.0);
            let light = rng.unit_vector();
            let randoms = Vec2::new(rng.uniform(), rng.uniform());
            inputs.push(
                SurfaceProbeInput::new(
                    index as u32,
                    point - t * direction,
                    direction,
                    t,
                    light,
                    UVec2::new(rng.next_u32(), rng.next_u32()),
                    rng.next_u32(),
                )
                .with_randoms(randoms, rng.uniform()),
            );
        }
    }
    let context = common::validated_context();
    let runner = SurfaceProbeRunner::new(&context, &words).expect("the probe runs");
    let outputs: Vec<SurfaceProbeOutput> = runner.run(&inputs).expect("the probe runs");

    let (mut worst_value, mut worst_bsdf, mut worst_angle, mut worst_sample) =
        (0f32, 0f32, 0f32, 0f32);
    let (mut transmitted, mut coated, mut sheened, mut unlit, mut other_lobe) = (0, 0, 0, 0, 0);
    let (mut smooth, mut delta) = (0, 0);
    let relative = |gpu: f32, cpu: f32| (gpu - cpu).abs() / gpu.abs().max(cpu.abs()).max(1e-3);
    for (input, gpu) in inputs.iter().zip(&outputs) {
        let triangle_index = input.triangle_seed[0];
        let origin = Vec3::from_slice(&input.ray_origin[..3]);
        let direction = Vec3::from_slice(&input.ray_direction[..3]);
        let t = input.ray_origin[3];
        let light = Vec3::from_slice(&input.light[..3]);
        let context = format!("triangle {triangle_index}, ray {origin} + t {direction}, t {t}");
        let triangle = get_triangle(&texels, triangle_index);
        let surface = get_surface(
            &texels,
            triangle_index,
            &triangle,
            origin + t * direction,
            direction,
        );
        let material = &surface.material;
        let values = [
            (gpu.layers[0] - material.transmission).abs(),
            (gpu.layers[1] - material.thickness).abs(),
            (gpu.layers[2] - material.clearcoat).abs(),
            (gpu.layers[3] - material.clearcoat_roughness).abs(),
            difference(&gpu.clearcoat_normal, surface.clearcoat_normal),
            (gpu.clearcoat_normal[3] - surface.eta).abs(),
            difference(&gpu.extras, surface.unlit_color),
            difference(&gpu.base_color, material.base_color),
        ];
        let value = values.into_iter().fold(0.0, f32::max);
        assert!(value <= VALUE_TOLERANCE, "{context}: {values:?}");
        worst_value = worst_value.max(value);
        assert_eq!(
            gpu.factors[3] == 1.0,
            has_delta_lobe(&surface),
            "{context}: has_delta_lobe"
        );
        smooth += usize::from(has_delta_lobe(&surface));
        coated += usize::from(material.clearcoat > 0.0);
        // The velvet ball: its sheen shows in the BSDF and its density compared below.
        sheened += usize::from(material.sheen_color != Vec3::ZERO);
        unlit += usize::from(surface.unlit_color != Vec3::ZERO);

        let view = -direction;
        let bsdf = get_bsdf(&surface, view, light);
        let density = get_bsdf_density(&surface, view, light);
        let bsdf_error =
            relative(gpu.reflection[0], bsdf.x).max(relative(gpu.reflection[3], density));
        assert!(
            bsdf_error <= LAYERED_TOLERANCE,
            "{context}: bsdf {:?} density {} vs {bsdf} {density}",
            gpu.reflection,
            gpu.reflection[3]
        );
        worst_bsdf = worst_bsdf.max(bsdf_error);

        let random_numbers = Vec2::new(input.randoms[0], input.randoms[1]);
        let sample = sample_bsdf(&surface, view, random_numbers, input.randoms[2]);
        let gpu_direction = Vec3::from_slice(&gpu.sampled[..3]);
        let angle = if sample.direction.is_finite() && gpu_direction.is_finite() {
            gpu_direction.dot(sample.direction).clamp(-1.0, 1.0).acos()
        } else {
            0.0
        };
        if angle > SAMPLED_DIRECTION_TOLERANCE || gpu.sample_weight[3] as u32 != sample.lobes {
            // A lobe choice within rounding of its boundary.
            other_lobe += 1;
            continue;
        }
        worst_angle = worst_angle.max(angle);
        transmitted += usize::from(sample.lobes & BSDF_LOBE_TRANSMIT != 0);
        delta += usize::from(sample.lobes & BSDF_LOBE_DELTA != 0);
        // A delta pick (the smooth glass and pane): density 0 on both, weight its own f / p
        assert!(
            sample.lobes & BSDF_LOBE_DELTA == 0 || (sample.density == 0.0 && gpu.sampled[3] == 0.0),
            "{context}: a delta pick's density {} vs {}",
            gpu.sampled[3],
            sample.density
        );
        // The density of a narrow lobe near its peak (alpha 10^-4 had densities up to 10^10
        // at grazing views before roughness 0 became a delta lobe; the scene's clear coat:
        // alpha 9e-4) turns the half
        // vector's ulps into per cent or more (measured: 3% at 4.7e4, a factor 3 at 8.7e9),
        // so densities are compared only below 10^3; the weight, the
        // estimator's factor (f / p with both huge), agrees to LAYERED_TOLERANCE everywhere.
        assert!(
            sample.density > 1.0e3 || relative(gpu.sampled[3], sample.density) <= LAYERED_TOLERANCE,
            "{context}: density {} vs {}",
            gpu.sampled[3],
            sample.density
        );
        let sample_error =
            relative(gpu.sample_weight[0], sample.weight.x).max((gpu.extras[3] - sample.eta).abs());
        assert!(
            sample_error <= LAYERED_TOLERANCE,
            "{context}: sample {:?} {:?} vs {sample:?}",
            gpu.sampled,
            gpu.sample_weight
        );
        worst_sample = worst_sample.max(sample_error);
    }
    println!(
        "{} inputs ({transmitted} transmitted samples, {delta} delta picks at {smooth} surfaces \
         with a delta lobe, {coated} coated, {sheened} with sheen, {unlit} unlit, {other_lobe} \
         other lobe); largest GPU-CPU differences: values {worst_value:.2e}, bsdf and density \
         {worst_bsdf:.2e}, sampled direction {worst_angle:.2e} rad, sample {worst_sample:.2e}",
        inputs.len()
    );
    assert!(
        transmitted >= 100 && coated >= 20 && sheened >= 20 && unlit >= 10 && delta >= 100,
        "{transmitted} {coated} {sheened} {unlit} {delta}"
    );
    // Lobe choices that rounding flips: a few per ten thousand.
    assert!(
        other_lobe * 200 <= inputs.len(),
        "{other_lobe} of {} took another lobe",
        inputs.len()
    );
    common::assert_validation_silent(&context);
}
