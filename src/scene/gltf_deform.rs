//! A glTF node's mesh posed at the loader's time: its morph targets and, on a node with a
//! skin, its joints, read from the file and checked, then applied to each primitive's
//! vertices by `morph_targets.rs` and `skinning.rs` (morph targets first, as glTF orders
//! them). Broken skins and targets are one-line errors naming the skin or mesh and the
//! accessor.

use glam::{Mat3, Mat4, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions, Iter};
use gltf::{Document, Node};

use super::gltf_animation::Pose;
use super::gltf_loader::{check_accessor, label, malformed};
use super::morph_targets::{apply_morph_targets, default_weights, MorphTarget};
use super::skinning::{joint_matrices, skin_vertices, Influences};
use super::SceneError;

/// How one node draws its mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct NodeDeformation {
    /// One weight per morph target of the mesh (empty without targets).
    pub morph_weights: Vec<f32>,
    /// For a node with a skin: the skin's name and its joints' skinning matrices (bind
    /// space to world space), in the order of its `joints`.
    pub skin: Option<(String, Vec<Mat4>)>,
}

/// What posing one primitive found besides its vertices.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct PosedPrimitive {
    /// The number of vertices whose joint weights were renormalised.
    pub renormalised: usize,
    /// On a skinned node: each vertex's blended linear map, bind space to world space (for
    /// `skinning::skin_mirrors`); `None` without a skin.
    pub skin_maps: Option<Vec<Mat3>>,
}

/// Poses the meshes of one load.
pub(super) struct Deformer<'a> {
    path: &'a std::path::Path,
    buffers: &'a [gltf::buffer::Data],
    pose: Pose,
    /// Every node's local-to-world matrix in the pose (`None` for a node on a cycle).
    node_to_world: Vec<Option<Mat4>>,
}

