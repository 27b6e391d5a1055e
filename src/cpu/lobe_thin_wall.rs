//! Rust twins of `glsl/lobe_thin_wall.glsl`: the thin-wall lobe of KHR_materials_transmission
//! (the GGX lobe mirrored through the surface, weighted by Schlick's Fresnel). Its quartet:
//! value `get_thin_wall_btdf`, density `get_thin_wall_density`, sample `sample_thin_wall`,
//! weight `get_thin_wall_reflection_probability` (reflection against transmission; the layered
//! mix picks the lobe with `get_transmission_probability` and `is_refracting`). Smooth
//! (roughness 0): a delta lobe, whose peaks carry `get_dielectric_schlick_fresnel`
//! (`cpu::fresnel`) and `get_smooth_thin_wall_transmittance` at n.v. Same names, same maths.

use crate::cpu::brdf::{
    get_ggx_distribution, get_ggx_reflection_density, get_luminance, get_smith_visibility, reflect,
    sample_ggx_visible_normal, MaterialSample,
};
use crate::cpu::fresnel::get_dielectric_schlick_fresnel;
use glam::{Vec2, Vec3};

/// Twin of `mirror_through_surface`.
pub fn mirror_through_surface(local_direction: Vec3) -> Vec3 {
    Vec3::new(local_direction.x, local_direction.y, -local_direction.z)
}

/// Twin of `get_thin_wall_reflection_probability`.
pub fn get_thin_wall_reflection_probability(material: &MaterialSample, view_dot_half: f32) -> f32 {
    let fresnel = get_dielectric_schlick_fresnel(material, view_dot_half);
    let reflected = get_luminance(fresnel);
    let transmitted = get_luminance((1.0 - fresnel) * material.base_color);
    if reflected + transmitted > 0.0 {
        reflected / (reflected + transmitted)
    } else {
        1.0
    }
}

/// Twin of `get_thin_wall_btdf`: (1 - F) base_color D V at the mirrored light (light below).
pub fn get_thin_wall_btdf(
    material: &MaterialSample,
    alpha: f32,
    local_view: Vec3,
    local_light: Vec3,
) -> Vec3 {
    if !(local_light.z < 0.0) {
        return Vec3::ZERO;
    }
    let mirrored = mirror_through_surface(local_light);
    let local_half = (local_view + mirrored).normalize();
    let fresnel = get_dielectric_schlick_fresnel(material, local_view.dot(local_half));
    (1.0 - fresnel)
        * material.base_color
        * get_ggx_distribution(alpha, local_half)
        * get_smith_visibility(alpha, local_view.z, mirrored.z)
}

/// Twin of `get_smooth_thin_wall_transmittance`: what a smooth thin wall's straight-through
/// peak carries, (1 - F) base_color at v.h = n.v.
pub fn get_smooth_thin_wall_transmittance(material: &MaterialSample, normal_dot_view: f32) -> Vec3 {
    (1.0 - get_dielectric_schlick_fresnel(material, normal_dot_view)) * material.base_color
}

/// Twin of `get_thin_wall_density`: both branches summed whichever side the light is on.
pub fn get_thin_wall_density(
    material: &MaterialSample,
    alpha: f32,
    local_view: Vec3,
    local_light: Vec3,
) -> f32 {
    let mut density = 0.0;
    let reflected_sum = local_view + local_light;
    if reflected_sum.dot(reflected_sum) > 0.0 {
        let local_half = reflected_sum.normalize();
        density = get_thin_wall_reflection_probability(material, local_view.dot(local_half))
            * get_ggx_reflection_density(alpha, local_view, local_half);
    }
    let mirrored_sum = local_view + mirror_through_surface(local_light);
    if mirrored_sum.dot(mirrored_sum) > 0.0 {
        let local_half = mirrored_sum.normalize();
        density += (1.0
            - get_thin_wall_reflection_probability(material, local_view.dot(local_half)))
            * get_ggx_reflection_density(alpha, local_view, local_half);
    }
    density
}

/// Twin of `sample_thin_wall`.
pub fn sample_thin_wall(
    random_numbers: Vec2,
    lobe_random: f32,
    material: &MaterialSample,
    alpha: f32,
    local_view: Vec3,
) -> Vec3 {
    let local_half = sample_ggx_visible_normal(random_numbers, alpha, local_view);
    let reflected = reflect(-local_view, local_half);
    if lobe_random < get_thin_wall_reflection_probability(material, local_view.dot(local_half)) {
        return reflected;
    }
    mirror_through_surface(reflected)
}
