//! How far apart two results of the same function are, and which inputs are too close to a
//! decision boundary for two correct implementations to agree on.
//!
//! Floats are compared in units of `f32::EPSILON` = 2^-23, the ulp of 1.0 ("ulps of one"):
//! the components of unit vectors are at most 1, so this is the absolute error that rounding
//! of order one ulp produces, and it stays meaningful for components near 0, where an
//! ulp-by-ulp distance is huge for any absolute error.
//!
//! Ray-triangle intersection is ill-conditioned near the triangle's edges (the hit/miss
//! decision flips with rounding), for rays that graze the plane (the determinant cancels),
//! and near t = 0 (the t >= 0 test flips). `ray_triangle_geometry` measures these in f64, so
//! that comparisons skip (and count) such inputs instead of demanding the impossible.

use glam::Vec3;

/// |a - b| in units of 2^-23 (the ulp of 1.0).
pub fn ulps_of_one(a: f32, b: f32) -> f64 {
    (f64::from(a) - f64::from(b)).abs() / f64::from(f32::EPSILON)
}

/// The largest `ulps_of_one` over the components of two vectors.
pub fn max_ulps_of_one(a: Vec3, b: Vec3) -> f64 {
    (0..3).map(|i| ulps_of_one(a[i], b[i])).fold(0.0, f64::max)
}

/// |a - b| / max(|a|, |b|), 0 when both are 0 and infinite when exactly one is NaN or
/// infinite.
pub fn relative_error(a: f32, b: f32) -> f64 {
    let (a, b) = (f64::from(a), f64::from(b));
    if a == b {
        return 0.0;
    }
    if !(a.is_finite() && b.is_finite()) {
        return f64::INFINITY;
    }
    (a - b).abs() / a.abs().max(b.abs())
}

/// The largest relative error of the components of two vectors, relative to the largest
/// component magnitude of either (so that a component near 0 does not dominate).
pub fn vector_relative_error(a: Vec3, b: Vec3) -> f64 {
    let (a, b) = (a.as_dvec3(), b.as_dvec3());
    if a == b {
        return 0.0;
    }
    if !(a.is_finite() && b.is_finite()) {
        return f64::INFINITY;
    }
    let scale = a.abs().max_element().max(b.abs().max_element());
    (a - b).abs().max_element() / scale
}

/// Rays at an angle with cosine below this to the triangle's plane graze it: the
/// determinant of the intersection's linear system then cancels to fewer than 13 of its 24
/// bits in f32, and two algorithms may decide hit or miss differently.
pub const GRAZING_COSINE: f64 = 1e-3;

/// Half-width, in barycentric coordinates, of the band around a triangle's edges in which
/// hit/miss is left undecided, for a ray perpendicular to the triangle; it grows as
/// 1 / cos for oblique rays (rounding errors of barycentrics scale with the determinant's
/// inverse). 1e-5 is about 80 ulps of one: the f32 barycentrics of all the algorithms in
/// use (Cramer's rule, Möller–Trumbore, inverse(mat3)) are within a few ulps times the ratio
/// of coordinate magnitudes (at most ~10 for the generated inputs).
pub const EDGE_EPSILON: f64 = 1e-5;

/// t counts as near 0, where the t >= 0 test may flip, when |t| is within this many units
/// of `RayTriangleGeometry::t_error_unit` of 0 (the tolerance on t, `T_TOLERANCE_UNITS`).
pub const NEAR_ORIGIN_UNITS: f64 = 64.0;

/// How far two correct f32 computations of t may be apart, in units of
/// `RayTriangleGeometry::t_error_unit` = 2^-23 (|t| + |o - v_0| / |d|) / max(|cos|, 1e-3):
/// the ray parameter is a ratio of two dot products, the numerator with magnitude up to
/// |o - v_0| |n| and the denominator cancelling by the factor |cos|, so each algorithm's
/// error is a small multiple of this unit. Measured on lavapipe: 7.3 units for Möller–Trumbore
/// against the workshop's Cramer's rule (2^16 random cases, `vkpath check
/// tests/solutions/ray_triangle_moller_trumbore.glsl`), 0 for GPU against CPU twin
/// (tests/gpu_twins.rs); 64 leaves a margin of almost 9x.
pub const T_TOLERANCE_UNITS: f64 = 64.0;

