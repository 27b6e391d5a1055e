//! The texture functions of `glsl/textures.glsl` on the GPU (`glsl/probe_sample_texture.comp`)
//! against their Rust twins (`vkpath::cpu::textures`), on the same atlas, slots and inputs:
//! every wrap mode (also mixed between u and v) × sRGB on and off × nearest and bilinear ×
//! identity and rotating transforms, at random coordinates, texel centres, far outside
//! [0, 1] (±1e4), negative, and at NaN and infinities. Integer results (wrapping) and the
//! texture transform must match bit for bit, texels and samples within bounds justified
//! below; every test prints its measured maximum errors and asserts that the validation
//! layer stayed silent.

use crate::common;

use glam::{IVec2, UVec4, Vec2, Vec4};
use vkpath::contract::{WRAP_CLAMP_TO_EDGE, WRAP_MIRRORED_REPEAT, WRAP_REPEAT};
use vkpath::cpu::textures::{
    get_texel, sample_texture, srgb_to_linear, transform_tex_coord, unpack_texture_slot,
    wrap_texel_coordinate, TextureSlot,
};
use vkpath::probe::inputs::InputRng;
use vkpath::probe::texture_probe::{TextureProbeInput, TextureProbeOutput, TextureProbeRunner};
use vkpath::render::gpu_textures::{GpuTextureSlot, TextureAtlas};
use vkpath::scene::textures::{DecodedImage, Texture, TextureTransform, WrapMode};

/// Largest difference between a GPU and a CPU texel or sample whose texture is not sRGB:
/// none. The twins read the same bytes, scale them by the same correctly rounded product,
/// and the shader's `precise` arithmetic (transform, u * width - 0.5, floor, weights and
/// the weighted sum) is rounded operation by operation as Rust rounds it. Measured on
/// lavapipe (95 040 inputs on 648 slots): 0, and the transform bit for bit.
const LINEAR_TOLERANCE: f32 = 0.0;

/// Largest difference for sRGB textures (values in [0, 1]): the GPU's pow() is
/// exp2(2.4 * log2(x)), which Vulkan bounds to about 2e-6 relative for these arguments
/// (log2: 2^-21 absolute near 1, 3 ulps elsewhere; exp2: 3 + 2|x| ulps), and the linear
/// segment's division is only 2.5 ulps; a bilinear mix is a convex combination, so it keeps
/// the bound. 4e-6 is that bound with a margin of 2; the measured error is printed.
/// Measured on lavapipe: 2.4e-7 for samples (2 ulps of one), 1.8e-7 for texels, 6.7e-7
/// relative for srgb_to_linear() on random arguments in [0, 1).
const SRGB_TOLERANCE: f32 = 4.0e-6;

/// The same texture in several samplers: its texels (RGBA8, random bytes) and size.
struct TestTexture {
    width: u32,
    height: u32,
    texels: Vec<[u8; 4]>,
}

/// Textures of power-of-two sizes (texel centres exactly representable), odd sizes, a
/// single texel, a single row and a single column.
fn test_textures(rng: &mut InputRng) -> Vec<TestTexture> {
    [(4, 4), (3, 5), (1, 1), (7, 1), (1, 6), (16, 8)]
        .into_iter()
        .map(|(width, height)| TestTexture {
            width,
            height,
            texels: (0..width * height)
                .map(|_| rng.next_u32().to_le_bytes())
                .collect(),
        })
        .collect()
}

/// The samplers every texture is tested with: (wrap_s, wrap_t, nearest, srgb, transform).
fn sampler_cases() -> Vec<(WrapMode, WrapMode, bool, bool, TextureTransform)> {
    let modes = [
        WrapMode::Repeat,
        WrapMode::ClampToEdge,
        WrapMode::MirroredRepeat,
    ];
    let transforms = [
        TextureTransform::identity(),
        TextureTransform::from_gltf([0.25, -0.5], 0.7, [1.5, -2.0]),
        TextureTransform::from_gltf([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5]),
    ];
    let mut cases = Vec::new();
    for wrap_s in modes {
        for wrap_t in modes {
            for nearest in [false, true] {
                for srgb in [false, true] {
                    for transform in transforms {
                        cases.push((wrap_s, wrap_t, nearest, srgb, transform));
                    }
                }
            }
        }
    }
    cases
}

