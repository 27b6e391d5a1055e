//! Runs probe kernels: uploads a buffer of inputs, dispatches one invocation per input
//! (`PROBE_WORKGROUP_SIZE` per workgroup, in several dispatches and chunks when the inputs
//! exceed the device's limits) and reads the outputs back.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::contract;
use crate::error::{Error, Result};
use crate::probe::kernel::ProbePipeline;
use crate::probe::layout::ProbePushConstants;
use crate::render::gpu_types::{GpuTriangle, RenderUniforms};
use crate::scene::Triangle;
use crate::vk::{
    Buffer, CommandRunner, ComputePipeline, Context, DescriptorSet, Recorder, TexelBufferView,
};

/// Most inputs uploaded at once: bounds the size of the input and output buffers (128 MiB
/// for the largest structs, 128 bytes) well below every device's `maxStorageBufferRange`
/// of at least 2^27 bytes, while 10^6 inputs still go in one chunk.
const MAX_INPUTS_PER_CHUNK: usize = 1 << 20;
/// Inputs of the first chunk of every run (see `ProbeRunner::run`).
const FIRST_CHUNK: usize = 256;

/// Runs probe kernels against one scene (the triangles that `ray_mesh_intersection`,
/// `compute_direct_illumination` and `get_ray_radiance` see).
pub struct ProbeRunner {
    context: Arc<Context>,
    commands: CommandRunner,
    triangles: TexelBufferView,
    uniforms: Buffer,
}

impl ProbeRunner {
    /// Uploads `scene_triangles` (a texel buffer, as the path tracer reads them) and the
    /// render uniforms whose `.z` is their count. An empty scene is allowed: the kernels that
    /// do not trace rays need none.
    pub fn new(context: &Arc<Context>, scene_triangles: &[Triangle]) -> Result<ProbeRunner> {
        let mut packed: Vec<GpuTriangle> = scene_triangles.iter().map(GpuTriangle::new).collect();
        let count = packed.len() as u32;
        if packed.is_empty() {
            // A buffer cannot be empty; the count of 0 keeps the shader from reading this.
            packed.push(bytemuck::Zeroable::zeroed());
        }
        let triangles = TexelBufferView::new(
            context,
            Buffer::with_data(
                context,
                "probe triangles",
                &packed,
                vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            )?,
            vk::Format::R32G32B32A32_UINT,
        )?;
        let mut uniforms: RenderUniforms = bytemuck::Zeroable::zeroed();
        uniforms.resolution_triangle_count_seed = [1, 1, count, 0];
        let uniforms = Buffer::with_data(
            context,
            "probe uniforms",
            &[uniforms],
            vk::BufferUsageFlags::UNIFORM_BUFFER,
        )?;
        Ok(ProbeRunner {
            context: context.clone(),
            commands: CommandRunner::new(context)?,
            triangles,
            uniforms,
        })
    }

    /// The device the probes run on.
    pub fn context(&self) -> &Arc<Context> {
        &self.context
    }

    /// Evaluates the probe's function on every input and returns the outputs in order.
    /// `I` and `O` must be the kernel's `probe_input_t` and `probe_output_t` (see
    /// `ProbeKind`); their sizes are checked.
    pub fn run<I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        pipeline: &ProbePipeline,
        inputs: &[I],
    ) -> Result<Vec<O>> {
        let kind = pipeline.kind();
        let (input_size, output_size) = (std::mem::size_of::<I>(), std::mem::size_of::<O>());
        if (input_size, output_size) != (kind.input_size(), kind.output_size()) {
            return Err(Error::InvalidSettings(format!(
                "probe {kind:?} takes {} and gives {} bytes per element, not {input_size} and {output_size}",
                kind.input_size(),
                kind.output_size()
            )));
        }
        let mut outputs = Vec::with_capacity(inputs.len());
        // A small first chunk: a function that loops without end (vkpath check) is found
        // after a few hundred calls instead of a million.
        let (first, rest) = inputs.split_at(inputs.len().min(FIRST_CHUNK));
        for chunk in std::iter::once(first).chain(rest.chunks(MAX_INPUTS_PER_CHUNK)) {
            if !chunk.is_empty() {
                outputs.extend(self.run_chunk::<I, O>(pipeline, chunk)?);
            }
        }
        Ok(outputs)
    }

    /// One upload, as many dispatches as the workgroup-count limit needs, one read-back.
    fn run_chunk<I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        pipeline: &ProbePipeline,
        inputs: &[I],
    ) -> Result<Vec<O>> {
        let count = inputs.len();
        let input_buffer = Buffer::with_data(
            &self.context,
            "probe inputs",
            inputs,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let output_buffer = Buffer::new(
            &self.context,
            "probe outputs",
            (count * std::mem::size_of::<O>()) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuToCpu,
        )?;
        let flag_buffer = Buffer::new(
            &self.context,
            "probe flags",
            (count * 4) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuToCpu,
        )?;
        let descriptors = pipeline.pipeline.allocate_descriptor_set()?;
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        descriptors.write_texel_buffer(contract::BINDING_TRIANGLES, &self.triangles);
        descriptors.write_buffer(
            contract::BINDING_RENDER_UNIFORMS,
            vk::DescriptorType::UNIFORM_BUFFER,
            &self.uniforms,
        );
        descriptors.write_buffer(contract::PROBE_BINDING_INPUTS, storage, &input_buffer);
        descriptors.write_buffer(contract::PROBE_BINDING_OUTPUTS, storage, &output_buffer);
        descriptors.write_buffer(contract::PROBE_BINDING_FLAGS, storage, &flag_buffer);

        let compute = &pipeline.pipeline;
        let max_groups = self.context.limits.max_compute_work_group_count[0] as usize;
        self.commands.run(|recorder| {
            record_probe_dispatches(recorder, compute, &descriptors, count, max_groups)
        })?;
        let flags: Vec<u32> = flag_buffer.read();
        let limited = flags.iter().take(count).filter(|&&flag| flag != 0).count();
        if limited > 0 {
            return Err(Error::LoopLimit(format!(
                "in {limited} of {count} calls, {}'s loops ran more than {} iterations (an endless loop?)",
                pipeline.kind().function_name(),
                crate::check::source::USER_LOOP_LIMIT
            )));
        }
        let mut outputs: Vec<O> = output_buffer.read();
        outputs.truncate(count);
        Ok(outputs)
    }
}

/// Records the dispatches that run a probe kernel over `count` inputs: as many workgroups as
/// the inputs need, split into dispatches of at most the device's workgroup-count limit, each
/// told its first input by `ProbePushConstants`; then the barriers that make the outputs
/// readable on the host. Every probe runner records its work with it.
pub(crate) fn record_probe_dispatches(
    recorder: &mut Recorder,
    pipeline: &ComputePipeline,
    descriptors: &DescriptorSet,
    count: usize,
    max_groups: usize,
) {
    let group_size = pipeline.workgroup_size()[0].max(1) as usize;
    let total_groups = count.div_ceil(group_size);
    recorder.bind(pipeline, descriptors);
    let mut first_group = 0;
    while first_group < total_groups {
        let groups = (total_groups - first_group).min(max_groups.max(1));
        let constants = ProbePushConstants {
            first: (first_group * group_size) as u32,
            count: count as u32,
        };
        recorder.push_constants(pipeline, &constants);
        recorder.dispatch(pipeline, [(groups * group_size) as u32, 1, 1]);
        first_group += groups;
    }
    recorder.compute_barrier();
    recorder.host_read_barrier();
}
