//! `render --medium` through the binary: bad coefficients, g outside (-1, 1), text that is no
//! medium and a medium with the workshop's integrator are each one error line, exit 2, with
//! nothing written; a fog render with mis writes its image and records the medium; `export
//! --medium` writes it into scene.json, and refuses a bad one as `render` does.

use crate::common;

/// Runs `render` with `args` in a fresh directory and expects the usage error `needle`.
fn expect_usage_error(args: &[&str], needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let mut full = vec![
        "render", "-o", "out.exr", "--width", "8", "--height", "8", "--spp", "1",
    ];
    full.extend_from_slice(args);
    let output = common::vkpath(dir.path(), &full);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(errors.len(), 1, "{args:?}: one error line, got {stderr}");
    assert!(errors[0].contains(needle), "{args:?}: {stderr}");
    assert!(
        std::fs::read_dir(dir.path()).unwrap().next().is_none(),
        "{args:?} wrote a file"
    );
}

#[test]
fn bad_media_are_one_line_usage_errors() {
    for (medium, needle) in [
        ("sigma_a=-0.1", "sigma_a has -0.1"),
        ("sigma_s=1,NaN,1", "sigma_s has NaN"),
        ("sigma_s=inf", "sigma_s has inf"),
        ("sigma_s=1:g=1", "g=1"),
        ("sigma_s=1:g=-2", "g=-2"),
        ("sigma_s=1,2", "one number for all channels or three"),
        ("fog", "is not one of"),
    ] {
        expect_usage_error(&["--integrator", "mis", "--medium", medium], needle);
    }
    expect_usage_error(
        &["--integrator", "workshop", "--medium", "sigma_s=1"],
        "--integrator workshop renders no media",
    );
}

#[test]
fn a_fog_render_records_its_medium() {
    let dir = tempfile::tempdir().unwrap();
    let output = common::vkpath(
        dir.path(),
        &[
            "render",
            "-o",
            "fog.exr",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "2",
            "--integrator",
            "mis",
            "--medium",
            "sigma_a=0.1:sigma_s=1,2,3:g=0.5",
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let exr = std::fs::read(dir.path().join("fog.exr")).unwrap();
    let needle = b"sigma_a=0.1,0.1,0.1:sigma_s=1,2,3:g=0.5";
    assert!(
        exr.windows(needle.len()).any(|w| w == needle),
        "the EXR's metadata should record the medium"
    );
}

#[test]
fn export_writes_the_medium_into_the_manifest() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = |name: &str| -> serde_json::Value {
        let text = std::fs::read_to_string(dir.path().join(name).join("scene.json")).unwrap();
        serde_json::from_str(&text).unwrap()
    };
    let export = |args: &[&str]| common::vkpath(dir.path(), args);
    let output = export(&[
        "export",
        "--output-dir",
        "fog",
        "--medium",
        "sigma_a=0.1:sigma_s=0.25,0.5,1:g=-0.3",
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let medium = &manifest("fog")["medium"];
    assert_eq!(medium["sigma_a"], serde_json::json!([0.1, 0.1, 0.1]));
    assert_eq!(medium["sigma_s"], serde_json::json!([0.25, 0.5, 1.0]));
    assert_eq!(medium["g"], serde_json::json!(-0.3));
    // Without --medium: null, so that a reader can tell "no medium" from an old manifest.
    let output = export(&["export", "--output-dir", "clear"]);
    assert!(output.status.success());
    assert!(manifest("clear")["medium"].is_null());
    // A bad medium: one usage error line, exit 2, no directory made.
    let output = export(&["export", "--output-dir", "bad", "--medium", "sigma_s=1:g=1"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("g=1"), "{stderr}");
    assert!(!dir.path().join("bad").exists());
}
