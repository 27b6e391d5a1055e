//! Acceleration structures (`VK_KHR_acceleration_structure`) for ray queries: a bottom-level
//! structure over triangles, a top-level structure over instances of bottom-level ones, each
//! owning its handle and its buffer and destroyed on drop. Built on the device, one
//! submission each, with a barrier that makes the build visible to later builds and compute
//! shaders. Only on a context whose device has ray queries (`Context::ray_queries`).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::buffer::Buffer;
use super::commands::{CommandRunner, Recorder};
use super::context::Context;
use super::error::{CallContext, VkError, VkResult};

/// Bytes that a build needs on the device (`VkAccelerationStructureBuildSizesInfoKHR`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuildSizes {
    /// The structure itself.
    pub structure: u64,
    /// Scratch memory during the build (freed after it).
    pub scratch: u64,
}

/// One instance of a bottom-level structure in a top-level one.
#[derive(Clone, Copy, Debug)]
pub struct InstanceDescription {
    /// Object to world space, row-major 3x4 (`VkTransformMatrixKHR`).
    pub transform: [[f32; 4]; 3],
    /// `gl_InstanceCustomIndexEXT` / `rayQueryGetIntersectionInstanceCustomIndexEXT`: at most
    /// `MAX_CUSTOM_INDEX`.
    pub custom_index: u32,
    /// The bottom-level structure's device address (`AccelerationStructure::address`).
    pub bottom_level_address: u64,
}

/// The largest instance custom index (24 bits).
pub const MAX_CUSTOM_INDEX: u32 = (1 << 24) - 1;

/// The identity transform of an instance.
pub const IDENTITY_TRANSFORM: [[f32; 4]; 3] = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
];

/// `VkAccelerationStructureInstanceKHR` as bytes: ash's struct holds bit fields and a union,
/// which bytemuck cannot cast.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuInstance {
    transform: [[f32; 4]; 3],
    /// Custom index (bits 0..24) and visibility mask (bits 24..32).
    custom_index_and_mask: u32,
    /// Shader binding table offset (bits 0..24, unused by ray queries) and
    /// `VkGeometryInstanceFlagsKHR` (bits 24..32).
    binding_offset_and_flags: u32,
    bottom_level_address: u64,
}

/// A built acceleration structure and the buffer that holds it.
pub struct AccelerationStructure {
    /// Keeps the device alive as long as the structure.
    _context: Arc<Context>,
    loader: ash::khr::acceleration_structure::Device,
    /// The structure's handle.
    pub handle: vk::AccelerationStructureKHR,
    /// Its device address (what an instance refers to).
    pub address: u64,
    /// Bytes of its buffer.
    pub size: u64,
    /// The buffer that holds it (kept alive with it).
    _buffer: Buffer,
}

/// The scratch alignment of `context`'s device, or an error where it has no ray queries.
fn scratch_alignment(context: &Context) -> VkResult<u64> {
    context
        .ray_queries
        .limits()
        .map(|limits| limits.scratch_alignment)
        .ok_or(VkError::Call {
            what: "building an acceleration structure on a device without ray queries",
            result: vk::Result::ERROR_EXTENSION_NOT_PRESENT,
        })
}

/// A buffer's device address.
fn device_address(context: &Context, buffer: &Buffer) -> u64 {
    // SAFETY: the buffer was created with SHADER_DEVICE_ADDRESS on a device with the
    // bufferDeviceAddress feature.
    unsafe {
        context.device.get_buffer_device_address(
            &vk::BufferDeviceAddressInfo::default().buffer(buffer.handle),
        )
    }
}

/// The usage of buffers that builds read.
const BUILD_INPUT: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR.as_raw()
        | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS.as_raw(),
);

/// The geometry of `triangle_count` triangles whose vertices (three per triangle, no index
/// buffer) lie at `vertex_address` as tightly packed `[f32; 3]`s.
fn triangle_geometry(
    vertex_address: u64,
    triangle_count: u32,
    opaque: bool,
) -> vk::AccelerationStructureGeometryKHR<'static> {
    let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
        .vertex_format(vk::Format::R32G32B32_SFLOAT)
        .vertex_data(vk::DeviceOrHostAddressConstKHR {
            device_address: vertex_address,
        })
        .vertex_stride(12)
        .max_vertex((3 * triangle_count).saturating_sub(1))
        .index_type(vk::IndexType::NONE_KHR);
    // Non-opaque geometry reaches the kernel's alpha test once per triangle and ray.
    let flags = if opaque {
        vk::GeometryFlagsKHR::OPAQUE
    } else {
        vk::GeometryFlagsKHR::NO_DUPLICATE_ANY_HIT_INVOCATION
    };
    vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
        .geometry(vk::AccelerationStructureGeometryDataKHR { triangles })
        .flags(flags)
}