impl<'a> Deformer<'a> {
    /// The deformer of a file in `pose`.
    pub fn new(
        path: &'a std::path::Path,
        document: &Document,
        buffers: &'a [gltf::buffer::Data],
        pose: Pose,
    ) -> Deformer<'a> {
        let node_to_world = node_to_world(document, &pose);
        Deformer {
            path,
            buffers,
            pose,
            node_to_world,
        }
    }

    /// The pose's local-to-parent matrices, for the loader's walk of the hierarchy.
    pub fn local_transforms(&self) -> &std::collections::HashMap<usize, Mat4> {
        &self.pose.local_transforms
    }

    /// How `node` (which has `mesh`) draws it: its morph weights (animated, else the
    /// node's, else the mesh's, else zeros) and its skin's joint matrices.
    pub fn node(&self, node: &Node, mesh: &gltf::Mesh) -> Result<NodeDeformation, SceneError> {
        let mesh_name = label(mesh.name(), mesh.index());
        let counts: Vec<usize> = mesh.primitives().map(|p| p.morph_targets().len()).collect();
        let target_count = counts.iter().copied().max().unwrap_or(0);
        if counts.iter().any(|&c| c != target_count) {
            return Err(malformed(
                self.path,
                format!("mesh '{mesh_name}': its primitives have different numbers of morph targets ({counts:?})"),
            ));
        }
        let morph_weights = match self.pose.morph_weights.get(&node.index()) {
            Some(weights) => weights.clone(),
            None => {
                default_weights(node.weights(), mesh.weights(), target_count).map_err(|reason| {
                    let node = label(node.name(), node.index());
                    malformed(
                        self.path,
                        format!("node '{node}' mesh '{mesh_name}': {reason}"),
                    )
                })?
            }
        };
        let skin = match node.skin() {
            Some(skin) => Some(self.skin(&skin)?),
            None => None,
        };
        Ok(NodeDeformation {
            morph_weights,
            skin,
        })
    }

    /// A skin's name and joint matrices: each joint's world matrix times its inverse bind
    /// matrix (the identity without `inverseBindMatrices`).
    fn skin(&self, skin: &gltf::Skin) -> Result<(String, Vec<Mat4>), SceneError> {
        let name = label(skin.name(), skin.index());
        let bad = |reason: String| malformed(self.path, format!("skin '{name}': {reason}"));
        let joints: Vec<Node> = skin.joints().collect();
        if joints.is_empty() {
            return Err(bad("has no joints".into()));
        }
        let inverse_bind = match skin.inverse_bind_matrices() {
            None => vec![Mat4::IDENTITY; joints.len()],
            Some(accessor) => {
                let accessor_name = label(accessor.name(), accessor.index());
                check_accessor(&accessor, Dimensions::Mat4, &[DataType::F32])
                    .map_err(|reason| bad(format!("inverseBindMatrices {reason}")))?;
                // glTF 2.0 § 5.28.2: at least one matrix per joint; more are valid (the
                // first `joints.len()` are the joints')
                let count = accessor.count();
                if count < joints.len() {
                    return Err(bad(format!(
                        "inverseBindMatrices accessor '{accessor_name}' holds {count} matrices for {} joints",
                        joints.len()
                    )));
                }
                let mut matrices: Vec<Mat4> = Iter::<[[f32; 4]; 4]>::new(accessor, self.buffer())
                    .map(|iter| iter.map(|m| Mat4::from_cols_array_2d(&m)).collect())
                    .unwrap_or_default();
                if matrices.len() != count {
                    return Err(bad(format!(
                        "inverseBindMatrices accessor '{accessor_name}' lies outside its buffer"
                    )));
                }
                matrices.truncate(joints.len());
                matrices
            }
        };
        let worlds = joints
            .iter()
            .map(|joint| {
                self.node_to_world
                    .get(joint.index())
                    .copied()
                    .flatten()
                    .ok_or_else(|| {
                        bad(format!(
                            "joint node '{}' lies on a cycle of the node hierarchy",
                            label(joint.name(), joint.index())
                        ))
                    })
            })
            .collect::<Result<Vec<Mat4>, SceneError>>()?;
        Ok((name, joint_matrices(&worlds, &inverse_bind)))
    }

    /// The buffer lookup of accessor readers.
    fn buffer(&self) -> impl Clone + Fn(gltf::Buffer<'_>) -> Option<&'a [u8]> {
        let buffers = self.buffers;
        move |buffer: gltf::Buffer<'_>| buffers.get(buffer.index()).map(|d| &d[..])
    }

    /// Poses one primitive's vertices in place (`context` names it in messages): morph
    /// targets with the node's weights, then its skin, which leaves them in world space.
    pub fn primitive(
        &self,
        primitive: &gltf::Primitive,
        context: &str,
        deformation: &NodeDeformation,
        positions: &mut [Vec3],
        mut normals: Option<&mut Vec<Vec3>>,
        mut tangents: Option<&mut Vec<Vec4>>,
    ) -> Result<PosedPrimitive, SceneError> {
        let targets = self.morph_targets(primitive, context, positions.len())?;
        if deformation.morph_weights.iter().any(|&w| w != 0.0) {
            apply_morph_targets(
                &targets,
                &deformation.morph_weights,
                positions,
                normals.as_deref_mut(),
                tangents.as_deref_mut(),
            );
        }
        let Some((skin, matrices)) = &deformation.skin else {
            return Ok(PosedPrimitive::default());
        };
        let mut influences = self.influences(primitive, context, skin, positions.len())?;
        if let Some((vertex, slot, joint)) = influences.joint_past(matrices.len()) {
            let set = slot / 4;
            let accessor = primitive
                .get(&gltf::Semantic::Joints(set as u32))
                .map_or_else(String::new, |a| label(a.name(), a.index()));
            return Err(malformed(
                self.path,
                format!(
                    "skin '{skin}': {context}: JOINTS_{set} accessor '{accessor}' gives vertex {vertex} joint {joint}, but the skin has {} joints",
                    matrices.len()
                ),
            ));
        }
        let renormalised = influences.normalise_weights();
        let skin_maps = skin_vertices(&influences, matrices, positions, normals, tangents);
        Ok(PosedPrimitive {
            renormalised,
            skin_maps: Some(skin_maps),
        })
    }

    /// The primitive's morph targets, each attribute checked: VEC3 floats, one per vertex.
    fn morph_targets(
        &self,
        primitive: &gltf::Primitive,
        context: &str,
        vertex_count: usize,
    ) -> Result<Vec<MorphTarget>, SceneError> {
        let read = |accessor: Option<gltf::Accessor>, what: &str, target: usize| {
            let Some(accessor) = accessor else {
                return Ok(None);
            };
            let name = label(accessor.name(), accessor.index());
            let bad = |reason: String| {
                malformed(
                    self.path,
                    format!("{context}: morph target {target} {what}: {reason}"),
                )
            };
            check_accessor(&accessor, Dimensions::Vec3, &[DataType::F32])
                .map_err(|reason| bad(reason.to_string()))?;
            if accessor.count() != vertex_count {
                return Err(bad(format!(
                    "accessor '{name}' holds {} elements for {vertex_count} vertices",
                    accessor.count()
                )));
            }
            let values: Vec<Vec3> = Iter::<[f32; 3]>::new(accessor, self.buffer())
                .map(|iter| iter.map(Vec3::from).collect())
                .unwrap_or_default();
            if values.len() != vertex_count {
                return Err(bad(format!("accessor '{name}' lies outside its buffer")));
            }
            Ok(Some(values))
        };
        primitive
            .morph_targets()
            .enumerate()
            .map(|(i, target)| {
                Ok(MorphTarget {
                    positions: read(target.positions(), "POSITION", i)?,
                    normals: read(target.normals(), "NORMAL", i)?,
                    tangents: read(target.tangents(), "TANGENT", i)?,
                })
            })
            .collect()
    }

    /// The primitive's JOINTS_n and WEIGHTS_n sets, checked: JOINTS_0 present, each JOINTS_n
    /// with its WEIGHTS_n, VEC4 of the types glTF allows, one element per vertex.
    fn influences(
        &self,
        primitive: &gltf::Primitive,
        context: &str,
        skin: &str,
        vertex_count: usize,
    ) -> Result<Influences, SceneError> {
        let bad =
            |reason: String| malformed(self.path, format!("skin '{skin}': {context}: {reason}"));
        let reader = primitive.reader(self.buffer());
        // Each set's joints and weights, one element per vertex.
        let mut sets: Vec<JointSet> = Vec::new();
        for set in 0u32.. {
            let Some(joints) = primitive.get(&gltf::Semantic::Joints(set)) else {
                break;
            };
            let weights = primitive
                .get(&gltf::Semantic::Weights(set))
                .ok_or_else(|| bad(format!("has JOINTS_{set} but no WEIGHTS_{set}")))?;
            for (accessor, what, types) in [
                (&joints, "JOINTS", &[DataType::U8, DataType::U16][..]),
                (
                    &weights,
                    "WEIGHTS",
                    &[DataType::F32, DataType::U8, DataType::U16][..],
                ),
            ] {
                let name = label(accessor.name(), accessor.index());
                check_accessor(accessor, Dimensions::Vec4, types)
                    .map_err(|reason| bad(format!("{what}_{set} {reason}")))?;
                if accessor.count() != vertex_count {
                    return Err(bad(format!(
                        "{what}_{set} accessor '{name}' holds {} elements for {vertex_count} vertices",
                        accessor.count()
                    )));
                }
            }
            let joint_values: Vec<[u16; 4]> = reader
                .read_joints(set)
                .map(|j| j.into_u16().collect())
                .unwrap_or_default();
            let weight_values: Vec<[f32; 4]> = reader
                .read_weights(set)
                .map(|w| w.into_f32().collect())
                .unwrap_or_default();
            if joint_values.len() != vertex_count || weight_values.len() != vertex_count {
                return Err(bad(format!(
                    "JOINTS_{set} or WEIGHTS_{set} data lies outside its buffer"
                )));
            }
            sets.push((joint_values, weight_values));
        }
        if sets.is_empty() {
            return Err(bad(
                "has no JOINTS_0 attribute, so it cannot be skinned".into()
            ));
        }
        let width = 4 * sets.len();
        let mut influences = Influences {
            joints: Vec::with_capacity(width * vertex_count),
            weights: Vec::with_capacity(width * vertex_count),
            width,
        };
        for vertex in 0..vertex_count {
            for (joints, weights) in &sets {
                influences.joints.extend(joints[vertex].map(u32::from));
                influences.weights.extend(weights[vertex]);
            }
        }
        Ok(influences)
    }
}

