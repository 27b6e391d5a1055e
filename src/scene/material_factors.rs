//! A material's constant factors, by glTF's names and with glTF's defaults, and the one
//! conversion from them to the material vkpath renders: the glTF loader reads a file's
//! factors into `MaterialFactors` (and adds its textures), `Scene::from_arrays` (Python's
//! `Scene.from_arrays`) takes them from its caller, so that the same factors give the same
//! material, and the same pixels, by construction.
//!
//! Each factor's name, type, glTF source and default are its row of
//! `super::material_params::MATERIAL_PARAMS`; `Default` is made from it.

use glam::{Vec3, Vec4};

use super::material_params::MATERIAL_PARAMS;
use super::materials::{AlphaMode, Clearcoat, PbrMaterial, Sheen, Transmission};

/// The factors of a glTF metallic-roughness material and its extensions, without textures.
/// `Default` is glTF's default material (white, metallic 1, roughness 1, opaque).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialFactors {
    /// `baseColorFactor`: linear RGB and alpha (default 1).
    pub base_color: Vec4,
    /// `metallicFactor` in [0, 1] (default 1).
    pub metallic: f32,
    /// `roughnessFactor` in [0, 1], perceptual (default 1).
    pub roughness: f32,
    /// `emissiveFactor`, linear RGB (default 0).
    pub emission: Vec3,
    /// KHR_materials_emissive_strength `emissiveStrength`: multiplies `emission` (default 1).
    pub emissive_strength: f32,
    /// KHR_materials_specular `specularFactor` (default 1).
    pub specular: f32,
    /// KHR_materials_specular `specularColorFactor`, linear RGB (default 1).
    pub specular_color: Vec3,
    /// KHR_materials_ior `ior` (default 1.5).
    pub ior: f32,
    /// KHR_materials_transmission `transmissionFactor` in [0, 1] (default 0: opaque).
    pub transmission: f32,
    /// KHR_materials_volume `thicknessFactor` (default 0: thin-walled).
    pub thickness: f32,
    /// KHR_materials_volume `attenuationColor`, linear RGB (default 1: no absorption).
    pub attenuation_color: Vec3,
    /// KHR_materials_volume `attenuationDistance` (default infinite: no absorption).
    pub attenuation_distance: f32,
    /// KHR_materials_volume_scatter `multiscatterColor`, the multi-scatter albedo, linear
    /// RGB (default 0: the volume only absorbs).
    pub multiscatter_color: Vec3,
    /// KHR_materials_volume_scatter `scatterAnisotropy`, the Henyey-Greenstein g in (-1, 1)
    /// (default 0: isotropic).
    pub scatter_anisotropy: f32,
    /// KHR_materials_clearcoat `clearcoatFactor` in [0, 1] (default 0: no coat).
    pub clearcoat: f32,
    /// KHR_materials_clearcoat `clearcoatRoughnessFactor` in [0, 1] (default 0).
    pub clearcoat_roughness: f32,
    /// KHR_materials_sheen `sheenColorFactor`, linear RGB (default 0: no sheen).
    pub sheen_color: Vec3,
    /// KHR_materials_sheen `sheenRoughnessFactor` in [0, 1] (default 0).
    pub sheen_roughness: f32,
    /// `alphaMode` with `alphaCutoff` (default opaque).
    pub alpha_mode: AlphaMode,
    /// `doubleSided` (default false): the emission shines from the back side too.
    pub double_sided: bool,
    /// KHR_materials_unlit: camera rays see the base colour; nothing reflects or emits.
    pub unlit: bool,
}

impl Default for MaterialFactors {
    /// glTF's default material: every factor at its row's `default` in `MATERIAL_PARAMS`.
    fn default() -> MaterialFactors {
        let mut factors = MaterialFactors {
            base_color: Vec4::ZERO,
            metallic: 0.0,
            roughness: 0.0,
            emission: Vec3::ZERO,
            emissive_strength: 0.0,
            specular: 0.0,
            specular_color: Vec3::ZERO,
            ior: 0.0,
            transmission: 0.0,
            thickness: 0.0,
            attenuation_color: Vec3::ZERO,
            attenuation_distance: 0.0,
            multiscatter_color: Vec3::ZERO,
            scatter_anisotropy: 0.0,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            sheen_color: Vec3::ZERO,
            sheen_roughness: 0.0,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            unlit: false,
        };
        for param in MATERIAL_PARAMS {
            if let Some(factor) = &param.factor {
                (factor.set)(&mut factors, param.default);
            }
        }
        factors
    }
}

