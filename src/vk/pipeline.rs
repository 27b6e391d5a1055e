//! A compute pipeline with one descriptor set layout, push constants and specialization
//! constants, and a descriptor set to bind its resources.

use std::sync::Arc;

use ash::vk;

use super::acceleration_structure::AccelerationStructure;
use super::buffer::{Buffer, TexelBufferView};
use super::context::Context;
use super::error::{CallContext, VkError, VkResult};
use super::image::StorageImage;
use super::pipeline_cache::SLOW_BUILD_NOTICE_AFTER;
use super::sampler::Sampler;

/// A compute pipeline and its layouts.
pub struct ComputePipeline {
    context: Arc<Context>,
    /// Layout of descriptor set 0.
    pub(crate) descriptor_set_layout: vk::DescriptorSetLayout,
    /// The pipeline layout (set 0 and the push-constant range).
    pub(crate) layout: vk::PipelineLayout,
    /// The pipeline.
    pub(crate) pipeline: vk::Pipeline,
    bindings: Vec<(u32, vk::DescriptorType)>,
    workgroup_size: [u32; 3],
}

/// SPIR-V bytes (as embedded or written by a compiler) as words.
pub fn spirv_words(bytes: &[u8]) -> VkResult<Vec<u32>> {
    ash::util::read_spv(&mut std::io::Cursor::new(bytes))
        .map_err(|e| VkError::InvalidSpirv(e.to_string()))
}

/// The workgroup size that SPIR-V declares for its entry point (`OpExecutionMode ...
/// LocalSize x y z`), if it declares one with literals.
fn declared_workgroup_size(spirv: &[u32]) -> Option<[u32; 3]> {
    /// `OpExecutionMode` and its `LocalSize` mode.
    const OP_EXECUTION_MODE: u32 = 16;
    const EXECUTION_MODE_LOCAL_SIZE: u32 = 17;
    let mut index = 5; // after the header
    while index < spirv.len() {
        let word = spirv[index];
        let (length, opcode) = ((word >> 16) as usize, word & 0xffff);
        if length == 0 {
            return None;
        }
        if opcode == OP_EXECUTION_MODE
            && length == 6
            && spirv.get(index + 2) == Some(&EXECUTION_MODE_LOCAL_SIZE)
        {
            return Some([spirv[index + 3], spirv[index + 4], spirv[index + 5]]);
        }
        index += length;
    }
    None
}

/// Runs `build`, and calls the pipeline cache store's `building_slowly` from another thread
/// if it takes longer than `SLOW_BUILD_NOTICE_AFTER` (a driver compiles while `build` runs,
/// so the notice comes while the wait is on, not after it); only where the cache started
/// cold (the first run on the device).
fn build_telling_when_slow<T>(context: &Context, build: impl FnOnce() -> T) -> T {
    let Some(store) = context.cold_pipeline_cache_store() else {
        return build();
    };
    let (done, finished) = std::sync::mpsc::channel::<()>();
    std::thread::scope(|scope| {
        scope.spawn(move || {
            if finished.recv_timeout(SLOW_BUILD_NOTICE_AFTER)
                == Err(std::sync::mpsc::RecvTimeoutError::Timeout)
            {
                store.building_slowly();
            }
        });
        let result = build();
        // Wakes the watcher (a send to a watcher that has given up is fine to lose).
        let _ = done.send(());
        result
    })
}

