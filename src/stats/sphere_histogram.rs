//! Histograms of directions on the unit sphere, binned equal-area in (phi, cos theta)
//! relative to a frame, and the counts a target density predicts for each bin: the two
//! halves of the χ² test of `super::chi2` (after Mitsuba's `ChiSquare` and pbrt's tests).

use glam::{DVec3, Vec3};

use crate::stats::StatsError;

/// A grid on the sphere: `phi_bin_count` equal intervals of the azimuth phi in [0, 2 pi)
/// times `cos_theta_bin_count` equal intervals of cos theta in [-1, 1]. By Archimedes'
/// hat-box theorem every bin has the same solid angle, 4 pi / bin count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SphereGrid {
    /// Number of intervals of phi.
    pub phi_bin_count: usize,
    /// Number of intervals of cos theta.
    pub cos_theta_bin_count: usize,
}

impl Default for SphereGrid {
    /// Mitsuba's resolution: 50 phi bins x 101 cos-theta bins. The odd count puts a bin
    /// astride the equator, so hemisphere samplers are also checked right at the horizon.
    fn default() -> SphereGrid {
        SphereGrid {
            phi_bin_count: 50,
            cos_theta_bin_count: 101,
        }
    }
}

/// One bin's extent: phi in [phi_min, phi_max], cos theta in [cos_theta_min, cos_theta_max].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereBin {
    /// Lower azimuth, radians.
    pub phi_min: f64,
    /// Upper azimuth, radians.
    pub phi_max: f64,
    /// Lower cos theta.
    pub cos_theta_min: f64,
    /// Upper cos theta.
    pub cos_theta_max: f64,
}

impl SphereGrid {
    /// The number of bins.
    pub fn bin_count(&self) -> usize {
        self.phi_bin_count * self.cos_theta_bin_count
    }

    /// An error unless both counts are positive.
    pub fn validate(&self) -> Result<(), StatsError> {
        if self.phi_bin_count == 0 || self.cos_theta_bin_count == 0 {
            return Err(StatsError::InvalidParameter(format!(
                "empty sphere grid {self:?}"
            )));
        }
        Ok(())
    }

    /// The bin of a unit direction in the grid's frame, index cos_theta_bin * phi_bin_count +
    /// phi_bin. Values on the upper edge (phi -> 2 pi, cos theta = 1) go to the last bin.
    pub fn bin_index(&self, local_direction: DVec3) -> usize {
        let mut phi = local_direction.y.atan2(local_direction.x);
        if phi < 0.0 {
            phi += std::f64::consts::TAU;
        }
        let cos_theta = local_direction.z.clamp(-1.0, 1.0);
        let phi_bin = ((phi / std::f64::consts::TAU * self.phi_bin_count as f64) as usize)
            .min(self.phi_bin_count - 1);
        let cos_theta_bin = (((cos_theta + 1.0) * 0.5 * self.cos_theta_bin_count as f64) as usize)
            .min(self.cos_theta_bin_count - 1);
        cos_theta_bin * self.phi_bin_count + phi_bin
    }

    /// The extent of bin `index` (see `bin_index`).
    pub fn bin(&self, index: usize) -> SphereBin {
        let phi_bin = (index % self.phi_bin_count) as f64;
        let cos_theta_bin = (index / self.phi_bin_count) as f64;
        let phi_step = std::f64::consts::TAU / self.phi_bin_count as f64;
        let cos_theta_step = 2.0 / self.cos_theta_bin_count as f64;
        SphereBin {
            phi_min: phi_bin * phi_step,
            phi_max: (phi_bin + 1.0) * phi_step,
            cos_theta_min: -1.0 + cos_theta_bin * cos_theta_step,
            cos_theta_max: -1.0 + (cos_theta_bin + 1.0) * cos_theta_step,
        }
    }
}

/// An orthonormal frame in which directions are binned: theta is measured from `normal`, phi
/// from `tangent` towards `bitangent`. World space, f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereFrame {
    /// The local x axis.
    pub tangent: DVec3,
    /// The local y axis.
    pub bitangent: DVec3,
    /// The local z axis (theta = 0).
    pub normal: DVec3,
}

