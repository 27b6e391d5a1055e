//! Every GLSL function has a Rust twin of the same name (`../shared/STYLE.md`: two twins, one
//! name), or is listed in `WITHOUT_TWINS` below with the reason it has none. The test reads the
//! sources (`glsl/`, `src/`), so a new GLSL function without a twin fails it until the twin is
//! written or the function is listed with its reason; a listed function that gains a twin
//! fails it too, so that the list stays true.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The GLSL functions that have no Rust function of the same name, and why.
const WITHOUT_TWINS: &[(&str, &str)] = &[
    // Reads of the GPU's own storage: the Rust side holds the same data as plain slices and
    // structs (src/bvh, src/lights, src/scene), so a twin would be an index into an array.
    ("get_bvh_node_count", "the node count of the BVH texel buffer; Rust has nodes.len()"),
    ("get_light_count", "the first texel of the light list; Rust has lights.len()"),
    ("get_light_triangle_index", "a texel read of the light list; Rust indexes the list"),
    ("get_light_cumulative_probability", "a texel read of the light CDF; Rust indexes the CDF"),
    ("get_packed_triangle", "a texel read of the triangle buffer; Rust indexes the triangles"),
    // Motion blur's reads of the keys after the triangles (glsl/scene.glsl): texel reads and
    // a lerp between two keys; the host's keys are scene::motion's slices.
    ("get_motion_texel_offset", "where the keys start in the triangle buffer: a texel offset"),
    ("get_moving_packed_triangle", "get_packed_triangle of the keys, lerped at the sample's time"),
    ("get_camera_at_time", "the keys' cameras read from the triangle buffer and lerped"),
    // Open work, not a reason to keep: the CPU renderer has no motion blur yet, so the time
    // draw and the moving camera have no twins; tests/motion_blur_cli.rs checks the blur
    // against the mean of still renders instead.
    ("get_time_random_number", "no twin yet: the CPU renderer has no motion blur (open)"),
    ("get_moving_camera_ray", "no twin yet: the CPU renderer has no motion blur (open)"),
    ("unpack_triangle", "copies std430 fields into the workshop's struct; Rust's GpuTriangle layout is tested instead"),
    ("pack_triangle", "the probes' inverse of unpack_triangle: probe output plumbing"),
    ("get_probe_index", "which input a probe invocation reads: probe plumbing, no maths"),
    ("get_display_material", "the exercise display's push constants into a material_t: plumbing"),
    (
        "cwbvh_overflow_index",
        "where a stack entry lies in workgroup-shared memory (gl_LocalInvocationIndex): the CPU traversal's stack is one array",
    ),
    // The device's own traversal (VK_KHR_ray_query): the hardware walks its acceleration
    // structures; the reference is the software BVH (whose twins are tested), and
    // tests/ray_query_cli.rs checks the ray-query renders against the BVH's, image for image.
    ("ray_query_closest_hit", "a rayQueryEXT loop of the device's traversal; checked against the BVH's renders (tests/ray_query_cli.rs)"),
    ("ray_query_any_hit", "a rayQueryEXT loop of the device's traversal; checked against the BVH's renders (tests/ray_query_cli.rs)"),
    ("is_ray_query_defined", "keeps non-finite rays from the device's traversal, whose result for them Vulkan leaves undefined; the Rust traversal has no such limit"),
    // GPU bookkeeping with no CPU counterpart.
    ("visit_bvh_child", "counts traversal iterations for the lavapipe loop budget (GPU only)"),
    ("get_light_search_iterations", "an iteration bound for the loop budget (GPU only)"),
    ("is_guide_training", "a specialization-constant test (GUIDING == GUIDING_TRAINING)"),
    ("get_first_hit_view", "the --aov first-hit views, checked by tests/material_aov.rs images"),
    // Path-loop steps whose maths is twinned piecewise (each callee has its twin) and checked
    // whole by the CPU reference renders (integrators_agree, lights_render).
    ("get_found_environment", "MIS weight of get_environment_density and get_power_heuristic_weight, both twinned"),
    ("sample_environment_light", "sample_environment, get_environment_density and _radiance, all twinned"),
    ("sample_punctual_light", "uniform choice + get_punctual_irradiance, which is twinned"),
    // The global medium's plumbing (glsl/scattering_vertex.glsl, glsl/path_loop.glsl).
    ("get_global_medium", "reads the medium's specialization constants into a medium_t; the host holds crate::medium::Medium"),
    ("survives_russian_roulette", "the path loop's roulette step, inline in cpu/path_loop.rs's loop and checked whole by the CPU reference renders"),
    // A gap, not a design: the CPU reference does not skip the start triangle this way.
    ("starts_on_triangle_plane", "gap: the CPU reference offsets rays instead; to be twinned with a probe"),
];

/// The GLSL functions defined at the top level of the files in `glsl/`, with their files.
fn glsl_functions(folder: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut functions = BTreeMap::<String, BTreeSet<String>>::new();
    for path in files(folder, &["glsl", "comp", "h"]) {
        let text = std::fs::read_to_string(&path).expect("readable shader");
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        for name in top_level_definitions(&without_comments_and_directives(&text)) {
            functions.entry(name).or_default().insert(file.clone());
        }
    }
    functions
}

/// The names of every `fn` in the Rust files under `folder`.
fn rust_functions(folder: &Path) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    for path in files(folder, &["rs"]) {
        let text = std::fs::read_to_string(&path).expect("readable source");
        let mut rest = text.as_str();
        while let Some(at) = rest.find("fn ") {
            let before = rest[..at].chars().last();
            rest = &rest[at + 3..];
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                names.insert(name);
            }
        }
    }
    names
}

