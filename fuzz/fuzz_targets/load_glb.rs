//! The input as a `.glb` file (binary glTF: header, JSON chunk, BIN chunk; other buffers as
//! data URIs or files in its folder, which holds nothing else), loaded with
//! `vkpath::Scene::load`: it must not panic, hang or take unbounded memory, and an error must
//! be one line.
#![no_main]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;

/// A folder of this process's own for the input file.
fn folder() -> &'static Path {
    static FOLDER: OnceLock<PathBuf> = OnceLock::new();
    FOLDER.get_or_init(|| {
        let folder = std::env::temp_dir().join(format!("vkpath-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        folder
    })
}

fuzz_target!(|data: &[u8]| {
    let path = folder().join("scene.glb");
    std::fs::write(&path, data).unwrap();
    if let Err(error) = vkpath::Scene::load(&path) {
        let message = error.to_string();
        assert!(
            !message.contains(['\n', '\r']),
            "an error of several lines: {message:?}"
        );
    }
});