impl SphereFrame {
    /// The world frame: theta from +z, phi from +x.
    pub const WORLD: SphereFrame = SphereFrame {
        tangent: DVec3::X,
        bitangent: DVec3::Y,
        normal: DVec3::Z,
    };

    /// A frame around a normal, tangents from Duff et al., "Building an Orthonormal Basis,
    /// Revisited" (JCGT 2017). The normal is normalized in f64 first; an error if it has no
    /// direction (zero or non-finite).
    pub fn from_normal(normal: Vec3) -> Result<SphereFrame, StatsError> {
        let normal = normal.as_dvec3().try_normalize().ok_or_else(|| {
            StatsError::InvalidParameter(format!("normal {normal} has no direction"))
        })?;
        let (tangent, bitangent) = normal.any_orthonormal_pair();
        Ok(SphereFrame {
            tangent,
            bitangent,
            normal,
        })
    }

    /// World to frame coordinates.
    pub fn to_local(&self, world_direction: DVec3) -> DVec3 {
        DVec3::new(
            world_direction.dot(self.tangent),
            world_direction.dot(self.bitangent),
            world_direction.dot(self.normal),
        )
    }

    /// Frame to world coordinates.
    pub fn to_world(&self, local_direction: DVec3) -> DVec3 {
        local_direction.x * self.tangent
            + local_direction.y * self.bitangent
            + local_direction.z * self.normal
    }
}

/// Counts of directions per bin.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionHistogram {
    /// Count per bin (see `SphereGrid::bin_index`).
    pub counts: Vec<u64>,
    /// Samples that are no direction: non-finite, or of length off 1 by more than
    /// `UNIT_LENGTH_TOLERANCE`. Not binned; any of them fails the test.
    pub invalid_count: u64,
    /// All samples seen, binned or invalid.
    pub sample_count: u64,
}

/// How far from 1 a sample's length may be: f32 samplers are within a few ulps (1e-7 each),
/// so 1e-4 only rejects directions that a sampler got wrong, not rounded.
pub const UNIT_LENGTH_TOLERANCE: f64 = 1e-4;

/// Bins directions (world space) in `grid` relative to `frame`.
pub fn histogram_directions(
    samples: impl IntoIterator<Item = Vec3>,
    grid: &SphereGrid,
    frame: &SphereFrame,
) -> Result<DirectionHistogram, StatsError> {
    grid.validate()?;
    let mut histogram = DirectionHistogram {
        counts: vec![0; grid.bin_count()],
        invalid_count: 0,
        sample_count: 0,
    };
    for sample in samples {
        histogram.sample_count += 1;
        let direction = sample.as_dvec3();
        if !direction.is_finite() || (direction.length() - 1.0).abs() > UNIT_LENGTH_TOLERANCE {
            histogram.invalid_count += 1;
            continue;
        }
        histogram.counts[grid.bin_index(frame.to_local(direction))] += 1;
    }
    Ok(histogram)
}

/// The distribution that the samples should follow.
#[derive(Clone, Copy)]
pub enum TargetDensity<'a> {
    /// Uniform on the sphere, 1 / (4 pi) w.r.t. solid angle. Expected counts are exact.
    UniformSphere,
    /// Uniform on the hemisphere around the frame's normal, 1 / (2 pi) w.r.t. solid angle,
    /// 0 below. Expected counts are exact.
    UniformHemisphere,
    /// Spherical coordinates around the frame's normal with theta uniform in
    /// [0, `theta_max`] and phi uniform: the naive samplers (theta = pi u on the sphere,
    /// theta = pi/2 u on the hemisphere), crowded at the pole. Expected counts are exact:
    /// a bin's probability is its share of theta times its share of phi.
    UniformTheta {
        /// The largest polar angle, in (0, pi].
        theta_max: f64,
    },
    /// Any density w.r.t. solid angle of a world-space unit direction; each bin's
    /// probability is integrated numerically (composite Simpson), which is accurate for
    /// smooth densities and approximate in the bins that a discontinuity crosses.
    SolidAngle(&'a dyn Fn(Vec3) -> f64),
}

