//! Making a renderer: the settings and the device's limits checked, the scene uploaded (or
//! taken from a sequence's earlier render), the kernel's variant and pipelines built, the
//! accumulation image made and cleared.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::accel::choose_traversal;
use crate::camera::Camera;
use crate::contract;
use crate::error::{Error, Result};
use crate::guiding::GuideGrid;
use crate::kernels::specialization::{path_tracer_specialization, SpecializationParts};
use crate::kernels::variant::{path_tracer_variant, KernelSource, Traversal, VariantSettings};
use crate::kernels::{Bound, KernelPipeline, Resource, PATH_TRACER};
use crate::render::converged_pixels::ConvergedPixels;
use crate::render::gpu_scene::{GpuScene, KeptParts};
use crate::render::guide_buffers::GuideBuffers;
use crate::render::region::{ACCUMULATION_BYTES_PER_PIXEL, ACCUMULATION_COPIES};
use crate::render::sequence::{AccumulationImages, KeptUpload, SequenceCache, UploadKey};
use crate::render::settings::RenderSettings;
use crate::render::tiles::{scene_bytes, tile_layout, Tiles};
use crate::scene::Scene;
use crate::vk::{Buffer, CommandRunner, Context, StorageImage};

use super::guide_training::TrainingKernel;
use super::loop_budget::LoopBudget;
use super::Renderer;

impl Renderer {
    /// Prepares a render: validates the settings, uploads the scene's triangles and the
    /// camera, creates the pipeline and clears the accumulation image.
    pub fn new(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
    ) -> Result<Renderer> {
        Renderer::create(context, scene, camera, settings, None, None)
    }

    /// Prepares a render like `new`, one of a sequence on the same device: it takes from
    /// `sequence` what an earlier render left there (`SequenceCache`: the pipeline of the
    /// same variant, the accumulation image of the same size, the scene upload when the
    /// scene's data are the same bit for bit), building only the rest. The image is bit
    /// for bit `new`'s. Give the renderer back with `keep_for_next` when it is done.
    pub fn in_sequence(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
        sequence: &mut SequenceCache,
    ) -> Result<Renderer> {
        Renderer::create(context, scene, camera, settings, None, Some(sequence))
    }

    /// Leaves the pipeline, the accumulation image and the scene upload in `sequence` for
    /// the next render (`in_sequence`).
    pub fn keep_for_next(self, sequence: &mut SequenceCache) {
        let images = AccumulationImages {
            accumulation: self.accumulation,
            readback: self.readback,
            tile_upload: self.tiles.and_then(Tiles::into_upload),
        };
        sequence.keep(images, self.scene);
    }

    /// Prepares a render like `new`, with the kernel's SPIR-V given instead of the embedded
    /// one: `glsl/path_tracer.comp` compiled at run time, e.g. with a user's functions by
    /// `vkpath check`. `traversal` says how it was compiled (`Bvh` with `USE_BVH` defined,
    /// the others without) and, for `ConstantTriangles`, that the constant triangles must be
    /// able to trace the scene (`Traversal::constant_triangles_can_trace`).
    pub fn with_kernel(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
        spirv: &[u32],
        traversal: Traversal,
    ) -> Result<Renderer> {
        if traversal == Traversal::ConstantTriangles {
            let materials = scene.needs_material_kernels();
            let capacity = Traversal::constant_triangle_capacity(materials);
            if scene.triangles.len() > capacity {
                return Err(Error::InvalidSettings(format!(
                    "a kernel with constant triangles holds at most {capacity} triangles, the scene has {}",
                    scene.triangles.len()
                )));
            }
            if scene.uses_alpha() {
                return Err(Error::InvalidSettings(
                    "a kernel with constant triangles runs no alpha test, and the scene has alpha-tested materials: use the BVH or the linear loop".into(),
                ));
            }
        }
        Renderer::create(
            context,
            scene,
            camera,
            settings,
            Some((spirv, traversal)),
            None,
        )
    }