impl ComputePipeline {
    /// Creates a pipeline from SPIR-V (entry point `main`) whose set 0 has `bindings`, with
    /// `push_constant_size` bytes of push constants (0 for none) and 32-bit specialization
    /// constants given as (constant_id, value).
    pub fn new(
        context: &Arc<Context>,
        spirv: &[u32],
        bindings: &[(u32, vk::DescriptorType)],
        push_constant_size: u32,
        specialization: &[(u32, u32)],
    ) -> VkResult<ComputePipeline> {
        if spirv.first() != Some(&0x0723_0203) {
            return Err(VkError::InvalidSpirv(
                "missing the SPIR-V magic number".into(),
            ));
        }
        let workgroup_size = declared_workgroup_size(spirv).ok_or_else(|| {
            VkError::InvalidSpirv("no literal workgroup size (LocalSize) declared".into())
        })?;
        let device = &context.device;
        let layout_bindings: Vec<_> = bindings
            .iter()
            .map(|&(binding, kind)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(binding)
                    .descriptor_type(kind)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let mut pipeline = ComputePipeline {
            context: context.clone(),
            descriptor_set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            bindings: bindings.to_vec(),
            workgroup_size,
        };
        // SAFETY: valid create infos on a live device; on error, Drop destroys what exists.
        unsafe {
            pipeline.descriptor_set_layout = device
                .create_descriptor_set_layout(
                    &vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings),
                    None,
                )
                .during("creating a descriptor set layout")?;
            let set_layouts = [pipeline.descriptor_set_layout];
            let ranges = [vk::PushConstantRange::default()
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
                .size(push_constant_size)];
            let mut layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
            if push_constant_size > 0 {
                layout_info = layout_info.push_constant_ranges(&ranges);
            }
            pipeline.layout = device
                .create_pipeline_layout(&layout_info, None)
                .during("creating a pipeline layout")?;
            let module = device
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(spirv), None)
                .during("creating a shader module")?;
            let entries: Vec<_> = specialization
                .iter()
                .enumerate()
                .map(|(i, &(id, _))| vk::SpecializationMapEntry {
                    constant_id: id,
                    offset: 4 * i as u32,
                    size: 4,
                })
                .collect();
            let data: Vec<u8> = specialization
                .iter()
                .flat_map(|&(_, v)| v.to_ne_bytes())
                .collect();
            let specialization_info = vk::SpecializationInfo::default()
                .map_entries(&entries)
                .data(&data);
            let stage = vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::COMPUTE)
                .module(module)
                .name(c"main")
                .specialization_info(&specialization_info);
            let info = [vk::ComputePipelineCreateInfo::default()
                .stage(stage)
                .layout(pipeline.layout)];
            let created = build_telling_when_slow(context, || {
                device.create_compute_pipelines(context.pipeline_cache(), &info, None)
            });
            device.destroy_shader_module(module, None);
            pipeline.pipeline = created
                .map_err(|(_, result)| result)
                .during("creating a compute pipeline")?[0];
        }
        context.pipeline_built();
        Ok(pipeline)
    }

    /// The workgroup size (x, y, z) that the kernel declares.
    pub fn workgroup_size(&self) -> [u32; 3] {
        self.workgroup_size
    }

    /// Allocates a descriptor set for this pipeline's set 0 from a pool of its own.
    pub fn allocate_descriptor_set(&self) -> VkResult<DescriptorSet> {
        DescriptorSet::new(&self.context, self.descriptor_set_layout, &self.bindings)
    }
}

impl Drop for ComputePipeline {
    fn drop(&mut self) {
        // SAFETY: users wait for work using the pipeline before dropping it; null handles
        // are ignored by vkDestroy*.
        unsafe {
            let device = &self.context.device;
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.descriptor_set_layout, None);
        }
    }
}

/// A descriptor set with the pool it came from.
pub struct DescriptorSet {
    context: Arc<Context>,
    pool: vk::DescriptorPool,
    /// The set.
    pub(crate) set: vk::DescriptorSet,
}

