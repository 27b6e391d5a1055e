//! Linear blend skinning, as glTF 2.0 defines it (spec section 3.7.3): each vertex follows
//! its joints, `v' = Σ wᵢ · jointToWorld(jᵢ) · inverseBind(jᵢ) · v`, straight into world
//! space (the skinned mesh node's own transform is ignored). Normals follow the inverse
//! transpose of the blended matrix, tangents the matrix itself. Pure maths, no file format:
//! `gltf_deform.rs` reads the skins, joints and weights into these types.

use glam::{Mat3, Mat4, Vec3, Vec4};

/// How far from 1 a vertex's weight sum may be before it is renormalised: a few roundings
/// of f32 sums (2⁻²³ each) stay well below it, a quantised or careless exporter's sum does
/// not.
pub const WEIGHT_SUM_TOLERANCE: f32 = 1e-5;

/// A primitive's joint influences: `width` (4 per JOINTS_n/WEIGHTS_n set) joint indices and
/// weights per vertex, vertex after vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Influences {
    /// Indices into the skin's `joints` list.
    pub joints: Vec<u32>,
    /// The joints' weights, in [0, 1], normally summing to 1 per vertex.
    pub weights: Vec<f32>,
    /// Influences per vertex: 4 times the number of sets.
    pub width: usize,
}

impl Influences {
    /// The number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.joints.len().checked_div(self.width).unwrap_or(0)
    }

    /// The first influence whose joint is not below `joint_count`: its vertex, its slot
    /// among the vertex's `width` (set `slot / 4`) and its joint index.
    pub fn joint_past(&self, joint_count: usize) -> Option<(usize, usize, u32)> {
        let at = self
            .joints
            .iter()
            .position(|&j| j as usize >= joint_count)?;
        Some((at / self.width, at % self.width, self.joints[at]))
    }

    /// Scales each vertex's weights to sum to 1 where their sum is further than
    /// [`WEIGHT_SUM_TOLERANCE`] from it (glTF: clients should); a vertex whose weights are
    /// all zero is left alone (it then keeps its bind-space position). The number of
    /// vertices changed or left alone so.
    pub fn normalise_weights(&mut self) -> usize {
        let mut changed = 0;
        for weights in self.weights.chunks_mut(self.width.max(1)) {
            let sum: f32 = weights.iter().sum();
            if (sum - 1.0).abs() <= WEIGHT_SUM_TOLERANCE {
                continue;
            }
            changed += 1;
            if sum > 0.0 && sum.is_finite() {
                weights.iter_mut().for_each(|w| *w /= sum);
            }
        }
        changed
    }
}

/// Each joint's skinning matrix, bind space to world space:
/// `joint_to_world[j] * inverse_bind[j]`.
pub fn joint_matrices(joint_to_world: &[Mat4], inverse_bind: &[Mat4]) -> Vec<Mat4> {
    joint_to_world
        .iter()
        .zip(inverse_bind)
        .map(|(world, inverse_bind)| *world * *inverse_bind)
        .collect()
}

/// The blended matrix of one vertex: `Σ wᵢ · joint_matrices[jᵢ]` over its influences with a
/// weight other than zero; the identity where there is none. Joint indices must be in range.
pub fn skin_matrix(joints: &[u32], weights: &[f32], joint_matrices: &[Mat4]) -> Mat4 {
    let mut blended = Mat4::ZERO;
    let mut any = false;
    for (&joint, &weight) in joints.iter().zip(weights) {
        if weight != 0.0 {
            blended += joint_matrices[joint as usize] * weight;
            any = true;
        }
    }
    if any {
        blended
    } else {
        Mat4::IDENTITY
    }
}

