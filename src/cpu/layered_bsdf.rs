//! Rust twins of `glsl/layered_bsdf.glsl`: the layers of glTF materials beyond
//! metallic-roughness. KHR_materials_transmission with KHR_materials_ior and
//! KHR_materials_volume (a rough dielectric BSDF after Walter et al. 2007 with the exact
//! Fresnel reflectance, or a thin wall whose GGX lobe is mirrored through the surface), and
//! KHR_materials_clearcoat (`fresnel_coat`: a GGX coat weighted by clearcoat F(N_c . V)), and
//! KHR_materials_sheen (the Charlie lobe of Estevez & Kulla 2017 over the base, which it
//! scales by 1 - max(sheen colour) E(n.v), E tabulated in `cpu::sheen_albedo_table`).
//! Same names, same maths; directions are unit vectors pointing away from the surface,
//! `local_` ones in the shading frame (z the normal, the view above it). `eta` is the far
//! side's index of refraction over the view's side's.
//!
//! Each lobe's twins live in their own module (`cpu::lobe_dielectric`, `cpu::lobe_thin_wall`,
//! `cpu::lobe_sheen`, `cpu::lobe_clearcoat`), re-exported here; their Fresnel terms come from
//! `cpu::fresnel` and their GGX terms from `cpu::brdf`; this module keeps the layered mix.

use glam::{Vec2, Vec3};

use crate::cpu::brdf::{
    get_brdf_density, get_brdf_mirror_probability, get_ggx_alpha, get_ggx_distribution,
    get_smith_visibility, get_specular_probability, sample_brdf, to_local, MaterialSample,
};
use crate::cpu::fresnel::{
    get_dielectric_fresnel, get_dielectric_schlick_fresnel, get_metal_schlick_fresnel,
};
use crate::cpu::importance_sampling::sample_hemisphere_cosine;
use crate::cpu::shading_basis::get_shading_basis;
use crate::cpu::workshop::M_PI;

pub use crate::cpu::lobe_clearcoat::{
    get_clearcoat_brdf, get_clearcoat_density, get_clearcoat_weight, sample_clearcoat,
};
pub use crate::cpu::lobe_dielectric::{
    get_refraction_half, get_rough_dielectric_bsdf, get_rough_dielectric_density,
    get_smooth_dielectric_transmittance, refract, sample_rough_dielectric,
};
pub use crate::cpu::lobe_sheen::{
    get_charlie_distribution, get_sheen_albedo, get_sheen_albedo_entry, get_sheen_alpha,
    get_sheen_brdf, get_sheen_lambda, get_sheen_lambda_fit, get_sheen_visibility, get_sheen_weight,
    has_sheen,
};
pub use crate::cpu::lobe_thin_wall::{
    get_smooth_thin_wall_transmittance, get_thin_wall_btdf, get_thin_wall_density,
    get_thin_wall_reflection_probability, mirror_through_surface, sample_thin_wall,
};

/// Twin of `is_layered`: transmission, a clear coat or sheen.
pub fn is_layered(material: &MaterialSample) -> bool {
    material.transmission > 0.0 || material.clearcoat > 0.0 || has_sheen(material)
}

/// Twin of `is_refracting`: a volume of another index (not a thin wall).
pub fn is_refracting(material: &MaterialSample) -> bool {
    material.thickness > 0.0 && material.ior != 1.0
}

/// Twin of `get_transmission_probability`: (1 - metallic) transmission.
pub fn get_transmission_probability(material: &MaterialSample) -> f32 {
    (1.0 - material.metallic) * material.transmission
}

/// Twin of `get_transmissive_bsdf`: the metallic-roughness BSDF with transmission, without
/// the coat and the cosine, in the shading frame.
pub fn get_transmissive_bsdf(
    material: &MaterialSample,
    eta: f32,
    local_view: Vec3,
    local_light: Vec3,
) -> Vec3 {
    let alpha = get_ggx_alpha(material.roughness);
    if local_light.z > 0.0 {
        let local_half = (local_view + local_light).normalize();
        let view_dot_half = local_view.dot(local_half);
        let specular = get_ggx_distribution(alpha, local_half)
            * get_smith_visibility(alpha, local_view.z, local_light.z);
        let dielectric_fresnel = get_dielectric_schlick_fresnel(material, view_dot_half);
        let diffuse = (1.0 - dielectric_fresnel) * material.base_color / M_PI;
        let dielectric = if is_refracting(material) {
            (1.0 - material.transmission) * (diffuse + dielectric_fresnel * specular)
                + material.transmission * get_dielectric_fresnel(view_dot_half, eta) * specular
        } else {
            dielectric_fresnel * specular + (1.0 - material.transmission) * diffuse
        };
        let metal = get_metal_schlick_fresnel(material, view_dot_half) * specular;
        return dielectric.lerp(metal, material.metallic);
    }
    let transmitted = if is_refracting(material) {
        get_rough_dielectric_bsdf(alpha, eta, local_view, local_light).y * material.base_color
    } else {
        get_thin_wall_btdf(material, alpha, local_view, local_light)
    };
    (1.0 - material.metallic) * material.transmission * transmitted
}