/// The geometry of instances at `instance_address`.
fn instance_geometry(instance_address: u64) -> vk::AccelerationStructureGeometryKHR<'static> {
    let instances = vk::AccelerationStructureGeometryInstancesDataKHR::default()
        .array_of_pointers(false)
        .data(vk::DeviceOrHostAddressConstKHR {
            device_address: instance_address,
        });
    vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::INSTANCES)
        .geometry(vk::AccelerationStructureGeometryDataKHR { instances })
}

/// What a build of `kind` over `geometry` with `primitive_count` primitives needs.
fn build_sizes(
    context: &Context,
    kind: vk::AccelerationStructureTypeKHR,
    geometry: &vk::AccelerationStructureGeometryKHR,
    primitive_count: u32,
) -> BuildSizes {
    let loader = ash::khr::acceleration_structure::Device::new(&context.instance, &context.device);
    let geometries = [*geometry];
    let info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
        .ty(kind)
        .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
        .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
        .geometries(&geometries);
    let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
    // SAFETY: a valid build description; the device has the extension (the callers check).
    unsafe {
        loader.get_acceleration_structure_build_sizes(
            vk::AccelerationStructureBuildTypeKHR::DEVICE,
            &info,
            &[primitive_count],
            &mut sizes,
        )
    };
    BuildSizes {
        structure: sizes.acceleration_structure_size,
        scratch: sizes.build_scratch_size,
    }
}

/// What a bottom-level structure over `triangle_count` triangles needs on `context`'s device.
pub fn bottom_level_sizes(context: &Context, triangle_count: u32, opaque: bool) -> BuildSizes {
    build_sizes(
        context,
        vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
        &triangle_geometry(0, triangle_count, opaque),
        triangle_count,
    )
}

/// What a top-level structure over `instance_count` instances needs on `context`'s device.
pub fn top_level_sizes(context: &Context, instance_count: u32) -> BuildSizes {
    build_sizes(
        context,
        vk::AccelerationStructureTypeKHR::TOP_LEVEL,
        &instance_geometry(0),
        instance_count,
    )
}

impl AccelerationStructure {
    /// Builds a bottom-level structure over triangles given as three vertex positions each
    /// (object space), `opaque` or not (non-opaque triangles reach the kernel's candidate
    /// loop, once per ray). Primitive `i` is triangle `i`.
    pub fn bottom_level(
        context: &Arc<Context>,
        commands: &CommandRunner,
        name: &str,
        positions: &[[[f32; 3]; 3]],
        opaque: bool,
    ) -> VkResult<AccelerationStructure> {
        let vertices = Buffer::device_local_with_data(
            context,
            commands,
            &format!("{name} vertices"),
            bytemuck::cast_slice(positions),
            BUILD_INPUT,
        )?;
        let count = positions.len() as u32;
        let geometry = triangle_geometry(device_address(context, &vertices), count, opaque);
        AccelerationStructure::build(
            context,
            commands,
            name,
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            geometry,
            count,
        )
    }

    /// Builds a top-level structure over `instances`, all visible to every ray (mask 0xff),
    /// with no culling of back faces (the workshop's triangle test has none).
    pub fn top_level(
        context: &Arc<Context>,
        commands: &CommandRunner,
        name: &str,
        instances: &[InstanceDescription],
    ) -> VkResult<AccelerationStructure> {
        let gpu_instances: Vec<GpuInstance> = instances
            .iter()
            .map(|instance| GpuInstance {
                transform: instance.transform,
                custom_index_and_mask: (instance.custom_index & MAX_CUSTOM_INDEX) | (0xff << 24),
                binding_offset_and_flags: vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE
                    .as_raw() << 24,
                bottom_level_address: instance.bottom_level_address,
            })
            .collect();
        let instance_buffer = Buffer::device_local_with_data(
            context,
            commands,
            &format!("{name} instances"),
            bytemuck::cast_slice(&gpu_instances),
            BUILD_INPUT,
        )?;
        let geometry = instance_geometry(device_address(context, &instance_buffer));
        AccelerationStructure::build(
            context,
            commands,
            name,
            vk::AccelerationStructureTypeKHR::TOP_LEVEL,
            geometry,
            instances.len() as u32,
        )
    }

