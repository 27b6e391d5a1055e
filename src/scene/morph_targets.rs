//! Morph targets, as glTF 2.0 defines them (spec section 3.7.2.2): a primitive's vertex
//! attributes plus the weighted sum of its targets' displacements,
//! `v = base + Σ wᵢ · deltaᵢ`, with the weights of the node (else of the mesh, else zeros),
//! which `weights` animation channels may replace. Pure maths, no file format:
//! `gltf_deform.rs` reads the file's targets and weights into these types.

use glam::{Vec3, Vec4};

use super::animation::{check_keys, hermite_basis, key_segment, Interpolation, SamplerError};

/// One morph target's displacements, one element per vertex of its primitive (`None`
/// where the target leaves that attribute alone).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    /// Position displacements, object space.
    pub positions: Option<Vec<Vec3>>,
    /// Normal displacements (the sum is normalised by the loader afterwards).
    pub normals: Option<Vec<Vec3>>,
    /// Tangent displacements, xyz only (the handedness w is never morphed).
    pub tangents: Option<Vec<Vec3>>,
}

/// `base[v] + Σ weights[i] · deltas[i][v]` for every vertex `v`; targets without deltas
/// (`None`) and zero weights add nothing. Every delta list has `base.len()` elements.
pub fn morph_vectors(base: &mut [Vec3], deltas: &[Option<&[Vec3]>], weights: &[f32]) {
    for (delta, &weight) in deltas.iter().zip(weights) {
        let Some(delta) = delta else { continue };
        if weight == 0.0 {
            continue;
        }
        for (value, d) in base.iter_mut().zip(delta.iter()) {
            *value += weight * *d;
        }
    }
}

/// Applies `targets` with `weights` to a primitive's positions, and to its normals and
/// tangents where it has them (tangents' w kept).
pub fn apply_morph_targets(
    targets: &[MorphTarget],
    weights: &[f32],
    positions: &mut [Vec3],
    normals: Option<&mut Vec<Vec3>>,
    tangents: Option<&mut Vec<Vec4>>,
) {
    let deltas = |pick: fn(&MorphTarget) -> Option<&Vec<Vec3>>| -> Vec<Option<&[Vec3]>> {
        targets.iter().map(|t| pick(t).map(Vec::as_slice)).collect()
    };
    morph_vectors(positions, &deltas(|t| t.positions.as_ref()), weights);
    if let Some(normals) = normals {
        morph_vectors(normals, &deltas(|t| t.normals.as_ref()), weights);
    }
    if let Some(tangents) = tangents {
        let mut xyz: Vec<Vec3> = tangents.iter().map(|t| t.truncate()).collect();
        morph_vectors(&mut xyz, &deltas(|t| t.tangents.as_ref()), weights);
        for (tangent, moved) in tangents.iter_mut().zip(xyz) {
            *tangent = moved.extend(tangent.w);
        }
    }
}

/// A node's or mesh's `weights` list whose length is not its mesh's morph-target count.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the {whose}'s weights list {found} values for {target_count} morph targets")]
pub struct WeightCountError {
    /// Whose list it is: "node" or "mesh".
    pub whose: &'static str,
    /// How many values it lists.
    pub found: usize,
    /// The number of morph targets.
    pub target_count: usize,
}

/// The morph weights a node draws its mesh with, when no animation drives them: the node's
/// `weights`, else the mesh's, else zeros, `target_count` of them. `Err` names the list whose
/// length is not the target count.
pub fn default_weights(
    node_weights: Option<&[f32]>,
    mesh_weights: Option<&[f32]>,
    target_count: usize,
) -> Result<Vec<f32>, WeightCountError> {
    let (list, whose) = match (node_weights, mesh_weights) {
        (Some(list), _) => (list, "node"),
        (None, Some(list)) => (list, "mesh"),
        (None, None) => return Ok(vec![0.0; target_count]),
    };
    if list.len() != target_count {
        return Err(WeightCountError {
            whose,
            found: list.len(),
            target_count,
        });
    }
    Ok(list.to_vec())
}

