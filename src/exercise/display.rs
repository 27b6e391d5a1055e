//! Runs the sample display (`glsl/exercise_samples.comp`) once and reads its colours back.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use glam::Vec3;

use super::view::{BrdfDisplaySetup, ExerciseSampler, SampleDisplayPushConstants};
use crate::contract::{EXERCISE_SAMPLER_DIRECTIONS, EXERCISE_SAMPLE_COUNT};
use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::kernels::{self, Bound, Resource};
use crate::render::settings::MAX_IMAGE_SIDE;
use crate::shaders;
use crate::vk::spirv_words;
use crate::vk::{Buffer, CommandRunner, Context};

/// Bytes per pixel of the output buffer (one `vec4`).
const BYTES_PER_PIXEL: u64 = 16;

/// Draws the `EXERCISE_SAMPLE_COUNT` samples of `sampler` (drawn from `seed`) on the unit
/// sphere, as the workshop's framework displays them for Exercises 4 and 5
/// (`ExerciseSampler::Brdf` with `BrdfDisplaySetup::default()`).
/// \return Display colours (linear RGB, alpha 1) as an image of one sample per pixel
pub fn render_sample_display(
    context: &Arc<Context>,
    sampler: ExerciseSampler,
    width: u32,
    height: u32,
    seed: u32,
) -> Result<RenderedImage> {
    let spirv = spirv_words(shaders::EXERCISE_SAMPLES)?;
    render_sample_display_with(context, &spirv, sampler, width, height, seed)
}

/// Draws the `EXERCISE_SAMPLE_COUNT` samples of `sample_brdf` for `brdf`'s material and view
/// (drawn from `seed`) on the unit sphere as `render_sample_display` draws its samplers, with
/// the view direction and its mirror direction marked.
/// \return Display colours (linear RGB, alpha 1) as an image of one sample per pixel
pub fn render_brdf_sample_display(
    context: &Arc<Context>,
    brdf: &BrdfDisplaySetup,
    width: u32,
    height: u32,
    seed: u32,
) -> Result<RenderedImage> {
    let spirv = spirv_words(shaders::EXERCISE_SAMPLES)?;
    let constants =
        SampleDisplayPushConstants::new(ExerciseSampler::Brdf, width, height, seed, brdf);
    draw_sample_display(context, &spirv, &constants)
}

/// Draws `directions` (world space, unit length, at most `EXERCISE_SAMPLE_COUNT`) on the
/// unit sphere as `render_sample_display` draws a sampler's samples
/// (`EXERCISE_SAMPLER_DIRECTIONS`): e.g. samples of a path guide's cell
/// (`vkpath exercise guide-cell`).
/// \return Display colours (linear RGB, alpha 1) as an image of one sample per pixel
pub fn render_direction_display(
    context: &Arc<Context>,
    directions: &[Vec3],
    width: u32,
    height: u32,
) -> Result<RenderedImage> {
    let count = EXERCISE_SAMPLE_COUNT as usize;
    if directions.is_empty() || directions.len() > count {
        return Err(Error::InvalidSettings(format!(
            "the display draws 1..={count} directions, not {}",
            directions.len()
        )));
    }
    // The kernel draws all EXERCISE_SAMPLE_COUNT: the rest repeat the first.
    let words: Vec<[f32; 4]> = (0..count)
        .map(|i| {
            directions
                .get(i)
                .unwrap_or(&directions[0])
                .extend(0.0)
                .to_array()
        })
        .collect();
    let spirv = spirv_words(shaders::EXERCISE_SAMPLES)?;
    let mut constants = SampleDisplayPushConstants::new(
        ExerciseSampler::Sphere,
        width,
        height,
        0,
        &BrdfDisplaySetup::default(),
    );
    constants.resolution_sampler_seed[2] = EXERCISE_SAMPLER_DIRECTIONS;
    draw_sample_display_of(context, &spirv, &constants, &words)
}

/// `render_sample_display` with `glsl/exercise_samples.comp` compiled elsewhere (e.g. with
/// a user's sampler, for `vkpath check`).
pub fn render_sample_display_with(
    context: &Arc<Context>,
    spirv: &[u32],
    sampler: ExerciseSampler,
    width: u32,
    height: u32,
    seed: u32,
) -> Result<RenderedImage> {
    let constants =
        SampleDisplayPushConstants::new(sampler, width, height, seed, &BrdfDisplaySetup::default());
    draw_sample_display(context, spirv, &constants)
}

/// Runs the display kernel `spirv` once with `constants` and reads its colours back.
fn draw_sample_display(
    context: &Arc<Context>,
    spirv: &[u32],
    constants: &SampleDisplayPushConstants,
) -> Result<RenderedImage> {
    draw_sample_display_of(context, spirv, constants, &[[0.0; 4]])
}

/// `draw_sample_display` with the directions `EXERCISE_SAMPLER_DIRECTIONS` draws.
fn draw_sample_display_of(
    context: &Arc<Context>,
    spirv: &[u32],
    constants: &SampleDisplayPushConstants,
    directions: &[[f32; 4]],
) -> Result<RenderedImage> {
    let [width, height, _, _] = constants.resolution_sampler_seed;
    if width == 0 || height == 0 || width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE {
        return Err(Error::InvalidSettings(format!(
            "image size {width}x{height} is outside 1..={MAX_IMAGE_SIDE} pixels per side"
        )));
    }
    let byte_size = u64::from(width) * u64::from(height) * BYTES_PER_PIXEL;
    let device_limit = u64::from(context.limits.max_storage_buffer_range);
    if byte_size > device_limit {
        return Err(Error::InvalidSettings(format!(
            "image size {width}x{height} needs {byte_size} bytes, more than the device's storage buffer limit of {device_limit}"
        )));
    }
    let pixels = Buffer::new(
        context,
        "sample display",
        byte_size,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )?;
    let direction_buffer = Buffer::with_data(
        context,
        "sample display directions",
        directions,
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let build = kernels::EXERCISE_SAMPLES.builds()[0];
    let pipeline = kernels::EXERCISE_SAMPLES.pipeline(context, &build, spirv, &[])?;
    let descriptors = pipeline.descriptor_set(|resource| match resource {
        Resource::ExercisePixels => Some(Bound::Buffer(&pixels)),
        Resource::ExerciseDirections => Some(Bound::Buffer(&direction_buffer)),
        _ => None,
    })?;
    let pipeline = &pipeline.pipeline;
    let commands = CommandRunner::new(context)?;
    commands.run(|recorder| {
        recorder.bind(pipeline, &descriptors);
        recorder.push_constants(pipeline, constants);
        recorder.dispatch(pipeline, [width, height, 1]);
        recorder.host_read_barrier();
    })?;
    let colors: Vec<[f32; 4]> = pixels.read();
    Ok(RenderedImage {
        width,
        height,
        second_moment: colors
            .iter()
            .map(|c| [c[0] * c[0], c[1] * c[1], c[2] * c[2]])
            .collect(),
        sample_count: vec![1.0; colors.len()],
        mean: colors,
    })
}