    /// `new` (`kernel` = `None`: the embedded kernel for the traversal that `settings.accel`
    /// chooses), `with_kernel` and `in_sequence` (with `sequence`; a given kernel is never
    /// kept in one).
    fn create(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
        kernel: Option<(&[u32], Traversal)>,
        sequence: Option<&mut SequenceCache>,
    ) -> Result<Renderer> {
        let mut sequence = sequence.filter(|_| kernel.is_none());
        let started = Instant::now();
        settings.validate()?;
        let area = settings.area();
        let tile_list = tile_layout(context, scene, &settings, area);
        let (image_width, image_height) = tile_list
            .first()
            .map_or((area.width(), area.height()), |t| (t.width(), t.height()));
        validate(context, scene, &settings, image_width, image_height)?;
        let commands = CommandRunner::new(context)?;
        let gpu_scene = upload_scene(
            context,
            &commands,
            (scene, camera, &settings),
            kernel.map(|(_, traversal)| traversal),
            sequence.as_deref_mut(),
        )?;
        // (`auto`'s compressed tree may have made way for the 4-wide one)
        let traversal = gpu_scene.traversal;
        let Kernels {
            pipeline,
            training_kernel,
            guide_buffers,
            samples_per_dispatch,
        } = build_kernels(
            context,
            (scene, camera, &settings),
            &gpu_scene,
            kernel.map(|(spirv, _)| spirv),
            sequence.as_deref_mut(),
        )?;
        let tiled = !tile_list.is_empty();
        let kept = sequence.and_then(|s| s.take_images(image_width, image_height, tiled));
        let AccumulationImages {
            accumulation,
            readback,
            tile_upload,
        } = match kept {
            Some(images) => images,
            None => accumulation_images(context, image_width, image_height, tiled)?,
        };
        let converged_pixels = ConvergedPixels::new(context)?;
        let descriptors = pipeline.descriptor_set(|resource| match resource {
            Resource::Accumulation => Some(Bound::StorageImage(&accumulation)),
            Resource::ConvergedPixels => Some(Bound::Buffer(&converged_pixels.buffer)),
            Resource::Guide => Some(Bound::TexelBuffer(&guide_buffers.guide)),
            Resource::GuideSplats => Some(Bound::Buffer(&guide_buffers.splats)),
            other => gpu_scene.resource(other),
        })?;
        commands.run(|recorder| recorder.clear_storage_image(&accumulation))?;
        let tiles = tile_upload.map(|upload| Tiles::every_frame(tile_list, upload));
        Ok(Renderer {
            context: context.clone(),
            settings,
            commands,
            pipeline,
            training_pipeline: None,
            training_kernel,
            descriptors,
            area,
            tiles,
            accumulation,
            readback,
            scene: gpu_scene,
            first_sample: 0,
            samples_done: 0,
            frames_per_batch: 1,
            samples_per_dispatch,
            seconds_per_frame: None,
            rays_traced: 0.0,
            setup_seconds: started.elapsed().as_secs_f64(),
            traversal,
            guide_buffers,
            converged_pixels,
            guide_report: None,
            guide: None,
        })
    }
}

/// A renderer's scene on the device: uploaded, or taken from `sequence` where an earlier
/// render left it (the camera aimed again; of a scene that moved, the parts that did not
/// kept), for the traversal `given` with a given kernel or else the one the device and
/// `settings.accel` choose.
fn upload_scene(
    context: &Arc<Context>,
    commands: &CommandRunner,
    (scene, camera, settings): (&Scene, &Camera, &RenderSettings),
    given: Option<Traversal>,
    sequence: Option<&mut SequenceCache>,
) -> Result<GpuScene> {
    // The device decides too: its ray queries under --accel auto and hardware
    // (`crate::accel::choose_traversal`, which refuses or warns where it cannot).
    let traversal = match given {
        Some(traversal) => traversal,
        None => {
            let moving = sequence.as_ref().is_some_and(|s| s.moving_geometry);
            let choice = choose_traversal(context, scene, settings.accel, moving)?;
            if let Some(warning) = &choice.warning {
                log::warn!("{warning}");
            }
            choice.traversal
        }
    };
    // A sequence's earlier upload of the same data needs only the camera written again;
    // of a scene that moved, the parts that did not are kept.
    let kept = match sequence {
        Some(sequence) => sequence.take_scene(scene, UploadKey::new(settings, traversal)),
        None => KeptUpload::Parts(KeptParts::default()),
    };
    Ok(match kept {
        KeptUpload::Whole(mut gpu_scene) => {
            gpu_scene.aim(scene, camera, settings);
            gpu_scene
        }
        KeptUpload::Parts(parts) => {
            GpuScene::upload(context, commands, scene, camera, settings, traversal, parts)?
        }
    })
}

/// What a renderer dispatches: the path tracer's pipeline (a sequence's where it has one of
/// the same variant), a guided render's training kernel, the guide's buffers and the samples
/// each dispatch may take.
struct Kernels {
    /// The render's pipeline.
    pipeline: Arc<KernelPipeline>,
    /// What the training pipeline is built from (`--guiding` only).
    training_kernel: Option<TrainingKernel>,
    /// The guide and its training splats (bound, unread, when not guiding).
    guide_buffers: GuideBuffers,
    /// The loop budget's samples per dispatch.
    samples_per_dispatch: u32,
}

