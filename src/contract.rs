//! Binding indices, workgroup sizes, specialization-constant ids and their values, and the
//! numbers that the GLSL functions and their Rust twins share, generated from
//! `glsl/shared.h` by `build.rs`: integers as `u32`, float literals as `f32`, each with its
//! literal exactly as the header writes it, so that Rust and the shaders read the same float.
#![allow(
    clippy::excessive_precision,
    reason = "the header's literals, digit for digit, as the shaders read them"
)]

include!(concat!(env!("OUT_DIR"), "/contract.rs"));

#[cfg(test)]
mod tests {
    use super::*;

    /// The value of `#define name <value>` in `glsl/shared.h` as embedded in the binary.
    fn define(name: &str) -> &'static str {
        let header = crate::shaders::GLSL_SOURCES
            .iter()
            .find(|(file, _)| *file == "shared.h")
            .map(|(_, text)| *text)
            .expect("shared.h is embedded");
        let prefix = format!("#define {name} ");
        header
            .lines()
            .find_map(|line| line.strip_prefix(&prefix))
            .unwrap_or_else(|| panic!("shared.h defines {name}"))
            .trim()
    }

    #[test]
    fn constants_are_the_headers_values() {
        for (name, value) in [
            ("WORKGROUP_SIZE_X", WORKGROUP_SIZE_X),
            ("BINDING_LIGHTS", BINDING_LIGHTS),
            ("DEFAULT_MAX_PATH_LENGTH", DEFAULT_MAX_PATH_LENGTH),
            ("USER_OPAQUE_BINDING_FIRST", USER_OPAQUE_BINDING_FIRST),
        ] {
            assert_eq!(define(name).parse::<u32>(), Ok(value), "{name}");
        }
        for (name, value) in [
            ("NO_HIT_T", NO_HIT_T),
            ("RAY_ORIGIN_OFFSET", RAY_ORIGIN_OFFSET),
            ("SHADOW_RAY_MARGIN", SHADOW_RAY_MARGIN),
            (
                "MIN_SPHERICAL_SAMPLING_SOLID_ANGLE",
                MIN_SPHERICAL_SAMPLING_SOLID_ANGLE,
            ),
            (
                "MAX_SPHERICAL_SAMPLING_SOLID_ANGLE",
                MAX_SPHERICAL_SAMPLING_SOLID_ANGLE,
            ),
            ("MIN_LIGHT_COSINE", MIN_LIGHT_COSINE),
            ("SAMPLE_VIEW_ELEVATION_COS", SAMPLE_VIEW_ELEVATION_COS),
            ("SAMPLE_VIEW_ELEVATION_SIN", SAMPLE_VIEW_ELEVATION_SIN),
            ("SAMPLE_VIEW_HALF_HEIGHT", SAMPLE_VIEW_HALF_HEIGHT),
            ("BVH_SLAB_PADDING", BVH_SLAB_PADDING),
            ("BVH_MIN_DIRECTION", BVH_MIN_DIRECTION),
        ] {
            let parsed: f32 = define(name).parse().expect("a float literal");
            assert_eq!(parsed.to_bits(), value.to_bits(), "{name}");
        }
    }

    #[test]
    fn powers_of_two_are_exact() {
        // The comments promise these; a literal with a digit too few would break them.
        assert_eq!(RAY_ORIGIN_OFFSET, 2.0f32.powi(-17));
        assert_eq!(SHADOW_RAY_MARGIN, 2.0f32.powi(-14));
    }
}