/// Files under `folder` (recursively) with one of `extensions`, sorted.
fn files(folder: &Path, extensions: &[&str]) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut folders = vec![folder.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).expect("readable folder") {
            let path = entry.expect("folder entry").path();
            if path.is_dir() {
                folders.push(path);
            } else if path
                .extension()
                .is_some_and(|e| extensions.iter().any(|x| e == *x))
            {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

/// The text without `//` and `/* */` comments and without preprocessor lines (a `#define`
/// body is not a definition at the top level).
fn without_comments_and_directives(text: &str) -> String {
    let mut code = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, chars.peek()) {
            ('/', Some('/')) => {
                for c in chars.by_ref() {
                    if c == '\n' {
                        code.push('\n');
                        break;
                    }
                }
            }
            ('/', Some('*')) => {
                chars.next();
                let mut previous = ' ';
                for c in chars.by_ref() {
                    if previous == '*' && c == '/' {
                        break;
                    }
                    previous = c;
                }
            }
            _ => code.push(c),
        }
    }
    let mut lines = Vec::new();
    let mut continued = false;
    for line in code.lines() {
        let directive = continued || line.trim_start().starts_with('#');
        continued = directive && line.trim_end().ends_with('\\');
        lines.push(if directive { "" } else { line });
    }
    lines.join("\n")
}

/// The names of the functions defined at brace depth 0: a `{` there whose header (the text
/// since the last `;`, `{` or `}`) reads `type name(parameters)`.
fn top_level_definitions(code: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut depth = 0usize;
    let mut header_start = 0;
    for (at, c) in code.char_indices() {
        match c {
            '{' => {
                if depth == 0 {
                    if let Some(name) = function_name(&code[header_start..at]) {
                        names.push(name);
                    }
                }
                depth += 1;
                header_start = at + 1;
            }
            '}' => {
                depth = depth.saturating_sub(1);
                header_start = at + 1;
            }
            ';' if depth == 0 => header_start = at + 1,
            _ => {}
        }
    }
    names
}

/// `name` when `header` is `[qualifiers] type name(parameters)`, else None (a struct, a
/// `layout(...) buffer` block).
fn function_name(header: &str) -> Option<String> {
    let header = header.trim();
    if !header.ends_with(')') || header.starts_with("layout") {
        return None;
    }
    let open = header.find('(')?;
    let words: Vec<&str> = header[..open].split_whitespace().collect();
    match words.as_slice() {
        [.., _type, name] if !["struct", "buffer", "uniform"].contains(name) => {
            Some(name.to_string())
        }
        _ => None,
    }
}

#[test]
fn every_glsl_function_has_a_rust_twin_or_a_reason() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let glsl = glsl_functions(&root.join("glsl"));
    let rust = rust_functions(&root.join("src"));
    // The scanner must see the workshop's functions, or it would pass on nothing.
    for known in [
        "get_random_numbers",
        "sample_sphere",
        "sample_hemisphere",
        "ray_triangle_intersection",
        "get_ray_radiance",
    ] {
        assert!(glsl.contains_key(known), "the scan of glsl/ missed {known}");
    }
    assert!(
        glsl.len() > 200,
        "the scan of glsl/ found only {} functions",
        glsl.len()
    );
    let listed: BTreeMap<&str, &str> = WITHOUT_TWINS.iter().copied().collect();
    let without: Vec<(&String, &BTreeSet<String>)> = glsl
        .iter()
        .filter(|(name, _)| name.as_str() != "main" && !rust.contains(name.as_str()))
        .collect();
    let unlisted: Vec<String> = without
        .iter()
        .filter(|(name, _)| !listed.contains_key(name.as_str()))
        .map(|(name, files)| {
            format!(
                "{name} ({})",
                files.iter().cloned().collect::<Vec<_>>().join(", ")
            )
        })
        .collect();
    assert!(
        unlisted.is_empty(),
        "GLSL functions without a Rust twin of the same name: {unlisted:?}; write the twin and a test that runs both, or list the function in WITHOUT_TWINS with the reason"
    );
    let twinned: Vec<&str> = listed
        .keys()
        .copied()
        .filter(|name| !without.iter().any(|(n, _)| n.as_str() == *name))
        .collect();
    assert!(
        twinned.is_empty(),
        "listed in WITHOUT_TWINS but now twinned or gone (take them off the list): {twinned:?}"
    );
    println!(
        "{} GLSL functions, {} without a twin (each listed with its reason)",
        glsl.len() - usize::from(glsl.contains_key("main")),
        without.len()
    );
}

#[test]
fn the_scanner_finds_definitions_and_skips_blocks_and_macros() {
    let code = without_comments_and_directives(
        "struct ray_t { vec3 o; };\n\
         layout(std430, binding = 0) buffer b { uint x[]; };\n\
         #define F(x) \\\n  float g(x) { return x; }\n\
         // float commented(float x) { return x; }\n\
         /* vec3 block(vec3 v) { return v; } */\n\
         float f(float x, vec2 y) { if (x > 0.0) { return x; } return y.x; }\n\
         highp uvec2 pcg2d(uvec2 v)\n{ return v; }\n\
         void declared_only(float x);\n",
    );
    assert_eq!(top_level_definitions(&code), ["f", "pcg2d"]);
}
