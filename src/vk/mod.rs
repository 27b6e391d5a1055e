//! A thin Vulkan layer over `ash` that knows nothing of path tracing: context (instance,
//! device, queue, allocator), buffers, storage images, samplers, compute pipelines, command
//! submission, validation messages and errors. Each resource frees itself on drop and holds
//! an `Arc<Context>`, so the device outlives it.

pub mod acceleration_structure;
pub mod buffer;
pub mod commands;
pub mod context;
pub mod device_choice;
pub mod error;
pub mod image;
pub mod pipeline;
pub mod pipeline_cache;
pub mod ray_query_support;
pub mod sampler;
pub mod validation;

pub use acceleration_structure::AccelerationStructure;
pub use buffer::{Buffer, TexelBufferView};
pub use commands::{CommandRunner, Recorder};
pub use context::{list_devices, Context, ContextOptions, DeviceInfo, DeviceKind};
pub use device_choice::{choose_devices, format_uuid, DeviceChoice, DeviceEnvironment, PciBusInfo};
pub use error::{VkError, VkResult};
pub use image::StorageImage;
pub use pipeline::{spirv_words, ComputePipeline, DescriptorSet};
pub use pipeline_cache::{PipelineCacheKey, PipelineCacheStore};
pub use ray_query_support::{RayQueryLimits, RayQuerySupport};
pub use sampler::Sampler;
pub use validation::ValidationMessages;
