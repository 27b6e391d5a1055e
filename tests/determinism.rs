//! The same scene, seed and spp give a bit-identical EXR on the same device, however the
//! samples are split into frames.

use crate::common;

#[test]
fn exr_is_bit_identical_whatever_the_samples_per_frame() {
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for samples_per_frame in ["1", "3", "7"] {
        let name = format!("spf{samples_per_frame}.exr");
        let output = common::vkpath(
            dir.path(),
            &[
                "render",
                "--integrator",
                "workshop",
                "-o",
                &name,
                "--width",
                "20",
                "--height",
                "12",
                "--spp",
                "7",
                "--seed",
                "42",
                "--samples-per-frame",
                samples_per_frame,
                "--moments",
            ],
        );
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        files.push(std::fs::read(dir.path().join(&name)).unwrap());
    }
    assert!(
        files[0] == files[1] && files[1] == files[2],
        "EXR files differ between frame splits"
    );
}

#[test]
fn different_seeds_give_different_images() {
    let dir = tempfile::tempdir().unwrap();
    for seed in ["1", "2"] {
        let output = common::vkpath(
            dir.path(),
            &[
                "render",
                "--integrator",
                "workshop",
                "-o",
                &format!("seed{seed}.exr"),
                "--width",
                "16",
                "--height",
                "16",
                "--spp",
                "2",
                "--seed",
                seed,
            ],
        );
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let a = std::fs::read(dir.path().join("seed1.exr")).unwrap();
    let b = std::fs::read(dir.path().join("seed2.exr")).unwrap();
    assert_ne!(a, b);
}