/// Twin of `get_transmissive_density`.
pub fn get_transmissive_density(
    material: &MaterialSample,
    eta: f32,
    shading_normal: Vec3,
    view: Vec3,
    light: Vec3,
) -> f32 {
    let transmission_probability = get_transmission_probability(material);
    let mut density =
        (1.0 - transmission_probability) * get_brdf_density(material, shading_normal, view, light);
    if transmission_probability > 0.0 {
        let basis = get_shading_basis(shading_normal);
        let alpha = get_ggx_alpha(material.roughness);
        let (local_view, local_light) = (to_local(basis, view), to_local(basis, light));
        let lobe = if is_refracting(material) {
            get_rough_dielectric_density(alpha, eta, local_view, local_light)
        } else {
            get_thin_wall_density(material, alpha, local_view, local_light)
        };
        density += transmission_probability * lobe;
    }
    density
}

/// Twin of `get_transmissive_delta_weight`: f / p of a delta pick of
/// `sample_transmissive_bsdf` (roughness 0), its transmission (`transmitted`) or its
/// reflection, whose probability sums the two routes to the mirror direction.
pub fn get_transmissive_delta_weight(
    material: &MaterialSample,
    eta: f32,
    local_view: Vec3,
    transmitted: bool,
) -> Vec3 {
    let normal_dot_view = local_view.z;
    let refracting = is_refracting(material);
    let reflection_probability = if refracting {
        get_dielectric_fresnel(normal_dot_view, eta)
    } else {
        get_thin_wall_reflection_probability(material, normal_dot_view)
    };
    if transmitted {
        let transmittance = if refracting {
            get_smooth_dielectric_transmittance(eta, normal_dot_view) * material.base_color
        } else {
            get_smooth_thin_wall_transmittance(material, normal_dot_view)
        };
        return transmittance / (1.0 - reflection_probability);
    }
    let schlick_fresnel = get_dielectric_schlick_fresnel(material, normal_dot_view);
    let dielectric = if refracting {
        (1.0 - material.transmission) * schlick_fresnel
            + material.transmission * get_dielectric_fresnel(normal_dot_view, eta)
    } else {
        schlick_fresnel
    };
    let reflectance = dielectric.lerp(
        get_metal_schlick_fresnel(material, normal_dot_view),
        material.metallic,
    );
    let transmission_probability = get_transmission_probability(material);
    reflectance
        / (transmission_probability * reflection_probability
            + (1.0 - transmission_probability)
                * get_specular_probability(material, normal_dot_view))
}

/// Twin of `sample_transmissive_bsdf`: the direction, and for a delta pick (roughness 0; the
/// shader's `out_delta`) its weight `get_transmissive_delta_weight` (`out_delta_weight`).
pub fn sample_transmissive_bsdf(
    random_numbers: Vec2,
    lobe_random: f32,
    material: &MaterialSample,
    eta: f32,
    shading_normal: Vec3,
    view: Vec3,
) -> (Vec3, Option<Vec3>) {
    let transmission_probability = get_transmission_probability(material);
    let basis = get_shading_basis(shading_normal);
    let local_view = to_local(basis, view);
    let alpha = get_ggx_alpha(material.roughness);
    if lobe_random < transmission_probability {
        let reflection_random = lobe_random / transmission_probability;
        let local_light = if is_refracting(material) {
            sample_rough_dielectric(random_numbers, reflection_random, alpha, eta, local_view)
        } else {
            sample_thin_wall(
                random_numbers,
                reflection_random,
                material,
                alpha,
                local_view,
            )
        };
        let delta_weight = (alpha == 0.0)
            .then(|| get_transmissive_delta_weight(material, eta, local_view, local_light.z < 0.0));
        return ((basis * local_light).normalize(), delta_weight);
    }
    let delta_weight = (random_numbers[0]
        < get_brdf_mirror_probability(material, shading_normal, view))
    .then(|| get_transmissive_delta_weight(material, eta, local_view, false));
    (
        sample_brdf(random_numbers, material, shading_normal, view),
        delta_weight,
    )
}

