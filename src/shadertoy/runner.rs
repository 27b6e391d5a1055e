//! Running a ShaderToy program on a device: one compute pipeline per pass, two `rgba32f`
//! images per buffer (ping-ponged: a pass writes this frame's and reads the previous
//! frame's), a target for the Image pass, and one descriptor set per pass and frame parity,
//! so that a frame is five dispatches with barriers between them and no descriptor updates.
//!
//! Every loop of the user's code is guarded (`pass.comp`): past `loop_limit` iterations in
//! one invocation its loops end and the pass sets its bit in a small report buffer, which
//! the host reads after every frame, so that a loop without end is an error naming the
//! pass, never a hang or (on lavapipe, which ends long loops silently) a wrong image.

use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::shadertoy::inputs::{FramePushConstants, PassConstants};
use crate::shadertoy::kernel::{compile_pass, PassError, UserTab};
use crate::shadertoy::program::{reads_previous_frame, ChannelSource, PassKind, Program};
use crate::shadertoy::textures::{flip_rows, read_channel_file, read_cube_channel};
use crate::vk::{
    Buffer, CommandRunner, ComputePipeline, Context, DescriptorSet, Sampler, StorageImage,
};

/// Binding of the pass's target.
const BINDING_TARGET: u32 = 0;
/// Binding of `iChannel0`; the others follow.
const BINDING_CHANNEL_FIRST: u32 = 1;
/// Binding of the uniform block of ShaderToy's constant inputs.
const BINDING_CONSTANTS: u32 = 5;
/// Binding of the buffer where passes report that their loops ran past the limit.
const BINDING_LOOP_REPORT: u32 = 6;
/// Specialization constant of a pass's bit in the loop report.
const SPEC_PASS_BIT: u32 = 0;
/// Specialization constant of the loop limit.
const SPEC_LOOP_LIMIT: u32 = 1;
/// Loop iterations one invocation may run on a GPU before its loops are ended (an endless
/// loop is stopped before a watchdog resets the device; a million iterations per pixel is
/// far beyond what a ShaderToy program runs).
const GPU_LOOP_LIMIT: u32 = 1 << 20;

/// Loop iterations one invocation of a pass may run on `context`'s device: on CPU devices
/// (lavapipe) llvmpipe's limit per SIMD program divided by its width, so that the driver
/// never ends a loop silently (glsl/shared.h), `GPU_LOOP_LIMIT` elsewhere.
pub fn loop_limit(context: &Context) -> u32 {
    if context.info.kind.is_gpu() {
        GPU_LOOP_LIMIT
    } else {
        crate::contract::LLVMPIPE_LOOP_LIMIT / crate::contract::LLVMPIPE_SIMD_WIDTH
    }
}
/// Largest image side accepted (ShaderToy's canvases are far smaller).
pub const MAX_SIDE: u32 = 8192;

/// A pass on the device.
struct GpuPass {
    kind: PassKind,
    /// The user's file, for messages.
    file: String,
    pipeline: ComputePipeline,
    /// Descriptor sets for even and odd frames.
    sets: [DescriptorSet; 2],
    /// The uniform buffer the sets point at (kept alive with them).
    _constants: Buffer,
}

/// A ShaderToy program ready to run frame after frame.
pub struct ShadertoyRunner {
    context: Arc<Context>,
    commands: CommandRunner,
    width: u32,
    height: u32,
    /// Pipelines and descriptor sets, in the order the passes run.
    passes: Vec<GpuPass>,
    /// Two images per buffer of the program (index: frame parity).
    buffers: [Option<[StorageImage; 2]>; 4],
    /// The Image pass's target.
    image_target: StorageImage,
    /// Images of channel files and the black texture of unbound channels (kept alive for
    /// the descriptor sets).
    _textures: Vec<StorageImage>,
    _sampler: Sampler,
    /// Frames run so far.
    frames: u32,
    /// Where the passes report loops past the limit (one bit per pass; host-visible).
    loop_report: Buffer,
    /// Loop iterations one invocation may run (see `loop_limit`).
    loop_limit: u32,
    /// Compiler warnings, naming the user's files.
    pub warnings: String,
    /// What the intake changed in each tab, one line each, naming the file.
    pub notes: Vec<String>,
}

