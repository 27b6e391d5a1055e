//! Rust twin of `glsl/scattering_vertex.glsl` over the Lambert surface
//! (`crate::cpu::surface`): the point where a path scatters, as the light estimator
//! (`crate::cpu::lights`), MIS, path guiding (`crate::cpu::path_guiding`) and the path loop
//! (`crate::cpu::path_loop`) see it: a surface point (`SCATTERING_VERTEX_SURFACE`) or a
//! point in a medium (`SCATTERING_VERTEX_MEDIUM`), whose scattering is the phase function
//! (`crate::cpu::phase_function`). Same names, same maths as the GLSL (where
//! `SCENE_HAS_MEDIUM` is true: the GPU folds the medium's branches away without one).

use glam::Vec3;

use crate::cpu::phase_function::{get_phase_function, get_phase_function_density};
use crate::cpu::surface::{
    get_bsdf, get_bsdf_density, get_departure_origin, get_light_sample_origin,
    get_reflected_radiance, has_only_delta_lobes, Surface,
};

/// `SCATTERING_VERTEX_SURFACE`: the vertex is a surface point.
pub const SCATTERING_VERTEX_SURFACE: u32 = 0;
/// `SCATTERING_VERTEX_MEDIUM`: the vertex is a point in a medium.
pub const SCATTERING_VERTEX_MEDIUM: u32 = 1;

/// Twin of `scattering_vertex_t`: a point where a path scatters, with what the light
/// estimator needs of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScatteringVertex {
    /// `SCATTERING_VERTEX_*`: what scatters here.
    pub kind: u32,
    /// The point, world space (on the surface).
    pub position: Vec3,
    /// Unit direction towards where the path came from (minus the ray's direction), world
    /// space.
    pub view: Vec3,
    /// Where shadow rays from this vertex start, world space (`get_light_sample_origin`).
    pub light_sample_origin: Vec3,
    /// The normal with which the light tree bounds what the vertex receives, unit or 0 (no
    /// bound): `get_light_selection_normal`.
    pub light_selection_normal: Vec3,
    /// The phase function's g, in (-1, 1) (kind `SCATTERING_VERTEX_MEDIUM`; 0 at a surface).
    pub anisotropy: f32,
    /// The surface hit (kind `SCATTERING_VERTEX_SURFACE`; all zero in a medium, where the
    /// GLSL leaves it undefined).
    pub surface: Surface,
}

/// Twin of `get_light_selection_normal` (Lambert: the geometric normal on the ray's side).
pub fn get_light_selection_normal(surface: &Surface) -> Vec3 {
    surface.geometric_normal
}

/// Twin of `get_surface_vertex`: the vertex of a surface hit at `position`, seen along
/// `view` (unit, towards the ray's origin).
pub fn get_surface_vertex(surface: Surface, position: Vec3, view: Vec3) -> ScatteringVertex {
    ScatteringVertex {
        kind: SCATTERING_VERTEX_SURFACE,
        position,
        view,
        light_sample_origin: get_light_sample_origin(&surface, position),
        light_selection_normal: get_light_selection_normal(&surface),
        anisotropy: 0.0,
        surface,
    }
}

/// Twin of `get_medium_vertex`: a scattering event at `position` in a medium of phase
/// function g = `anisotropy`, seen along `view`: shadow rays start at the point, no bound.
pub fn get_medium_vertex(position: Vec3, view: Vec3, anisotropy: f32) -> ScatteringVertex {
    ScatteringVertex {
        kind: SCATTERING_VERTEX_MEDIUM,
        position,
        view,
        light_sample_origin: position,
        light_selection_normal: Vec3::ZERO,
        anisotropy,
        surface: Surface {
            geometric_normal: Vec3::ZERO,
            shading_normal: Vec3::ZERO,
            base_color: Vec3::ZERO,
            emission: Vec3::ZERO,
        },
    }
}

/// Twin of `is_medium_vertex`: whether the vertex lies in a medium.
pub fn is_medium_vertex(vertex: &ScatteringVertex) -> bool {
    vertex.kind == SCATTERING_VERTEX_MEDIUM
}

