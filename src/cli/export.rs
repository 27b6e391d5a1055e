//! `vkpath export`: writes a scene as PLY meshes and a JSON manifest (see `crate::scene::export`).

use std::path::PathBuf;

use super::options::SceneArgs;
use crate::scene::export::export_scene;

/// Arguments of `vkpath export`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExportArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Directory for scene.json and the mesh_<k>.ply files (created if missing).
    #[arg(long)]
    pub output_dir: PathBuf,
}

/// Runs `vkpath export`.
pub fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let scene = args.scene.load("vkpath export")?;
    let exported = export_scene(&scene, scene.camera.as_ref(), &args.output_dir)?;
    for file in exported.meshes.iter().chain([&exported.manifest]) {
        eprintln!("vkpath: wrote {}", file.display());
    }
    eprintln!(
        "vkpath export: {} triangles in {} meshes, {} punctual lights",
        scene.triangles.len(),
        exported.meshes.len(),
        scene.punctual_lights.len()
    );
    Ok(())
}