/// One JOINTS_n set's joint indices and its WEIGHTS_n, per vertex.
type JointSet = (Vec<[u16; 4]>, Vec<[f32; 4]>);

/// Every node's local-to-world matrix with the pose's local transforms: the product of the
/// local matrices from its root down (as the loader's walk multiplies them); `None` for a
/// node whose parent chain loops. Each node's matrix is its parent's times its own, found
/// once: linear in the node count, however deep the hierarchy (a chain of 100,000 nodes),
/// and without recursion.
fn node_to_world(document: &Document, pose: &Pose) -> Vec<Option<Mat4>> {
    let count = document.nodes().len();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for node in document.nodes() {
        for child in node.children() {
            if let Some(slot) = parent.get_mut(child.index()) {
                slot.get_or_insert(node.index());
            }
        }
    }
    let nodes: Vec<Node> = document.nodes().collect();
    let local = |i: usize| {
        pose.local_transforms
            .get(&i)
            .copied()
            .unwrap_or_else(|| Mat4::from_cols_array_2d(&nodes[i].transform().matrix()))
    };
    /// Where a node's matrix stands while the walk finds them.
    #[derive(Clone, Copy)]
    enum Found {
        /// Not reached yet.
        No,
        /// On the chain being climbed now: reaching it again means a cycle.
        Climbing,
        /// Found: the matrix, or `None` on or under a cycle.
        Yes(Option<Mat4>),
    }
    let mut found = vec![Found::No; count];
    let mut chain = Vec::new();
    for start in 0..count {
        // Climb from `start` to a root or to a node already found, then multiply down.
        chain.clear();
        let mut at = start;
        let base = loop {
            match found[at] {
                Found::Yes(world) => break world,
                Found::Climbing => break None,
                Found::No => {
                    found[at] = Found::Climbing;
                    chain.push(at);
                    match parent[at] {
                        Some(up) => at = up,
                        None => break Some(Mat4::IDENTITY),
                    }
                }
            }
        };
        let mut world = base;
        for &i in chain.iter().rev() {
            world = world.map(|w| w * local(i));
            found[i] = Found::Yes(world);
        }
    }
    found
        .into_iter()
        .map(|f| match f {
            Found::Yes(world) => world,
            Found::No | Found::Climbing => None,
        })
        .collect()
}
