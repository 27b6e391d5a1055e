//! The emissive triangles of a scene as light sampling needs them: a power-proportional CDF
//! and each triangle's selection probability, for multiple importance sampling. How the
//! shaders store them (`g_light_texels` and `g_light_selection_words` of
//! `glsl/emissive_lights.glsl`) is `super::gpu_emissive`'s business.

use glam::Vec3;

use crate::scene::Triangle;

/// Luminance of linear Rec. 709 RGB: the weight that makes light selection proportional to
/// perceived power.
pub fn luminance(color: Vec3) -> f32 {
    color.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Emitted power of a triangle up to a constant factor: area * pi * luminance of L_e, twice
/// that when it emits from both sides.
pub fn triangle_power(triangle: &Triangle) -> f32 {
    let area = 0.5
        * (triangle.positions[1] - triangle.positions[0])
            .cross(triangle.positions[2] - triangle.positions[0])
            .length();
    let sides = if triangle.double_sided { 2.0 } else { 1.0 };
    area * std::f32::consts::PI * sides * luminance(triangle.emission).max(0.0)
}

/// The number of lights among `triangles`: those with power (as `EmissiveTriangles` counts
/// them).
pub fn emissive_triangle_count(triangles: &[Triangle]) -> usize {
    triangles.iter().filter(|t| triangle_power(t) > 0.0).count()
}

/// The emissive-triangle table of a scene: which triangles emit, and how light sampling
/// chooses among them.
#[derive(Clone, Debug, PartialEq)]
pub struct EmissiveTriangles {
    /// Indices of the emissive triangles.
    pub triangle_indices: Vec<u32>,
    /// Cumulative selection probability of each light (the last is exactly 1).
    pub cdf: Vec<f32>,
    /// For every triangle of the scene, its selection probability (0 for non-emitters).
    pub selection_probability: Vec<f32>,
}

impl EmissiveTriangles {
    /// Builds the table; triangles with zero power are not lights.
    pub fn new(triangles: &[Triangle]) -> EmissiveTriangles {
        let powers: Vec<f64> = triangles
            .iter()
            .map(|t| f64::from(triangle_power(t)))
            .collect();
        let total: f64 = powers.iter().sum();
        let mut table = EmissiveTriangles {
            triangle_indices: Vec::new(),
            cdf: Vec::new(),
            selection_probability: vec![0.0; triangles.len()],
        };
        if !(total > 0.0) {
            return table;
        }
        let mut running = 0.0f64;
        for (index, &power) in powers.iter().enumerate() {
            if power > 0.0 {
                running += power;
                table.triangle_indices.push(index as u32);
                table.cdf.push((running / total) as f32);
                table.selection_probability[index] = (power / total) as f32;
            }
        }
        // Rounding must not leave a gap above the last light.
        if let Some(last) = table.cdf.last_mut() {
            *last = 1.0;
        }
        table
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selection_is_proportional_to_power() {
        let quad = |emission: f32, scale: f32| {
            Triangle::new(
                [Vec3::ZERO, Vec3::X * scale, Vec3::Y * scale],
                Vec3::ONE,
                Vec3::splat(emission),
                false,
            )
            .unwrap()
        };
        // Powers 1 : 0 : 4 (same emission, twice the side length) : 2 (twice the emission).
        let table = EmissiveTriangles::new(&[
            quad(1.0, 1.0),
            quad(0.0, 1.0),
            quad(1.0, 2.0),
            quad(2.0, 1.0),
        ]);
        assert_eq!(table.triangle_indices, vec![0, 2, 3]);
        let p = &table.selection_probability;
        assert!((p[0] - 1.0 / 7.0).abs() < 1e-6 && p[1] == 0.0);
        assert!((p[2] - 4.0 / 7.0).abs() < 1e-6 && (p[3] - 2.0 / 7.0).abs() < 1e-6);
        assert_eq!(*table.cdf.last().unwrap(), 1.0);
        assert_eq!(table.cdf.len(), 3);
    }

    #[test]
    fn a_scene_without_emitters_has_no_lights() {
        let t =
            Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], Vec3::ONE, Vec3::ZERO, false).unwrap();
        let table = EmissiveTriangles::new(&[t]);
        assert!(table.triangle_indices.is_empty());
        assert!(table.cdf.is_empty() && table.selection_probability == vec![0.0]);
    }
}