/// Twin of `get_vertex_scattering`: the BSDF f for light from `direction` towards the view.
pub fn get_vertex_scattering(vertex: &ScatteringVertex, direction: Vec3) -> Vec3 {
    if is_medium_vertex(vertex) {
        return Vec3::splat(get_phase_function(
            vertex.view,
            direction,
            vertex.anisotropy,
        ));
    }
    get_bsdf(&vertex.surface, vertex.view, direction)
}

/// Twin of `get_vertex_scattering_density`: the density w.r.t. solid angle with which the
/// vertex's own sampler finds `direction`.
pub fn get_vertex_scattering_density(vertex: &ScatteringVertex, direction: Vec3) -> f32 {
    if is_medium_vertex(vertex) {
        return get_phase_function_density(vertex.view, direction, vertex.anisotropy);
    }
    get_bsdf_density(&vertex.surface, vertex.view, direction)
}

/// Twin of `get_vertex_scattered_radiance`: f (n_s . l) L for a surface, given
/// `scattering` = `get_vertex_scattering(vertex, direction)`.
pub fn get_vertex_scattered_radiance(
    vertex: &ScatteringVertex,
    direction: Vec3,
    scattering: Vec3,
    radiance: Vec3,
) -> Vec3 {
    if is_medium_vertex(vertex) {
        return scattering * radiance;
    }
    get_reflected_radiance(&vertex.surface, direction, scattering, radiance)
}

/// Twin of `has_only_delta_scattering`: whether the vertex scatters only into Dirac peaks.
pub fn has_only_delta_scattering(vertex: &ScatteringVertex) -> bool {
    if is_medium_vertex(vertex) {
        return false;
    }
    has_only_delta_lobes(&vertex.surface)
}

