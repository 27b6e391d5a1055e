//! Rust twins of `glsl/fresnel.glsl`, the Fresnel room: Schlick's approximation, the exact
//! reflectance of a smooth dielectric interface, and the base layer's two Fresnel terms
//! (KHR_materials_specular, KHR_materials_ior) that every lobe reads. Same names, same maths.
//! A Fresnel modifier (thin-film iridescence, dispersion) plugs in here: it changes
//! `get_dielectric_schlick_fresnel` and `get_metal_schlick_fresnel` (and the refracting
//! lobes' `get_dielectric_fresnel`), and every lobe follows.

use glam::Vec3;

use crate::cpu::brdf::MaterialSample;

/// Twin of `get_schlick_fresnel`: f0 + (f90 - f0) (1 - |v.h|)^5.
pub fn get_schlick_fresnel(f0: Vec3, f90: Vec3, view_dot_half: f32) -> Vec3 {
    let weight = (1.0 - view_dot_half.abs()).max(0.0);
    let weight_squared = weight * weight;
    f0 + (f90 - f0) * (weight_squared * weight_squared * weight)
}

/// Twin of `get_dielectric_fresnel`: the exact unpolarised Fresnel reflectance of a smooth
/// dielectric interface (1 under total internal reflection). `cos_theta_i` is the cosine on
/// the incident side (negative: from the other side, `eta` inverted); `eta` the far side's
/// index of refraction over the incident side's.
pub fn get_dielectric_fresnel(cos_theta_i: f32, eta: f32) -> f32 {
    let mut cos_theta_i = cos_theta_i.clamp(-1.0, 1.0);
    let mut eta = eta;
    if cos_theta_i < 0.0 {
        eta = 1.0 / eta;
        cos_theta_i = -cos_theta_i;
    }
    let sin2_theta_t = (1.0 - cos_theta_i * cos_theta_i) / (eta * eta);
    if sin2_theta_t >= 1.0 {
        return 1.0;
    }
    let cos_theta_t = (1.0 - sin2_theta_t).max(0.0).sqrt();
    let r_parallel = (eta * cos_theta_i - cos_theta_t) / (eta * cos_theta_i + cos_theta_t);
    let r_perpendicular = (cos_theta_i - eta * cos_theta_t) / (cos_theta_i + eta * cos_theta_t);
    0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular)
}

/// Twin of `get_dielectric_f0`: min(((ior - 1)/(ior + 1))^2 specular_color, 1) specular.
pub fn get_dielectric_f0(material: &MaterialSample) -> Vec3 {
    let reflectance = (material.ior - 1.0) / (material.ior + 1.0);
    (reflectance * reflectance * material.specular_color).min(Vec3::ONE) * material.specular
}

/// Twin of `get_dielectric_schlick_fresnel`: the base dielectric's F_d, Schlick's with
/// F0 = `get_dielectric_f0` and F90 = specular at the cosine v.h.
pub fn get_dielectric_schlick_fresnel(material: &MaterialSample, view_dot_half: f32) -> Vec3 {
    get_schlick_fresnel(
        get_dielectric_f0(material),
        Vec3::splat(material.specular),
        view_dot_half,
    )
}

/// Twin of `get_metal_schlick_fresnel`: the base metal's F_m, Schlick's with F0 = base colour
/// and F90 = 1 at the cosine v.h.
pub fn get_metal_schlick_fresnel(material: &MaterialSample, view_dot_half: f32) -> Vec3 {
    get_schlick_fresnel(material.base_color, Vec3::ONE, view_dot_half)
}

#[cfg(test)]
#[path = "fresnel_tests.rs"]
mod tests;
