//! `vkpath check` through the binary on the example solutions of tests/solutions/: correct
//! functions written differently from the workshop's must pass, the typical mistakes must
//! fail with the right function named, and unusable files must be usage errors. Every run
//! has the validation layer on (the binary fails if it reports anything). Renders are small
//! (32 x 32 at 256 spp) to keep the suite fast on lavapipe.

use crate::common;

use std::path::Path;

use serde_json::Value;

use common::runs::Run as Outcome;

fn solution(name: &str) -> String {
    format!("{}/tests/solutions/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Runs `vkpath check` on a solution in a temporary directory, with small renders.
fn check(dir: &Path, name: &str, extra: &[&str]) -> Outcome {
    check_tabs(dir, &[name], extra, &[])
}

/// Checks `name` with `--json`, expects `exit` and the verdict `passed` for each function,
/// and returns the report.
fn expect_verdicts(name: &str, exit: i32, verdicts: &[(&str, bool)]) -> Value {
    let dir = tempfile::tempdir().expect("temporary directory");
    let outcome = check(dir.path(), name, &["--json"]);
    assert_eq!(
        outcome.code,
        Some(exit),
        "{name}: {}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    let report = outcome.json();
    let functions = report["functions"].as_array().expect("functions");
    let found: Vec<(&str, bool)> = functions
        .iter()
        .map(|f| {
            (
                f["function"].as_str().expect("name"),
                f["passed"].as_bool().expect("verdict"),
            )
        })
        .collect();
    assert_eq!(found, verdicts, "{name}: {}", outcome.stdout);
    for function in functions {
        println!(
            "{name}: {} {} — {} {}",
            function["function"],
            if function["passed"] == true {
                "PASS"
            } else {
                "FAIL"
            },
            function["summary"],
            function["measurements"]
        );
    }
    report
}

#[test]
fn moller_trumbore_passes() {
    let report = expect_verdicts(
        "ray_triangle_moller_trumbore.glsl",
        0,
        &[("ray_triangle_intersection", true)],
    );
    let function = &report["functions"][0];
    assert!(function["cases"].as_u64().expect("cases") > 60_000);
    // Near-degenerate rays are few.
    assert!(function["skipped"].as_u64().expect("skipped") < 650);
}

#[test]
fn intersection_without_t_check_fails_with_examples() {
    let report = expect_verdicts(
        "ray_triangle_without_t_check.glsl",
        1,
        &[("ray_triangle_intersection", false)],
    );
    let mismatch = &report["functions"][0]["mismatches"][0];
    let hint = report["functions"][0]["hint"]
        .as_str()
        .expect("a named mistake");
    assert!(hint.contains("t < 0"), "{hint}");
    assert_eq!(mismatch["expected"], "false");
    assert!(mismatch["actual"]
        .as_str()
        .expect("text")
        .starts_with("true, out_t = -"));
}

#[test]
fn pcg2d_written_differently_is_bit_exact() {
    expect_verdicts(
        "pcg2d_separate_statements.glsl",
        0,
        &[("get_random_numbers", true)],
    );
}

#[test]
fn pcg2d_with_a_typo_fails() {
    let report = expect_verdicts("pcg2d_typo.glsl", 1, &[("get_random_numbers", false)]);
    let function = &report["functions"][0];
    assert_eq!(
        function["failures"], function["cases"],
        "a hash changes every output"
    );
    assert!(function["mismatches"][0]["input"]
        .as_str()
        .expect("text")
        .starts_with("seed = uvec2("));
}

#[test]
fn pcg2d_that_never_writes_its_seed_back_is_told_so() {
    // PCG2D on a local copy of the seed (written for this test, a mistake attendees make):
    // the numbers are the reference's, the seed never advances. The hint says that, not
    // "compare the constants" (issue 58).
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("pcg2d_local_copy.glsl");
    std::fs::write(
        &path,
        "vec2 get_random_numbers(inout uvec2 seed) {\n    uvec2 state = 1664525u * seed + 1013904223u;\n    state.x += 1664525u * state.y;\n    state.y += 1664525u * state.x;\n    state ^= (state >> 16u);\n    state.x += 1664525u * state.y;\n    state.y += 1664525u * state.x;\n    state ^= (state >> 16u);\n    return vec2(state) * 2.32830643654e-10;\n}\n",
    )
    .expect("write");
    let outcome = common::runs::check(dir.path(), &[path.display().to_string()], &["--json"], &[]);
    assert_eq!(
        outcome.code,
        Some(1),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    let report = outcome.json();
    let verdict = common::runs::verdict(&report, "get_random_numbers").expect("verdict");
    let hint = verdict["hint"].as_str().expect("hint");
    assert!(
        hint.contains("leaves seed as it was") && !hint.contains("constants"),
        "{hint}"
    );
}

#[test]
fn sphere_sampler_written_differently_passes() {
    expect_verdicts(
        "sample_sphere_alternative.glsl",
        0,
        &[("sample_sphere", true)],
    );
}

#[test]
fn sphere_sampler_with_theta_pi_u_fails() {
    let report = expect_verdicts(
        "sample_sphere_theta_pi_u.glsl",
        1,
        &[("sample_sphere", false)],
    );
    assert_eq!(report["functions"][0]["measurements"]["p_value"], 0.0);
}

#[test]
fn hemisphere_by_flipping_passes() {
    expect_verdicts(
        "sample_hemisphere_flip.glsl",
        0,
        &[("sample_hemisphere", true)],
    );
}

#[test]
fn hemisphere_without_mirror_fails_with_directions_below() {
    let report = expect_verdicts(
        "sample_hemisphere_no_mirror.glsl",
        1,
        &[("sample_hemisphere", false)],
    );
    let mismatches = report["functions"][0]["mismatches"]
        .as_array()
        .expect("list");
    assert!(mismatches.iter().any(|m| m["actual"]
        .as_str()
        .expect("text")
        .contains("dot(normal, direction) = -")));
    let hint = report["functions"][0]["hint"]
        .as_str()
        .expect("a named mistake");
    assert!(hint.contains("mirror"), "{hint}");
}

#[test]
fn camera_and_mesh_written_differently_pass() {
    expect_verdicts(
        "camera_and_mesh_alternative.glsl",
        0,
        &[
            ("ray_mesh_intersection", true),
            ("get_primary_ray_direction", true),
        ],
    );
}

#[test]
fn estimators_written_differently_pass_and_write_images() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let outcome = check(dir.path(), "estimators_alternative.glsl", &[]);
    assert_eq!(
        outcome.code,
        Some(0),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    println!("{}", outcome.stdout);
    assert!(outcome.stdout.contains("PASS compute_direct_illumination"));
    assert!(outcome.stdout.contains("PASS get_ray_radiance"));
    for function in ["compute_direct_illumination", "get_ray_radiance"] {
        for suffix in ["reference", "yours", "difference"] {
            let path = dir
                .path()
                .join("out")
                .join(format!("{function}-{suffix}.png"));
            assert!(path.is_file(), "{} is missing", path.display());
        }
    }
}

#[test]
fn path_loop_without_throughput_fails() {
    let report = expect_verdicts(
        "path_loop_without_throughput.glsl",
        1,
        &[("get_ray_radiance", false)],
    );
    let measurements = &report["functions"][0]["measurements"];
    let (yours, reference) = (
        measurements["your_average"].as_f64().expect("number"),
        measurements["reference_average"].as_f64().expect("number"),
    );
    assert!(
        yours > 1.5 * reference,
        "{yours} vs {reference}: light is never attenuated"
    );
}

#[test]
fn compile_errors_name_the_users_file_and_line() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let outcome = check(dir.path(), "compile_error.glsl", &[]);
    assert_eq!(
        outcome.code,
        Some(1),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    let expected = format!("{}:7: error:", solution("compile_error.glsl"));
    assert!(outcome.stdout.contains(&expected), "{}", outcome.stdout);
    assert!(
        outcome.stdout.contains("FAIL sample_sphere"),
        "{}",
        outcome.stdout
    );
    assert!(
        !outcome.stdout.contains("user_functions.glsl"),
        "{}",
        outcome.stdout
    );
    let json = check(dir.path(), "compile_error.glsl", &["--json"]).json();
    let function = &json["functions"][0];
    assert_eq!(function["method"], "compile");
    assert!(function["hint"].as_str().expect("text").contains(&expected));
    assert_eq!(json["passed"], false);
}

#[test]
fn a_workshop_name_with_other_parameters_alone_is_nothing_to_judge() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let outcome = check(dir.path(), "wrong_signature.glsl", &[]);
    assert_eq!(
        outcome.code,
        Some(2),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    assert!(
        outcome.stderr.contains("nothing check can judge")
            && outcome
                .stderr
                .contains("sample_sphere (line 3): its parameters are vec3 (vec3)"),
        "{}",
        outcome.stderr
    );
}

/// The report's warnings of one function, as text.
fn warnings(report: &Value, function: &str) -> String {
    report["functions"]
        .as_array()
        .expect("functions")
        .iter()
        .find(|f| f["function"] == function)
        .map(|f| f["warnings"].to_string())
        .unwrap_or_default()
}

const ALL_FUNCTIONS: [&str; 8] = [
    "get_random_numbers",
    "sample_sphere",
    "sample_hemisphere",
    "ray_triangle_intersection",
    "ray_mesh_intersection",
    "get_primary_ray_direction",
    "compute_direct_illumination",
    "get_ray_radiance",
];

#[test]
fn a_whole_shadertoy_tab_is_judged_function_by_function() {
    // Every function passes; the tab as a program (its mainImage accumulating Buffer A)
    // self-intersects with its t >= 0 intersections and fails (tests/shadertoy_cli.rs).
    let mut verdicts: Vec<(&str, bool)> = ALL_FUNCTIONS.iter().map(|&f| (f, true)).collect();
    verdicts.push(("program", false));
    let report = expect_verdicts("shadertoy_tab_all_solved.glsl", 1, &verdicts);
    let notes = report["notes"].to_string();
    assert!(notes.contains("dropped mainImage()"), "{notes}");
    assert!(notes.contains("triangle_t is the workshop's"), "{notes}");
    // The slides' estimators pass; with the tab's own t >= 0 intersections they
    // self-intersect, which is a warning, not a failure.
    for estimator in ["compute_direct_illumination", "get_ray_radiance"] {
        let text = warnings(&report, estimator);
        assert!(
            text.contains("darker") && text.contains("self-intersection"),
            "{estimator}: {text}"
        );
    }
}

#[test]
fn one_mistake_in_a_tab_fails_only_that_function() {
    let mut verdicts: Vec<(&str, bool)> = ALL_FUNCTIONS
        .iter()
        .map(|&f| (f, f != "sample_sphere"))
        .collect();
    // The tab as a program is biased (its sampler, and self-intersection).
    verdicts.push(("program", false));
    let report = expect_verdicts("shadertoy_tab_theta_pi_u.glsl", 1, &verdicts);
    let sphere = &report["functions"][1];
    assert!(
        sphere["hint"]
            .as_str()
            .expect("a named mistake")
            .contains("θ = π u"),
        "{sphere}"
    );
    let images = sphere["images"].to_string();
    assert!(images.contains("sample_sphere-samples.png"), "{images}");
}

#[test]
fn a_webgl_page_shader_with_part_one() {
    let report = expect_verdicts(
        "webgl_page_part1.glsl",
        0,
        &[
            ("ray_triangle_intersection", true),
            ("ray_mesh_intersection", true),
            ("get_primary_ray_direction", true),
        ],
    );
    let notes = report["notes"].to_string();
    for dropped in ["dropped #version", "dropped main()", "u_resolution"] {
        assert!(notes.contains(dropped), "{dropped}: {notes}");
    }
}

#[test]
fn the_slides_path_loop_alone_passes_with_a_warning() {
    let report = expect_verdicts("slides_path_loop.glsl", 0, &[("get_ray_radiance", true)]);
    let text = warnings(&report, "get_ray_radiance");
    assert!(text.contains("accept hits at t >= 0"), "{text}");
}

#[test]
fn the_slides_direct_illumination_alone_passes() {
    expect_verdicts(
        "slides_direct_illumination.glsl",
        0,
        &[("compute_direct_illumination", true)],
    );
}

#[test]
fn another_courses_functions_are_listed_and_not_judged() {
    let report = expect_verdicts(
        "samplers_with_other_course.glsl",
        0,
        &[("sample_sphere", true), ("sample_hemisphere", true)],
    );
    let not_judged = report["not_judged"].as_array().expect("list");
    let names: Vec<&str> = not_judged
        .iter()
        .map(|n| n["function"].as_str().expect("name"))
        .collect();
    assert_eq!(names, ["ray_triangle_intersection", "get_ray_radiance"]);
    assert!(not_judged[0]["reason"]
        .as_str()
        .expect("text")
        .contains("bool (Ray, Triangle, out float)"));
}

#[test]
fn a_cosine_weighted_hemisphere_is_named() {
    let report = expect_verdicts(
        "sample_hemisphere_cosine.glsl",
        1,
        &[("sample_hemisphere", false)],
    );
    let hint = report["functions"][0]["hint"]
        .as_str()
        .expect("a named mistake");
    assert!(hint.contains("cosine-weighted"), "{hint}");
}

#[test]
fn a_shadertoy_image_tab_gets_its_inputs() {
    let verdicts: Vec<(&str, bool)> = ALL_FUNCTIONS[..7].iter().map(|&f| (f, true)).collect();
    let report = expect_verdicts("shadertoy_image_tab_exercise6.glsl", 0, &verdicts);
    let notes = report["notes"].to_string();
    assert!(
        notes.contains("supplied for your code: iResolution, iTime"),
        "{notes}"
    );
}

#[test]
fn a_file_that_includes_itself_is_read_once() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let file = dir.path().join("self.glsl");
    std::fs::write(
        &file,
        "#include \"self.glsl\"\n#include \"user_functions.glsl\"\n\
         vec3 sample_sphere(vec2 u) {\n    float z = 2.0 * u.y - 1.0;\n    float r = sqrt(1.0 - z * z);\n\
             return vec3(r * cos(2.0 * M_PI * u.x), r * sin(2.0 * M_PI * u.x), z);\n}\n",
    )
    .expect("writable");
    let run = common::runs::run(
        dir.path(),
        &[
            "check",
            file.to_str().expect("utf-8"),
            "--validate",
            "--json",
        ],
        &[],
    );
    assert_eq!(run.code, Some(0), "{}", run.stdout);
    let report = run.json();
    assert!(
        report["notes"].to_string().contains("dropped #include"),
        "{}",
        run.stdout
    );
}

#[test]
fn unusable_files_are_usage_errors() {
    let dir = tempfile::tempdir().expect("temporary directory");
    for (name, expected) in [
        (
            "no_workshop_function.glsl",
            "defines none of the workshop functions",
        ),
        ("does_not_exist.glsl", "cannot read"),
    ] {
        let outcome = check(dir.path(), name, &[]);
        assert_eq!(outcome.code, Some(2), "{name}: {}", outcome.stderr);
        assert!(
            outcome.stderr.contains(expected),
            "{name}: {}",
            outcome.stderr
        );
        assert_eq!(
            outcome
                .stderr
                .lines()
                .filter(|l| l.contains("error"))
                .count(),
            1,
            "one error line: {}",
            outcome.stderr
        );
    }
}

#[test]
fn an_endless_loop_fails_instead_of_being_cut_silently() {
    let report = expect_verdicts(
        "sample_sphere_endless_loop.glsl",
        1,
        &[("sample_sphere", false)],
    );
    let function = &report["functions"][0];
    assert_eq!(function["method"], "loop limit");
    let hint = function["hint"].as_str().expect("text");
    assert!(hint.contains("endless loop"), "{hint}");
    // Only what check has: no render options (--max-path-length, --accel, ...).
    assert!(!hint.contains("--"), "{hint}");
}

/// Runs `vkpath check` on several solutions (tabs) at once, with small renders.
fn check_tabs(dir: &Path, names: &[&str], extra: &[&str], env: &[(&str, &str)]) -> Outcome {
    let files: Vec<String> = names.iter().map(|name| solution(name)).collect();
    common::runs::check(dir, &files, extra, env)
}

/// The report's not-judged entry for `function`, as text ("" when there is none).
fn not_judged(report: &Value, function: &str) -> String {
    report["not_judged"]
        .as_array()
        .expect("not_judged")
        .iter()
        .find(|n| n["function"] == function)
        .map(|n| n["reason"].to_string())
        .unwrap_or_default()
}

#[test]
fn a_scene_in_a_texture_leaves_only_the_functions_that_read_it_unjudged() {
    let report = expect_verdicts(
        "page_shader_scene_in_texture.glsl",
        0,
        &[("sample_sphere", true), ("sample_hemisphere", true)],
    );
    let reason = not_judged(&report, "ray_mesh_intersection");
    assert!(
        reason.contains("u_scene") && reason.contains("fetch_triangle"),
        "{report}"
    );
    let notes = report["notes"].to_string();
    assert!(
        notes.contains("dropped 'uniform sampler2D u_scene'"),
        "{notes}"
    );
}

#[test]
fn a_loop_bounded_by_a_uniform_gets_the_workshops_path_length() {
    let report = expect_verdicts("uniform_path_length.glsl", 0, &[("get_ray_radiance", true)]);
    let notes = report["notes"].to_string();
    assert!(
        notes.contains("'uniform int maxPathLength' is MAX_PATH_LENGTH = 5 here"),
        "{notes}"
    );
}

#[test]
fn a_stray_seed_line_at_file_scope_is_dropped_and_everything_judged() {
    let report = expect_verdicts(
        "seed_line_at_file_scope.glsl",
        1,
        &[
            ("get_random_numbers", true),
            ("sample_sphere", false),
            ("sample_hemisphere", true),
            ("get_primary_ray_direction", true),
        ],
    );
    let notes = report["notes"].to_string();
    assert!(
        notes.contains("seed_line_at_file_scope.glsl:7: dropped 'uvec2 seed = uvec2"),
        "{notes}"
    );
}

#[test]
fn a_ray_query_shader_has_its_pcg2d_judged() {
    let report = expect_verdicts("ray_query_vulkan.glsl", 0, &[("get_random_numbers", true)]);
    let reason = not_judged(&report, "ray_mesh_intersection");
    assert!(reason.contains("ray queries"), "{report}");
}

#[test]
fn a_seed_without_inout_is_judged_and_fails_named() {
    let report = expect_verdicts(
        "pcg2d_without_inout.glsl",
        1,
        &[("get_random_numbers", false)],
    );
    let hint = report["functions"][0]["hint"].to_string();
    assert!(
        hint.contains("'uvec2' where the workshop's is 'inout uvec2'")
            && hint.contains("never advances"),
        "{hint}"
    );
}

#[test]
fn a_stub_is_named_as_the_exercises_stub() {
    let report = expect_verdicts(
        "ray_triangle_stub.glsl",
        1,
        &[
            ("sample_sphere", true),
            ("ray_triangle_intersection", false),
        ],
    );
    let hint = report["functions"][1]["hint"].to_string();
    assert!(
        hint.contains("still the exercise's stub") && hint.contains("return false;"),
        "{hint}"
    );
}

#[test]
fn a_common_tab_and_an_image_tab_are_one_program() {
    let dir = tempfile::tempdir().expect("temporary directory");
    // Given in the wrong order on purpose: the Common tab (no entry point) goes first anyway.
    let outcome = check_tabs(
        dir.path(),
        &["image_tab_needs_common.glsl", "common_tab.glsl"],
        &["--json"],
        &[],
    );
    assert_eq!(
        outcome.code,
        Some(0),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    let report = outcome.json();
    let functions = report["functions"].as_array().expect("functions");
    let verdicts: Vec<(&str, &str, bool)> = functions
        .iter()
        .map(|f| {
            (
                f["function"].as_str().expect("name"),
                f["file"].as_str().expect("file"),
                f["passed"] == true,
            )
        })
        .collect();
    let common = solution("common_tab.glsl");
    let image = solution("image_tab_needs_common.glsl");
    assert_eq!(
        verdicts,
        [
            ("get_random_numbers", common.as_str(), true),
            ("sample_sphere", image.as_str(), true)
        ]
    );
    assert_eq!(functions[1]["line"], 4, "the Image tab's own line");

    let alone = check_tabs(dir.path(), &["image_tab_needs_common.glsl"], &[], &[]);
    assert_eq!(alone.code, Some(1), "{}", alone.stdout);
    assert!(
        alone.stdout.contains(
            "'spherical_direction' is not defined in any of your files; if your program has a Common tab, pass it first"
        ),
        "{}",
        alone.stdout
    );
}

#[test]
fn a_crash_while_judging_one_function_loses_only_its_verdict() {
    let dir = tempfile::tempdir().expect("temporary directory");
    // The test-only fault switch aborts the checking process, as a driver crash would.
    let crash = [("VKPATH_CHECK_FAULT", "sample_sphere")];
    let file = "seed_line_at_file_scope.glsl";
    let text = check_tabs(dir.path(), &[file], &[], &crash);
    assert_eq!(text.code, Some(1), "{}\n{}", text.stdout, text.stderr);
    assert!(
        text.stdout.contains("NOT JUDGED sample_sphere")
            && text
                .stdout
                .contains("the Vulkan driver crashed running your function"),
        "{}",
        text.stdout
    );
    // Verdicts before and after the crash are printed.
    for function in [
        "get_random_numbers",
        "sample_hemisphere",
        "get_primary_ray_direction",
    ] {
        assert!(
            text.stdout.contains(&format!("PASS {function}")),
            "{function}: {}",
            text.stdout
        );
    }
    let json = check_tabs(dir.path(), &[file], &["--json"], &crash);
    assert_eq!(json.code, Some(1));
    let report = json.json();
    assert_eq!(report["lost"][0]["function"], "sample_sphere", "{report}");
    assert_eq!(
        report["functions"].as_array().map(Vec::len),
        Some(3),
        "{report}"
    );
}

#[test]
fn an_unusable_file_still_gets_a_json_report() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let outcome = check(dir.path(), "no_workshop_function.glsl", &["--json"]);
    assert_eq!(outcome.code, Some(2));
    let report = outcome.json();
    assert!(
        report["error"]
            .as_str()
            .expect("error text")
            .contains("defines none of the workshop functions"),
        "{report}"
    );
}

#[test]
fn each_pass_is_compiled_on_its_own_after_the_common_tab() {
    // Buffer A and the Image tab both define sample_sphere, as ShaderToy allows (each pass is
    // one compilation of the Common tab and that pass): read as one text they would be a
    // redefinition and nothing would compile. Each is judged, naming its own tab and line;
    // the Common tab's get_random_numbers is judged once.
    let dir = tempfile::tempdir().expect("temporary directory");
    let outcome = check_tabs(
        dir.path(),
        &[
            "buffer_a_tab_same_names.glsl",
            "image_tab_needs_common.glsl",
            "common_tab.glsl",
        ],
        &["--json"],
        &[],
    );
    assert_eq!(
        outcome.code,
        Some(0),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    let report = outcome.json();
    let verdicts: Vec<(String, String, u64, bool)> = report["functions"]
        .as_array()
        .expect("functions")
        .iter()
        .map(|f| {
            (
                f["function"].as_str().expect("name").to_string(),
                f["file"].as_str().expect("file").to_string(),
                f["line"].as_u64().expect("line"),
                f["passed"] == true,
            )
        })
        .collect();
    let (common, buffer, image) = (
        solution("common_tab.glsl"),
        solution("buffer_a_tab_same_names.glsl"),
        solution("image_tab_needs_common.glsl"),
    );
    assert_eq!(
        verdicts,
        [
            ("get_random_numbers".into(), common, 6, true),
            ("sample_sphere".into(), buffer.clone(), 7, true),
            ("sample_sphere".into(), image, 4, true),
            ("sample_hemisphere".into(), buffer, 11, true),
        ],
        "{report:#}"
    );
    assert!(report["compile_errors"].is_null(), "{report:#}");
}

#[test]
fn a_program_without_the_running_mean_is_not_judged_and_leaves_the_exit_status_to_the_functions() {
    // The workshop's Exercise 7 tab with its running mean taken out (each frame overwrites
    // the last): the program's recovered frame estimates go negative, so comparing it with
    // the reference means nothing. Its functions are all right.
    let dir = tempfile::tempdir().expect("temporary directory");
    let tab = std::fs::read_to_string(solution("programs/exercise7_tab.glsl")).expect("tab");
    let mean = "out_color.rgb = mix(previous, out_color.rgb, 1.0 / float(iFrame + 1));";
    assert!(tab.contains(mean));
    let path = dir.path().join("no_running_mean.glsl");
    std::fs::write(&path, tab.replace(mean, "out_color.rgb += 0.0 * previous;")).expect("write");
    let files = [path.display().to_string()];
    let outcome = common::runs::check(dir.path(), &files, &["--json", "--frames", "8"], &[]);
    assert_eq!(
        outcome.code,
        Some(0),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    let report: Value = serde_json::from_str(&outcome.stdout).expect("JSON report");
    assert_eq!(report["passed"], true);
    assert!(
        common::runs::verdict(&report, "program").is_none(),
        "{report}"
    );
    let reason = not_judged(&report, "program");
    assert!(reason.contains("running mean"), "{report}");
}

#[test]
fn a_wgsl_port_is_named_as_wgsl_with_exit_status_2() {
    // A port of the workshop's sampler to WGSL (written for this test).
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("sampler_port.wgsl");
    std::fs::write(
        &path,
        "// sample_sphere, ported\nfn sample_sphere(u: vec2<f32>) -> vec3<f32> {\n    let z = 1.0 - 2.0 * u.x;\n    return vec3<f32>(0.0, 0.0, z);\n}\n",
    )
    .expect("write");
    let outcome = common::runs::check(dir.path(), &[path.display().to_string()], &[], &[]);
    assert_eq!(outcome.code, Some(2), "{}", outcome.stderr);
    assert!(
        outcome.stderr.contains("is WGSL (line 2") && outcome.stderr.contains("check reads GLSL"),
        "{}",
        outcome.stderr
    );
    assert_eq!(
        outcome.stderr.trim().lines().count(),
        1,
        "{}",
        outcome.stderr
    );
}

/// Checks `files` with `--json --frames 8`, expects exit status 0 (the functions pass), no
/// program verdict and the program listed as not judged; returns the reason.
fn program_not_judged(dir: &Path, files: &[String]) -> String {
    let outcome = common::runs::check(dir, files, &["--json", "--frames", "8"], &[]);
    assert_eq!(
        outcome.code,
        Some(0),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    let report = outcome.json();
    assert_eq!(report["passed"], true, "{report}");
    assert!(
        common::runs::verdict(&report, "program").is_none(),
        "{report}"
    );
    assert_eq!(
        common::runs::verdict(&report, "get_random_numbers").map(|v| v["passed"].clone()),
        Some(Value::Bool(true)),
        "{report}"
    );
    not_judged(&report, "program")
}

#[test]
fn a_program_of_another_scene_or_colour_is_not_judged_and_leaves_the_exit_status_to_the_functions()
{
    let dir = tempfile::tempdir().expect("temporary directory");
    // Its own scene: a height field read from iChannel0 while tracing (known from the text).
    let reason = program_not_judged(dir.path(), &[solution("programs/height_field_tab.glsl")]);
    assert!(
        reason.contains("reads iChannel0 as a texture")
            && reason.contains("height_field_tab.glsl:19"),
        "{reason}"
    );
    // A constant colour written over the traced one: known from the frames.
    let reason = program_not_judged(dir.path(), &[solution("programs/constant_colour_tab.glsl")]);
    assert!(reason.contains("every pixel the same value"), "{reason}");
    // A constant colour without tracing at all: known from the text.
    let tab = std::fs::read_to_string(solution("programs/constant_colour_tab.glsl")).expect("tab");
    let call = "out_color.rgb = get_ray_radiance(";
    assert!(tab.contains(call));
    let path = dir.path().join("constant_only.glsl");
    std::fs::write(&path, tab.replace(call, "out_color.rgb = vec3(")).expect("write");
    let reason = program_not_judged(dir.path(), &[path.display().to_string()]);
    assert!(reason.contains("never calls get_ray_radiance"), "{reason}");
    // More passes than ShaderToy has: not judged either (never a lost verdict).
    let seed = &tab[tab.find("vec2 get_random_numbers").expect("seed")
        ..tab.find("bool ray_mesh").expect("mesh")];
    let common = dir.path().join("common.glsl");
    std::fs::write(
        &common,
        format!("{seed}vec3 get_ray_radiance(vec3 o) {{ return o; }}\n"),
    )
    .expect("write");
    let mut files = vec![common.display().to_string()];
    for pass in 0..6 {
        let path = dir.path().join(format!("pass{pass}.glsl"));
        std::fs::write(&path, "void mainImage(out vec4 c, in vec2 p) { c = vec4(get_ray_radiance(vec3(p, 0.0)), 1.0); }\n").expect("write");
        files.push(path.display().to_string());
    }
    let reason = program_not_judged(dir.path(), &files);
    assert!(reason.contains("6 tabs with mainImage"), "{reason}");
    // The text says the same: NOT JUDGED, never FAIL.
    let text = check(
        dir.path(),
        "programs/height_field_tab.glsl",
        &["--frames", "8"],
    );
    assert_eq!(text.code, Some(0), "{}", text.stdout);
    assert!(
        text.stdout.contains("NOT JUDGED program") && !text.stdout.contains("FAIL"),
        "{}",
        text.stdout
    );
}

#[test]
fn an_endless_loop_that_traces_the_scene_each_iteration_fails_in_seconds() {
    // Every iteration of the loop traces the scene: the full renders (and the program's
    // frames) would spend minutes on the loop guard's 20 000 iterations a path; the probe
    // render of a few pixels finds it first. 60 s leaves room for a loaded machine (it took
    // 1.5 s and 6.7 s on lavapipe with 2 shared cores, over 120 s before the probe).
    let started = std::time::Instant::now();
    let report = expect_verdicts(
        "path_loop_continue_for_break.glsl",
        1,
        &[("get_ray_radiance", false)],
    );
    let function = &report["functions"][0];
    assert_eq!(function["method"], "loop limit", "{report}");
    let hint = function["hint"].as_str().expect("text");
    assert!(hint.contains("`continue` where a `break`"), "{hint}");
    assert!(!hint.contains("--"), "{hint}");

    // The same mistake in the workshop's whole tab: get_ray_radiance and the program fail.
    let dir = tempfile::tempdir().expect("temporary directory");
    let tab = std::fs::read_to_string(solution("programs/exercise7_tab.glsl")).expect("tab");
    let miss = "for (int i = 0; i != MAX_PATH_LENGTH; ++i) {\n        float t;\n        triangle_t tri;\n        if (!ray_mesh_intersection(t, tri, origin, direction))\n            break;";
    assert!(tab.contains(miss));
    let path = dir.path().join("continue_for_break.glsl");
    let endless = "for (int i = 0; i != MAX_PATH_LENGTH; ) {\n        float t;\n        triangle_t tri;\n        if (!ray_mesh_intersection(t, tri, origin, direction))\n            continue;\n        ++i;";
    std::fs::write(&path, tab.replace(miss, endless)).expect("write");
    let outcome = common::runs::check(
        dir.path(),
        &[path.display().to_string()],
        &["--json", "--frames", "8"],
        &[],
    );
    assert_eq!(outcome.code, Some(1), "{}", outcome.stderr);
    let report = outcome.json();
    let program = common::runs::verdict(&report, "program").expect("program verdict");
    assert_eq!(program["method"], "loop limit", "{report}");
    assert!(!program["hint"].as_str().expect("text").contains("--"));
    assert!(
        started.elapsed() < std::time::Duration::from_secs(60),
        "{:?}",
        started.elapsed()
    );
}

#[test]
fn a_program_whose_types_live_in_the_common_tab_is_told_to_pass_it_first() {
    // The workshop's tab with its struct moved to a Common tab. Function mode compiles without
    // it (vkpath declares the workshop's triangle_t), the program does not: its compile error
    // must say what function mode says, at the tab's own line.
    let dir = tempfile::tempdir().expect("temporary directory");
    let tab = std::fs::read_to_string(solution("programs/exercise7_tab.glsl")).expect("tab");
    let start = tab
        .find("// A triangle with its shading attributes")
        .expect("struct");
    let end = start + tab[start..].find("};\n").expect("struct end") + 3;
    let image = dir.path().join("image_tab.glsl");
    let common = dir.path().join("types_common.glsl");
    std::fs::write(&image, format!("{}{}", &tab[..start], &tab[end..])).expect("write");
    std::fs::write(&common, &tab[start..end]).expect("write");
    let (image, common) = (image.display().to_string(), common.display().to_string());
    let alone = common::runs::check(
        dir.path(),
        std::slice::from_ref(&image),
        &["--json", "--frames", "8"],
        &[],
    );
    assert_eq!(alone.code, Some(1), "{}", alone.stderr);
    let report = alone.json();
    let program = common::runs::verdict(&report, "program").expect("program verdict");
    assert_eq!(
        program["summary"],
        "does not compile as a ShaderToy program: 'triangle_t' is not defined in any of your files; if your program has a Common tab, pass it first",
        "{report}"
    );
    // ray_triangle_intersection's line in the user's file (28 in the whole tab, 7 lines up).
    let hint = program["hint"].as_str().expect("hint");
    assert!(hint.contains(&format!("{image}:21: error")), "{hint}");
    assert_eq!(
        report["functions"]
            .as_array()
            .expect("functions")
            .iter()
            .filter(|f| f["passed"] == false)
            .count(),
        1,
        "only the program fails: {report}"
    );
    // With its Common tab (given second: it goes first anyway) the program compiles.
    let both = common::runs::check(
        dir.path(),
        &[image, common],
        &["--json", "--frames", "8"],
        &[],
    );
    let report = both.json();
    let program = common::runs::verdict(&report, "program").expect("program verdict");
    assert_eq!(program["method"], "render", "{report}");
}
