//! Rust twin of `glsl/sample_dimensions.glsl`: the fixed sample dimensions of the
//! importance-sampled integrators (cosine, nee, mis). Each decision of a sample draws its pair
//! of random numbers at a dimension pair fixed by what it is and by its path vertex, not by
//! the order the code draws in (pbrt-v4's wavefront `samples.cpp`): the camera's pairs first,
//! then a block of `VERTEX_PAIRS` per vertex, vertex `i`'s decision `offset` at
//! `CAMERA_PAIRS + i * VERTEX_PAIRS + offset`. A test reads the GLSL file and checks that
//! every constant agrees.

/// The pixel jitter of the box filter.
pub const CAMERA_PAIR_PIXEL: u32 = 0;
/// Reserved: the point on the lens (depth of field).
pub const CAMERA_PAIR_LENS: u32 = 1;
/// The time within the shutter interval (motion blur, `glsl/motion_time.glsl`; its first number).
pub const CAMERA_PAIR_TIME: u32 = 2;
/// How many pairs the camera has: the first vertex's pairs start here.
pub const CAMERA_PAIRS: u32 = 3;

/// The emissive triangle's choice (its first number: by power or by the light tree).
pub const VERTEX_PAIR_LIGHT_SELECTION: u32 = 0;
/// The point on the chosen emissive triangle (solid angle or area).
pub const VERTEX_PAIR_LIGHT_POINT: u32 = 1;
/// The environment map's texel (a constant environment: its direction).
pub const VERTEX_PAIR_ENVIRONMENT_TEXEL: u32 = 2;
/// The point within the environment map's texel.
pub const VERTEX_PAIR_ENVIRONMENT_POINT: u32 = 3;
/// The punctual light's choice (its first number).
pub const VERTEX_PAIR_PUNCTUAL_SELECTION: u32 = 4;
/// The BSDF's (or the cosine's) direction.
pub const VERTEX_PAIR_DIRECTION: u32 = 5;
/// A layered material's lobe choice (its first number).
pub const VERTEX_PAIR_LOBE: u32 = 6;
/// Path guiding: BSDF or guide (its first number).
pub const VERTEX_PAIR_GUIDE_CHOICE: u32 = 7;
/// Path guiding: the guide's direction.
pub const VERTEX_PAIR_GUIDE_DIRECTION: u32 = 8;
/// Russian roulette's survival (its first number).
pub const VERTEX_PAIR_RUSSIAN_ROULETTE: u32 = 9;
/// The global medium's distance sample on the segment that ends at this vertex: its
/// channel (first number) and distance (second).
pub const VERTEX_PAIR_MEDIUM_DISTANCE: u32 = 10;
/// How many pairs each vertex has.
pub const VERTEX_PAIRS: u32 = 11;

/// Every constant of the table by its GLSL name, in the file's order (what the test compares).
pub const SAMPLE_DIMENSIONS: &[(&str, u32)] = &[
    ("CAMERA_PAIR_PIXEL", CAMERA_PAIR_PIXEL),
    ("CAMERA_PAIR_LENS", CAMERA_PAIR_LENS),
    ("CAMERA_PAIR_TIME", CAMERA_PAIR_TIME),
    ("CAMERA_PAIRS", CAMERA_PAIRS),
    ("VERTEX_PAIR_LIGHT_SELECTION", VERTEX_PAIR_LIGHT_SELECTION),
    ("VERTEX_PAIR_LIGHT_POINT", VERTEX_PAIR_LIGHT_POINT),
    (
        "VERTEX_PAIR_ENVIRONMENT_TEXEL",
        VERTEX_PAIR_ENVIRONMENT_TEXEL,
    ),
    (
        "VERTEX_PAIR_ENVIRONMENT_POINT",
        VERTEX_PAIR_ENVIRONMENT_POINT,
    ),
    (
        "VERTEX_PAIR_PUNCTUAL_SELECTION",
        VERTEX_PAIR_PUNCTUAL_SELECTION,
    ),
    ("VERTEX_PAIR_DIRECTION", VERTEX_PAIR_DIRECTION),
    ("VERTEX_PAIR_LOBE", VERTEX_PAIR_LOBE),
    ("VERTEX_PAIR_GUIDE_CHOICE", VERTEX_PAIR_GUIDE_CHOICE),
    ("VERTEX_PAIR_GUIDE_DIRECTION", VERTEX_PAIR_GUIDE_DIRECTION),
    ("VERTEX_PAIR_RUSSIAN_ROULETTE", VERTEX_PAIR_RUSSIAN_ROULETTE),
    ("VERTEX_PAIR_MEDIUM_DISTANCE", VERTEX_PAIR_MEDIUM_DISTANCE),
    ("VERTEX_PAIRS", VERTEX_PAIRS),
];

