//! The device's own acceleration structures for a scene (`--accel hardware`, and `--accel
//! auto` on devices with ray queries): which traversal a render takes on its device
//! (`choose_traversal`: ray queries, their absence, their limits and memory), and the
//! structures built over the scene's triangles (`SceneStructures`), which
//! `glsl/ray_query.glsl` traverses.
//!
//! Layout: one bottom-level structure over all triangles in the scene's order (world space,
//! so an identity instance), one instance of it in the top-level structure with custom index
//! 0 (its first triangle): the kernel's triangle index is custom index + primitive index, and
//! every per-triangle buffer (triangles, shading data, lights) stays in the scene's order.
//! The scene arrives flattened (`Scene::triangles`, meshes that several nodes use copied per
//! node), so there is one mesh to instance; a scene that keeps its meshes apart would get one
//! bottom level per mesh and an instance per node, each instance's custom index its copy's
//! first triangle.

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::kernels::variant::{Accel, Traversal};
use crate::render::tiles::scene_bytes;
use crate::scene::{Scene, Triangle};
use crate::vk::acceleration_structure::{
    bottom_level_sizes, top_level_sizes, InstanceDescription, IDENTITY_TRANSFORM,
};
use crate::vk::{AccelerationStructure, CommandRunner, Context, RayQuerySupport};

/// Instances of the top-level structure (one per bottom level: one today).
const INSTANCE_COUNT: u64 = 1;

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

/// What the device's structures for `scene` need, in bytes, while they are built: the
/// structures, their scratch memory and the vertex input (twice: its staging copy).
pub fn build_bytes(context: &Context, scene: &Scene) -> u64 {
    let triangles = scene.triangles.len() as u32;
    let bottom = bottom_level_sizes(context, triangles, !scene.uses_alpha());
    let top = top_level_sizes(context, INSTANCE_COUNT as u32);
    bottom.structure
        + bottom.scratch
        + top.structure
        + top.scratch
        + 2 * VERTEX_BYTES_PER_TRIANGLE * u64::from(triangles)
}

/// Why the device's structures cannot hold `scene` (its limits on primitives, instances and
/// custom indices; its memory beside the scene's other buffers), or `Ok` where they can.
/// The device must have ray queries.
pub fn check_fits(context: &Context, scene: &Scene) -> std::result::Result<(), String> {
    let Some(limits) = context.ray_queries.limits() else {
        return Err("it has no ray queries".into());
    };
    let triangles = scene.triangles.len() as u64;
    if triangles > limits.max_primitive_count {
        return Err(format!(
            "the scene's {triangles} triangles exceed its acceleration structures' limit of {} per structure",
            limits.max_primitive_count
        ));
    }
    if INSTANCE_COUNT > limits.max_instance_count {
        return Err(format!(
            "its acceleration structures hold at most {} instances",
            limits.max_instance_count
        ));
    }
    let needed = build_bytes(context, scene) + scene_bytes(scene);
    let available = context.device_memory_bytes();
    if available > 0 && needed > available {
        return Err(format!(
            "the scene's acceleration structures and buffers need about {} MB, more than its {} MB",
            needed >> 20,
            available >> 20
        ));
    }
    Ok(())
}

/// The traversal of `scene` for `accel` on `context`'s device (`Traversal::choose_on_device`),
/// checked against the device: `Accel::Hardware` on a device without ray queries, or with a
/// scene beyond its structures' limits, is an error of one line naming the device and what it
/// lacks; `Accel::Auto` falls back to the BVH there, with one warning where the structures
/// cannot hold the scene.
pub fn choose_traversal(context: &Context, scene: &Scene, accel: Accel) -> Result<TraversalChoice> {
    let ray_queries = context.ray_queries.is_available();
    let traversal = Traversal::choose_on_device(
        scene.triangles.len(),
        accel,
        scene.needs_material_kernels(),
        scene.uses_alpha(),
        ray_queries,
    );
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
    match (check_fits(context, scene), accel) {
        (Ok(()), _) => Ok(TraversalChoice {
            traversal,
            warning: None,
        }),
        (Err(reason), Accel::Hardware) => Err(Error::InvalidSettings(format!(
            "--accel hardware cannot hold the scene on '{device}': {reason}; use --accel bvh"
        ))),
        (Err(reason), _) => Ok(TraversalChoice {
            traversal: Traversal::Bvh,
            warning: Some(format!(
                "the BVH instead of '{device}''s ray queries: {reason}"
            )),
        }),
    }
}

/// The device's structures over a scene's triangles, as `glsl/ray_query.glsl` reads them.
pub struct SceneStructures {
    /// The top-level structure (bound at `BINDING_ACCELERATION_STRUCTURE`).
    pub top: AccelerationStructure,
    /// The bottom-level structure over the triangles, which `top` instances.
    bottom: AccelerationStructure,
}

impl SceneStructures {
    /// Builds the structures over `triangles` (in the order the kernel's buffers hold them),
    /// opaque unless some material is `alpha`-tested, after checking that they fit
    /// (`check_fits`).
    pub fn build(
        context: &Arc<Context>,
        commands: &CommandRunner,
        scene: &Scene,
        triangles: &[Triangle],
    ) -> Result<SceneStructures> {
        check_fits(context, scene).map_err(|reason| {
            Error::InvalidSettings(format!(
                "the scene's acceleration structures do not fit '{}': {reason}",
                context.info.name
            ))
        })?;
        let positions: Vec<[[f32; 3]; 3]> = triangles
            .iter()
            .map(|triangle| triangle.positions.map(|p| p.to_array()))
            .collect();
        let bottom = AccelerationStructure::bottom_level(
            context,
            commands,
            "scene triangles' structure",
            &positions,
            !scene.uses_alpha(),
        )?;
        let top = AccelerationStructure::top_level(
            context,
            commands,
            "scene instances' structure",
            &[InstanceDescription {
                transform: IDENTITY_TRANSFORM,
                custom_index: 0,
                bottom_level_address: bottom.address,
            }],
        )?;
        Ok(SceneStructures { top, bottom })
    }

    /// Bytes of both structures on the device.
    pub fn bytes(&self) -> u64 {
        self.top.size + self.bottom.size
    }
}
