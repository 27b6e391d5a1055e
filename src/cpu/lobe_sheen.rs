//! Rust twins of `glsl/lobe_sheen.glsl`: the Charlie sheen lobe of KHR_materials_sheen
//! (Estevez & Kulla 2017), E(n.v) tabulated in `cpu::sheen_albedo_table`. Its quartet: value
//! `get_sheen_brdf`; density and sample: the cosine's (`sample_hemisphere_cosine`), mixed in by
//! `get_layered_density` and `sample_layered_bsdf`; weight `get_sheen_weight` (`has_sheen`:
//! whether it is there). Same names, same maths.

use crate::contract::{SHEEN_ALBEDO_SIZE, SHEEN_MIN_ALPHA};
use crate::cpu::brdf::MaterialSample;
use crate::cpu::sheen_albedo_table::SHEEN_ALBEDO;
use crate::cpu::workshop::M_PI;
use glam::{Vec2, Vec3};

/// Twin of `has_sheen`.
pub fn has_sheen(material: &MaterialSample) -> bool {
    material.sheen_color.max_element() > 0.0
}

/// Twin of `get_sheen_alpha`.
pub fn get_sheen_alpha(sheen_roughness: f32) -> f32 {
    (sheen_roughness * sheen_roughness).max(SHEEN_MIN_ALPHA)
}

/// Twin of `get_charlie_distribution`.
pub fn get_charlie_distribution(alpha: f32, normal_dot_half: f32) -> f32 {
    let sin_squared = (1.0 - normal_dot_half * normal_dot_half).max(0.0);
    (2.0 + 1.0 / alpha) * sin_squared.powf(0.5 / alpha) / (2.0 * M_PI)
}

/// GLSL's `mix(x, y, t)`.
fn mix(x: f32, y: f32, t: f32) -> f32 {
    x * (1.0 - t) + y * t
}

/// Twin of `get_sheen_lambda_fit`: Estevez & Kulla's L(x).
pub fn get_sheen_lambda_fit(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let a = mix(21.5473, 25.3245, t);
    let b = mix(3.82987, 3.32435, t);
    let c = mix(0.19823, 0.16801, t);
    let d = mix(-1.97760, -1.27393, t);
    let e = mix(-4.32054, -4.85967, t);
    a / (1.0 + b * x.powf(c)) + d * x + e
}

/// Twin of `get_sheen_lambda`.
pub fn get_sheen_lambda(cos_theta: f32, alpha: f32) -> f32 {
    let c = cos_theta.abs();
    if c < 0.5 {
        get_sheen_lambda_fit(c, alpha).exp()
    } else {
        (2.0 * get_sheen_lambda_fit(0.5, alpha) - get_sheen_lambda_fit(1.0 - c, alpha)).exp()
    }
}

/// Twin of `get_sheen_visibility`.
pub fn get_sheen_visibility(alpha: f32, normal_dot_view: f32, normal_dot_light: f32) -> f32 {
    (1.0 / ((1.0
        + get_sheen_lambda(normal_dot_view, alpha)
        + get_sheen_lambda(normal_dot_light, alpha))
        * 4.0
        * normal_dot_view
        * normal_dot_light))
        .clamp(0.0, 1.0)
}

/// Twin of `get_sheen_brdf`: sheen_color D V.
pub fn get_sheen_brdf(material: &MaterialSample, normal: Vec3, view: Vec3, light: Vec3) -> Vec3 {
    let normal_dot_view = normal.dot(view);
    let normal_dot_light = normal.dot(light);
    if normal_dot_view <= 0.0 || normal_dot_light <= 0.0 {
        return Vec3::ZERO;
    }
    let alpha = get_sheen_alpha(material.sheen_roughness);
    let normal_dot_half = normal.dot((view + light).normalize());
    material.sheen_color
        * get_charlie_distribution(alpha, normal_dot_half)
        * get_sheen_visibility(alpha, normal_dot_view, normal_dot_light)
}

/// Twin of `get_sheen_albedo_entry`: entry `k` of the table (`SHEEN_ALBEDO`), which the
/// shaders read from the end of `g_material_texels`.
pub fn get_sheen_albedo_entry(k: usize) -> f32 {
    SHEEN_ALBEDO[k]
}

/// Twin of `get_sheen_albedo`: E(n.v, roughness), bilinear in the table.
pub fn get_sheen_albedo(normal_dot_view: f32, sheen_roughness: f32) -> f32 {
    let size = SHEEN_ALBEDO_SIZE as i32;
    let last = (SHEEN_ALBEDO_SIZE - 1) as f32;
    let position = Vec2::new(normal_dot_view, sheen_roughness).clamp(Vec2::ZERO, Vec2::ONE) * last;
    let low = (position.x as i32).min(size - 2);
    let low_y = (position.y as i32).min(size - 2);
    let weight = position - Vec2::new(low as f32, low_y as f32);
    let row = (low * size + low_y) as usize;
    let size = size as usize;
    let below = mix(
        get_sheen_albedo_entry(row),
        get_sheen_albedo_entry(row + 1),
        weight.y,
    );
    let above = mix(
        get_sheen_albedo_entry(row + size),
        get_sheen_albedo_entry(row + size + 1),
        weight.y,
    );
    mix(below, above, weight.x)
}

/// Twin of `get_sheen_weight`: max(sheen colour) E(n.v), at most 1.
pub fn get_sheen_weight(material: &MaterialSample, normal_dot_view: f32) -> f32 {
    (material.sheen_color.max_element()
        * get_sheen_albedo(normal_dot_view, material.sheen_roughness))
    .clamp(0.0, 1.0)
}
