//! The input as an OBJ file and its MTL library, loaded with `vkpath::Scene::load`: it must
//! not panic, hang or take unbounded memory, and an error must be one line.
//!
//! The input is `OBJ` or `OBJ SEPARATOR MTL` with `SEPARATOR` = `\n#--mtl--\n`: the part
//! before it is written as scene.obj, the part after as scene.mtl (which the OBJ names with
//! `mtllib scene.mtl`; the seed corpus does).
#![no_main]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;

/// Between the OBJ and the MTL text in an input.
const SEPARATOR: &[u8] = b"\n#--mtl--\n";

/// A folder of this process's own for the input files.
fn folder() -> &'static Path {
    static FOLDER: OnceLock<PathBuf> = OnceLock::new();
    FOLDER.get_or_init(|| {
        let folder = std::env::temp_dir().join(format!("vkpath-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        folder
    })
}

fuzz_target!(|data: &[u8]| {
    let (obj, mtl) = match data.windows(SEPARATOR.len()).position(|w| w == SEPARATOR) {
        Some(at) => (&data[..at], Some(&data[at + SEPARATOR.len()..])),
        None => (data, None),
    };
    let path = folder().join("scene.obj");
    let library = folder().join("scene.mtl");
    std::fs::write(&path, obj).unwrap();
    match mtl {
        Some(mtl) => std::fs::write(&library, mtl).unwrap(),
        None => {
            let _ = std::fs::remove_file(&library);
        }
    }
    if let Err(error) = vkpath::Scene::load(&path) {
        let message = error.to_string();
        assert!(
            !message.contains(['\n', '\r']),
            "an error of several lines: {message:?}"
        );
    }
});
