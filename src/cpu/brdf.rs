//! Rust twins of `glsl/brdf.glsl`: the glTF 2.0 metallic-roughness BRDF (Appendix B, with
//! KHR_materials_specular and KHR_materials_ior) and its importance sampling (visible GGX
//! normals by spherical caps, a lobe chosen by its estimated weight). Same names, same
//! maths; directions are unit vectors, `view` and `light` point away from the surface.

use glam::{Mat3, Vec2, Vec3};

use crate::contract::MIN_GGX_ALPHA;
use crate::cpu::fresnel::{get_dielectric_schlick_fresnel, get_metal_schlick_fresnel};
use crate::cpu::shading_basis::get_shading_basis;
use crate::cpu::workshop::M_PI;

/// Twin of `material_t`: a surface point's material after texture lookups.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialSample {
    /// Base colour, linear RGB in [0, 1].
    pub base_color: Vec3,
    /// 0: dielectric, 1: metal.
    pub metallic: f32,
    /// Perceptual roughness in [0, 1] (GGX alpha = roughness^2, at least `MIN_GGX_ALPHA`;
    /// 0 exactly: a delta lobe).
    pub roughness: f32,
    /// KHR_materials_specular's specularFactor (0 with metallic 0: Lambertian).
    pub specular: f32,
    /// KHR_materials_specular's specularColorFactor, linear RGB.
    pub specular_color: Vec3,
    /// KHR_materials_ior's index of refraction (glTF's default 1.5).
    pub ior: f32,
    /// KHR_materials_transmission's transmission in [0, 1] (`crate::cpu::layered_bsdf`).
    pub transmission: f32,
    /// KHR_materials_volume's thickness: 0 thin-walled, above 0 a refracting volume.
    pub thickness: f32,
    /// The volume's absorption coefficient per unit length.
    pub attenuation: Vec3,
    /// KHR_materials_clearcoat's clearcoat in [0, 1].
    pub clearcoat: f32,
    /// The clear coat's perceptual roughness.
    pub clearcoat_roughness: f32,
    /// KHR_materials_sheen's colour, linear RGB.
    pub sheen_color: Vec3,
    /// The sheen's perceptual roughness.
    pub sheen_roughness: f32,
}

impl MaterialSample {
    /// glTF's default material with this base colour, metallic and roughness (specular 1,
    /// specular colour white, ior 1.5).
    pub fn gltf(base_color: Vec3, metallic: f32, roughness: f32) -> MaterialSample {
        get_base_material(base_color, metallic, roughness, 1.0, Vec3::ONE, 1.5)
    }
}

/// Twin of `get_base_material`: the one constructor of a `MaterialSample`, the
/// metallic-roughness factors with every layer off (0). A new field gets its "off" value here
/// and nowhere else.
pub fn get_base_material(
    base_color: Vec3,
    metallic: f32,
    roughness: f32,
    specular: f32,
    specular_color: Vec3,
    ior: f32,
) -> MaterialSample {
    MaterialSample {
        base_color,
        metallic,
        roughness,
        specular,
        specular_color,
        ior,
        transmission: 0.0,
        thickness: 0.0,
        attenuation: Vec3::ZERO,
        clearcoat: 0.0,
        clearcoat_roughness: 0.0,
        sheen_color: Vec3::ZERO,
        sheen_roughness: 0.0,
    }
}

/// Twin of `get_ggx_alpha`: max(roughness^2, `MIN_GGX_ALPHA`), and 0 for roughness 0
/// exactly: a delta (perfectly specular) lobe, which `get_ggx_distribution` gives no value.
pub fn get_ggx_alpha(roughness: f32) -> f32 {
    if roughness == 0.0 {
        0.0
    } else {
        (roughness * roughness).max(MIN_GGX_ALPHA)
    }
}

/// GLSL's `vector * matrix`: the vector in the basis's local coordinates.
pub(crate) fn to_local(basis: Mat3, vector: Vec3) -> Vec3 {
    basis.transpose() * vector
}

/// Twin of `get_ggx_distribution`: GGX's D(h) from the local half vector, 0 below and 0
/// for alpha 0 (a delta lobe).
pub fn get_ggx_distribution(alpha: f32, local_half: Vec3) -> f32 {
    if local_half.z <= 0.0 || alpha == 0.0 {
        return 0.0;
    }
    let stretched = (local_half.x * local_half.x + local_half.y * local_half.y) / (alpha * alpha)
        + local_half.z * local_half.z;
    1.0 / (M_PI * alpha * alpha * stretched * stretched)
}