/// A ray and a triangle, solved in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayTriangleGeometry {
    /// Ray parameter of the plane hit (in units of |d|).
    pub t: f64,
    /// Barycentric coordinates (w, u, v) of the plane hit, w = 1 - u - v.
    pub barycentrics: [f64; 3],
    /// |cos| of the angle between the ray and the triangle's normal.
    pub cos_incidence: f64,
    /// The unit in which t errors are measured: 2^-23 (|t| + |o - v_0| / |d|) /
    /// max(|cos|, GRAZING_COSINE).
    pub t_error_unit: f64,
}

/// Why two correct implementations may disagree on a ray-triangle input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Degeneracy {
    /// The ray grazes the plane (|cos| < `GRAZING_COSINE`) or is parallel to it.
    Grazing,
    /// The plane hit is within the edge band (`EDGE_EPSILON / |cos|`) of an edge or vertex.
    NearEdge,
    /// t is within `NEAR_ORIGIN_UNITS` error units of 0.
    NearOrigin,
}

/// Solves origin + t d = v_0 + u (v_1 - v_0) + v (v_2 - v_0) in f64. `None` for a ray
/// parallel to the plane or a degenerate triangle.
pub fn ray_triangle_geometry(
    ray_origin: Vec3,
    ray_direction: Vec3,
    positions: [Vec3; 3],
) -> Option<RayTriangleGeometry> {
    let [v0, v1, v2] = positions.map(|p| p.as_dvec3());
    let (origin, direction) = (ray_origin.as_dvec3(), ray_direction.as_dvec3());
    let (edge_1, edge_2) = (v1 - v0, v2 - v0);
    let normal = edge_1.cross(edge_2);
    let determinant = -direction.dot(normal);
    let scale = direction.length() * normal.length();
    if determinant == 0.0 || scale == 0.0 || !determinant.is_finite() {
        return None;
    }
    let offset = origin - v0;
    let direction_cross_offset = direction.cross(offset);
    let t = offset.dot(normal) / determinant;
    let u = -edge_2.dot(direction_cross_offset) / determinant;
    let v = edge_1.dot(direction_cross_offset) / determinant;
    let cos_incidence = determinant.abs() / scale;
    let t_error_unit = f64::from(f32::EPSILON) * (t.abs() + offset.length() / direction.length())
        / cos_incidence.max(GRAZING_COSINE);
    Some(RayTriangleGeometry {
        t,
        barycentrics: [1.0 - u - v, u, v],
        cos_incidence,
        t_error_unit,
    })
}

impl RayTriangleGeometry {
    /// Whether the exact ray hits the triangle (t >= 0, inside or on the edges).
    pub fn hits(&self) -> bool {
        self.t >= 0.0 && self.barycentrics.iter().all(|&b| b >= 0.0)
    }

    /// Why two correct implementations may disagree here, if they may.
    pub fn degeneracy(&self) -> Option<Degeneracy> {
        if self.cos_incidence < GRAZING_COSINE {
            return Some(Degeneracy::Grazing);
        }
        let band = EDGE_EPSILON / self.cos_incidence;
        // Only edges the hit could cross matter: all barycentrics > -band, one within band.
        let min = self
            .barycentrics
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        if min.abs() < band {
            return Some(Degeneracy::NearEdge);
        }
        if self.t.abs() < NEAR_ORIGIN_UNITS * self.t_error_unit {
            return Some(Degeneracy::NearOrigin);
        }
        None
    }

    /// |t_a - t_b| in units of `t_error_unit`.
    pub fn t_error_units(&self, t_a: f32, t_b: f32) -> f64 {
        (f64::from(t_a) - f64::from(t_b)).abs() / self.t_error_unit
    }
}

/// `ray_triangle_geometry`'s degeneracy, with `Grazing` for parallel rays.
pub fn ray_triangle_degeneracy(
    ray_origin: Vec3,
    ray_direction: Vec3,
    positions: [Vec3; 3],
) -> Option<Degeneracy> {
    match ray_triangle_geometry(ray_origin, ray_direction, positions) {
        Some(geometry) => geometry.degeneracy(),
        None => Some(Degeneracy::Grazing),
    }
}