/// Keyframes of a `weights` channel: every key holds one weight per morph target (and, for
/// `CUBICSPLINE`, an in tangent and an out tangent list around it).
#[derive(Clone, Debug, PartialEq)]
pub struct WeightsSampler {
    /// Key times in seconds, strictly increasing, at least one.
    pub times: Vec<f32>,
    /// `interpolation.output_count(times.len()) * target_count` scalars, key after key.
    pub values: Vec<f32>,
    /// The number of morph targets, the width of each key's list.
    pub target_count: usize,
    /// How values between keys are found.
    pub interpolation: Interpolation,
}

impl WeightsSampler {
    /// A sampler, checked as node samplers are; the output count is in weight lists, i.e.
    /// scalars over `target_count` (which must divide it).
    pub fn new(
        times: Vec<f32>,
        values: Vec<f32>,
        target_count: usize,
        interpolation: Interpolation,
    ) -> Result<WeightsSampler, SamplerError> {
        let expected = interpolation.output_count(times.len()) * target_count;
        // Counted in scalars, so that "has 5 values, needs 6" names what the file holds.
        check_keys(&times, values.len(), expected)?;
        Ok(WeightsSampler {
            times,
            values,
            target_count,
            interpolation,
        })
    }

    /// Element `element` (a value, or for cubic splines a tangent or value) as a list.
    fn list(&self, element: usize) -> &[f32] {
        &self.values[element * self.target_count..(element + 1) * self.target_count]
    }

    /// The key value `k`'s weight list (the middle of a cubic spline's triple).
    fn value(&self, k: usize) -> &[f32] {
        match self.interpolation {
            Interpolation::CubicSpline => self.list(3 * k + 1),
            _ => self.list(k),
        }
    }

    /// The weights at `time`: LINEAR per weight, STEP the key at or before, CUBICSPLINE the
    /// Hermite spline per weight (glTF appendix C); clamped to the first and last key.
    pub fn sample(&self, time: f32) -> Vec<f32> {
        let (k, s) = match key_segment(&self.times, time) {
            Ok(segment) => segment,
            Err(key) => return self.value(key).to_vec(),
        };
        let (a, b) = (self.value(k), self.value(k + 1));
        match self.interpolation {
            Interpolation::Step => a.to_vec(),
            // a + (b − a)s, as glam's lerp of node channels.
            Interpolation::Linear => a.iter().zip(b).map(|(a, b)| a + (b - a) * s).collect(),
            Interpolation::CubicSpline => {
                let delta = self.times[k + 1] - self.times[k];
                let [h00, h10, h01, h11] = hermite_basis(s);
                let out_tangent = self.list(3 * k + 2);
                let in_tangent = self.list(3 * (k + 1));
                (0..self.target_count)
                    .map(|i| {
                        a[i] * h00
                            + out_tangent[i] * delta * h10
                            + b[i] * h01
                            + in_tangent[i] * delta * h11
                    })
                    .collect()
            }
        }
    }
}

/// One `weights` channel: a node's morph weights driven by a sampler.
#[derive(Clone, Debug, PartialEq)]
pub struct WeightsChannel {
    /// The node's index in the file.
    pub node: usize,
    /// Its keyframes, one weight per morph target of the node's mesh.
    pub sampler: WeightsSampler,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weight_half_gives_the_midpoint_and_weights_add() {
        let mut positions = vec![Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO];
        let up = vec![Vec3::new(0.0, 0.0, 2.0); 2];
        let right = vec![Vec3::new(4.0, 0.0, 0.0); 2];
        let targets = [
            MorphTarget {
                positions: Some(up),
                ..MorphTarget::default()
            },
            MorphTarget {
                positions: Some(right),
                ..MorphTarget::default()
            },
        ];
        let mut half = positions.clone();
        apply_morph_targets(&targets, &[0.5, 0.0], &mut half, None, None);
        // Halfway between (1, 2, 3) and (1, 2, 5).
        assert_eq!(half[0], Vec3::new(1.0, 2.0, 4.0));
        apply_morph_targets(&targets, &[1.0, 0.25], &mut positions, None, None);
        assert_eq!(positions[0], Vec3::new(2.0, 2.0, 5.0));
        assert_eq!(positions[1], Vec3::new(1.0, 0.0, 2.0));
    }

