//! The device's own acceleration structures for a scene (`--accel hardware`, and `--accel
//! auto` on devices with ray queries): which traversal a render takes on its device
//! (`choose_traversal`: ray queries, their absence, their limits and memory), and the
//! structures built over the scene's triangles (`SceneStructures`), which
//! `glsl/ray_query.glsl` traverses.
//!
//! Layout (`plan`): one bottom-level structure per mesh that glTF nodes draw, an instance per
//! node, and world-space bottom levels over the triangles no node's copy covers (all of them
//! for other scenes); each instance's custom index is its first triangle, so the kernel's
//! triangle index is custom index + primitive index, and every per-triangle buffer
//! (triangles, shading data, lights) stays in the scene's order. Every frame of an animation
//! loads its scene again, so its structures are built again.

pub mod plan;

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::kernels::variant::{Accel, Traversal, TraversalContext};
use crate::render::tiles::scene_bytes;
use crate::scene::Scene;
use crate::vk::acceleration_structure::{
    bottom_level_sizes, top_level_sizes, InstanceDescription, MAX_CUSTOM_INDEX,
};
use crate::vk::{AccelerationStructure, CommandRunner, Context, DeviceKind, RayQuerySupport};
use plan::StructurePlan;

/// Bytes of the bottom level's vertex input per triangle (three `[f32; 3]`), held on the
/// device (and in a staging buffer) while it is built.
const VERTEX_BYTES_PER_TRIANGLE: u64 = 36;

/// The traversal a render takes on its device, and the warning to print when `--accel auto`
/// fell back from the device's ray queries to the BVH.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TraversalChoice {
    /// How rays find hits.
    pub traversal: Traversal,
    /// One line for the user, where the choice is not what `accel` would take on a device
    /// whose structures hold the scene.
    pub warning: Option<String>,
}

/// What the device's structures of `plan` need, in bytes, while they are built: the
/// structures, their scratch memory (all of it: a conservative bound, each build frees its
/// own) and the vertex input (twice: its staging copy).
pub fn build_bytes(context: &Context, plan: &StructurePlan, opaque: bool) -> u64 {
    let top = top_level_sizes(context, plan.instance_count() as u32);
    let bottom: u64 = plan
        .bottom_levels
        .iter()
        .map(|level| {
            let count = level.positions.len() as u32;
            let sizes = bottom_level_sizes(context, count, opaque);
            sizes.structure + sizes.scratch + 2 * VERTEX_BYTES_PER_TRIANGLE * u64::from(count)
        })
        .sum();
    bottom + top.structure + top.scratch
}

/// Why a device's structures cannot hold a scene (`check_fits`), in words that follow "the
/// scene's acceleration structures do not fit 'DEVICE': ".
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum StructureFitError {
    /// The device has no ray queries.
    #[error("it has no ray queries")]
    NoRayQueries,
    /// One structure holds more triangles than the device's structures may.
    #[error(
        "the scene's {triangles} triangles in one structure exceed its acceleration structures' limit of {limit}"
    )]
    Triangles {
        /// Triangles of the largest bottom level.
        triangles: u64,
        /// The device's `maxPrimitiveCount`.
        limit: u64,
    },
    /// More instances than the device's top level may hold.
    #[error(
        "the scene's {instances} instances exceed its acceleration structures' limit of {limit}"
    )]
    Instances {
        /// Instances in the top level.
        instances: u64,
        /// The device's `maxInstanceCount`.
        limit: u64,
    },
    /// An instance's first triangle beyond the 24-bit custom index.
    #[error("an instance starts at triangle {0}, beyond the 24-bit custom index")]
    CustomIndex(u64),
    /// The structures and the scene's other buffers need more than the device's memory.
    #[error(
        "the scene's acceleration structures and buffers need about {needed_mb} MB, more than its {available_mb} MB"
    )]
    Memory {
        /// What they need, in MiB (rounded down).
        needed_mb: u64,
        /// The device's memory, in MiB (rounded down).
        available_mb: u64,
    },
}

/// Why the device's structures cannot hold `scene` as `plan` lays it out (its limits on
/// triangles per structure, instances and custom indices; its memory beside the scene's other
/// buffers), or `Ok` where they can. The device must have ray queries.
pub fn check_fits(
    context: &Context,
    scene: &Scene,
    plan: &StructurePlan,
) -> std::result::Result<(), StructureFitError> {
    let Some(limits) = context.ray_queries.limits() else {
        return Err(StructureFitError::NoRayQueries);
    };
    let largest = plan
        .bottom_levels
        .iter()
        .map(|level| level.positions.len() as u64)
        .max()
        .unwrap_or(0);
    if largest > limits.max_primitive_count {
        return Err(StructureFitError::Triangles {
            triangles: largest,
            limit: limits.max_primitive_count,
        });
    }
    let instances = plan.instance_count() as u64;
    if instances > limits.max_instance_count {
        return Err(StructureFitError::Instances {
            instances,
            limit: limits.max_instance_count,
        });
    }
    if plan.largest_first_triangle() > u64::from(MAX_CUSTOM_INDEX) {
        return Err(StructureFitError::CustomIndex(
            plan.largest_first_triangle(),
        ));
    }
    let needed = build_bytes(context, plan, !scene.uses_alpha()) + scene_bytes(scene);
    let available = context.device_memory_bytes();
    if available > 0 && needed > available {
        return Err(StructureFitError::Memory {
            needed_mb: needed >> 20,
            available_mb: available >> 20,
        });
    }
    Ok(())
}