/// Twin of `get_layered_base_cosine`.
pub fn get_layered_base_cosine(geometric_normal: Vec3, shading_normal: Vec3, light: Vec3) -> f32 {
    let geometric_cosine = geometric_normal.dot(light);
    let shading_cosine = shading_normal.dot(light);
    if (geometric_cosine > 0.0 && shading_cosine > 0.0)
        || (geometric_cosine < 0.0 && shading_cosine < 0.0)
    {
        shading_cosine.abs()
    } else {
        0.0
    }
}

/// Twin of `get_layered_bsdf`: fresnel_coat over `get_transmissive_bsdf`, times the cosine.
pub fn get_layered_bsdf(
    material: &MaterialSample,
    eta: f32,
    geometric_normal: Vec3,
    shading_normal: Vec3,
    clearcoat_normal: Vec3,
    view: Vec3,
    light: Vec3,
) -> Vec3 {
    let mut bsdf = Vec3::ZERO;
    let base_cosine = get_layered_base_cosine(geometric_normal, shading_normal, light);
    if base_cosine > 0.0 {
        let basis = get_shading_basis(shading_normal);
        bsdf = get_transmissive_bsdf(material, eta, to_local(basis, view), to_local(basis, light))
            * base_cosine;
    }
    if has_sheen(material) {
        bsdf *= 1.0 - get_sheen_weight(material, shading_normal.dot(view));
        if geometric_normal.dot(light) > 0.0 {
            bsdf += get_sheen_brdf(material, shading_normal, view, light)
                * shading_normal.dot(light).max(0.0);
        }
    }
    if material.clearcoat > 0.0 {
        let coat_weight = get_clearcoat_weight(material, clearcoat_normal.dot(view));
        bsdf *= 1.0 - coat_weight;
        if geometric_normal.dot(light) > 0.0 {
            bsdf += coat_weight
                * get_clearcoat_brdf(material, clearcoat_normal, view, light)
                * clearcoat_normal.dot(light).max(0.0);
        }
    }
    bsdf
}

/// Twin of `get_layered_density`.
pub fn get_layered_density(
    material: &MaterialSample,
    eta: f32,
    shading_normal: Vec3,
    clearcoat_normal: Vec3,
    view: Vec3,
    light: Vec3,
) -> f32 {
    let mut density = get_transmissive_density(material, eta, shading_normal, view, light);
    if has_sheen(material) {
        let sheen_weight = get_sheen_weight(material, shading_normal.dot(view));
        density = (1.0 - sheen_weight) * density
            + sheen_weight * shading_normal.dot(light).max(0.0) / M_PI;
    }
    if material.clearcoat > 0.0 {
        let coat_weight = get_clearcoat_weight(material, clearcoat_normal.dot(view));
        density = (1.0 - coat_weight) * density
            + coat_weight * get_clearcoat_density(material, clearcoat_normal, view, light);
    }
    density
}

/// Twin of `sample_layered_bsdf`: the direction, and for a delta pick (a smooth coat, or the
/// base's as `sample_transmissive_bsdf` says; the shader's `out_delta`) its weight f / p
/// (`out_delta_weight`: 1 for the coat).
pub fn sample_layered_bsdf(
    random_numbers: Vec2,
    lobe_random: f32,
    material: &MaterialSample,
    eta: f32,
    shading_normal: Vec3,
    clearcoat_normal: Vec3,
    view: Vec3,
) -> (Vec3, Option<Vec3>) {
    let mut lobe_random = lobe_random;
    if material.clearcoat > 0.0 {
        let coat_weight = get_clearcoat_weight(material, clearcoat_normal.dot(view));
        if lobe_random < coat_weight {
            let delta_weight =
                (get_ggx_alpha(material.clearcoat_roughness) == 0.0).then_some(Vec3::ONE);
            return (
                sample_clearcoat(random_numbers, material, clearcoat_normal, view),
                delta_weight,
            );
        }
        lobe_random = (lobe_random - coat_weight) / (1.0 - coat_weight);
    }
    if has_sheen(material) {
        let sheen_weight = get_sheen_weight(material, shading_normal.dot(view));
        if lobe_random < sheen_weight {
            return (
                sample_hemisphere_cosine(random_numbers, shading_normal),
                None,
            );
        }
        lobe_random = (lobe_random - sheen_weight) / (1.0 - sheen_weight);
    }
    sample_transmissive_bsdf(
        random_numbers,
        lobe_random,
        material,
        eta,
        shading_normal,
        view,
    )
}

/// Twin of `get_absorption`: exp(-sigma distance) per channel.
pub fn get_absorption(material: &MaterialSample, distance: f32) -> Vec3 {
    Vec3::from((-material.attenuation * distance).to_array().map(f32::exp))
}

#[cfg(test)]
#[path = "layered_bsdf_tests.rs"]
mod tests;
