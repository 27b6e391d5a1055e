//! Vose's alias table over an environment map's texels, which importance-samples the map
//! (`sample_environment` of `glsl/environment.glsl`, `crate::cpu::environment`).

use super::emissive::luminance;
use super::environment::{texel_solid_angle, EnvironmentMap};

/// Vose's alias table over a map's texels, weighted by luminance times the texel's solid
/// angle: `sample_environment` picks texel i with probability `probabilities[i]` in O(1) and
/// a point uniformly in solid angle over it, so its density there is `densities[i]`.
#[derive(Clone, Debug, PartialEq)]
pub struct AliasTable {
    /// The probability of choosing each texel (sums to 1; uniform when the map is black).
    pub probabilities: Vec<f32>,
    /// The sampler's density w.r.t. solid angle over each texel: its probability over its
    /// solid angle (`texel_solid_angle`).
    pub densities: Vec<f32>,
    /// For bucket i: keep i when the bucket's second random number is below this, else take
    /// `aliases[i]`.
    pub thresholds: Vec<f32>,
    /// For bucket i: the texel taken otherwise.
    pub aliases: Vec<u32>,
}

impl AliasTable {
    /// The table for `map`.
    pub fn new(map: &EnvironmentMap) -> AliasTable {
        let (width, height) = (map.width as usize, map.height as usize);
        let solid_angles: Vec<f64> = (0..map.height)
            .map(|row| texel_solid_angle(row, map.width, map.height))
            .collect();
        let mut weights: Vec<f64> = Vec::with_capacity(width * height);
        for (y, solid_angle) in solid_angles.iter().enumerate() {
            for x in 0..width {
                weights
                    .push(f64::from(luminance(map.texels[y * width + x]).max(0.0)) * solid_angle);
            }
        }
        let total: f64 = weights.iter().sum();
        let count = weights.len();
        if !(total > 0.0) {
            weights.iter_mut().for_each(|w| *w = 1.0);
        }
        let total: f64 = weights.iter().sum();
        let probabilities: Vec<f64> = weights.iter().map(|w| w / total).collect();
        let mut scaled: Vec<f64> = probabilities.iter().map(|p| p * count as f64).collect();
        let mut thresholds = vec![1.0f32; count];
        let mut aliases: Vec<u32> = (0..count as u32).collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) =
            (0..count).partition(|&i| scaled[i] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            thresholds[s] = scaled[s] as f32;
            aliases[s] = l as u32;
            scaled[l] -= 1.0 - scaled[s];
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // What remains is 1 up to rounding: kept with certainty.
        AliasTable {
            densities: probabilities
                .iter()
                .enumerate()
                .map(|(i, &p)| (p / solid_angles[i / width]) as f32)
                .collect(),
            probabilities: probabilities.iter().map(|&p| p as f32).collect(),
            thresholds,
            aliases,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn alias_table_reproduces_the_probabilities() {
        let map = EnvironmentMap {
            width: 4,
            height: 2,
            texels: [0.0, 1.0, 2.0, 3.0, 0.5, 0.0, 8.0, 1.0]
                .map(Vec3::splat)
                .to_vec(),
        };
        let table = AliasTable::new(&map);
        // Each bucket has mass 1/n; bucket i gives t_i/n to i and the rest to its alias.
        let n = table.probabilities.len();
        let mut mass = vec![0.0f64; n];
        for i in 0..n {
            mass[i] += f64::from(table.thresholds[i]) / n as f64;
            mass[table.aliases[i] as usize] += (1.0 - f64::from(table.thresholds[i])) / n as f64;
        }
        for (m, p) in mass.iter().zip(&table.probabilities) {
            assert!(
                (m - f64::from(*p)).abs() < 1e-6,
                "{mass:?} vs {:?}",
                table.probabilities
            );
        }
        assert_eq!(table.probabilities[0], 0.0);
        assert!((table.probabilities.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    }
}