    /// Creates a structure of `kind` and builds it over `geometry` on the device; returns
    /// once the build has finished.
    fn build(
        context: &Arc<Context>,
        commands: &CommandRunner,
        name: &str,
        kind: vk::AccelerationStructureTypeKHR,
        geometry: vk::AccelerationStructureGeometryKHR,
        primitive_count: u32,
    ) -> VkResult<AccelerationStructure> {
        let alignment = scratch_alignment(context)?;
        let sizes = build_sizes(context, kind, &geometry, primitive_count);
        let buffer = Buffer::new(
            context,
            name,
            sizes.structure,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR
                | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
            MemoryLocation::GpuOnly,
        )?;
        let loader =
            ash::khr::acceleration_structure::Device::new(&context.instance, &context.device);
        let create_info = vk::AccelerationStructureCreateInfoKHR::default()
            .buffer(buffer.handle)
            .size(sizes.structure)
            .ty(kind);
        // SAFETY: the buffer is alive, large enough and made for acceleration structures.
        let handle = unsafe { loader.create_acceleration_structure(&create_info, None) }
            .during("creating an acceleration structure")?;
        let mut structure = AccelerationStructure {
            _context: context.clone(),
            loader: loader.clone(),
            handle,
            address: 0,
            size: sizes.structure,
            _buffer: buffer,
        };
        // Scratch memory, its address rounded up to the device's alignment.
        let scratch = Buffer::new(
            context,
            &format!("{name} scratch"),
            sizes.scratch + alignment,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
            MemoryLocation::GpuOnly,
        )?;
        let scratch_address = device_address(context, &scratch).next_multiple_of(alignment);
        let geometries = [geometry];
        let info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(kind)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .dst_acceleration_structure(handle)
            .geometries(&geometries)
            .scratch_data(vk::DeviceOrHostAddressKHR {
                device_address: scratch_address,
            });
        let ranges =
            [vk::AccelerationStructureBuildRangeInfoKHR::default()
                .primitive_count(primitive_count)];
        commands.run(|recorder| {
            // SAFETY: the command buffer is recording; inputs, scratch and destination stay
            // alive until run() has waited for the build.
            unsafe {
                loader.cmd_build_acceleration_structures(
                    recorder.command_buffer(),
                    &[info],
                    &[&ranges],
                )
            };
            built_barrier(context, recorder);
        })?;
        // SAFETY: the structure was created on this device.
        let address = unsafe {
            loader.get_acceleration_structure_device_address(
                &vk::AccelerationStructureDeviceAddressInfoKHR::default()
                    .acceleration_structure(handle),
            )
        };
        structure.address = address;
        Ok(structure)
    }
}

/// Makes a build's writes visible to later builds (a top level reads its bottom levels) and
/// to compute shaders' ray queries.
fn built_barrier(context: &Context, recorder: &mut Recorder) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR)
        .dst_access_mask(
            vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR | vk::AccessFlags::SHADER_READ,
        );
    // SAFETY: the command buffer is recording.
    unsafe {
        context.device.cmd_pipeline_barrier(
            recorder.command_buffer(),
            vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
            vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR
                | vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::DependencyFlags::empty(),
            &[barrier],
            &[],
            &[],
        )
    };
}

impl Drop for AccelerationStructure {
    fn drop(&mut self) {
        // SAFETY: users wait for the work that uses the structure before dropping it; the
        // buffer is dropped after the handle.
        unsafe {
            self.loader
                .destroy_acceleration_structure(self.handle, None)
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn instances_have_vulkans_layout() {
        assert_eq!(
            std::mem::size_of::<GpuInstance>(),
            std::mem::size_of::<vk::AccelerationStructureInstanceKHR>()
        );
        assert_eq!(std::mem::offset_of!(GpuInstance, custom_index_and_mask), 48);
        assert_eq!(std::mem::offset_of!(GpuInstance, bottom_level_address), 56);
    }
}