/// Builds the kernels of rendering `scene`, uploaded as `gpu_scene`, seen by `camera` with
/// `settings`: the variant the scene, camera and settings need, compiled from `given` SPIR-V
/// or the embedded one.
fn build_kernels(
    context: &Arc<Context>,
    (scene, camera, settings): (&Scene, &Camera, &RenderSettings),
    gpu_scene: &GpuScene,
    given: Option<&[u32]>,
    sequence: Option<&mut SequenceCache>,
) -> Result<Kernels> {
    let traversal = gpu_scene.traversal;
    // A given kernel was compiled as the variant room says of one (the plain macros)
    let source = match given {
        Some(_) => KernelSource::Given,
        None => KernelSource::Embedded,
    };
    // The camera is the render's own (a sequence's upload may be an earlier frame's)
    let variant_settings = VariantSettings {
        thin_lens: !camera.lens.is_pinhole(),
        ..gpu_scene.variant_settings
    };
    let variant = path_tracer_variant(&gpu_scene.summary, &variant_settings, traversal, source)?;
    let build = variant.build;
    let guiding = settings.guiding.is_some();
    let budget = LoopBudget::of(context, settings, scene, gpu_scene, traversal)?;
    let mut settings_specialization = settings.specialization();
    // Motion blur: the keys' count (glsl/scene.glsl); a still render passes none, so its
    // kernels are the still ones, bit for bit
    if let Some(motion) = &scene.motion {
        settings_specialization.push((contract::SPEC_MOTION_STEPS, motion.steps()));
    }
    let (loop_limit, loops) = budget.limit_and_loops();
    let parts = SpecializationParts {
        settings: &settings_specialization,
        traversal,
        triangles: &scene.triangles,
        variant: &variant,
        loop_limit,
        loops,
    };
    let specialization_with = |guiding_value| path_tracer_specialization(&parts, guiding_value);
    let guide_buffers = if guiding {
        GuideBuffers::guided(
            context,
            GuideGrid::around_triangles(scene.triangles.iter().map(|t| t.positions)),
        )?
    } else {
        GuideBuffers::unguided(context)?
    };
    let spirv = match given {
        Some(spirv) => spirv.to_vec(),
        None => build.embedded_spirv()?,
    };
    let render_specialization = specialization_with(if guiding {
        contract::GUIDING_ON
    } else {
        contract::GUIDING_OFF
    });
    let build_pipeline = || PATH_TRACER.pipeline(context, &build, &spirv, &render_specialization);
    let pipeline = match sequence {
        Some(sequence) => sequence.pipeline(&build, &render_specialization, build_pipeline)?,
        None => Arc::new(build_pipeline()?),
    };
    let training_kernel = guiding.then(|| TrainingKernel {
        build,
        specialization: specialization_with(contract::GUIDING_TRAINING),
        spirv,
    });
    Ok(Kernels {
        pipeline,
        training_kernel,
        guide_buffers,
        samples_per_dispatch: budget.samples_per_dispatch,
    })
}

/// A new accumulation image of `width` x `height` texels with its read-back buffer and,
/// when `tiled`, its upload buffer.
fn accumulation_images(
    context: &Arc<Context>,
    width: u32,
    height: u32,
    tiled: bool,
) -> Result<AccumulationImages> {
    let accumulation = StorageImage::new(
        context,
        "accumulation",
        width,
        height,
        contract::ACCUMULATION_LAYER_COUNT,
    )?;
    let buffer = |name: &str, usage, location| {
        Buffer::new(context, name, accumulation.byte_size(), usage, location)
    };
    let readback = buffer(
        "readback",
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    let tile_upload = match tiled {
        true => Some(buffer(
            "tile upload",
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?),
        false => None,
    };
    Ok(AccumulationImages {
        accumulation,
        readback,
        tile_upload,
    })
}

/// Checks what a render needs before anything is allocated: valid settings, an image
/// within the device's limits, a scene with triangles.
fn validate(
    context: &Context,
    scene: &Scene,
    settings: &RenderSettings,
    image_width: u32,
    image_height: u32,
) -> Result<()> {
    let device_limit = context.limits.max_image_dimension2_d;
    if image_width > device_limit || image_height > device_limit {
        return Err(Error::InvalidSettings(format!(
            "a tile of {image_width}x{image_height} pixels exceeds the device's limit of \
             {device_limit} pixels per side: use a smaller --tile-size"
        )));
    }
    if scene.triangles.is_empty() {
        return Err(Error::MissingInput("the scene has no triangles".into()));
    }
    // What the render allocates on the device: the triangles (96 bytes each), with a BVH
    // their positions for the traversal (48 bytes each) and at most 1 wide node per triangle
    // (112 bytes each), the lights (16 bytes each and a header, and a selection word of 4 bytes
    // per triangle), the accumulation image (of the area or of a tile) and its read-back and upload buffers (48 bytes per pixel each).
    let triangles = scene.triangles.len() as u64;
    let scene_bytes = scene_bytes(scene);
    let image_bytes = u64::from(image_width)
        * u64::from(image_height)
        * ACCUMULATION_COPIES
        * ACCUMULATION_BYTES_PER_PIXEL;
    let available = context.device_memory_bytes();
    if available > 0 && scene_bytes + image_bytes > available {
        return Err(Error::InvalidSettings(format!(
            "the render needs about {} MB on '{}' ({} MB for {triangles} triangles, {} MB for \
             {image_width}x{image_height} pixels of the {}x{} image at once), more than its {} MB: \
             use a smaller --tile-size or scene",
            (scene_bytes + image_bytes) >> 20,
            context.info.name,
            scene_bytes >> 20,
            image_bytes >> 20,
            settings.width,
            settings.height,
            available >> 20
        )));
    }
    Ok(())
}
