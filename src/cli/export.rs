//! `vkpath export`: writes a scene as PLY meshes and a JSON manifest (see `crate::scene::export`).

use std::path::PathBuf;

use super::render::load_scene_source;
use crate::scene::export::export_scene;

/// Arguments of `vkpath export`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExportArgs {
    /// Scene file (.gltf, .glb or .obj); the workshop's Cornell box when omitted.
    pub scene: Option<PathBuf>,
    /// Instead of a scene file: the generated scale-test scene of about this many triangles.
    #[arg(long, conflicts_with = "scene")]
    pub generated: Option<usize>,
    /// Directory for scene.json and the mesh_<k>.ply files (created if missing).
    #[arg(long)]
    pub output_dir: PathBuf,
}

/// Runs `vkpath export`.
pub fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let scene = load_scene_source(args.scene.as_deref(), args.generated, "vkpath export")?;
    let manifest = export_scene(&scene, scene.camera.as_ref(), &args.output_dir)?;
    eprintln!(
        "vkpath export: {} triangles -> {}",
        scene.triangles.len(),
        manifest.display()
    );
    Ok(())
}