/// Whether a ray's closest hit in a mesh is ambiguous: some triangle that the ray may hit
/// at or before the exact closest hit (within the t tolerance) is degenerate for it
/// (`Degeneracy`), or two triangles are hit at t within the tolerance of each other (a
/// shared edge, a tie). Elsewhere every correct `ray_mesh_intersection` finds the same
/// triangle.
pub fn ray_mesh_is_ambiguous(
    ray_origin: Vec3,
    ray_direction: Vec3,
    scene_positions: impl IntoIterator<Item = [Vec3; 3]>,
) -> bool {
    let geometries: Vec<Option<RayTriangleGeometry>> = scene_positions
        .into_iter()
        .map(|positions| ray_triangle_geometry(ray_origin, ray_direction, positions))
        .collect();
    let closest = geometries
        .iter()
        .flatten()
        .filter(|g| g.hits())
        .map(|g| (g.t, g.t_error_unit))
        .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a });
    let horizon = closest.0 + T_TOLERANCE_UNITS * closest.1;
    let mut close_hits = 0;
    for geometry in &geometries {
        let Some(geometry) = geometry else {
            continue;
        };
        let tolerance = T_TOLERANCE_UNITS * geometry.t_error_unit;
        if geometry.t > horizon + tolerance {
            continue;
        }
        if geometry.degeneracy().is_some() {
            return true;
        }
        if geometry.hits() {
            close_hits += 1;
        }
    }
    close_hits > 1
}

#[cfg(test)]
mod tests {
    use super::*;

    const UNIT: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

    #[test]
    fn ulps_and_relative_errors() {
        assert_eq!(ulps_of_one(1.0, 1.0 + f32::EPSILON), 1.0);
        assert_eq!(ulps_of_one(0.0, 2.0 * f32::EPSILON), 2.0);
        assert_eq!(
            max_ulps_of_one(Vec3::ZERO, Vec3::new(0.0, f32::EPSILON, 0.0)),
            1.0
        );
        assert_eq!(relative_error(2.0, 1.0), 0.5);
        assert_eq!(relative_error(0.0, 0.0), 0.0);
        assert_eq!(relative_error(f32::NAN, 1.0), f64::INFINITY);
        assert_eq!(
            vector_relative_error(Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 0.0)),
            0.5
        );
    }

    #[test]
    fn geometry_of_a_clear_hit_and_its_degeneracies() {
        let g = ray_triangle_geometry(Vec3::new(0.25, 0.25, 2.0), -Vec3::Z, UNIT).unwrap();
        assert_eq!(g.t, 2.0);
        assert_eq!(g.barycentrics, [0.5, 0.25, 0.25]);
        assert_eq!(g.cos_incidence, 1.0);
        assert!(g.hits() && g.degeneracy().is_none());
        // On the diagonal edge u + v = 1.
        let edge = ray_triangle_geometry(Vec3::new(0.5, 0.5, 2.0), -Vec3::Z, UNIT).unwrap();
        assert_eq!(edge.degeneracy(), Some(Degeneracy::NearEdge));
        // Grazing and parallel.
        let grazing = ray_triangle_degeneracy(
            Vec3::new(-1.0, 0.25, 1e-4),
            Vec3::new(1.0, 0.0, -1e-4),
            UNIT,
        );
        assert_eq!(grazing, Some(Degeneracy::Grazing));
        assert_eq!(
            ray_triangle_degeneracy(Vec3::new(0.2, 0.2, 1.0), Vec3::X, UNIT),
            Some(Degeneracy::Grazing)
        );
        // Starting on the triangle.
        let origin = ray_triangle_degeneracy(Vec3::new(0.2, 0.2, 0.0), Vec3::Z, UNIT);
        assert_eq!(origin, Some(Degeneracy::NearOrigin));
        // Behind: a clear miss.
        let behind = ray_triangle_geometry(Vec3::new(0.2, 0.2, 1.0), Vec3::Z, UNIT).unwrap();
        assert!(!behind.hits() && behind.degeneracy().is_none());
    }

    #[test]
    fn mesh_ambiguity_at_shared_edges_only() {
        // Two triangles sharing the diagonal of the unit square, and a parallel one behind.
        let square = [
            [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)],
            [Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            [
                Vec3::new(0.0, 0.0, -1.0),
                Vec3::new(1.0, 0.0, -1.0),
                Vec3::new(0.5, 0.5, -1.0),
            ],
        ];
        let down = -Vec3::Z;
        assert!(!ray_mesh_is_ambiguous(
            Vec3::new(0.7, 0.2, 1.0),
            down,
            square
        ));
        assert!(ray_mesh_is_ambiguous(
            Vec3::new(0.5, 0.5, 1.0),
            down,
            square
        ));
        // A degenerate case far behind the closest hit does not matter.
        let behind_edge = Vec3::new(0.75, 0.25, 1.0);
        assert!(!ray_mesh_is_ambiguous(
            behind_edge,
            down,
            square[..2].iter().copied()
        ));
        assert!(!ray_mesh_is_ambiguous(behind_edge, down, square));
    }
}