/// Twin of GLSL `get_vertex_dimension_pair`: the first dimension pair of path vertex `vertex`
/// (0: the camera ray's hit); add a `VERTEX_PAIR_*` offset to it.
pub fn get_vertex_dimension_pair(vertex: u32) -> u32 {
    CAMERA_PAIRS + vertex * VERTEX_PAIRS
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The GLSL file as embedded in the binary, as the shaders include it.
    fn glsl() -> &'static str {
        crate::shaders::GLSL_SOURCES
            .iter()
            .find(|(file, _)| *file == "sample_dimensions.glsl")
            .map(|(_, text)| *text)
            .expect("sample_dimensions.glsl is embedded")
    }

    /// The `const uint NAME = Nu;` lines of the GLSL file, in order.
    fn glsl_constants() -> Vec<(String, u32)> {
        glsl()
            .lines()
            .filter_map(|line| line.trim().strip_prefix("const uint "))
            .map(|rest| {
                let (name, value) = rest.split_once('=').expect("const uint NAME = VALUE;");
                let value = value.trim().trim_end_matches(';').trim_end_matches('u');
                (
                    name.trim().to_string(),
                    value.parse().expect("a decimal uint"),
                )
            })
            .collect()
    }

    #[test]
    fn glsl_and_rust_tables_agree() {
        let constants = glsl_constants();
        let rust: Vec<(String, u32)> = SAMPLE_DIMENSIONS
            .iter()
            .map(|&(name, value)| (name.to_string(), value))
            .collect();
        assert_eq!(
            constants, rust,
            "glsl/sample_dimensions.glsl against the twin"
        );
        // The formula too: its body is the expression below.
        assert!(
            glsl().contains("return CAMERA_PAIRS + uint(vertex) * VERTEX_PAIRS;"),
            "get_vertex_dimension_pair changed: change its twin"
        );
    }

    #[test]
    fn every_pair_has_its_own_place() {
        // The camera's pairs lie below CAMERA_PAIRS, each vertex's offsets below VERTEX_PAIRS,
        // and no two rows of either share a pair.
        let (camera, vertex): (Vec<_>, Vec<_>) = SAMPLE_DIMENSIONS
            .iter()
            .filter(|(name, _)| !name.ends_with("PAIRS"))
            .partition(|(name, _)| name.starts_with("CAMERA_"));
        for (rows, bound) in [(camera, CAMERA_PAIRS), (vertex, VERTEX_PAIRS)] {
            let mut values: Vec<u32> = rows.iter().map(|&&(_, value)| value).collect();
            values.sort_unstable();
            assert_eq!(values, (0..bound).collect::<Vec<_>>());
        }
        // Consecutive vertices' blocks follow each other without overlap.
        assert_eq!(get_vertex_dimension_pair(0), CAMERA_PAIRS);
        assert_eq!(
            get_vertex_dimension_pair(4) + VERTEX_PAIRS,
            get_vertex_dimension_pair(5)
        );
    }
}
