//! Runs probe kernels, the one runner of them all: `Probe` uploads a buffer of inputs,
//! dispatches one invocation per input (`PROBE_WORKGROUP_SIZE` per workgroup, in several
//! dispatches and chunks when the inputs exceed the device's limits) and reads the outputs
//! back, binding what the kernel's table (`crate::kernels::bindings`) asks for besides its
//! inputs, outputs and flags from the caller. `ProbeRunner` runs the workshop functions'
//! probes against a scene (`ProbeScene`); the BRDF, texture and BVH probes use `Probe` with
//! their own resources.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::kernels::{Bound, Kernel, KernelPipeline, Resource};
use crate::probe::kernel::ProbePipeline;
use crate::probe::layout::ProbePushConstants;
use crate::render::gpu_types::{GpuTriangle, RenderUniforms};
use crate::scene::Triangle;
use crate::vk::{Buffer, CommandRunner, Context, DescriptorSet, Recorder, TexelBufferView};

/// Most inputs uploaded at once: bounds the size of the input and output buffers (128 MiB
/// for the largest structs, 128 bytes) well below every device's `maxStorageBufferRange`
/// of at least 2^27 bytes, while 10^6 inputs still go in one chunk.
const MAX_INPUTS_PER_CHUNK: usize = 1 << 20;
/// Inputs of the first chunk of every run: a function that loops without end (`vkpath
/// check`) is found after a few hundred calls instead of a million.
const FIRST_CHUNK: usize = 256;

/// A probe kernel that reads one RGBA32_UINT texel buffer besides its inputs (the guide's,
/// the light tree's or the punctual lights' words): the buffer is uploaded once and bound
/// as `resource` for every run.
pub struct TexelBufferProbe {
    probe: Probe,
    resource: Resource,
    texels: TexelBufferView,
}

impl TexelBufferProbe {
    /// Uploads `data` (whole texels of four 32-bit words) for `kernel`'s embedded build,
    /// which evaluates `function` (for messages) and reads them as `resource`.
    pub fn new<T: bytemuck::Pod>(
        context: &Arc<Context>,
        kernel: &'static Kernel,
        function: &str,
        resource: Resource,
        data: &[T],
    ) -> Result<TexelBufferProbe> {
        let label = format!("probe texels of {function}");
        let buffer = Buffer::with_data(
            context,
            &label,
            data,
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
        )?;
        Ok(TexelBufferProbe {
            probe: Probe::embedded(context, kernel, &[], function)?,
            resource,
            texels: TexelBufferView::rgba32_uint(context, buffer, &label)?,
        })
    }

    /// Evaluates the function on every input and returns the outputs in order.
    pub fn run<I: bytemuck::Pod, O: bytemuck::Pod>(&self, inputs: &[I]) -> Result<Vec<O>> {
        let texels = Bound::TexelBuffer(&self.texels);
        self.probe.run_with(&[(self.resource, texels)], inputs)
    }
}

/// A probe kernel's pipeline, ready to evaluate its function on buffers of inputs.
pub struct Probe {
    context: Arc<Context>,
    commands: CommandRunner,
    pipeline: KernelPipeline,
    /// What it evaluates, for messages.
    function: String,
}

impl Probe {
    /// The pipeline of `kernel`'s plain build from `spirv` (embedded, or compiled at run
    /// time with a user's functions), with `specialization`; `function` names what it
    /// evaluates in messages.
    pub fn new(
        context: &Arc<Context>,
        kernel: &'static Kernel,
        spirv: &[u32],
        specialization: &[(u32, u32)],
        function: &str,
    ) -> Result<Probe> {
        let build = kernel.builds()[0];
        Ok(Probe {
            context: context.clone(),
            commands: CommandRunner::new(context)?,
            pipeline: kernel.pipeline(context, &build, spirv, specialization)?,
            function: function.to_string(),
        })
    }

    /// `new` with the kernel's embedded SPIR-V.
    pub fn embedded(
        context: &Arc<Context>,
        kernel: &'static Kernel,
        specialization: &[(u32, u32)],
        function: &str,
    ) -> Result<Probe> {
        let spirv = kernel.builds()[0].embedded_spirv()?;
        Probe::new(context, kernel, &spirv, specialization, function)
    }

    /// The device it runs on.
    pub fn context(&self) -> &Arc<Context> {
        &self.context
    }