/// The expected count of each bin: `sample_count` times the bin's probability under the
/// target density.
/// \param quadrature_resolution Simpson intervals per axis and bin for
///        `TargetDensity::SolidAngle` (rounded up to even, at least 2)
pub fn expected_counts(
    target: TargetDensity,
    grid: &SphereGrid,
    frame: &SphereFrame,
    sample_count: u64,
    quadrature_resolution: usize,
) -> Result<Vec<f64>, StatsError> {
    grid.validate()?;
    let n = sample_count as f64;
    let probability = |index: usize| -> f64 {
        let bin = grid.bin(index);
        let phi_extent = bin.phi_max - bin.phi_min;
        match target {
            TargetDensity::UniformSphere => 1.0 / grid.bin_count() as f64,
            TargetDensity::UniformHemisphere => {
                // Solid angle of the bin above the horizon (cos theta >= 0), times 1 / (2 pi).
                let covered = (bin.cos_theta_max.max(0.0) - bin.cos_theta_min.max(0.0)).max(0.0);
                phi_extent * covered / std::f64::consts::TAU
            }
            TargetDensity::UniformTheta { theta_max } => {
                let theta = |cos_theta: f64| cos_theta.clamp(-1.0, 1.0).acos().min(theta_max);
                let theta_share = (theta(bin.cos_theta_min) - theta(bin.cos_theta_max)) / theta_max;
                theta_share * phi_extent / std::f64::consts::TAU
            }
            TargetDensity::SolidAngle(density) => {
                integrate_over_bin(density, &bin, frame, quadrature_resolution)
            }
        }
    };
    Ok((0..grid.bin_count())
        .map(|index| n * probability(index))
        .collect())
}

