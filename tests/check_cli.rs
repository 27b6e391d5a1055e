//! `vkpath check` through the binary on the example solutions of tests/solutions/: correct
//! functions written differently from the workshop's must pass, the typical mistakes must
//! fail with the right function named, and unusable files must be usage errors. Every run
//! has the validation layer on (the binary fails if it reports anything). Renders are small
//! (32 x 32 at 256 spp) to keep the suite fast on lavapipe.

mod common;

use std::path::Path;

use serde_json::Value;

/// The outcome of one `vkpath check`.
struct Outcome {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

impl Outcome {
    /// The JSON report (runs with `--json`).
    fn json(&self) -> Value {
        serde_json::from_str(&self.stdout)
            .unwrap_or_else(|e| panic!("not JSON ({e}): {}\n{}", self.stdout, self.stderr))
    }
}

fn solution(name: &str) -> String {
    format!("{}/tests/solutions/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Runs `vkpath check` on a solution in a temporary directory, with small renders.
fn check(dir: &Path, name: &str, extra: &[&str]) -> Outcome {
    let file = solution(name);
    let mut args = vec![
        "check",
        &file,
        "--validate",
        "--size",
        "32",
        "--spp",
        "256",
        "--output-dir",
        "out",
    ];
    args.extend_from_slice(extra);
    let output = common::vkpath(dir, &args);
    let outcome = Outcome {
        code: output.status.code(),
        stdout: String::from_utf8_lossy(&output.stdout).into(),
        stderr: String::from_utf8_lossy(&output.stderr).into(),
    };
    assert!(
        !outcome.stderr.contains("panicked"),
        "{name} panicked: {}",
        outcome.stderr
    );
    outcome
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
        !outcome.stdout.contains("user_functions.glsl"),
        "{}",
        outcome.stdout
    );
    let json = check(dir.path(), "compile_error.glsl", &["--json"]).json();
    assert!(json["compile_errors"]
        .as_str()
        .expect("text")
        .contains(&expected));
    assert_eq!(json["passed"], false);
}

#[test]
fn wrong_signature_is_reported() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let outcome = check(dir.path(), "wrong_signature.glsl", &[]);
    assert_eq!(
        outcome.code,
        Some(1),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    assert!(
        outcome
            .stdout
            .contains("wrong_signature.glsl:3: error: sample_sphere is defined as vec3 (vec3)"),
        "{}",
        outcome.stdout
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