impl DescriptorSet {
    fn new(
        context: &Arc<Context>,
        layout: vk::DescriptorSetLayout,
        bindings: &[(u32, vk::DescriptorType)],
    ) -> VkResult<DescriptorSet> {
        let sizes: Vec<_> = bindings
            .iter()
            .map(|&(_, kind)| vk::DescriptorPoolSize {
                ty: kind,
                descriptor_count: 1,
            })
            .collect();
        let device = &context.device;
        // SAFETY: valid create infos on a live device.
        let pool = unsafe {
            device.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(1)
                    .pool_sizes(&sizes),
                None,
            )
        }
        .during("creating a descriptor pool")?;
        let layouts = [layout];
        let set = unsafe {
            device.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(pool)
                    .set_layouts(&layouts),
            )
        };
        match set {
            Ok(sets) => Ok(DescriptorSet {
                context: context.clone(),
                pool,
                set: sets[0],
            }),
            Err(result) => {
                unsafe { device.destroy_descriptor_pool(pool, None) };
                Err(VkError::Call {
                    what: "allocating a descriptor set",
                    result,
                })
            }
        }
    }

    /// Points `binding` at a whole buffer.
    pub fn write_buffer(&self, binding: u32, kind: vk::DescriptorType, buffer: &Buffer) {
        let info = [vk::DescriptorBufferInfo::default()
            .buffer(buffer.handle)
            .range(vk::WHOLE_SIZE)];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(kind)
            .buffer_info(&info);
        // SAFETY: the buffer is alive; the set is not in use by pending work.
        unsafe { self.context.device.update_descriptor_sets(&[write], &[]) };
    }

    /// Points `binding` at a uniform texel buffer.
    pub fn write_texel_buffer(&self, binding: u32, view: &TexelBufferView) {
        let views = [view.handle];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)
            .texel_buffer_view(&views);
        // SAFETY: the view is alive; the set is not in use by pending work.
        unsafe { self.context.device.update_descriptor_sets(&[write], &[]) };
    }

    /// Points `binding` at a storage image in GENERAL layout.
    pub fn write_storage_image(&self, binding: u32, image: &StorageImage) {
        let info = [vk::DescriptorImageInfo::default()
            .image_view(image.view)
            .image_layout(vk::ImageLayout::GENERAL)];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
            .image_info(&info);
        // SAFETY: the image is alive; the set is not in use by pending work.
        unsafe { self.context.device.update_descriptor_sets(&[write], &[]) };
    }
}

impl DescriptorSet {
    /// Points `binding` at an acceleration structure (a top-level one, for ray queries).
    pub fn write_acceleration_structure(&self, binding: u32, structure: &AccelerationStructure) {
        let handles = [structure.handle];
        let mut info = vk::WriteDescriptorSetAccelerationStructureKHR::default()
            .acceleration_structures(&handles);
        let mut write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
            .push_next(&mut info);
        write.descriptor_count = 1;
        // SAFETY: the structure is alive; the set is not in use by pending work.
        unsafe { self.context.device.update_descriptor_sets(&[write], &[]) };
    }

    /// Points `binding` at a combined image sampler: `image` (made with
    /// `StorageImage::sampled_2d`) in GENERAL layout, read through `sampler`.
    pub fn write_sampled_image(&self, binding: u32, image: &StorageImage, sampler: &Sampler) {
        let info = [vk::DescriptorImageInfo::default()
            .sampler(sampler.handle)
            .image_view(image.view)
            .image_layout(vk::ImageLayout::GENERAL)];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
            .image_info(&info);
        // SAFETY: the image and sampler are alive; the set is not in use by pending work.
        unsafe { self.context.device.update_descriptor_sets(&[write], &[]) };
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        // SAFETY: destroying the pool frees the set; users wait for pending work first.
        unsafe { self.context.device.destroy_descriptor_pool(self.pool, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workgroup_sizes_come_from_the_spirv() {
        // Header, an OpCapability Shader (2 words), then OpExecutionMode %4 LocalSize 8 4 1.
        let spirv = [
            0x0723_0203,
            0x0001_0500,
            0,
            10,
            0,
            (2 << 16) | 17,
            1,
            (6 << 16) | 16,
            4,
            17,
            8,
            4,
            1,
        ];
        assert_eq!(declared_workgroup_size(&spirv), Some([8, 4, 1]));
        assert_eq!(declared_workgroup_size(&spirv[..7]), None);
        let bytes: Vec<u8> = spirv.iter().flat_map(|w: &u32| w.to_le_bytes()).collect();
        assert_eq!(spirv_words(&bytes).unwrap(), spirv);
        assert!(spirv_words(&bytes[..7]).is_err());
    }
}