/// The integral of a density w.r.t. solid angle over a bin. In (phi, cos theta) the solid
/// angle element is d phi d(cos theta), so this is a plain 2D integral over a rectangle,
/// done with composite Simpson.
fn integrate_over_bin(
    density: &dyn Fn(Vec3) -> f64,
    bin: &SphereBin,
    frame: &SphereFrame,
    resolution: usize,
) -> f64 {
    let intervals = resolution.max(2).next_multiple_of(2);
    let phi_step = (bin.phi_max - bin.phi_min) / intervals as f64;
    let cos_theta_step = (bin.cos_theta_max - bin.cos_theta_min) / intervals as f64;
    // Simpson weights 1, 4, 2, 4, ..., 4, 1 (times step / 3).
    let weight = |k: usize| {
        if k == 0 || k == intervals {
            1.0
        } else if k % 2 == 1 {
            4.0
        } else {
            2.0
        }
    };
    let mut sum = 0.0;
    for i in 0..=intervals {
        let phi = bin.phi_min + i as f64 * phi_step;
        for j in 0..=intervals {
            let cos_theta = bin.cos_theta_min + j as f64 * cos_theta_step;
            let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
            let local = DVec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
            sum += weight(i) * weight(j) * density(frame.to_world(local).as_vec3());
        }
    }
    sum * (phi_step / 3.0) * (cos_theta_step / 3.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_have_equal_area_and_cover_the_sphere() {
        let grid = SphereGrid::default();
        let expected = expected_counts(
            TargetDensity::UniformSphere,
            &grid,
            &SphereFrame::WORLD,
            5050,
            4,
        )
        .unwrap();
        assert!(expected.iter().all(|&e| (e - 1.0).abs() < 1e-12));
        // The generic quadrature of the constant 1/(4 pi) agrees with the analytic path.
        let uniform = |_: Vec3| 1.0 / (4.0 * std::f64::consts::PI);
        let numeric = expected_counts(
            TargetDensity::SolidAngle(&uniform),
            &grid,
            &SphereFrame::WORLD,
            5050,
            4,
        )
        .unwrap();
        assert!(numeric.iter().all(|&e| (e - 1.0).abs() < 1e-9));
    }

    #[test]
    fn uniform_theta_matches_its_density() {
        // theta = pi u has density 1 / (2 pi^2 sin theta); away from the poles, where
        // Simpson's rule is accurate, the exact bins agree with the quadrature.
        let grid = SphereGrid::default();
        let exact = expected_counts(
            TargetDensity::UniformTheta {
                theta_max: std::f64::consts::PI,
            },
            &grid,
            &SphereFrame::WORLD,
            1_000_000,
            4,
        )
        .unwrap();
        assert!((exact.iter().sum::<f64>() - 1e6).abs() < 1e-6);
        let density = |d: Vec3| {
            let sin_theta = (1.0 - f64::from(d.z).powi(2)).sqrt();
            1.0 / (2.0 * std::f64::consts::PI.powi(2) * sin_theta)
        };
        let numeric = expected_counts(
            TargetDensity::SolidAngle(&density),
            &grid,
            &SphereFrame::WORLD,
            1_000_000,
            8,
        )
        .unwrap();
        for index in 0..grid.bin_count() {
            let bin = grid.bin(index);
            if bin.cos_theta_max.abs() < 0.9 && bin.cos_theta_min.abs() < 0.9 {
                assert!(
                    (exact[index] / numeric[index] - 1.0).abs() < 1e-4,
                    "bin {index}"
                );
            }
        }
    }

    #[test]
    fn hemisphere_expectation_halves_the_sphere() {
        let grid = SphereGrid::default();
        let frame = SphereFrame::from_normal(Vec3::new(1.0, 2.0, -3.0)).unwrap();
        let expected = expected_counts(
            TargetDensity::UniformHemisphere,
            &grid,
            &frame,
            1_000_000,
            4,
        )
        .unwrap();
        assert!((expected.iter().sum::<f64>() - 1e6).abs() < 1e-6);
        // Bins below the equator bin (cos-theta bins 0..50) expect nothing; those above
        // (51..101) expect 2 n / bins; the equator bin half of that.
        let full = 2e6 / grid.bin_count() as f64;
        for (index, &e) in expected.iter().enumerate() {
            let row = index / grid.phi_bin_count;
            let wanted = if row < 50 {
                0.0
            } else if row == 50 {
                0.5 * full
            } else {
                full
            };
            assert!((e - wanted).abs() < 1e-6, "bin {index}: {e} vs {wanted}");
        }
    }

    #[test]
    fn frames_are_orthonormal_and_bin_their_normal_at_the_pole() {
        let grid = SphereGrid::default();
        for normal in [Vec3::Z, -Vec3::Z, -Vec3::X, Vec3::new(0.3, -0.5, 0.8)] {
            let frame = SphereFrame::from_normal(normal).unwrap();
            let n = normal.as_dvec3().normalize();
            assert!(
                (frame.tangent.dot(frame.bitangent)).abs() < 1e-12
                    && (frame.tangent.dot(n)).abs() < 1e-12
            );
            assert!(
                (frame.tangent.cross(frame.bitangent) - n).length() < 1e-12,
                "right-handed"
            );
            let index = grid.bin_index(frame.to_local(n));
            assert_eq!(index / grid.phi_bin_count, grid.cos_theta_bin_count - 1);
            assert!(
                (frame.to_world(frame.to_local(DVec3::new(0.1, 0.2, 0.3)))
                    - DVec3::new(0.1, 0.2, 0.3))
                .length()
                    < 1e-12
            );
        }
        assert!(SphereFrame::from_normal(Vec3::ZERO).is_err());
    }

    #[test]
    fn histogram_rejects_non_directions() {
        let grid = SphereGrid {
            phi_bin_count: 4,
            cos_theta_bin_count: 2,
        };
        let samples = [
            Vec3::X,
            Vec3::Y,
            Vec3::new(0.6, 0.0, -0.8),
            Vec3::splat(f32::NAN),
            Vec3::new(2.0, 0.0, 0.0),
        ];
        let histogram = histogram_directions(samples, &grid, &SphereFrame::WORLD).unwrap();
        assert_eq!((histogram.invalid_count, histogram.sample_count), (2, 5));
        // +x: phi 0, cos theta 0 -> upper row (the equator is the rows' boundary); +y: phi
        // pi / 2 -> second phi bin; (0.6, 0, -0.8): phi 0, lower row.
        assert_eq!(histogram.counts, vec![1, 0, 0, 0, 1, 1, 0, 0]);
        assert!(histogram_directions(
            [],
            &SphereGrid {
                phi_bin_count: 0,
                cos_theta_bin_count: 3
            },
            &SphereFrame::WORLD
        )
        .is_err());
    }
}