    #[test]
    fn normals_and_tangents_morph_and_keep_their_handedness() {
        let target = MorphTarget {
            positions: None,
            normals: Some(vec![Vec3::new(1.0, 0.0, -1.0)]),
            tangents: Some(vec![Vec3::new(0.0, 2.0, 0.0)]),
        };
        let mut positions = vec![Vec3::ONE];
        let mut normals = vec![Vec3::Z];
        let mut tangents = vec![Vec4::new(1.0, 0.0, 0.0, -1.0)];
        apply_morph_targets(
            &[target],
            &[0.5],
            &mut positions,
            Some(&mut normals),
            Some(&mut tangents),
        );
        assert_eq!(positions[0], Vec3::ONE);
        assert_eq!(normals[0], Vec3::new(0.5, 0.0, 0.5));
        assert_eq!(tangents[0], Vec4::new(1.0, 1.0, 0.0, -1.0));
    }

    #[test]
    fn node_weights_override_the_mesh_and_lengths_are_checked() {
        assert_eq!(default_weights(None, None, 2), Ok(vec![0.0, 0.0]));
        assert_eq!(
            default_weights(None, Some(&[0.3, 0.7]), 2),
            Ok(vec![0.3, 0.7])
        );
        assert_eq!(
            default_weights(Some(&[1.0, 0.0]), Some(&[0.3, 0.7]), 2),
            Ok(vec![1.0, 0.0])
        );
        let error = default_weights(None, Some(&[0.3]), 2)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("mesh's weights list 1 values for 2"),
            "{error}"
        );
    }

    #[test]
    fn weight_lists_interpolate_per_target() {
        // Two targets: (0, 1) at 0 s, (1, 0) at 2 s.
        let linear = WeightsSampler::new(
            vec![0.0, 2.0],
            vec![0.0, 1.0, 1.0, 0.0],
            2,
            Interpolation::Linear,
        )
        .unwrap();
        assert_eq!(linear.sample(1.0), vec![0.5, 0.5]);
        assert_eq!(linear.sample(0.5), vec![0.25, 0.75]);
        assert_eq!(linear.sample(-1.0), vec![0.0, 1.0]);
        assert_eq!(linear.sample(3.0), vec![1.0, 0.0]);
        let step = WeightsSampler {
            interpolation: Interpolation::Step,
            ..linear.clone()
        };
        assert_eq!(step.sample(1.9), vec![0.0, 1.0]);
        assert_eq!(step.sample(2.0), vec![1.0, 0.0]);
        // Cubic: w(t) = t³ − t for the first target, with exact tangents 3t² − 1 the Hermite
        // spline reproduces it; the second target holds 5 with zero tangents.
        let f = |t: f32| t * t * t - t;
        let df = |t: f32| 3.0 * t * t - 1.0;
        let values: Vec<f32> = [0.0f32, 2.0]
            .iter()
            .flat_map(|&t| [df(t), 0.0, f(t), 5.0, df(t), 0.0])
            .collect();
        let cubic =
            WeightsSampler::new(vec![0.0, 2.0], values, 2, Interpolation::CubicSpline).unwrap();
        for t in [0.0, 0.5, 1.3, 2.0] {
            let got = cubic.sample(t);
            assert!((got[0] - f(t)).abs() < 1e-5, "t {t}: {got:?}");
            assert_eq!(got[1], 5.0);
        }
    }

    #[test]
    fn weight_output_counts_must_fit_the_target_count() {
        assert_eq!(
            WeightsSampler::new(vec![0.0, 1.0], vec![0.0; 3], 2, Interpolation::Linear),
            Err(SamplerError::OutputCount(3, 4))
        );
        assert_eq!(
            WeightsSampler::new(vec![0.0, 1.0], vec![0.0; 4], 2, Interpolation::CubicSpline),
            Err(SamplerError::OutputCount(4, 12))
        );
    }
}