/// A compiled program: the SPIR-V of each pass (in the program's order), the compiler's
/// warnings and the intake's notes (one line each, naming the file).
pub type CompiledPasses = (Vec<Vec<u32>>, String, Vec<String>);

/// Compiles every pass of `program` for `resolution` (width, height) pixels, each pass on
/// its own after the Common tab; the first failure is the compiler's messages (naming the
/// user's file and line). Returns the SPIR-V of each pass, the warnings and the intake's
/// notes.
pub fn compile_program(
    program: &Program,
    resolution: (u32, u32),
) -> std::result::Result<CompiledPasses, PassError> {
    let common = program
        .common
        .as_ref()
        .map(|(path, text)| UserTab::new(path, text, resolution));
    let mut notes = Vec::new();
    if let Some(common) = &common {
        notes.extend(common.notes());
    }
    let mut spirv = Vec::new();
    let mut warnings = String::new();
    for pass in &program.passes {
        let tab = UserTab::new(&pass.path, &pass.text, resolution);
        notes.extend(tab.notes());
        let cube_channels = pass
            .channels
            .each_ref()
            .map(|c| matches!(c, Some(ChannelSource::Cube(_))));
        let compiled = compile_pass(common.as_ref(), &tab, cube_channels)?;
        if !compiled.warnings.trim().is_empty() && !warnings.contains(&compiled.warnings) {
            warnings.push_str(&compiled.warnings);
            warnings.push('\n');
        }
        spirv.push(compiled.spirv);
    }
    Ok((spirv, warnings, notes))
}