/// The traversal of `scene` for `accel` on `context`'s device (`Traversal::choose_on_device`:
/// `auto` takes ray queries on a hardware device, not on a CPU one), for one frame of a
/// sequence whose geometry moves where `moving_geometry`, checked against the device: `Accel::Hardware` on a device without ray queries, or with a
/// scene beyond its structures' limits, is an error of one line naming the device and what it
/// lacks; `Accel::Auto` falls back to the BVH there, with one warning where the structures
/// cannot hold the scene.
pub fn choose_traversal(
    context: &Context,
    scene: &Scene,
    accel: Accel,
    moving_geometry: bool,
) -> Result<TraversalChoice> {
    let on = TraversalContext {
        ray_queries: context.ray_queries.is_available(),
        cpu: context.info.kind == DeviceKind::Cpu,
        moving_geometry: moving_geometry || scene.motion.is_some(),
    };
    let traversal = Traversal::choose_on_device(
        scene.triangles.len(),
        accel,
        scene.needs_material_kernels(),
        scene.uses_alpha(),
        on,
    );
    if scene.motion.is_some() {
        return Ok(motion_blur_traversal(traversal, accel));
    }
    let device = &context.info.name;
    if traversal != Traversal::RayQuery {
        return Ok(TraversalChoice {
            traversal,
            warning: None,
        });
    }
    if let RayQuerySupport::Missing(lacking) = &context.ray_queries {
        return Err(Error::InvalidSettings(format!(
            "--accel hardware needs ray queries, and '{device}' lacks {lacking}: use --accel auto or bvh, or a driver with VK_KHR_ray_query (README: \"Ray queries\")"
        )));
    }
    let plan = StructurePlan::of(&scene.triangles, &scene.mesh_instances);
    match (check_fits(context, scene, &plan), accel) {
        (Ok(()), _) => Ok(TraversalChoice {
            traversal,
            warning: None,
        }),
        (Err(reason), Accel::Hardware) => Err(Error::InvalidSettings(format!(
            "--accel hardware cannot hold the scene on '{device}': {reason}; use --accel bvh"
        ))),
        (Err(reason), _) => Ok(TraversalChoice {
            traversal: Traversal::CompressedBvh,
            warning: Some(format!(
                "the BVH instead of '{device}''s ray queries: {reason}"
            )),
        }),
    }
}

/// What traces a motion-blurred scene (`Scene::motion`): the 4-wide BVH over the triangles'
/// boxes across the shutter, or the loop over all triangles read from the buffer, which
/// both interpolate the keys (`glsl/scene.glsl`). The device's ray queries (no motion
/// extension is used) and the compressed tree (whose leaves hold the still triangles' tight
/// boxes) make way for the BVH, with one line where the command asked for them; the
/// constant triangles (compiled in, still) for the loop.
fn motion_blur_traversal(traversal: Traversal, accel: Accel) -> TraversalChoice {
    let (traversal, warning) = match traversal {
        Traversal::RayQuery | Traversal::CompressedBvh => (
            Traversal::Bvh,
            (accel != Accel::Auto).then(|| {
                format!(
                    "motion blur: the 4-wide BVH instead of the {}, which holds the scene at one time",
                    traversal.name()
                )
            }),
        ),
        Traversal::ConstantTriangles => (Traversal::Linear, None),
        traversal => (traversal, None),
    };
    TraversalChoice { traversal, warning }
}

/// The device's structures over a scene's triangles, as `glsl/ray_query.glsl` reads them.
pub struct SceneStructures {
    /// The top-level structure (bound at `BINDING_ACCELERATION_STRUCTURE`).
    pub top: AccelerationStructure,
    /// The bottom-level structures, which `top` instances.
    bottom: Vec<AccelerationStructure>,
    /// Instances in `top`.
    instance_count: usize,
}

impl SceneStructures {
    /// Builds the structures of `scene` (its triangles in their scene order, the order of
    /// the kernel's buffers), opaque unless some material is alpha-tested, after checking
    /// that they fit (`check_fits`).
    pub fn build(
        context: &Arc<Context>,
        commands: &CommandRunner,
        scene: &Scene,
    ) -> Result<SceneStructures> {
        let plan = StructurePlan::of(&scene.triangles, &scene.mesh_instances);
        check_fits(context, scene, &plan).map_err(|reason| {
            Error::InvalidSettings(format!(
                "the scene's acceleration structures do not fit '{}': {reason}",
                context.info.name
            ))
        })?;
        let mut bottom = Vec::with_capacity(plan.bottom_levels.len());
        let mut instances = Vec::with_capacity(plan.instance_count());
        for level in &plan.bottom_levels {
            let structure = AccelerationStructure::bottom_level(
                context,
                commands,
                "scene mesh's structure",
                &level.positions,
                !scene.uses_alpha(),
            )?;
            instances.extend(level.instances.iter().map(|instance| InstanceDescription {
                transform: instance.transform,
                custom_index: instance.first_triangle,
                bottom_level_address: structure.address,
            }));
            bottom.push(structure);
        }
        let top = AccelerationStructure::top_level(
            context,
            commands,
            "scene instances' structure",
            &instances,
        )?;
        Ok(SceneStructures {
            top,
            bottom,
            instance_count: instances.len(),
        })
    }

    /// Bytes of all structures on the device.
    pub fn bytes(&self) -> u64 {
        self.top.size + self.bottom.iter().map(|b| b.size).sum::<u64>()
    }

    /// Bottom-level structures (meshes and world-space runs).
    pub fn bottom_level_count(&self) -> usize {
        self.bottom.len()
    }

    /// Instances in the top level.
    pub fn instance_count(&self) -> usize {
        self.instance_count
    }
}
