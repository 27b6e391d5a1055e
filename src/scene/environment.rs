//! Light from infinitely far away: an equirectangular environment map (`--environment`) or
//! a constant colour (`--background`), and the alias table that importance-samples the map.
//!
//! Convention: world +Y is up; a unit direction d = (x, y, z) looks up
//! u = 0.5 + atan2(x, -z) / (2 pi), v = acos(y) / pi, with (u, v) = (0, 0) the image's
//! top-left corner, so the image's centre is the direction -Z. The map is piecewise constant
//! (each texel's radiance over its patch of the sphere, no filtering), which is what the
//! sampler's density describes exactly. `rotation_degrees` turns the map about +Y,
//! right-handed: with 90, what was seen looking down -Z is seen looking down -X.

use std::path::Path;

use glam::Vec3;

use super::lights::luminance;

/// The environment's radiance (linear RGB) per texel, rows top-down.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// Width in texels (u), at least 1.
    pub width: u32,
    /// Height in texels (v), at least 1.
    pub height: u32,
    /// `width * height` radiances, finite and non-negative.
    pub texels: Vec<Vec3>,
}

/// What a ray that leaves the scene sees.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// The map, or `None` for a constant colour.
    pub map: Option<EnvironmentMap>,
    /// The constant colour (without a map), linear RGB radiance.
    pub background: Vec3,
    /// Factor on the map's radiance (`--environment-strength`).
    pub strength: f32,
    /// Turn about +Y in degrees (`--environment-rotation`).
    pub rotation_degrees: f32,
}

/// Largest map vkpath reads: 16384 x 8192 texels (32 bytes each on the GPU: 4 GiB).
pub const MAX_ENVIRONMENT_TEXELS: u64 = 16384 * 8192;

impl Environment {
    /// A constant environment of radiance `background`.
    pub fn constant(background: Vec3) -> Environment {
        Environment {
            map: None,
            background,
            strength: 1.0,
            rotation_degrees: 0.0,
        }
    }

    /// Whether any light comes from it.
    pub fn emits_light(&self) -> bool {
        match &self.map {
            Some(map) => self.strength > 0.0 && map.texels.iter().any(|t| t.max_element() > 0.0),
            None => self.background.max_element() > 0.0,
        }
    }
}

/// Reads an equirectangular map from a Radiance `.hdr` or OpenEXR `.exr` file; non-finite or
/// negative radiance is an error naming the texel.
pub fn load_environment_map(path: &Path) -> Result<EnvironmentMap, String> {
    let shown = super::printable(&path.display().to_string());
    let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
    let (width, height, texels) = match extension.as_deref() {
        Some("exr") => {
            let exr = crate::image_io::exr_input::read_exr(path)
                .map_err(|e| format!("cannot read environment map '{shown}': {e}"))?;
            let image = exr.image;
            let texels: Vec<Vec3> = image
                .mean
                .iter()
                .map(|p| Vec3::new(p[0], p[1], p[2]))
                .collect();
            (image.width, image.height, texels)
        }
        Some("hdr") => {
            let bytes = super::files::read_bounded(path, super::files::MAX_SCENE_FILE_BYTES)
                .map_err(|e| e.to_string())?;
            let image = image::load_from_memory_with_format(&bytes, image::ImageFormat::Hdr)
                .map_err(|e| format!("cannot read environment map '{shown}': {e}"))?
                .into_rgb32f();
            let (width, height) = image.dimensions();
            let texels: Vec<Vec3> = image.pixels().map(|p| Vec3::from(p.0)).collect();
            (width, height, texels)
        }
        _ => {
            return Err(format!(
                "environment map '{shown}' must be a .hdr (Radiance) or .exr (OpenEXR) file"
            ))
        }
    };
    if u64::from(width) * u64::from(height) > MAX_ENVIRONMENT_TEXELS || width == 0 || height == 0 {
        return Err(format!(
            "environment map '{shown}' has {width}x{height} texels; vkpath reads 1 to {MAX_ENVIRONMENT_TEXELS} texels"
        ));
    }
    if let Some(index) = texels
        .iter()
        .position(|t: &Vec3| !t.is_finite() || t.min_element() < 0.0)
    {
        return Err(format!(
            "environment map '{shown}' has a negative or non-finite texel at ({}, {})",
            index % width as usize,
            index / width as usize
        ));
    }
    Ok(EnvironmentMap {
        width,
        height,
        texels,
    })
}

/// Solid angle (sr) of the patch of the sphere that texel row `row` of a `width` x `height`
/// map covers, one texel of it: 2 pi / width (cos theta_top - cos theta_bottom), as
/// 2 sin(pi (row + 1/2) / height) sin(pi / (2 height)) without cancellation.
pub fn texel_solid_angle(row: u32, width: u32, height: u32) -> f64 {
    use std::f64::consts::PI;
    let height = f64::from(height);
    2.0 * PI / f64::from(width)
        * 2.0
        * (PI * (f64::from(row) + 0.5) / height).sin()
        * (PI / (2.0 * height)).sin()
}

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

    #[test]
    fn a_black_map_samples_uniformly_and_does_not_emit() {
        let map = EnvironmentMap {
            width: 2,
            height: 1,
            texels: vec![Vec3::ZERO; 2],
        };
        assert_eq!(AliasTable::new(&map).probabilities, vec![0.5, 0.5]);
        let environment = Environment {
            map: Some(map),
            ..Environment::constant(Vec3::ONE)
        };
        assert!(!environment.emits_light());
        assert!(Environment::constant(Vec3::splat(0.1)).emits_light());
    }
}