impl ShadertoyRunner {
    /// Compiles the program's passes (see `compile_program`; a failure is
    /// `Error::ShaderCompilation` with the compiler's messages) and creates everything it
    /// needs for `width` x `height` pixels; every buffer starts at zero.
    pub fn new(
        context: &Arc<Context>,
        program: &Program,
        width: u32,
        height: u32,
    ) -> Result<ShadertoyRunner> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(Error::InvalidSettings(format!(
                "{width}x{height} pixels: width and height must be 1..={MAX_SIDE}"
            )));
        }
        let (spirv, warnings, notes) = compile_program(program, (width, height))
            .map_err(|error| Error::ShaderCompilation(error.to_string()))?;
        let loop_limit = loop_limit(context);
        let loop_report = Buffer::with_data(
            context,
            "shadertoy loop report",
            &[0u32],
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let commands = CommandRunner::new(context)?;
        let sampler = Sampler::linear_clamp(context)?;
        let mut textures = Vec::new();
        let black = StorageImage::sampled_2d(context, "black channel", 1, 1)?;
        commands.run(|r| r.clear_storage_image(&black))?;
        textures.push(black);
        let mut buffers: [Option<[StorageImage; 2]>; 4] = Default::default();
        for pass in &program.passes {
            if let Some(index) = pass.kind.buffer_index() {
                let name = pass.kind.name();
                let pair = [
                    StorageImage::sampled_2d(context, name, width, height)?,
                    StorageImage::sampled_2d(context, name, width, height)?,
                ];
                commands.run(|r| {
                    r.clear_storage_image(&pair[0]);
                    r.clear_storage_image(&pair[1]);
                })?;
                buffers[index] = Some(pair);
            }
        }
        let image_target = StorageImage::sampled_2d(context, "image", width, height)?;
        commands.run(|r| r.clear_storage_image(&image_target))?;

        // Channel files (2D textures and cube maps), each loaded once.
        let mut files: Vec<(&ChannelSource, usize, (u32, u32))> = Vec::new();
        for pass in &program.passes {
            for source in pass.channels.iter().flatten() {
                if files.iter().any(|(s, _, _)| *s == source) {
                    continue;
                }
                let (texture, (w, h), texels) = match source {
                    ChannelSource::Cube(path) => {
                        let (side, texels) = read_cube_channel(path)?;
                        let cube = StorageImage::sampled_cube(context, "channel cube map", side)?;
                        (cube, (side, side), texels)
                    }
                    ChannelSource::File(path) => {
                        let (w, h, texels) = read_channel_file(path)?;
                        let image = StorageImage::sampled_2d(context, "channel image", w, h)?;
                        (image, (w, h), texels)
                    }
                    ChannelSource::Buffer(_) => continue,
                };
                let staging = Buffer::with_data(
                    context,
                    "channel staging",
                    &texels,
                    vk::BufferUsageFlags::TRANSFER_SRC,
                )?;
                commands.run(|r| {
                    r.clear_storage_image(&texture);
                    r.copy_buffer_to_image(&staging, &texture);
                    r.compute_barrier();
                })?;
                files.push((source, textures.len(), (w, h)));
                textures.push(texture);
            }
        }

        let bindings = [
            (BINDING_TARGET, vk::DescriptorType::STORAGE_IMAGE),
            (
                BINDING_CHANNEL_FIRST,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            ),
            (
                BINDING_CHANNEL_FIRST + 1,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            ),
            (
                BINDING_CHANNEL_FIRST + 2,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            ),
            (
                BINDING_CHANNEL_FIRST + 3,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            ),
            (BINDING_CONSTANTS, vk::DescriptorType::UNIFORM_BUFFER),
            (BINDING_LOOP_REPORT, vk::DescriptorType::STORAGE_BUFFER),
        ];
        let push_size = std::mem::size_of::<FramePushConstants>() as u32;
        let mut passes = Vec::new();
        for (index, (pass, spirv)) in program.passes.iter().zip(&spirv).enumerate() {
            let specialization = [
                (SPEC_PASS_BIT, 1u32 << index),
                (SPEC_LOOP_LIMIT, loop_limit),
            ];
            let pipeline =
                ComputePipeline::new(context, spirv, &bindings, push_size, &specialization)?;
            // What each channel reads at frame parity p: its image and its size.
            let channel = |c: usize, parity: usize| -> (&StorageImage, (u32, u32)) {
                match &pass.channels[c] {
                    None => (&textures[0], (1, 1)),
                    Some(source @ (ChannelSource::File(_) | ChannelSource::Cube(_))) => {
                        let (_, index, size) = files
                            .iter()
                            .find(|(s, _, _)| *s == source)
                            .expect("loaded above");
                        (&textures[*index], *size)
                    }
                    Some(ChannelSource::Buffer(source)) => {
                        let pair = source
                            .buffer_index()
                            .and_then(|i| buffers[i].as_ref())
                            .expect("Program::bind checks that the buffer exists");
                        let previous = reads_previous_frame(pass.kind, *source);
                        (
                            &pair[if previous { 1 - parity } else { parity }],
                            (width, height),
                        )
                    }
                }
            };
            let sizes = [0, 1, 2, 3].map(|c| channel(c, 0).1);
            let constants = Buffer::with_data(
                context,
                "shadertoy constants",
                &[PassConstants::new(width, height, sizes)],
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            )?;
            let sets = [
                pipeline.allocate_descriptor_set()?,
                pipeline.allocate_descriptor_set()?,
            ];
            for (parity, set) in sets.iter().enumerate() {
                let target = match pass.kind.buffer_index() {
                    Some(i) => &buffers[i].as_ref().expect("created above")[parity],
                    None => &image_target,
                };
                set.write_storage_image(BINDING_TARGET, target);
                for c in 0..4 {
                    set.write_sampled_image(
                        BINDING_CHANNEL_FIRST + c as u32,
                        channel(c, parity).0,
                        &sampler,
                    );
                }
                set.write_buffer(
                    BINDING_CONSTANTS,
                    vk::DescriptorType::UNIFORM_BUFFER,
                    &constants,
                );
                set.write_buffer(
                    BINDING_LOOP_REPORT,
                    vk::DescriptorType::STORAGE_BUFFER,
                    &loop_report,
                );
            }
            passes.push(GpuPass {
                kind: pass.kind,
                file: pass.path.display().to_string(),
                pipeline,
                sets,
                _constants: constants,
            });
        }
        Ok(ShadertoyRunner {
            context: context.clone(),
            commands,
            width,
            height,
            passes,
            buffers,
            image_target,
            _textures: textures,
            _sampler: sampler,
            frames: 0,
            loop_report,
            loop_limit,
            warnings,
            notes,
        })
    }

    /// Frames run so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Runs the next frame: every pass in order, each seeing what the passes before it
    /// wrote this frame. Returns when the device has finished it. A pass whose loops ran
    /// past the limit in some pixel is `Error::LoopLimit` naming it (the frame does not
    /// count: its images hold loops that were cut short).
    pub fn run_frame(&mut self) -> Result<()> {
        let frame = self.frames;
        let parity = (frame % 2) as usize;
        let constants = FramePushConstants::for_frame(frame);
        let size = [self.width, self.height, 1];
        let passes = &self.passes;
        self.commands.run(|r| {
            for pass in passes {
                r.bind(&pass.pipeline, &pass.sets[parity]);
                r.push_constants(&pass.pipeline, &constants);
                r.dispatch(&pass.pipeline, size);
                r.compute_barrier();
            }
            r.host_read_barrier();
        })?;
        let report = self.loop_report.read::<u32>().first().copied().unwrap_or(0);
        if report != 0 {
            let passes: Vec<String> = self
                .passes
                .iter()
                .enumerate()
                .filter(|(index, _)| report & (1 << index) != 0)
                .map(|(_, pass)| format!("{} ({})", pass.file, pass.kind.name()))
                .collect();
            return Err(Error::LoopLimit(format!(
                "frame {frame}: the loops of {} ran past {} iterations in one pixel (all loops of one call \
                 together): an endless loop, or more work per pixel than vkpath runs on this device{}",
                passes.join(" and "),
                self.loop_limit,
                if self.context.info.kind.is_gpu() {
                    ""
                } else {
                    " (on a CPU device llvmpipe would end such loops silently and the image would be wrong)"
                }
            )));
        }
        self.frames += 1;
        Ok(())
    }

    /// The latest contents of a pass's target as an image (rows top-down, RGBA as the
    /// shader wrote them; zero before the first frame). `None` when the program lacks it.
    pub fn read(&self, kind: PassKind) -> Result<Option<RenderedImage>> {
        let target = match kind.buffer_index() {
            None => &self.image_target,
            Some(index) => match &self.buffers[index] {
                None => return Ok(None),
                // The last frame wrote the image of its parity.
                Some(pair) => &pair[(self.frames.max(1) as usize - 1) % 2],
            },
        };
        let host = Buffer::new(
            &self.context,
            "shadertoy readback",
            target.byte_size(),
            vk::BufferUsageFlags::TRANSFER_DST,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        self.commands
            .run(|r| r.copy_image_to_buffer(target, &host))?;
        let bottom_up: Vec<[f32; 4]> = host.read();
        let mean = flip_rows(&bottom_up, self.width, self.height);
        let count = mean.len();
        Ok(Some(RenderedImage {
            width: self.width,
            height: self.height,
            mean,
            second_moment: vec![[0.0; 3]; count],
            sample_count: vec![1.0; count],
        }))
    }

    /// The passes, in the order they run.
    pub fn pass_kinds(&self) -> Vec<PassKind> {
        self.passes.iter().map(|p| p.kind).collect()
    }
}