/// Skins a primitive in place: positions to world space, normals by the inverse transpose of
/// each vertex's blended matrix (normalised), tangents' xyz by the matrix (normalised; w
/// negated where the matrix mirrors, as a mirroring node transform flips the bitangent's
/// handedness). `influences` covers every vertex and its joints are in range of
/// `joint_matrices`. Returns each vertex's blended linear map (the upper 3 x 3), which
/// [`skin_mirrors`] reads to keep a mirrored triangle's winding.
pub fn skin_vertices(
    influences: &Influences,
    joint_matrices: &[Mat4],
    positions: &mut [Vec3],
    mut normals: Option<&mut Vec<Vec3>>,
    mut tangents: Option<&mut Vec<Vec4>>,
) -> Vec<Mat3> {
    let width = influences.width;
    let mut linear_maps = Vec::with_capacity(positions.len());
    for (v, position) in positions.iter_mut().enumerate() {
        let range = v * width..(v + 1) * width;
        let matrix = skin_matrix(
            &influences.joints[range.clone()],
            &influences.weights[range],
            joint_matrices,
        );
        *position = matrix.transform_point3(*position);
        let linear = Mat3::from_mat4(matrix);
        if let Some(normal) = normals.as_mut().and_then(|n| n.get_mut(v)) {
            *normal = skin_normal(linear, *normal);
        }
        if let Some(tangent) = tangents.as_mut().and_then(|t| t.get_mut(v)) {
            // B = w N x T; under an orthogonal M, (M N) x (M T) = det(M) M (N x T), so the
            // mapped bitangent M B needs w det(M): its sign flips where M mirrors.
            let handedness = if linear.determinant() < 0.0 {
                -tangent.w
            } else {
                tangent.w
            };
            *tangent = (linear * tangent.truncate())
                .normalize_or_zero()
                .extend(handedness);
        }
        linear_maps.push(linear);
    }
    linear_maps
}

/// Whether skinning mirrors a triangle whose corners' blended linear maps are `corners`:
/// whether the map at its centroid has a negative determinant. Blending is linear in the
/// weights, so the centroid's map (the corners' weights averaged) is the corners' maps
/// averaged, and its determinant has the sign of their sum's. A mirrored triangle's
/// counter-clockwise side is its back: the loader swaps two corners, as it does under a
/// node transform with a negative determinant.
pub fn skin_mirrors(corners: [Mat3; 3]) -> bool {
    (corners[0] + corners[1] + corners[2]).determinant() < 0.0
}

