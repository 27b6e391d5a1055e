//! Rust twins of the surface seam's Lambert model (`glsl/lambert_surface.glsl`, behind the
//! interface of `glsl/surface.glsl`; the workshop's diffuse triangles): the surface seam that
//! the path loop and the light estimators see a hit through. The glTF model's maths are
//! twinned in `crate::cpu::brdf` and `crate::cpu::materials`.

use glam::{Vec2, Vec3};

use crate::cpu::importance_sampling::{get_hemisphere_cosine_density, sample_hemisphere_cosine};
use crate::cpu::integrator::{is_double_sided, offset_ray_origin, orient_towards_ray};
use crate::cpu::workshop::{sample_hemisphere, M_PI};
use crate::scene::Triangle;

/// `BSDF_LOBE_REFLECT`: the direction leaves on the view's side.
pub const BSDF_LOBE_REFLECT: u32 = 1;
/// `BSDF_LOBE_TRANSMIT`: the direction crosses the surface.
pub const BSDF_LOBE_TRANSMIT: u32 = 2;
/// `BSDF_LOBE_DELTA`: a Dirac peak, no density to weigh by MIS.
pub const BSDF_LOBE_DELTA: u32 = 4;

/// Twin of `surface_t` (Lambert): a hit point as the integrators shade it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// Unit geometric normal, on the side the ray came from.
    pub geometric_normal: Vec3,
    /// Unit shading normal (Lambert: the geometric normal).
    pub shading_normal: Vec3,
    /// The albedo (`material.base_color`).
    pub base_color: Vec3,
    /// Emitted radiance towards the ray's origin (0 from the back of one-sided emitters).
    pub emission: Vec3,
}

/// Twin of `bsdf_sample_t`: a direction sampled at a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Unit direction away from the surface.
    pub direction: Vec3,
    /// Density w.r.t. solid angle.
    pub density: f32,
    /// `get_bsdf` / density; zero ends the path.
    pub weight: Vec3,
    /// `BSDF_LOBE_*` of the lobe sampled.
    pub lobes: u32,
    /// The relative index of refraction the direction crossed (1: reflections, thin walls).
    pub eta: f32,
}

/// Twin of `has_layers` (Lambert: never).
pub fn has_layers(_surface: &Surface) -> bool {
    false
}

/// Twin of `is_transmissive` (Lambert: never).
pub fn is_transmissive(_surface: &Surface) -> bool {
    false
}

/// Twin of `has_delta_lobe` (Lambert: never).
pub fn has_delta_lobe(_surface: &Surface) -> bool {
    false
}

/// Twin of `has_only_delta_lobes` (Lambert: never).
pub fn has_only_delta_lobes(_surface: &Surface) -> bool {
    false
}

/// Twin of `get_camera_emission` (Lambert: the emission).
pub fn get_camera_emission(surface: &Surface) -> Vec3 {
    surface.emission
}

/// Twin of `get_volume_transmittance` (Lambert: no volumes).
pub fn get_volume_transmittance(_surface: &Surface, _distance: f32) -> Vec3 {
    Vec3::ONE
}

/// Twin of `get_surface` (Lambert): the hit triangle, its normal facing the ray.
pub fn get_surface(
    scene_triangles: &[Triangle],
    triangle_index: usize,
    ray_direction: Vec3,
) -> Surface {
    let mut triangle = scene_triangles[triangle_index];
    orient_towards_ray(
        &mut triangle,
        ray_direction,
        is_double_sided(scene_triangles, triangle_index),
    );
    Surface {
        geometric_normal: triangle.normal,
        shading_normal: triangle.normal,
        base_color: triangle.color,
        emission: triangle.emission,
    }
}

/// Twin of `get_front_emission` (Lambert): the triangle's emission.
pub fn get_front_emission(triangle: &Triangle) -> Vec3 {
    triangle.emission
}

/// Twin of `get_bsdf` (Lambert): a / pi max(0, n . l), 0 below the geometric surface.
pub fn get_bsdf(surface: &Surface, _view: Vec3, light: Vec3) -> Vec3 {
    if surface.geometric_normal.dot(light) <= 0.0 {
        return Vec3::ZERO;
    }
    surface.base_color / M_PI * surface.shading_normal.dot(light).max(0.0)
}

/// Twin of `get_reflected_radiance` (Lambert): a / pi L (n . l), in the workshop's order.
pub fn get_reflected_radiance(surface: &Surface, light: Vec3, _bsdf: Vec3, radiance: Vec3) -> Vec3 {
    surface.base_color / M_PI * radiance * surface.shading_normal.dot(light)
}

/// Twin of `get_bsdf_density` (Lambert): the cosine density around the geometric normal.
pub fn get_bsdf_density(surface: &Surface, _view: Vec3, light: Vec3) -> f32 {
    get_hemisphere_cosine_density(surface.geometric_normal, light)
}

