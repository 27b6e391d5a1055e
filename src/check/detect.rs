//! Which workshop functions a user's GLSL file defines, and whether each definition has the
//! workshop's signature. A definition is a function name at global scope followed by its
//! parameter list and `{`; the workshop's prototypes (`glsl/workshop.glsl`) give the
//! expected return and parameter types, so that nothing is written twice.

pub use crate::glsl_intake::functions::{find_functions, FoundFunction, Signature};
use crate::shaders::GLSL_SOURCES;

/// The workshop functions that a user may replace (each has a prototype in
/// `glsl/workshop.glsl` and a `USER_DEFINES_<NAME>` guard around its reference definition).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub enum WorkshopFunction {
    /// `vec2 get_random_numbers(inout uvec2 seed)`
    GetRandomNumbers,
    /// `vec3 sample_sphere(vec2 random_numbers)`
    SampleSphere,
    /// `vec3 sample_hemisphere(vec2 random_numbers, vec3 normal)`
    SampleHemisphere,
    /// `bool ray_triangle_intersection(out float out_t, vec3 ray_origin, vec3 ray_direction,
    /// triangle_t triangle)`
    RayTriangleIntersection,
    /// `bool ray_mesh_intersection(out float out_t, out triangle_t out_triangle,
    /// vec3 ray_origin, vec3 ray_direction)`
    RayMeshIntersection,
    /// `vec3 get_primary_ray_direction(float x, float y, vec3 camera_position,
    /// vec3 left_bottom, vec3 right, vec3 up)`
    GetPrimaryRayDirection,
    /// `vec3 compute_direct_illumination(vec3 shading_position, triangle_t triangle,
    /// inout uvec2 seed)`
    ComputeDirectIllumination,
    /// `vec3 get_ray_radiance(vec3 ray_origin, vec3 ray_direction, inout uvec2 seed)`
    GetRayRadiance,
}

impl WorkshopFunction {
    /// Every replaceable function, in the workshop's order.
    pub const ALL: [WorkshopFunction; 8] = [
        WorkshopFunction::GetRandomNumbers,
        WorkshopFunction::SampleSphere,
        WorkshopFunction::SampleHemisphere,
        WorkshopFunction::RayTriangleIntersection,
        WorkshopFunction::RayMeshIntersection,
        WorkshopFunction::GetPrimaryRayDirection,
        WorkshopFunction::ComputeDirectIllumination,
        WorkshopFunction::GetRayRadiance,
    ];

    /// The GLSL name.
    pub fn name(self) -> &'static str {
        match self {
            WorkshopFunction::GetRandomNumbers => "get_random_numbers",
            WorkshopFunction::SampleSphere => "sample_sphere",
            WorkshopFunction::SampleHemisphere => "sample_hemisphere",
            WorkshopFunction::RayTriangleIntersection => "ray_triangle_intersection",
            WorkshopFunction::RayMeshIntersection => "ray_mesh_intersection",
            WorkshopFunction::GetPrimaryRayDirection => "get_primary_ray_direction",
            WorkshopFunction::ComputeDirectIllumination => "compute_direct_illumination",
            WorkshopFunction::GetRayRadiance => "get_ray_radiance",
        }
    }

    /// The function with GLSL name `name`.
    pub fn from_name(name: &str) -> Option<WorkshopFunction> {
        WorkshopFunction::ALL.into_iter().find(|f| f.name() == name)
    }

    /// The macro that skips the reference definition: `USER_DEFINES_<NAME>`.
    pub fn user_defines_macro(self) -> String {
        format!("USER_DEFINES_{}", self.name().to_uppercase())
    }

    /// The workshop's signature, read from the prototype in `glsl/workshop.glsl`.
    pub fn signature(self) -> Option<Signature> {
        let workshop = GLSL_SOURCES
            .iter()
            .find(|(name, _)| *name == "workshop.glsl")
            .map(|(_, text)| *text)?;
        find_functions(workshop)
            .into_iter()
            .find(|found| found.name == self.name() && !found.has_body)
            .map(|found| found.signature)
    }
}

/// A workshop function that the user's file defines.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Definition {
    /// Which function.
    pub function: WorkshopFunction,
    /// The line of the user's file where its name stands (from 1).
    pub line: usize,
    /// Its signature as written.
    pub signature: Signature,
}

impl Definition {
    /// Whether the signature is the workshop's (a different one would be an overload that
    /// the reference code never calls).
    pub fn has_workshop_signature(&self) -> bool {
        self.function.signature().as_ref() == Some(&self.signature)
    }
}

/// The workshop functions defined in `source`, in the order they appear. A function
/// defined twice appears twice (the compiler then reports the redefinition).
pub fn find_definitions(source: &str) -> Vec<Definition> {
    find_functions(source)
        .into_iter()
        .filter(|found| found.has_body)
        .filter_map(|found| {
            Some(Definition {
                function: WorkshopFunction::from_name(&found.name)?,
                line: found.line,
                signature: found.signature,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workshop_prototypes_give_every_signature() {
        for function in WorkshopFunction::ALL {
            assert!(function.signature().is_some(), "{function:?}");
        }
        assert_eq!(
            WorkshopFunction::GetRandomNumbers.signature(),
            Some(Signature {
                return_type: "vec2".into(),
                parameters: vec!["inout uvec2".into()]
            })
        );
        let intersection = WorkshopFunction::RayTriangleIntersection
            .signature()
            .unwrap();
        assert_eq!(
            intersection.parameters,
            ["out float", "vec3", "vec3", "triangle_t"]
        );
        assert_eq!(
            WorkshopFunction::SampleSphere.user_defines_macro(),
            "USER_DEFINES_SAMPLE_SPHERE"
        );
    }

    #[test]
    fn definitions_are_found_with_their_lines_and_calls_are_not() {
        let source = "// vec3 sample_sphere(vec2 r) { in a comment }\n\
            /* vec3 get_ray_radiance(vec3 a, vec3 b, inout uvec2 s) {\n */\n\
            #define HELPER(x) sample_hemisphere(x) {\n\
            float helper(float x) { return x; }\n\
            vec3\nsample_sphere (const in vec2 random_numbers)\n{\n\
                vec3 d = sample_hemisphere(random_numbers, vec3(0.0));\n\
                if (ray_triangle_intersection(t, o, d, tri)) { }\n\
                return d;\n}\n\
            vec3 sample_hemisphere(vec2 u, vec3 n);\n\
            vec3 sample_hemisphere(highp vec2 u, vec3 n) { return n; }\n";
        let found = find_definitions(source);
        let names: Vec<(&str, usize)> = found.iter().map(|d| (d.function.name(), d.line)).collect();
        assert_eq!(names, [("sample_sphere", 7), ("sample_hemisphere", 14)]);
        assert!(found.iter().all(Definition::has_workshop_signature));
    }

    #[test]
    fn wrong_signatures_are_recognized() {
        let found = find_definitions(
            "vec3 sample_sphere(vec3 random_numbers) { return random_numbers; }\n\
             vec2 get_random_numbers(uvec2 seed) { return vec2(0.0); }\n\
             bool ray_triangle_intersection(out float t, vec3 o, vec3 d, triangle_t tri) { return false; }\n",
        );
        assert_eq!(found.len(), 3);
        assert!(!found[0].has_workshop_signature());
        assert!(!found[1].has_workshop_signature(), "inout is part of it");
        assert!(found[2].has_workshop_signature());
        assert_eq!(
            found[1].signature.to_string(),
            "vec2 (uvec2)",
            "signatures print readably"
        );
    }
}