    /// Evaluates the kernel on every input and returns the outputs in order. `I` and `O`
    /// must be the kernel's input and output structs; `resources` gives what the kernel
    /// binds besides them.
    pub fn run<'a, I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        resources: impl Fn(Resource) -> Option<Bound<'a>>,
        inputs: &[I],
    ) -> Result<Vec<O>> {
        let mut outputs = Vec::with_capacity(inputs.len());
        let (first, rest) = inputs.split_at(inputs.len().min(FIRST_CHUNK));
        for chunk in std::iter::once(first).chain(rest.chunks(MAX_INPUTS_PER_CHUNK)) {
            if !chunk.is_empty() {
                outputs.extend(self.run_chunk::<I, O>(&resources, chunk)?);
            }
        }
        Ok(outputs)
    }

    /// `run` with the kernel's other resources as a table of (resource, what is bound).
    pub fn run_with<I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        bound: &[(Resource, Bound<'_>)],
        inputs: &[I],
    ) -> Result<Vec<O>> {
        let find = |resource| bound.iter().find(|(r, _)| *r == resource).map(|(_, b)| *b);
        self.run(find, inputs)
    }

    /// One upload, as many dispatches as the workgroup-count limit needs, one read-back.
    fn run_chunk<'a, I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        resources: &impl Fn(Resource) -> Option<Bound<'a>>,
        inputs: &[I],
    ) -> Result<Vec<O>> {
        let count = inputs.len();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let input_buffer = Buffer::with_data(&self.context, "probe inputs", inputs, usage)?;
        let readable = |name, bytes: usize| {
            Buffer::new(
                &self.context,
                name,
                bytes as u64,
                usage,
                MemoryLocation::GpuToCpu,
            )
        };
        let output_buffer = readable("probe outputs", count * std::mem::size_of::<O>())?;
        let flag_buffer = match self.pipeline.binds(Resource::ProbeFlags) {
            true => Some(readable("probe flags", count * 4)?),
            false => None,
        };
        let descriptors = self.pipeline.descriptor_set(|resource| match resource {
            Resource::ProbeInputs => Some(Bound::Buffer(&input_buffer)),
            Resource::ProbeOutputs => Some(Bound::Buffer(&output_buffer)),
            Resource::ProbeFlags => flag_buffer.as_ref().map(Bound::Buffer),
            other => resources(other),
        })?;
        let max_groups = self.context.limits.max_compute_work_group_count[0] as usize;
        let group_size = self.pipeline.pipeline.workgroup_size()[0].max(1) as usize;
        if self.pipeline.kernel().push_constant_size == 0 && count.div_ceil(group_size) > max_groups
        {
            return Err(Error::InvalidSettings(format!(
                "{} takes no first input, so it runs in one dispatch of at most {max_groups} \
                 workgroups, too few for {count} inputs",
                self.pipeline.kernel().source
            )));
        }
        self.commands
            .run(|recorder| self.record_dispatches(recorder, &descriptors, count, max_groups))?;
        if let Some(flag_buffer) = flag_buffer {
            let flags: Vec<u32> = flag_buffer.read();
            let limited = flags.iter().take(count).filter(|&&flag| flag != 0).count();
            if limited > 0 {
                return Err(Error::LoopLimit(format!(
                    "in {limited} of {count} calls, {}'s loops ran more than {} iterations (an endless loop?)",
                    self.function,
                    crate::check::source::USER_LOOP_LIMIT
                )));
            }
        }
        let mut outputs: Vec<O> = output_buffer.read();
        outputs.truncate(count);
        Ok(outputs)
    }

    /// Records the dispatches over `count` inputs: as many workgroups as the inputs need,
    /// split into dispatches of at most the device's workgroup-count limit, each told its
    /// first input by `ProbePushConstants` (kernels without push constants start at 0 and
    /// get one dispatch); then the barriers that make the outputs readable on the host.
    fn record_dispatches(
        &self,
        recorder: &mut Recorder,
        descriptors: &DescriptorSet,
        count: usize,
        max_groups: usize,
    ) {
        let pipeline = &self.pipeline.pipeline;
        let pushes = self.pipeline.kernel().push_constant_size > 0;
        let group_size = pipeline.workgroup_size()[0].max(1) as usize;
        let total_groups = count.div_ceil(group_size);
        recorder.bind(pipeline, descriptors);
        let mut first_group = 0;
        while first_group < total_groups {
            let groups = (total_groups - first_group).min(max_groups.max(1));
            if pushes {
                let constants = ProbePushConstants {
                    first: (first_group * group_size) as u32,
                    count: count as u32,
                };
                recorder.push_constants(pipeline, &constants);
            }
            recorder.dispatch(pipeline, [(groups * group_size) as u32, 1, 1]);
            first_group += groups;
        }
        recorder.compute_barrier();
        recorder.host_read_barrier();
    }
}

/// A scene as the probes that trace rays read it: its triangles (a texel buffer, as the path
/// tracer reads them) and the render uniforms whose `.z` is their count.
pub struct ProbeScene {
    triangles: TexelBufferView,
    uniforms: Buffer,
}

impl ProbeScene {
    /// Uploads `triangles`. An empty scene is allowed: the kernels that do not trace rays
    /// need none.
    pub fn new(context: &Arc<Context>, triangles: &[Triangle]) -> Result<ProbeScene> {
        let mut packed: Vec<GpuTriangle> = triangles.iter().map(GpuTriangle::new).collect();
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
        Ok(ProbeScene {
            triangles,
            uniforms,
        })
    }

    /// The scene's resource for a probe's binding table, `None` for others.
    pub fn resource(&self, resource: Resource) -> Option<Bound<'_>> {
        match resource {
            Resource::Triangles => Some(Bound::TexelBuffer(&self.triangles)),
            Resource::RenderUniforms => Some(Bound::Buffer(&self.uniforms)),
            _ => None,
        }
    }
}

/// Runs the workshop functions' probe kernels against one scene (the triangles that
/// `ray_mesh_intersection`, `compute_direct_illumination` and `get_ray_radiance` see).
pub struct ProbeRunner {
    context: Arc<Context>,
    scene: ProbeScene,
}

impl ProbeRunner {
    /// Uploads `scene_triangles` (see `ProbeScene::new`).
    pub fn new(context: &Arc<Context>, scene_triangles: &[Triangle]) -> Result<ProbeRunner> {
        Ok(ProbeRunner {
            context: context.clone(),
            scene: ProbeScene::new(context, scene_triangles)?,
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
        pipeline
            .probe
            .run(|resource| self.scene.resource(resource), inputs)
    }
}