/// Twin of `get_smith_visibility`: the height-correlated G_2 / (4 n.l n.v).
pub fn get_smith_visibility(alpha: f32, normal_dot_view: f32, normal_dot_light: f32) -> f32 {
    let alpha_squared = alpha * alpha;
    let view_term = normal_dot_light
        * (alpha_squared + (1.0 - alpha_squared) * normal_dot_view * normal_dot_view).sqrt();
    let light_term = normal_dot_view
        * (alpha_squared + (1.0 - alpha_squared) * normal_dot_light * normal_dot_light).sqrt();
    0.5 / (view_term + light_term)
}

/// Twin of `get_smith_masking`: GGX's G_1 for a direction of cosine `cos_theta` > 0.
pub fn get_smith_masking(alpha: f32, cos_theta: f32) -> f32 {
    let alpha_squared = alpha * alpha;
    2.0 * cos_theta
        / (cos_theta + (alpha_squared + (1.0 - alpha_squared) * cos_theta * cos_theta).sqrt())
}

/// Twin of `get_brdf`: the glTF BRDF without the cosine, 0 below either horizon.
pub fn get_brdf(material: &MaterialSample, normal: Vec3, view: Vec3, light: Vec3) -> Vec3 {
    let normal_dot_view = normal.dot(view);
    let normal_dot_light = normal.dot(light);
    if normal_dot_view <= 0.0 || normal_dot_light <= 0.0 {
        return Vec3::ZERO;
    }
    let basis = get_shading_basis(normal);
    let local_half = to_local(basis, view + light).normalize();
    let view_dot_half = view.dot(basis * local_half);
    let alpha = get_ggx_alpha(material.roughness);
    let specular = get_ggx_distribution(alpha, local_half)
        * get_smith_visibility(alpha, normal_dot_view, normal_dot_light);
    let dielectric_fresnel = get_dielectric_schlick_fresnel(material, view_dot_half);
    let dielectric =
        (1.0 - dielectric_fresnel) * material.base_color / M_PI + dielectric_fresnel * specular;
    let metal = get_metal_schlick_fresnel(material, view_dot_half) * specular;
    dielectric.lerp(metal, material.metallic)
}

/// Twin of `get_luminance`: Rec. 709 relative luminance of linear RGB.
pub fn get_luminance(color: Vec3) -> f32 {
    color.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Twin of `get_specular_probability`: the chance that `sample_brdf` takes the GGX lobe.
pub fn get_specular_probability(material: &MaterialSample, normal_dot_view: f32) -> f32 {
    let dielectric_fresnel = get_dielectric_schlick_fresnel(material, normal_dot_view);
    let metal_fresnel = get_metal_schlick_fresnel(material, normal_dot_view);
    let specular = get_luminance(dielectric_fresnel.lerp(metal_fresnel, material.metallic));
    let diffuse =
        (1.0 - material.metallic) * get_luminance((1.0 - dielectric_fresnel) * material.base_color);
    if specular + diffuse > 0.0 {
        specular / (specular + diffuse)
    } else {
        0.5
    }
}

/// Twin of `get_mirror_reflectance`: what the delta specular lobe's peak carries,
/// mix(F_d, F_m, metallic) at v.h = n.v.
pub fn get_mirror_reflectance(material: &MaterialSample, normal_dot_view: f32) -> Vec3 {
    let dielectric_fresnel = get_dielectric_schlick_fresnel(material, normal_dot_view);
    let metal_fresnel = get_metal_schlick_fresnel(material, normal_dot_view);
    dielectric_fresnel.lerp(metal_fresnel, material.metallic)
}

/// Twin of `get_brdf_mirror_probability`: the chance that `sample_brdf` returns the mirror
/// direction of a delta specular lobe (roughness 0), 0 for roughness above 0.
pub fn get_brdf_mirror_probability(material: &MaterialSample, normal: Vec3, view: Vec3) -> f32 {
    if get_ggx_alpha(material.roughness) != 0.0 {
        return 0.0;
    }
    let local_view = to_local(get_shading_basis(normal), view);
    get_specular_probability(material, local_view.z)
}

/// Twin of `get_brdf_mirror_weight`: f / p of `sample_brdf`'s mirror pick alone.
pub fn get_brdf_mirror_weight(material: &MaterialSample, normal: Vec3, view: Vec3) -> Vec3 {
    let local_view = to_local(get_shading_basis(normal), view);
    get_mirror_reflectance(material, local_view.z)
        / get_specular_probability(material, local_view.z)
}

/// Twin of `sample_ggx_visible_normal`: Dupuy and Benyoub's (2023) spherical caps.
pub fn sample_ggx_visible_normal(random_numbers: Vec2, alpha: f32, local_view: Vec3) -> Vec3 {
    let stretched_view =
        Vec3::new(alpha * local_view.x, alpha * local_view.y, local_view.z).normalize();
    let phi = 2.0 * M_PI * random_numbers[0];
    let z = (1.0 - random_numbers[1]) * (1.0 + stretched_view.z) - stretched_view.z;
    let sin_theta = (1.0 - z * z).clamp(0.0, 1.0).sqrt();
    let cap_point = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), z);
    let stretched_half = cap_point + stretched_view;
    Vec3::new(
        alpha * stretched_half.x,
        alpha * stretched_half.y,
        stretched_half.z,
    )
    .normalize()
}