/// Twin of `sample_bsdf` (Lambert): cosine sampling, weight exactly the albedo.
pub fn sample_bsdf(
    surface: &Surface,
    _view: Vec3,
    random_numbers: Vec2,
    _lobe_random: f32,
) -> BsdfSample {
    let direction = sample_hemisphere_cosine(random_numbers, surface.geometric_normal);
    let density = get_hemisphere_cosine_density(surface.geometric_normal, direction);
    BsdfSample {
        direction,
        density,
        weight: if density > 0.0 {
            surface.base_color
        } else {
            Vec3::ZERO
        },
        lobes: BSDF_LOBE_REFLECT,
        eta: 1.0,
    }
}

/// Twin of `sample_cosine_direction` (Lambert: `sample_bsdf` itself).
pub fn sample_cosine_direction(surface: &Surface, view: Vec3, random_numbers: Vec2) -> BsdfSample {
    sample_bsdf(surface, view, random_numbers, 0.0)
}

/// Twin of `sample_uniform_direction`: the workshop's uniform hemisphere, weight
/// `get_bsdf` 2 pi.
pub fn sample_uniform_direction(surface: &Surface, view: Vec3, random_numbers: Vec2) -> BsdfSample {
    let direction = sample_hemisphere(random_numbers, surface.geometric_normal);
    BsdfSample {
        direction,
        density: 0.5 / M_PI,
        weight: get_bsdf(surface, view, direction) * 2.0 * M_PI,
        lobes: BSDF_LOBE_REFLECT,
        eta: 1.0,
    }
}

/// Twin of `get_light_sample_origin`: just off the surface on the geometric normal's side.
pub fn get_light_sample_origin(surface: &Surface, position: Vec3) -> Vec3 {
    offset_ray_origin(position, surface.geometric_normal)
}

/// Twin of `get_departure_origin`: just off the surface on the side the sampled lobe leaves
/// to.
pub fn get_departure_origin(surface: &Surface, position: Vec3, lobes: u32) -> Vec3 {
    let side = if lobes & BSDF_LOBE_TRANSMIT != 0 {
        -surface.geometric_normal
    } else {
        surface.geometric_normal
    };
    offset_ray_origin(position, side)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lobe flags are glsl/surface.glsl's, digit for digit.
    #[test]
    fn lobe_flags_are_the_shaders() {
        let text = crate::shaders::GLSL_SOURCES
            .iter()
            .find(|(file, _)| *file == "surface.glsl")
            .map(|(_, text)| *text)
            .expect("surface.glsl is embedded");
        for (name, value) in [
            ("BSDF_LOBE_REFLECT", BSDF_LOBE_REFLECT),
            ("BSDF_LOBE_TRANSMIT", BSDF_LOBE_TRANSMIT),
            ("BSDF_LOBE_DELTA", BSDF_LOBE_DELTA),
        ] {
            assert!(
                text.contains(&format!("#define {name} {value}u")),
                "{name} = {value}"
            );
        }
    }

    fn lambert() -> Surface {
        Surface {
            geometric_normal: Vec3::new(0.0, 0.6, 0.8),
            shading_normal: Vec3::new(0.0, 0.6, 0.8),
            base_color: Vec3::new(0.25, 0.5, 0.75),
            emission: Vec3::ZERO,
        }
    }

    /// The seam's promise: a sample's weight is get_bsdf / density, and the density is
    /// get_bsdf_density at the sampled direction. (The sampler itself, Lambert's cosine
    /// sampling, passes chi^2 in `crate::cpu::importance_sampling`.)
    #[test]
    fn sample_weight_is_bsdf_over_density() {
        let surface = lambert();
        let view = Vec3::new(0.0, 0.0, 1.0);
        for i in 0..64 {
            let u = Vec2::new((i as f32 + 0.5) / 64.0, ((i * 37) % 64) as f32 / 64.0);
            let sample = sample_bsdf(&surface, view, u, 0.0);
            assert_eq!(
                sample.density,
                get_bsdf_density(&surface, view, sample.direction)
            );
            if sample.density > 0.0 {
                let expected = get_bsdf(&surface, view, sample.direction) / sample.density;
                // a (n.l)/pi / ((n.l)/pi) = a up to the rounding of two products and a
                // quotient: a few ulps of float.
                assert!(
                    (expected - sample.weight).abs().max_element() < 1e-5,
                    "{expected} vs {}",
                    sample.weight
                );
            }
        }
    }

    #[test]
    fn light_never_crosses_the_geometric_surface() {
        let surface = lambert();
        assert_eq!(
            get_bsdf(&surface, Vec3::Z, -surface.geometric_normal),
            Vec3::ZERO
        );
        let transmitted = get_departure_origin(&surface, Vec3::ZERO, BSDF_LOBE_TRANSMIT);
        assert!(transmitted.dot(surface.geometric_normal) < 0.0);
        let reflected = get_departure_origin(&surface, Vec3::ZERO, BSDF_LOBE_REFLECT);
        assert!(reflected.dot(surface.geometric_normal) > 0.0);
    }
}
