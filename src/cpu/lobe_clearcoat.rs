//! Rust twins of `glsl/lobe_clearcoat.glsl`: the clear-coat lobe of KHR_materials_clearcoat
//! (fresnel_coat: a GGX coat of ior `CLEARCOAT_IOR` with its own normal). Its quartet: value
//! `get_clearcoat_brdf`, density `get_clearcoat_density`, sample `sample_clearcoat`, weight
//! `get_clearcoat_weight`. A smooth coat (roughness 0) is a delta lobe whose pick
//! `sample_layered_bsdf` weighs 1. Same names, same maths.

use crate::contract::CLEARCOAT_IOR;
use crate::cpu::brdf::{
    get_ggx_alpha, get_ggx_distribution, get_ggx_reflection_density, get_smith_visibility, reflect,
    sample_ggx_visible_normal, to_local, MaterialSample,
};
use crate::cpu::fresnel::get_schlick_fresnel;
use crate::cpu::shading_basis::get_shading_basis;
use glam::{Vec2, Vec3};

/// Twin of `get_clearcoat_weight`: clearcoat times Schlick's F (F0 0.04) at N_c . V.
pub fn get_clearcoat_weight(material: &MaterialSample, clearcoat_normal_dot_view: f32) -> f32 {
    let reflectance = (CLEARCOAT_IOR - 1.0) / (CLEARCOAT_IOR + 1.0);
    material.clearcoat
        * get_schlick_fresnel(
            Vec3::splat(reflectance * reflectance),
            Vec3::ONE,
            clearcoat_normal_dot_view,
        )
        .x
}

/// Twin of `get_clearcoat_brdf`: the coat's D V around its normal.
pub fn get_clearcoat_brdf(
    material: &MaterialSample,
    clearcoat_normal: Vec3,
    view: Vec3,
    light: Vec3,
) -> f32 {
    let normal_dot_view = clearcoat_normal.dot(view);
    let normal_dot_light = clearcoat_normal.dot(light);
    if normal_dot_view <= 0.0 || normal_dot_light <= 0.0 {
        return 0.0;
    }
    let basis = get_shading_basis(clearcoat_normal);
    let local_half = to_local(basis, view + light).normalize();
    let alpha = get_ggx_alpha(material.clearcoat_roughness);
    get_ggx_distribution(alpha, local_half)
        * get_smith_visibility(alpha, normal_dot_view, normal_dot_light)
}

/// Twin of `get_clearcoat_density`.
pub fn get_clearcoat_density(
    material: &MaterialSample,
    clearcoat_normal: Vec3,
    view: Vec3,
    light: Vec3,
) -> f32 {
    let half_sum = view + light;
    if clearcoat_normal.dot(view) <= 0.0 || !(half_sum.dot(half_sum) > 0.0) {
        return 0.0;
    }
    let basis = get_shading_basis(clearcoat_normal);
    get_ggx_reflection_density(
        get_ggx_alpha(material.clearcoat_roughness),
        to_local(basis, view),
        to_local(basis, half_sum).normalize(),
    )
}

/// Twin of `sample_clearcoat`.
pub fn sample_clearcoat(
    random_numbers: Vec2,
    material: &MaterialSample,
    clearcoat_normal: Vec3,
    view: Vec3,
) -> Vec3 {
    let basis = get_shading_basis(clearcoat_normal);
    let local_view = to_local(basis, view);
    let local_half = sample_ggx_visible_normal(
        random_numbers,
        get_ggx_alpha(material.clearcoat_roughness),
        local_view,
    );
    (basis * reflect(-local_view, local_half)).normalize()
}