impl MaterialFactors {
    /// The material these factors describe, without textures (a loader adds its own) and
    /// not yet `sanitized` (a loader sanitizes after adding them).
    pub fn material(&self) -> PbrMaterial {
        let (attenuation, scattering) = Transmission::volume_coefficients(
            self.attenuation_color,
            self.attenuation_distance,
            self.multiscatter_color,
        );
        PbrMaterial {
            base_color: self.base_color,
            // KHR_materials_unlit: the base colour is all there is; nothing emits light.
            emission: if self.unlit {
                Vec3::ZERO
            } else {
                self.emissive_strength * self.emission
            },
            metallic: self.metallic,
            roughness: self.roughness,
            specular: self.specular,
            specular_color: self.specular_color,
            ior: self.ior,
            normal_scale: 1.0,
            alpha_mode: self.alpha_mode,
            double_sided: self.double_sided,
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            emissive_texture: None,
            specular_texture: None,
            specular_color_texture: None,
            transmission: Transmission {
                factor: self.transmission,
                thickness: self.thickness,
                attenuation,
                scattering,
                anisotropy: self.scatter_anisotropy,
                ..Transmission::default()
            },
            clearcoat: Clearcoat {
                factor: self.clearcoat,
                roughness: self.clearcoat_roughness,
                normal_scale: 1.0,
                ..Clearcoat::default()
            },
            sheen: Sheen {
                color: self.sheen_color,
                roughness: self.sheen_roughness,
                ..Sheen::default()
            },
            unlit: self.unlit,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_gltfs_default_material() {
        let material = MaterialFactors::default().material().sanitized();
        assert_eq!(material.base_color, Vec4::ONE);
        assert_eq!((material.metallic, material.roughness), (1.0, 1.0));
        assert_eq!((material.specular, material.ior), (1.0, 1.5));
        assert_eq!(material.emission, Vec3::ZERO);
        assert_eq!(material.transmission, Transmission::default());
        assert!(!material.is_layered() && !material.is_plain_lambertian());
    }

    #[test]
    fn strength_scales_emission_and_unlit_removes_it() {
        let factors = MaterialFactors {
            emission: Vec3::new(1.0, 0.5, 0.0),
            emissive_strength: 4.0,
            ..MaterialFactors::default()
        };
        assert_eq!(factors.material().emission, Vec3::new(4.0, 2.0, 0.0));
        let unlit = MaterialFactors {
            unlit: true,
            ..factors
        };
        assert_eq!(unlit.material().emission, Vec3::ZERO);
    }

    #[test]
    fn volume_attenuation_is_the_coefficient_of_colour_and_distance() {
        let factors = MaterialFactors {
            transmission: 1.0,
            thickness: 0.5,
            attenuation_color: Vec3::new(0.5, 1.0, 0.25),
            attenuation_distance: 2.0,
            ..MaterialFactors::default()
        };
        let transmission = factors.material().transmission;
        assert_eq!(
            transmission.attenuation,
            Transmission::attenuation_coefficient(Vec3::new(0.5, 1.0, 0.25), 2.0)
        );
        assert_eq!((transmission.factor, transmission.thickness), (1.0, 0.5));
    }

    #[test]
    fn volume_scatter_splits_the_extinction_by_the_drafts_albedo() {
        // rho_ss of the draft's formula, evaluated by hand (Python, f64) at 0.2, 0.5, 0.8
        let albedo = Transmission::single_scatter_albedo(Vec3::new(0.2, 0.5, 0.8));
        for (got, expected) in albedo
            .to_array()
            .into_iter()
            .zip([0.613357, 0.911709, 0.990589])
        {
            assert!((got - expected).abs() < 2e-6, "{got} vs {expected}");
        }
        assert_eq!(Transmission::single_scatter_albedo(Vec3::ONE), Vec3::ONE);
        let volume = |multiscatter_color| MaterialFactors {
            transmission: 1.0,
            thickness: 0.5,
            attenuation_color: Vec3::new(0.5, 0.8, 0.25),
            attenuation_distance: 2.0,
            multiscatter_color,
            scatter_anisotropy: 0.7,
            ..MaterialFactors::default()
        };
        let extinction = Transmission::attenuation_coefficient(Vec3::new(0.5, 0.8, 0.25), 2.0);
        // Albedo 1: all of sigma_t scatters, nothing absorbs
        let white = volume(Vec3::ONE).material().sanitized().transmission;
        assert_eq!(
            (white.attenuation, white.scattering),
            (Vec3::ZERO, extinction)
        );
        assert_eq!(white.anisotropy, 0.7);
        // In between: sigma_a + sigma_s = sigma_t, sigma_s = sigma_t rho_ss
        let grey = volume(Vec3::splat(0.5)).material().transmission;
        assert!(
            (grey.attenuation + grey.scattering - extinction)
                .abs()
                .max_element()
                < 1e-6
        );
        assert!(
            (grey.scattering - extinction * 0.911709)
                .abs()
                .max_element()
                < 1e-5
        );
    }

    #[test]
    fn a_multiscatter_colour_of_zero_absorbs_as_without_the_extension() {
        // The pure absorber: the same material, bit for bit, as KHR_materials_volume alone
        // (so its image is today's Beer-Lambert image), and the kernels keep their medium
        // compiled out (no material scatters)
        let without = MaterialFactors {
            transmission: 1.0,
            thickness: 1.0,
            attenuation_color: Vec3::new(0.5, 0.8, 0.25),
            attenuation_distance: 2.0,
            ..MaterialFactors::default()
        };
        let absorber = MaterialFactors {
            multiscatter_color: Vec3::ZERO,
            ..without
        };
        assert_eq!(absorber.material(), without.material());
        assert_eq!(
            absorber.material().transmission.attenuation,
            Transmission::attenuation_coefficient(Vec3::new(0.5, 0.8, 0.25), 2.0)
        );
        assert!(!absorber.material().transmission.scatters());
        let scattering = MaterialFactors {
            multiscatter_color: Vec3::new(0.0, 0.0, 0.1),
            ..without
        };
        assert!(scattering.material().transmission.scatters());
    }
}