/// Texture coordinates for one slot: texel centres (of the untransformed texture), random
/// ones in [-2, 3], far outside (±1e4 and beyond), texel edges, and non-finite ones.
fn tex_coords(rng: &mut InputRng, width: u32, height: u32) -> Vec<Vec2> {
    let mut coords = Vec::new();
    for y in 0..height {
        for x in 0..width {
            coords.push(Vec2::new(
                (x as f32 + 0.5) / width as f32,
                (y as f32 + 0.5) / height as f32,
            ));
            coords.push(Vec2::new(x as f32 / width as f32, y as f32 / height as f32));
        }
    }
    for _ in 0..64 {
        coords.push(Vec2::new(rng.range(-2.0, 3.0), rng.range(-2.0, 3.0)));
    }
    for _ in 0..16 {
        coords.push(Vec2::new(
            rng.range(-1.0e4, 1.0e4),
            rng.range(-1.0e4, 1.0e4),
        ));
    }
    for special in [
        Vec2::new(1.0e4, -1.0e4),
        Vec2::new(-1.0e4, 1.0e4),
        Vec2::new(-0.0, -1.0e-30),
        Vec2::new(1.0e30, -1.0e30),
        Vec2::new(f32::NAN, 0.5),
        Vec2::new(0.5, f32::NAN),
        Vec2::NAN,
        Vec2::new(f32::INFINITY, f32::NEG_INFINITY),
        Vec2::new(f32::MAX, -f32::MAX),
    ] {
        coords.push(special);
    }
    coords
}

/// Everything one test compares: the atlas, the slots (packed and as the twins take them)
/// and the inputs.
struct Cases {
    atlas: TextureAtlas,
    slots: Vec<GpuTextureSlot>,
    srgb: Vec<bool>,
    inputs: Vec<TextureProbeInput>,
}

fn cases() -> Cases {
    let mut rng = InputRng::new(7);
    let textures = test_textures(&mut rng);
    let plain: Vec<Texture> = textures
        .iter()
        .map(|t| {
            let image = DecodedImage {
                width: t.width,
                height: t.height,
                texels: t.texels.clone(),
            };
            Texture::new(image, WrapMode::Repeat, WrapMode::Repeat, false)
        })
        .collect();
    let atlas = TextureAtlas::new(&plain, u64::from(u32::MAX)).expect("small atlas");
    let (mut slots, mut srgb_flags, mut inputs) = (Vec::new(), Vec::new(), Vec::new());
    let wrap_modes = [WRAP_REPEAT, WRAP_CLAMP_TO_EDGE, WRAP_MIRRORED_REPEAT, 3];
    for (texture, &first_texel) in plain.iter().zip(&atlas.first_texels) {
        for (wrap_s, wrap_t, nearest, srgb, transform) in sampler_cases() {
            let sampler = Texture {
                wrap_s,
                wrap_t,
                nearest,
                ..texture.clone()
            };
            let slot_index = slots.len() as u32;
            slots.push(GpuTextureSlot::new(first_texel, &sampler, srgb, &transform));
            srgb_flags.push(srgb);
            for tex_coord in tex_coords(&mut rng, texture.width, texture.height) {
                let texel = IVec2::new(
                    (rng.range(-40.0, 40.0)) as i32,
                    (rng.range(-40.0, 40.0)) as i32,
                );
                let wrap = (
                    (rng.range(-1000.0, 1000.0)) as i32,
                    (rng.range(-1.0, 20.0)) as i32,
                    wrap_modes[(rng.next_u32() % 4) as usize],
                );
                inputs.push(TextureProbeInput::new(
                    slot_index,
                    tex_coord,
                    texel,
                    rng.uniform(),
                    wrap,
                ));
            }
        }
    }
    Cases {
        atlas,
        slots,
        srgb: srgb_flags,
        inputs,
    }
}