/// A normal under the linear map `linear`: its inverse transpose applied, normalised (zero
/// where the map is degenerate).
pub fn skin_normal(linear: Mat3, normal: Vec3) -> Vec3 {
    let inverse_transpose = linear.inverse().transpose();
    (inverse_transpose * normal).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::FRAC_PI_2;

    fn close(a: Vec3, b: Vec3) {
        assert!((a - b).length() < 1e-5, "{a} vs {b}");
    }

    fn one_set(joints: [u32; 4], weights: [f32; 4]) -> Influences {
        Influences {
            joints: joints.to_vec(),
            weights: weights.to_vec(),
            width: 4,
        }
    }

    /// A joint at (1, 0, 0) turned 90° about +Z, bound where it stands: its skinning matrix.
    fn turned_elbow() -> Mat4 {
        let bind = Mat4::from_translation(Vec3::X);
        let posed = bind * Mat4::from_rotation_z(FRAC_PI_2);
        joint_matrices(&[posed], &[bind.inverse()])[0]
    }

    #[test]
    fn a_vertex_bound_to_one_turned_joint_turns_about_it() {
        // (2, 0, 0) is one unit along +X from the joint; a quarter turn about +Z at the joint
        // takes it to (1, 1, 0).
        let mut positions = vec![Vec3::new(2.0, 0.0, 0.0)];
        let mut normals = vec![Vec3::X];
        let mut tangents = vec![Vec4::new(0.0, 1.0, 0.0, -1.0)];
        skin_vertices(
            &one_set([0, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]),
            &[turned_elbow()],
            &mut positions,
            Some(&mut normals),
            Some(&mut tangents),
        );
        close(positions[0], Vec3::new(1.0, 1.0, 0.0));
        close(normals[0], Vec3::Y);
        close(tangents[0].truncate(), -Vec3::X);
        assert_eq!(tangents[0].w, -1.0);
    }

    #[test]
    fn two_joints_half_and_half_average_their_positions() {
        // Joint 0 stays, joint 1 is the turned elbow: (2, 0, 0) goes halfway between (2, 0, 0)
        // and (1, 1, 0), to (1.5, 0.5, 0).
        let joints = [Mat4::IDENTITY, turned_elbow()];
        let mut positions = vec![Vec3::new(2.0, 0.0, 0.0)];
        skin_vertices(
            &one_set([0, 1, 0, 0], [0.5, 0.5, 0.0, 0.0]),
            &joints,
            &mut positions,
            None,
            None,
        );
        close(positions[0], Vec3::new(1.5, 0.5, 0.0));
        // More than four influences (a second set): the same split over eight slots.
        let spread = Influences {
            joints: vec![0, 0, 0, 0, 1, 1, 1, 1],
            weights: vec![0.125; 8],
            width: 8,
        };
        let mut positions = vec![Vec3::new(2.0, 0.0, 0.0)];
        skin_vertices(&spread, &joints, &mut positions, None, None);
        close(positions[0], Vec3::new(1.5, 0.5, 0.0));
    }

    #[test]
    fn normals_follow_the_inverse_transpose_under_non_uniform_scale() {
        // Scale x by 2: the plane x + y = 0 (normal (1, 1, 0)/√2) becomes x/2 + y = 0, whose
        // normal is (1/2, 1, 0) normalised, not the scaled (2, 1, 0).
        let scale = Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
        let mut positions = vec![Vec3::new(1.0, -1.0, 0.0)];
        let mut normals = vec![Vec3::new(1.0, 1.0, 0.0).normalize()];
        skin_vertices(
            &one_set([0, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]),
            &[scale],
            &mut positions,
            Some(&mut normals),
            None,
        );
        close(positions[0], Vec3::new(2.0, -1.0, 0.0));
        close(normals[0], Vec3::new(0.5, 1.0, 0.0).normalize());
        // The skinned surface's tangent (2, -1, 0) stays perpendicular to it.
        assert!(normals[0].dot(positions[0]).abs() < 1e-6);
    }

    #[test]
    fn a_mirroring_joint_flips_handedness_and_mirrors_its_triangles() {
        // A joint that mirrors x: positions and normals mirror, the tangent (1, 0, 0, w = 1)
        // becomes (-1, 0, 0) with w = -1 (so that w N x T is still the mapped bitangent).
        let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let mut positions = [Vec3::new(2.0, 1.0, 0.0)];
        let mut normals = vec![Vec3::Z; 2];
        let mut tangents = vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 2];
        let maps = skin_vertices(
            &one_set([0, 1, 0, 0], [1.0, 0.0, 0.0, 0.0]),
            &[mirror, Mat4::IDENTITY],
            &mut positions,
            Some(&mut normals),
            Some(&mut tangents),
        );
        close(positions[0], Vec3::new(-2.0, 1.0, 0.0));
        close(normals[0], Vec3::Z);
        assert_eq!(tangents[0], Vec4::new(-1.0, 0.0, 0.0, -1.0));
        // Only the skinned vertex (one position) changed.
        assert_eq!(tangents[1], Vec4::new(1.0, 0.0, 0.0, 1.0));
        let mirrored = maps[0];
        let kept = Mat3::IDENTITY;
        assert!(skin_mirrors([mirrored; 3]));
        assert!(!skin_mirrors([kept; 3]));
        // Two corners on the mirror, one kept: the centroid's map is diag(-1/3, 1, 1).
        assert!(skin_mirrors([mirrored, mirrored, kept]));
        assert!(!skin_mirrors([mirrored, kept, kept]));
    }

    #[test]
    fn weights_not_summing_to_one_are_normalised_and_counted() {
        let mut influences = Influences {
            joints: vec![0; 12],
            weights: vec![
                1.0, 0.0, 0.0, 0.0, // already 1
                0.5, 0.5, 0.5, 0.5, // sums to 2
                0.0, 0.0, 0.0, 0.0, // no weight: left alone
            ],
            width: 4,
        };
        assert_eq!(influences.normalise_weights(), 2);
        assert_eq!(&influences.weights[4..8], &[0.25; 4]);
        assert_eq!(&influences.weights[8..], &[0.0; 4]);
        // A vertex with no weight keeps its bind-space position.
        assert_eq!(
            skin_matrix(&[0; 4], &[0.0; 4], &[Mat4::ZERO]),
            Mat4::IDENTITY
        );
    }

    #[test]
    fn joints_past_the_skin_are_found() {
        let influences = Influences {
            joints: vec![0, 1, 0, 0, 2, 3, 0, 0],
            weights: vec![0.25; 8],
            width: 4,
        };
        assert_eq!(influences.vertex_count(), 2);
        assert_eq!(influences.joint_past(4), None);
        assert_eq!(influences.joint_past(3), Some((1, 1, 3)));
    }
}
