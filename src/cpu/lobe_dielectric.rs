//! Rust twins of `glsl/lobe_dielectric.glsl`: the rough dielectric lobe of
//! KHR_materials_transmission where light refracts (Walter et al. 2007 with the exact Fresnel
//! reflectance). Its quartet: value `get_rough_dielectric_bsdf`, density
//! `get_rough_dielectric_density`, sample `sample_rough_dielectric`; no weight of its own (the
//! layered mix picks it with `get_transmission_probability` and `is_refracting`,
//! `crate::cpu::layered_bsdf`). `refract` is GLSL's built-in, twinned here. Smooth
//! (roughness 0): a delta lobe, whose peaks carry `get_dielectric_fresnel` and
//! `get_smooth_dielectric_transmittance` at n.v. Same names, same maths.

use crate::cpu::brdf::{
    get_ggx_distribution, get_ggx_reflection_density, get_smith_masking, get_smith_visibility,
    reflect, sample_ggx_visible_normal,
};
use crate::cpu::fresnel::get_dielectric_fresnel;
use glam::{Vec2, Vec3};

/// Twin of `get_refraction_half`: normalize(eta l + v) facing the normal, 0 where none.
pub fn get_refraction_half(eta: f32, local_view: Vec3, local_light: Vec3) -> Vec3 {
    let half_sum = eta * local_light + local_view;
    if !(half_sum.dot(half_sum) > 0.0) {
        return Vec3::ZERO;
    }
    let local_half = half_sum.normalize();
    if local_half.z < 0.0 {
        -local_half
    } else {
        local_half
    }
}

/// Twin of `get_rough_dielectric_bsdf`: (reflection, transmission) of the rough dielectric.
pub fn get_rough_dielectric_bsdf(
    alpha: f32,
    eta: f32,
    local_view: Vec3,
    local_light: Vec3,
) -> Vec2 {
    if local_light.z > 0.0 {
        let local_half = (local_view + local_light).normalize();
        let fresnel = get_dielectric_fresnel(local_view.dot(local_half), eta);
        return Vec2::new(
            fresnel
                * get_ggx_distribution(alpha, local_half)
                * get_smith_visibility(alpha, local_view.z, local_light.z),
            0.0,
        );
    }
    if !(local_light.z < 0.0) {
        return Vec2::ZERO;
    }
    let local_half = get_refraction_half(eta, local_view, local_light);
    let view_dot_half = local_view.dot(local_half);
    let light_dot_half = local_light.dot(local_half);
    if !(view_dot_half > 0.0) || !(light_dot_half < 0.0) {
        return Vec2::ZERO;
    }
    let fresnel = get_dielectric_fresnel(view_dot_half, eta);
    let denominator = eta * light_dot_half + view_dot_half;
    let visibility = get_smith_visibility(alpha, local_view.z, -local_light.z);
    Vec2::new(
        0.0,
        4.0 * get_ggx_distribution(alpha, local_half)
            * visibility
            * (1.0 - fresnel)
            * -light_dot_half
            * view_dot_half
            / (denominator * denominator),
    )
}

/// Twin of `get_smooth_dielectric_transmittance`: what a smooth dielectric's refracted peak
/// carries for radiance, (1 - F) / eta^2 with F the exact Fresnel at n.v.
pub fn get_smooth_dielectric_transmittance(eta: f32, normal_dot_view: f32) -> f32 {
    (1.0 - get_dielectric_fresnel(normal_dot_view, eta)) / (eta * eta)
}

/// Twin of `get_rough_dielectric_density`: the density of `sample_rough_dielectric`,
/// reflection and refraction terms summed whichever side the light is on.
pub fn get_rough_dielectric_density(
    alpha: f32,
    eta: f32,
    local_view: Vec3,
    local_light: Vec3,
) -> f32 {
    let mut density = 0.0;
    let half_sum = local_view + local_light;
    if half_sum.dot(half_sum) > 0.0 {
        let reflection_half = half_sum.normalize();
        density = get_dielectric_fresnel(local_view.dot(reflection_half), eta)
            * get_ggx_reflection_density(alpha, local_view, reflection_half);
    }
    let local_half = get_refraction_half(eta, local_view, local_light);
    let view_dot_half = local_view.dot(local_half);
    let light_dot_half = local_light.dot(local_half);
    if view_dot_half > 0.0 && light_dot_half < 0.0 {
        let fresnel = get_dielectric_fresnel(view_dot_half, eta);
        let denominator = eta * light_dot_half + view_dot_half;
        let jacobian = eta * eta * -light_dot_half / (denominator * denominator);
        density += (1.0 - fresnel)
            * get_smith_masking(alpha, local_view.z)
            * get_ggx_distribution(alpha, local_half)
            * view_dot_half
            / local_view.z
            * jacobian;
    }
    density
}

/// GLSL's `refract(incident, normal, eta)`: 0 under total internal reflection.
pub fn refract(incident: Vec3, normal: Vec3, eta: f32) -> Vec3 {
    let normal_dot_incident = normal.dot(incident);
    let k = 1.0 - eta * eta * (1.0 - normal_dot_incident * normal_dot_incident);
    if k < 0.0 {
        Vec3::ZERO
    } else {
        eta * incident - (eta * normal_dot_incident + k.sqrt()) * normal
    }
}

/// Twin of `sample_rough_dielectric`: a visible normal, then reflection (lobe_random < F)
/// or refraction.
pub fn sample_rough_dielectric(
    random_numbers: Vec2,
    lobe_random: f32,
    alpha: f32,
    eta: f32,
    local_view: Vec3,
) -> Vec3 {
    let local_half = sample_ggx_visible_normal(random_numbers, alpha, local_view);
    let fresnel = get_dielectric_fresnel(local_view.dot(local_half), eta);
    let refracted = refract(-local_view, local_half, 1.0 / eta);
    if lobe_random < fresnel || refracted == Vec3::ZERO {
        return reflect(-local_view, local_half);
    }
    refracted
}