/// Twin of `get_ggx_reflection_density`: G_1(v) D(h) / (4 n.v) w.r.t. solid angle.
pub fn get_ggx_reflection_density(alpha: f32, local_view: Vec3, local_half: Vec3) -> f32 {
    let alpha_squared = alpha * alpha;
    let root = (alpha_squared + (1.0 - alpha_squared) * local_view.z * local_view.z).sqrt();
    get_ggx_distribution(alpha, local_half) / (2.0 * (local_view.z + root))
}

/// GLSL's `reflect(incident, normal)`: incident - 2 (normal.incident) normal.
pub(crate) fn reflect(incident: Vec3, normal: Vec3) -> Vec3 {
    incident - 2.0 * normal.dot(incident) * normal
}

/// Twin of `sample_brdf`: a light direction with density `get_brdf_density`.
pub fn sample_brdf(
    random_numbers: Vec2,
    material: &MaterialSample,
    normal: Vec3,
    view: Vec3,
) -> Vec3 {
    let basis = get_shading_basis(normal);
    let local_view = to_local(basis, view);
    let specular_probability = get_specular_probability(material, local_view.z);
    if random_numbers[0] < specular_probability {
        let lobe_randoms = Vec2::new(random_numbers[0] / specular_probability, random_numbers[1]);
        let local_half =
            sample_ggx_visible_normal(lobe_randoms, get_ggx_alpha(material.roughness), local_view);
        return (basis * reflect(-local_view, local_half)).normalize();
    }
    let u = (random_numbers[0] - specular_probability) / (1.0 - specular_probability);
    sample_diffuse_lobe(u, random_numbers[1], basis)
}

/// Twin of `sample_diffuse_lobe`: Malley's method, a uniform point on the unit disk
/// projected up to the hemisphere around the basis's third axis.
pub fn sample_diffuse_lobe(u: f32, phi_random: f32, basis: Mat3) -> Vec3 {
    let radius = u.sqrt();
    let phi = 2.0 * M_PI * phi_random;
    basis
        * Vec3::new(
            radius * phi.cos(),
            radius * phi.sin(),
            (1.0 - u).max(0.0).sqrt(),
        )
}

/// Twin of `get_lambert_brdf`: `get_brdf` of a Lambertian material (metallic and specular 0),
/// base colour / pi, 0 where the view or the light is below the normal.
pub fn get_lambert_brdf(material: &MaterialSample, normal: Vec3, view: Vec3, light: Vec3) -> Vec3 {
    if normal.dot(view) <= 0.0 || normal.dot(light) <= 0.0 {
        return Vec3::ZERO;
    }
    material.base_color / M_PI
}

/// Twin of `sample_lambert_brdf`: `sample_brdf` of a Lambertian material, the diffuse lobe
/// alone.
pub fn sample_lambert_brdf(random_numbers: Vec2, normal: Vec3) -> Vec3 {
    sample_diffuse_lobe(
        random_numbers[0],
        random_numbers[1],
        get_shading_basis(normal),
    )
}

/// Twin of `get_lambert_brdf_density`: max(0, n.l) / pi, 0 when the view is below.
pub fn get_lambert_brdf_density(normal: Vec3, view: Vec3, light: Vec3) -> f32 {
    if normal.dot(view) <= 0.0 {
        return 0.0;
    }
    normal.dot(light).max(0.0) / M_PI
}

/// Twin of `get_brdf_density`: the mixture density of `sample_brdf` w.r.t. solid angle.
pub fn get_brdf_density(material: &MaterialSample, normal: Vec3, view: Vec3, light: Vec3) -> f32 {
    let normal_dot_view = normal.dot(view);
    if normal_dot_view <= 0.0 {
        return 0.0;
    }
    let basis = get_shading_basis(normal);
    let local_view = to_local(basis, view);
    let specular_probability = get_specular_probability(material, normal_dot_view);
    let half_sum = view + light;
    let specular = if half_sum.dot(half_sum) > 0.0 {
        get_ggx_reflection_density(
            get_ggx_alpha(material.roughness),
            local_view,
            to_local(basis, half_sum).normalize(),
        )
    } else {
        0.0
    };
    let diffuse = normal.dot(light).max(0.0) / M_PI;
    specular_probability * specular + (1.0 - specular_probability) * diffuse
}

#[cfg(test)]
#[path = "brdf_tests.rs"]
mod tests;
