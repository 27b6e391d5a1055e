//! Which acceleration structures a scene gets on the device, decided without a device: one
//! bottom-level structure per mesh (`Scene::mesh_instances`, the glTF nodes' copies), in
//! object space, with an instance per copy, and one world-space bottom level per run of
//! triangles that no copy covers (every triangle of an OBJ, generated or built-in scene),
//! with an identity instance. Each instance's custom index is its copy's first triangle in
//! `Scene::triangles`, so that `glsl/ray_query.glsl` finds triangle custom index + primitive
//! index, the index that every per-triangle buffer uses.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Mat4, Vec4};

use crate::scene::{MeshInstance, Triangle};
use crate::vk::acceleration_structure::{IDENTITY_TRANSFORM, MAX_CUSTOM_INDEX};

/// One instance of a bottom-level structure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlannedInstance {
    /// Object to world space, row-major 3x4 (`VkTransformMatrixKHR`).
    pub transform: [[f32; 4]; 3],
    /// Its first triangle in `Scene::triangles` (the instance's custom index).
    pub first_triangle: u32,
}

/// One bottom-level structure: its triangles in object space, and its instances.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedBottomLevel {
    /// The triangles' vertices, object space.
    pub positions: Vec<[[f32; 3]; 3]>,
    /// Where it is drawn.
    pub instances: Vec<PlannedInstance>,
}

/// A scene's structures.
#[derive(Clone, Debug, PartialEq)]
pub struct StructurePlan {
    /// The bottom levels, each with its instances (in the top level in this order).
    pub bottom_levels: Vec<PlannedBottomLevel>,
}

/// `matrix` as `VkTransformMatrixKHR` rows, or `None` where it is not a finite affine map.
fn transform_rows(matrix: Mat4) -> Option<[[f32; 4]; 3]> {
    let rows = matrix.transpose();
    let finite = matrix.to_cols_array().iter().all(|x| x.is_finite());
    (finite && rows.w_axis == Vec4::W).then(|| {
        [
            rows.x_axis.to_array(),
            rows.y_axis.to_array(),
            rows.z_axis.to_array(),
        ]
    })
}

/// A world-space bottom level over `triangles[range]`, drawn once where it is.
fn world_space(triangles: &[Triangle], range: std::ops::Range<usize>) -> PlannedBottomLevel {
    PlannedBottomLevel {
        positions: triangles[range.clone()]
            .iter()
            .map(|triangle| triangle.positions.map(|p| p.to_array()))
            .collect(),
        instances: vec![PlannedInstance {
            transform: IDENTITY_TRANSFORM,
            first_triangle: range.start as u32,
        }],
    }
}

impl StructurePlan {
    /// The structures of a scene of `triangles` whose mesh copies are `instances`. A copy
    /// whose range leaves the triangles, overlaps an earlier copy, starts beyond
    /// `MAX_CUSTOM_INDEX` or has no affine transform is not instanced: its triangles join the
    /// world-space runs.
    pub fn of(triangles: &[Triangle], instances: &[MeshInstance]) -> StructurePlan {
        let mut sorted: Vec<&MeshInstance> = instances.iter().collect();
        sorted.sort_by_key(|instance| instance.first_triangle);
        let mut bottom_levels: Vec<PlannedBottomLevel> = Vec::new();
        // Bottom level of each mesh's shared positions
        let mut of_mesh: HashMap<*const Vec<[glam::Vec3; 3]>, usize> = HashMap::new();
        let mut covered_to = 0;
        for instance in sorted {
            let range = instance.triangles();
            let transform = transform_rows(instance.object_to_world);
            let fits = range.start >= covered_to
                && range.end <= triangles.len()
                && range.start <= MAX_CUSTOM_INDEX as usize;
            let Some(transform) = transform.filter(|_| fits) else {
                continue;
            };
            if range.start > covered_to {
                bottom_levels.push(world_space(triangles, covered_to..range.start));
            }
            covered_to = range.end;
            let planned = PlannedInstance {
                transform,
                first_triangle: range.start as u32,
            };
            let key = Arc::as_ptr(&instance.object_positions);
            match of_mesh.get(&key) {
                Some(&index) => bottom_levels[index].instances.push(planned),
                None => {
                    of_mesh.insert(key, bottom_levels.len());
                    bottom_levels.push(PlannedBottomLevel {
                        positions: instance
                            .object_positions
                            .iter()
                            .map(|corners| corners.map(|p| p.to_array()))
                            .collect(),
                        instances: vec![planned],
                    });
                }
            }
        }
        if covered_to < triangles.len() {
            bottom_levels.push(world_space(triangles, covered_to..triangles.len()));
        }
        StructurePlan { bottom_levels }
    }

    /// Instances in the top level.
    pub fn instance_count(&self) -> usize {
        self.bottom_levels.iter().map(|b| b.instances.len()).sum()
    }

    /// The largest first triangle of an instance (what its 24-bit custom index must hold).
    pub fn largest_first_triangle(&self) -> u64 {
        self.bottom_levels
            .iter()
            .flat_map(|b| &b.instances)
            .map(|i| u64::from(i.first_triangle))
            .max()
            .unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn triangle(x: f32) -> Triangle {
        Triangle::new(
            [
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x + 1.0, 0.0, 0.0),
                Vec3::Y,
            ],
            Vec3::ONE,
            Vec3::ZERO,
            false,
        )
        .unwrap()
    }

    #[test]
    fn copies_of_a_mesh_share_a_bottom_level_and_the_rest_is_world_space() {
        let triangles: Vec<Triangle> = (0..7).map(|i| triangle(i as f32)).collect();
        let mesh = Arc::new(vec![[Vec3::ZERO, Vec3::X, Vec3::Y]; 2]);
        let copy = |first, x: f32| MeshInstance {
            first_triangle: first,
            object_to_world: Mat4::from_translation(Vec3::new(x, 0.0, 0.0)),
            object_positions: mesh.clone(),
            node: None,
        };
        // Triangles 0 (loose), 1..3 and 3..5 (copies of one mesh), 5..7 (loose)
        let plan = StructurePlan::of(&triangles, &[copy(3, 2.0), copy(1, 1.0)]);
        assert_eq!(plan.bottom_levels.len(), 3);
        assert_eq!(plan.instance_count(), 4);
        let firsts: Vec<Vec<u32>> = plan
            .bottom_levels
            .iter()
            .map(|b| b.instances.iter().map(|i| i.first_triangle).collect())
            .collect();
        assert_eq!(firsts, [vec![0], vec![1, 3], vec![5]]);
        assert_eq!(plan.bottom_levels[0].positions.len(), 1);
        assert_eq!(plan.bottom_levels[1].positions.len(), 2);
        assert_eq!(plan.bottom_levels[2].positions.len(), 2);
        // Row-major rows: the translation is each row's last element
        assert_eq!(plan.bottom_levels[1].instances[1].transform[0][3], 2.0);
        assert_eq!(plan.largest_first_triangle(), 5);
        // An overlapping or out-of-range copy is not instanced: all world space
        let bad = StructurePlan::of(&triangles, &[copy(1, 1.0), copy(2, 1.0), copy(6, 1.0)]);
        assert_eq!(bad.instance_count(), 3);
        assert_eq!(bad.bottom_levels[2].positions.len(), 4);
        // No copies: one world-space bottom level, as for OBJ and generated scenes
        let plain = StructurePlan::of(&triangles, &[]);
        assert_eq!(plain.bottom_levels, [world_space(&triangles, 0..7)]);
    }
}
