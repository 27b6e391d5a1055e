//! `vkpath bench` end to end: its JSON names the scene, traversal, sampler and light
//! sampling, and reports finite, positive figures for every integrator asked for, against
//! the reference.

use crate::common;

use serde_json::Value;

fn bench(args: &[&str]) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let mut full = vec![
        "bench",
        "--width",
        "16",
        "--height",
        "16",
        "--spp",
        "4",
        "--reference-spp",
        "16",
        "--repeats",
        "1",
        "--json",
    ];
    full.extend_from_slice(args);
    let output = common::vkpath(dir.path(), &full);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{args:?}: {stderr}");
    serde_json::from_slice(&output.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

fn check_results(report: &Value, integrators: &[&str]) {
    let results = report["results"].as_array().unwrap();
    let names: Vec<&str> = results
        .iter()
        .map(|r| r["integrator"].as_str().unwrap())
        .collect();
    assert_eq!(names, integrators);
    for result in results {
        for key in [
            "samples_per_second",
            "rays_per_second",
            "relative_mse",
            "efficiency",
        ] {
            let value = result[key].as_f64().unwrap();
            assert!(
                value.is_finite() && value > 0.0,
                "{key} = {value} in {result}"
            );
        }
        // A path traces at least its camera ray.
        assert!(result["rays_per_second"].as_f64() >= result["samples_per_second"].as_f64());
    }
}

#[test]
fn cornell_box_bench_uses_constant_triangles() {
    let report = bench(&["--integrators", "workshop,mis", "--sampler", "sobol"]);
    assert_eq!(report["triangle_count"], 30);
    assert_eq!(report["traversal"], "constant triangles");
    assert_eq!(report["sampler"], "sobol");
    assert_eq!(report["light_sampling"], "solid-angle");
    check_results(&report, &["workshop", "mis"]);
}

#[test]
fn bench_reports_area_light_sampling() {
    let report = bench(&["--integrators", "nee", "--light-sampling", "area"]);
    assert_eq!(report["light_sampling"], "area");
    check_results(&report, &["nee"]);
}

#[test]
fn generated_scene_bench_uses_the_bvh() {
    let report = bench(&["--generated", "2000", "--integrators", "cosine"]);
    let triangles = report["triangle_count"].as_u64().unwrap();
    assert!((1900..=2100).contains(&triangles), "{triangles} triangles");
    // auto's BVH: the compressed tree
    assert_eq!(report["traversal"], "compressed BVH");
    check_results(&report, &["cosine"]);
}

/// `bench --startup` runs whole `vkpath render` processes (in temp cache directories of its
/// own) and reports every configuration's cold and warm seconds; what they are is a
/// measurement, so only their being there, finite and positive is checked.
#[test]
fn startup_bench_reports_cold_and_warm_runs_of_both_kernels() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "bench",
        "--startup",
        "--width",
        "8",
        "--height",
        "8",
        "--json",
    ];
    let output = common::vkpath(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let report: Value = serde_json::from_slice(&output.stdout).unwrap();
    let results = report.as_array().unwrap();
    assert_eq!(results.len(), 2, "{report}");
    assert!(results[1]["what"]
        .as_str()
        .unwrap()
        .ends_with("--background 1,1,1"));
    for result in results {
        for key in [
            "cold_seconds",
            "warm_seconds",
            "warm_no_cache_seconds",
            "cold_over_warm",
        ] {
            let value = result[key].as_f64().unwrap();
            assert!(
                value.is_finite() && value > 0.0,
                "{key} = {value} in {result}"
            );
        }
        for setup in result["setup_seconds"].as_array().unwrap() {
            let value = setup.as_f64().unwrap();
            assert!(
                value.is_finite() && value > 0.0,
                "setup {value} in {result}"
            );
        }
    }
}

/// A stored reference (`--reference`) is measured against as the bench's own would be: the
/// same render written by `vkpath render --moments` (the bench's reference seed, 0x5eed =
/// 24301, and settings) gives the same relMSE to the last bit, and the report names the
/// file, its spp and the relMSE its noise adds. A reference of another size is refused.
#[test]
fn a_stored_reference_measures_as_the_benchs_own() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("reference.exr");
    let output = common::vkpath(
        dir.path(),
        &[
            "render",
            "--width",
            "16",
            "--height",
            "16",
            "--spp",
            "16",
            "--integrator",
            "mis",
            "--sampler",
            "pcg",
            "--seed",
            "24301",
            "--moments",
            "--quiet",
            "-o",
            reference.to_str().unwrap(),
        ],
    );
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let own = bench(&["--integrators", "mis"]);
    let stored = |width: &str| {
        let args = [
            "bench",
            "--width",
            width,
            "--height",
            "16",
            "--spp",
            "4",
            "--repeats",
            "1",
            "--json",
            "--integrators",
            "mis",
            "--reference",
            reference.to_str().unwrap(),
        ];
        common::vkpath(dir.path(), &args)
    };
    let output = stored("16");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let report: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(own["reference"], "mis");
    assert_eq!(report["reference"], reference.to_str().unwrap());
    assert_eq!(report["reference_spp"], 16);
    assert_eq!(
        report["results"][0]["relative_mse"],
        own["results"][0]["relative_mse"]
    );
    assert_eq!(
        report["reference_noise_relative_mse"],
        own["reference_noise_relative_mse"]
    );
    let noise = report["reference_noise_relative_mse"].as_f64().unwrap();
    assert!(noise > 0.0 && noise.is_finite(), "{report}");
    let wrong = stored("8");
    assert!(!wrong.status.success());
    let stderr = String::from_utf8_lossy(&wrong.stderr);
    assert!(
        stderr.contains("reference") && stderr.contains("16x16"),
        "{stderr}"
    );
}
