//! Which ranges of a scene's triangles are copies of one mesh: the glTF loader flattens every
//! node's mesh into world-space triangles (`Scene::triangles`, what the kernels and the BVH
//! read), and records beside them each node's copy as a `MeshInstance` (its range, its
//! object-to-world transform and the mesh's object-space positions, shared between the
//! copies of one mesh). The device's acceleration structures (`crate::accel`) build one
//! bottom-level structure per mesh and an instance per copy from them, as animation needs.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Mat4, Vec3};

/// One node's copy of a mesh in `Scene::triangles`.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshInstance {
    /// Index in `Scene::triangles` of the copy's first triangle; the copy holds
    /// `object_positions.len()` triangles from there on.
    pub first_triangle: usize,
    /// Object to world space: triangle `first_triangle + i` is `object_positions[i]`
    /// transformed by it (up to rounding).
    pub object_to_world: Mat4,
    /// The copy's triangles in object space, in the order of its range (the triangles that
    /// the loader dropped as degenerate left out), shared by every copy of the same mesh
    /// whose triangles are the same.
    pub object_positions: Arc<Vec<[Vec3; 3]>>,
    /// The glTF node that draws the copy (`None` for other sources, e.g. Python's arrays):
    /// what the ground-truth AOVs (`--aov object_id`) name.
    pub node: Option<Arc<NodeLabel>>,
}

/// A glTF node as the ground-truth outputs name it: its index in the file, its name
/// (`#index` where it has none) and its path in the node tree (`/` then the names of its
/// ancestors and its own, `/` between).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NodeLabel {
    /// Index in the file's `nodes`.
    pub index: usize,
    /// Its name, printable, or `#index`.
    pub name: String,
    /// Its path from the scene's root, e.g. `/Tree/Leaf`.
    pub path: String,
    /// Index in the file's `meshes` of the mesh it draws.
    pub mesh: usize,
}

impl MeshInstance {
    /// The range of `Scene::triangles` the copy occupies.
    pub fn triangles(&self) -> std::ops::Range<usize> {
        self.first_triangle..self.first_triangle + self.object_positions.len()
    }
}

/// Records a loader's mesh copies, sharing the object-space positions of copies of one mesh.
#[derive(Default)]
pub(crate) struct InstanceRecorder {
    /// The last positions recorded of each mesh (by its index in the file) drawn with and
    /// without mirroring (which reorders each triangle's vertices).
    shared: HashMap<(usize, bool), Arc<Vec<[Vec3; 3]>>>,
}

impl InstanceRecorder {
    /// The copy of mesh `mesh` whose kept triangles start at `first_triangle` and are
    /// `object_positions` in object space, drawn with `object_to_world`; `None` where none
    /// was kept.
    pub(crate) fn instance(
        &mut self,
        mesh: usize,
        first_triangle: usize,
        object_to_world: Mat4,
        object_positions: Vec<[Vec3; 3]>,
    ) -> Option<MeshInstance> {
        if object_positions.is_empty() {
            return None;
        }
        let key = (mesh, object_to_world.determinant() < 0.0);
        let shared = match self.shared.get(&key) {
            Some(shared) if **shared == object_positions => shared.clone(),
            _ => {
                let shared = Arc::new(object_positions);
                self.shared.insert(key, shared.clone());
                shared
            }
        };
        Some(MeshInstance {
            first_triangle,
            object_to_world,
            object_positions: shared,
            node: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn copies_of_one_mesh_share_their_positions() {
        let quad = vec![[Vec3::ZERO, Vec3::X, Vec3::Y]];
        let mut recorder = InstanceRecorder::default();
        let a = recorder
            .instance(0, 0, Mat4::IDENTITY, quad.clone())
            .unwrap();
        let moved = Mat4::from_translation(Vec3::X);
        let b = recorder.instance(0, 1, moved, quad.clone()).unwrap();
        assert!(Arc::ptr_eq(&a.object_positions, &b.object_positions));
        assert_eq!(b.triangles(), 1..2);
        // A mirrored copy (its vertices reordered) differs, and leaves the others shared
        let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let mirrored = vec![[Vec3::ZERO, Vec3::Y, Vec3::X]];
        let c = recorder.instance(0, 2, mirror, mirrored).unwrap();
        assert!(!Arc::ptr_eq(&a.object_positions, &c.object_positions));
        let d = recorder.instance(0, 3, moved, quad.clone()).unwrap();
        assert!(Arc::ptr_eq(&a.object_positions, &d.object_positions));
        assert_eq!(recorder.instance(1, 4, moved, Vec::new()), None);
    }
}