/// Twin of `get_vertex_departure_origin`: where a path continues from after sampling a
/// direction with `lobes` (`BSDF_LOBE_*`).
pub fn get_vertex_departure_origin(vertex: &ScatteringVertex, lobes: u32) -> Vec3 {
    if is_medium_vertex(vertex) {
        return vertex.position;
    }
    get_departure_origin(&vertex.surface, vertex.position, lobes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::surface::BSDF_LOBE_TRANSMIT;
    use crate::shaders::GLSL_SOURCES;

    fn glsl(file: &str) -> &'static str {
        GLSL_SOURCES
            .iter()
            .find(|(name, _)| *name == file)
            .map(|(_, text)| *text)
            .unwrap_or_else(|| panic!("glsl/{file} is not among the shaders"))
    }

    /// The field names of the struct that `open` (e.g. `struct x {`) starts in `text`.
    fn fields(text: &str, open: &str, field: fn(&str) -> Option<String>) -> Vec<String> {
        let start = text.find(open).unwrap_or_else(|| panic!("no `{open}`"));
        text[start + open.len()..]
            .lines()
            .map(str::trim)
            .take_while(|line| !line.starts_with('}'))
            .filter(|line| !line.starts_with("//"))
            .filter_map(field)
            .collect()
    }

    #[test]
    fn the_twin_has_the_glsl_vertex_fields_in_order() {
        // `vec3 position;` in GLSL, `pub position: Vec3,` in Rust.
        let glsl_fields = fields(
            glsl("scattering_vertex.glsl"),
            "struct scattering_vertex_t {",
            |line| {
                let declaration = line.strip_suffix(';')?;
                Some(declaration.split_whitespace().last()?.to_string())
            },
        );
        let rust_fields = fields(
            include_str!("scattering_vertex.rs"),
            "pub struct ScatteringVertex {",
            |line| Some(line.strip_prefix("pub ")?.split(':').next()?.to_string()),
        );
        assert_eq!(glsl_fields, rust_fields);
        assert!(glsl_fields.contains(&"kind".to_string()));
    }

    /// The estimators, MIS, guiding and the path loop take the vertex: each function's GLSL
    /// definition has a `scattering_vertex_t` parameter and no `surface_t` one.
    #[test]
    fn the_estimators_take_the_vertex_not_the_surface() {
        let functions = [
            ("lights.glsl", "vec3 sample_direct_light("),
            ("lights.glsl", "vec3 estimate_light_sample("),
            ("path_guiding.glsl", "float get_path_direction_density("),
            ("path_guiding.glsl", "bsdf_sample_t get_guided_direction("),
            ("path_guiding.glsl", "uint get_path_guide_grid_cell("),
            ("path_guiding.glsl", "uint get_path_guide_cell("),
            ("path_guiding.glsl", "void record_guide_vertex("),
            ("path_loop.glsl", "bsdf_sample_t sample_path_direction("),
            (
                "path_loop.glsl",
                "bsdf_sample_t sample_guided_path_direction(",
            ),
        ];
        for (file, head) in functions {
            let text = glsl(file);
            let start = text
                .find(head)
                .unwrap_or_else(|| panic!("glsl/{file} defines no `{head}`"));
            let parameters = &text[start..start + text[start..].find(')').unwrap_or(0)];
            assert!(
                parameters.contains("scattering_vertex_t vertex")
                    && !parameters.contains("surface_t"),
                "glsl/{file}: {parameters})"
            );
        }
        // The path loop makes each hit a vertex.
        assert!(glsl("path_loop.glsl")
            .contains("= get_surface_vertex(surface, ray_origin, -ray_direction);"));
    }

    /// Shadow rays return a transmittance that the estimator multiplies in.
    #[test]
    fn shadow_rays_return_a_transmittance() {
        let lights = glsl("lights.glsl");
        assert!(lights.contains(
            "vec3 get_shadow_transmittance(vec3 origin, vec3 direction, float distance) {"
        ));
        assert!(lights.contains("return contribution * transmittance;"));
        assert!(!lights.contains("bool is_visible("));
    }

    /// A medium vertex scatters by the phase function: value = density, no cosine, never
    /// delta, shadow rays and departures from the point itself, no light tree bound.
    #[test]
    fn a_medium_vertex_scatters_by_its_phase_function() {
        let position = Vec3::new(1.0, 2.0, 3.0);
        let view = Vec3::new(0.0, 0.6, 0.8);
        let vertex = get_medium_vertex(position, view, 0.6);
        assert_eq!(vertex.kind, SCATTERING_VERTEX_MEDIUM);
        assert_eq!(vertex.light_sample_origin, position);
        assert_eq!(vertex.light_selection_normal, Vec3::ZERO);
        assert_eq!(get_vertex_departure_origin(&vertex, 0), position);
        assert!(!has_only_delta_scattering(&vertex));
        // Forwards (the ray's own direction, -view) and backwards
        for direction in [-view, view, Vec3::X] {
            let p = get_phase_function(view, direction, 0.6);
            assert_eq!(get_vertex_scattering(&vertex, direction), Vec3::splat(p));
            assert_eq!(get_vertex_scattering_density(&vertex, direction), p);
            let radiance = Vec3::new(1.0, 2.0, 4.0);
            assert_eq!(
                get_vertex_scattered_radiance(&vertex, direction, Vec3::splat(p), radiance),
                p * radiance
            );
        }
        assert!(get_vertex_scattering(&vertex, -view).x > get_vertex_scattering(&vertex, view).x);
    }

    #[test]
    fn a_surface_vertex_holds_what_the_estimators_read() {
        let surface = Surface {
            geometric_normal: Vec3::Y,
            shading_normal: Vec3::Y,
            base_color: Vec3::splat(0.5),
            emission: Vec3::ZERO,
        };
        let position = Vec3::new(1.0, 2.0, 3.0);
        let view = Vec3::new(0.0, 0.6, 0.8);
        let vertex = get_surface_vertex(surface, position, view);
        assert_eq!(vertex.kind, SCATTERING_VERTEX_SURFACE);
        assert_eq!(
            vertex.light_sample_origin,
            get_light_sample_origin(&surface, position)
        );
        // Shadow rays start just off the surface, on the light's side.
        assert!(vertex.light_sample_origin.y > position.y);
        assert_eq!(vertex.light_selection_normal, Vec3::Y);
        let light = Vec3::new(0.6, 0.8, 0.0);
        assert_eq!(
            get_vertex_scattering(&vertex, light),
            get_bsdf(&surface, view, light)
        );
        assert_eq!(
            get_vertex_scattering_density(&vertex, light),
            get_bsdf_density(&surface, view, light)
        );
        assert!(get_vertex_departure_origin(&vertex, BSDF_LOBE_TRANSMIT).y < position.y);
    }
}
