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

use glam::{Vec2, Vec3};

use crate::contract::{CLEARCOAT_IOR, SHEEN_ALBEDO_SIZE, SHEEN_MIN_ALPHA};
use crate::cpu::brdf::{
    get_brdf_density, get_dielectric_f0, get_ggx_alpha, get_ggx_distribution,
    get_ggx_reflection_density, get_luminance, get_schlick_fresnel, get_smith_visibility, reflect,
    sample_brdf, sample_ggx_visible_normal, to_local, MaterialSample,
};
use crate::cpu::importance_sampling::sample_hemisphere_cosine;
use crate::cpu::shading_basis::get_shading_basis;
use crate::cpu::sheen_albedo_table::SHEEN_ALBEDO;
use crate::cpu::workshop::M_PI;

/// Twin of `get_dielectric_fresnel`: the exact unpolarised Fresnel reflectance of a smooth
/// dielectric interface (1 under total internal reflection).
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

/// Twin of `get_smith_masking`: GGX's G_1 for a direction of cosine `cos_theta` > 0.
pub fn get_smith_masking(alpha: f32, cos_theta: f32) -> f32 {
    let alpha_squared = alpha * alpha;
    2.0 * cos_theta
        / (cos_theta + (alpha_squared + (1.0 - alpha_squared) * cos_theta * cos_theta).sqrt())
}

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

/// Twin of `mirror_through_surface`.
pub fn mirror_through_surface(local_direction: Vec3) -> Vec3 {
    Vec3::new(local_direction.x, local_direction.y, -local_direction.z)
}

/// Twin of `get_thin_wall_fresnel`: Schlick's F of the material's dielectric at v.h.
pub fn get_thin_wall_fresnel(material: &MaterialSample, view_dot_half: f32) -> Vec3 {
    get_schlick_fresnel(
        get_dielectric_f0(material),
        Vec3::splat(material.specular),
        view_dot_half,
    )
}

/// Twin of `get_thin_wall_reflection_probability`.
pub fn get_thin_wall_reflection_probability(material: &MaterialSample, view_dot_half: f32) -> f32 {
    let fresnel = get_thin_wall_fresnel(material, view_dot_half);
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
    let fresnel = get_thin_wall_fresnel(material, local_view.dot(local_half));
    (1.0 - fresnel)
        * material.base_color
        * get_ggx_distribution(alpha, local_half)
        * get_smith_visibility(alpha, local_view.z, mirrored.z)
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

/// Twin of `is_layered`: transmission, a clear coat or sheen.
pub fn is_layered(material: &MaterialSample) -> bool {
    material.transmission > 0.0 || material.clearcoat > 0.0 || has_sheen(material)
}

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
        let dielectric_fresnel = get_schlick_fresnel(
            get_dielectric_f0(material),
            Vec3::splat(material.specular),
            view_dot_half,
        );
        let diffuse = (1.0 - dielectric_fresnel) * material.base_color / M_PI;
        let dielectric = if is_refracting(material) {
            (1.0 - material.transmission) * (diffuse + dielectric_fresnel * specular)
                + material.transmission * get_dielectric_fresnel(view_dot_half, eta) * specular
        } else {
            dielectric_fresnel * specular + (1.0 - material.transmission) * diffuse
        };
        let metal = get_schlick_fresnel(material.base_color, Vec3::ONE, view_dot_half) * specular;
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

/// Twin of `sample_transmissive_bsdf`.
pub fn sample_transmissive_bsdf(
    random_numbers: Vec2,
    lobe_random: f32,
    material: &MaterialSample,
    eta: f32,
    shading_normal: Vec3,
    view: Vec3,
) -> Vec3 {
    let transmission_probability = get_transmission_probability(material);
    if lobe_random < transmission_probability {
        let reflection_random = lobe_random / transmission_probability;
        let basis = get_shading_basis(shading_normal);
        let local_view = to_local(basis, view);
        let alpha = get_ggx_alpha(material.roughness);
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
        return (basis * local_light).normalize();
    }
    sample_brdf(random_numbers, material, shading_normal, view)
}

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

/// Twin of `sample_layered_bsdf`.
pub fn sample_layered_bsdf(
    random_numbers: Vec2,
    lobe_random: f32,
    material: &MaterialSample,
    eta: f32,
    shading_normal: Vec3,
    clearcoat_normal: Vec3,
    view: Vec3,
) -> Vec3 {
    let mut lobe_random = lobe_random;
    if material.clearcoat > 0.0 {
        let coat_weight = get_clearcoat_weight(material, clearcoat_normal.dot(view));
        if lobe_random < coat_weight {
            return sample_clearcoat(random_numbers, material, clearcoat_normal, view);
        }
        lobe_random = (lobe_random - coat_weight) / (1.0 - coat_weight);
    }
    if has_sheen(material) {
        let sheen_weight = get_sheen_weight(material, shading_normal.dot(view));
        if lobe_random < sheen_weight {
            return sample_hemisphere_cosine(random_numbers, shading_normal);
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