fn twin_slot(slot: &GpuTextureSlot) -> TextureSlot {
    let [a, b, c] = slot.to_texels().map(UVec4::from_array);
    unpack_texture_slot(a, b, c)
}

/// Whether two floats are the same: equal bits, or both NaN.
fn same_float(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()) || (a == 0.0 && b == 0.0)
}

/// Largest errors of one run, by what they measure.
#[derive(Default, Debug)]
struct MaxErrors {
    linear_sample: f32,
    srgb_sample: f32,
    linear_texel: f32,
    srgb_texel: f32,
    srgb_to_linear_relative: f32,
    transform_mismatches: usize,
    wrap_mismatches: usize,
}

#[test]
fn texture_functions_match_their_twins() {
    let context = common::validated_context();
    let cases = cases();
    let runner =
        TextureProbeRunner::new(&context, &cases.atlas, &cases.slots).expect("texture probe");
    let outputs: Vec<TextureProbeOutput> = runner.run(&cases.inputs).expect("probe run");
    assert_eq!(outputs.len(), cases.inputs.len());
    let slots: Vec<TextureSlot> = cases.slots.iter().map(twin_slot).collect();
    let texels = &cases.atlas.texels;
    let mut worst = MaxErrors::default();
    let mut reported = 0;
    let mut report = |what: &str, input: &TextureProbeInput, gpu: String, cpu: String| {
        if reported < 10 {
            println!("{what} differs at {input:?}: GPU {gpu}, CPU {cpu}");
            reported += 1;
        }
    };
    for (input, output) in cases.inputs.iter().zip(&outputs) {
        let slot_index = input.slot_and_mode[0] as usize;
        let (slot, srgb) = (&slots[slot_index], cases.srgb[slot_index]);

        let sampled = sample_texture(texels, slot, input.tex_coord());
        assert!(output.sampled().is_finite(), "{input:?}: {:?}", output);
        let error = (output.sampled() - sampled).abs().max_element();
        let (worst_sample, tolerance) = if srgb {
            (&mut worst.srgb_sample, SRGB_TOLERANCE)
        } else {
            (&mut worst.linear_sample, LINEAR_TOLERANCE)
        };
        *worst_sample = worst_sample.max(error);
        if error > tolerance {
            report(
                "sample_texture",
                input,
                output.sampled().to_string(),
                sampled.to_string(),
            );
        }

        let texel = get_texel(texels, slot, input.texel());
        let error = (output.texel() - texel).abs().max_element();
        let worst_texel = if srgb {
            &mut worst.srgb_texel
        } else {
            &mut worst.linear_texel
        };
        *worst_texel = worst_texel.max(error);

        let transformed = transform_tex_coord(slot, input.tex_coord());
        let gpu_transformed = output.transformed();
        if !(same_float(gpu_transformed.x, transformed.x)
            && same_float(gpu_transformed.y, transformed.y))
        {
            worst.transform_mismatches += 1;
            report(
                "transform_tex_coord",
                input,
                gpu_transformed.to_string(),
                transformed.to_string(),
            );
        }

        let linear = srgb_to_linear(input.tex_coord[2]);
        let relative = (output.transformed_and_linear[2] - linear).abs() / linear.max(1e-30);
        worst.srgb_to_linear_relative = worst.srgb_to_linear_relative.max(relative);

        let [coordinate, size] = [input.texel_and_wrap[2], input.texel_and_wrap[3]];
        let wrapped = wrap_texel_coordinate(coordinate, size, input.slot_and_mode[1]);
        if output.wrapped[0] != wrapped {
            worst.wrap_mismatches += 1;
            report(
                "wrap_texel_coordinate",
                input,
                output.wrapped[0].to_string(),
                wrapped.to_string(),
            );
        }
    }
    println!(
        "texture twins: {} inputs on {} slots; max |GPU - CPU|: samples {} (linear), {} (sRGB); texels {} (linear), {} (sRGB); srgb_to_linear relative {}; transform mismatches {}, wrap mismatches {}",
        cases.inputs.len(),
        cases.slots.len(),
        worst.linear_sample,
        worst.srgb_sample,
        worst.linear_texel,
        worst.srgb_texel,
        worst.srgb_to_linear_relative,
        worst.transform_mismatches,
        worst.wrap_mismatches
    );
    assert_eq!(
        worst.wrap_mismatches, 0,
        "wrap_texel_coordinate must be exact"
    );
    assert_eq!(
        worst.transform_mismatches, 0,
        "transform_tex_coord must be bit-exact"
    );
    assert!(worst.linear_texel <= LINEAR_TOLERANCE, "{worst:?}");
    assert!(worst.linear_sample <= LINEAR_TOLERANCE, "{worst:?}");
    assert!(worst.srgb_texel <= SRGB_TOLERANCE, "{worst:?}");
    assert!(worst.srgb_sample <= SRGB_TOLERANCE, "{worst:?}");
    assert!(worst.srgb_to_linear_relative <= SRGB_TOLERANCE, "{worst:?}");
    common::assert_validation_silent(&context);
}

/// At the centre of a texel, with the identity transform and a power-of-two size, the GPU
/// returns exactly that texel's decoded value, whatever the wrap mode or filter.
#[test]
fn texel_centres_read_exactly_their_texel_on_the_gpu() {
    let context = common::validated_context();
    let mut rng = InputRng::new(11);
    let (width, height) = (8u32, 4u32);
    let image = DecodedImage {
        width,
        height,
        texels: (0..width * height)
            .map(|_| rng.next_u32().to_le_bytes())
            .collect(),
    };
    let texture = Texture::new(image, WrapMode::Repeat, WrapMode::Repeat, false);
    let atlas = TextureAtlas::new(std::slice::from_ref(&texture), 1 << 20).expect("fits");
    let mut slots = Vec::new();
    for wrap in [
        WrapMode::Repeat,
        WrapMode::ClampToEdge,
        WrapMode::MirroredRepeat,
    ] {
        for nearest in [false, true] {
            let sampler = Texture {
                wrap_s: wrap,
                wrap_t: wrap,
                nearest,
                ..texture.clone()
            };
            slots.push(GpuTextureSlot::new(
                0,
                &sampler,
                false,
                &TextureTransform::identity(),
            ));
        }
    }
    let mut inputs = Vec::new();
    for slot_index in 0..slots.len() as u32 {
        for y in 0..height {
            for x in 0..width {
                let centre = Vec2::new(
                    (x as f32 + 0.5) / width as f32,
                    (y as f32 + 0.5) / height as f32,
                );
                let texel = IVec2::new(x as i32, y as i32);
                inputs.push(TextureProbeInput::new(
                    slot_index,
                    centre,
                    texel,
                    0.5,
                    (0, 1, 0),
                ));
            }
        }
    }
    let runner = TextureProbeRunner::new(&context, &atlas, &slots).expect("texture probe");
    let outputs = runner.run(&inputs).expect("probe run");
    for (input, output) in inputs.iter().zip(&outputs) {
        let raw =
            texture.texels[(input.texel().y as u32 * width + input.texel().x as u32) as usize];
        let expected = Vec4::from_array(raw.map(|b| f32::from(b) / 255.0));
        assert_eq!(output.sampled(), output.texel(), "{input:?}");
        // Within one ulp of b / 255 (the twins multiply by the rounded 1/255).
        let error = (output.sampled() - expected).abs().max_element();
        assert!(
            error <= f32::EPSILON / 2.0,
            "{input:?}: {} vs {expected}",
            output.sampled()
        );
    }
    println!(
        "texel centres: {} lookups, each exactly its texel",
        inputs.len()
    );
    common::assert_validation_silent(&context);
}
