//! `vkpath export`: writes a scene as PLY meshes and a JSON manifest (see `crate::scene::export`).

use std::path::PathBuf;

use super::options::SceneArgs;
use crate::medium::Medium;
use crate::scene::export::{export_scene, layers_of, LAYERS};
use crate::scene::files::LoadOptions;
use crate::scene::gltf_file::{is_gltf_path, GltfFile};
use crate::scene::source::SceneSource;

/// Arguments of `vkpath export`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExportArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Directory for scene.json and the mesh_<k>.ply files (created if missing).
    #[arg(long)]
    pub output_dir: PathBuf,
    /// The global homogeneous medium to record in scene.json ("medium"), as `render
    /// --medium` takes it: sigma_a=R,G,B:sigma_s=R,G,B:g=G (docs/media.md).
    #[arg(long, value_name = "sigma_a=R,G,B:sigma_s=R,G,B:g=G")]
    pub medium: Option<Medium>,
}

/// Runs `vkpath export`.
pub fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let scene = args.scene.load("vkpath export")?;
    let exported = export_scene(
        &scene,
        scene.camera.as_ref(),
        args.medium.as_ref(),
        &args.output_dir,
    )?;
    for file in exported.meshes.iter().chain([&exported.manifest]) {
        eprintln!("vkpath: wrote {}", file.display());
    }
    eprintln!(
        "vkpath export: {} triangles in {} meshes, {} punctual lights{}",
        scene.triangles.len(),
        exported.meshes.len(),
        scene.punctual_lights.len(),
        args.medium
            .map(|medium| format!(", medium {medium}"))
            .unwrap_or_default()
    );
    if let Some(note) = layers_note(&scene) {
        eprintln!("{note}");
    }
    if let Some(note) = animations_note(args)? {
        eprintln!("{note}");
    }
    Ok(())
}

/// One line saying that a glTF file's animations are not exported (PLY meshes hold one
/// pose: time 0, as `render` without `--time` shows), naming them. None for a file
/// without animations or a scene that is no glTF file.
fn animations_note(args: &ExportArgs) -> anyhow::Result<Option<String>> {
    let SceneSource::File(path) = args.scene.source() else {
        return Ok(None);
    };
    if !is_gltf_path(&path) {
        return Ok(None);
    }
    let file = GltfFile::open(
        &path,
        &LoadOptions {
            allow_external_paths: args.scene.allow_external_paths,
            variant: args.scene.variant.clone(),
            ..LoadOptions::default()
        },
    )?;
    let names = file.animation_names();
    Ok((!names.is_empty()).then(|| {
        let quoted: Vec<String> = names.iter().map(|n| format!("'{n}'")).collect();
        format!(
            "vkpath export: note: {} animation{} ({}) not exported: the meshes hold the pose at time 0 s",
            names.len(),
            if names.len() == 1 { " is" } else { "s are" },
            quoted.join(", ")
        )
    }))
}

/// One line naming the materials that use layers beyond metallic-roughness (glass, coats,
/// sheen, unlit), whose factors `scene.json` holds apart: a consumer reading only the base
/// factors would render them as something else. None when no material does.
fn layers_note(scene: &crate::scene::Scene) -> Option<String> {
    let materials = &scene.materials.as_ref()?.materials;
    let layered: Vec<String> = materials
        .iter()
        .enumerate()
        .filter_map(|(index, material)| {
            let layers = layers_of(material);
            (!layers.is_empty()).then(|| format!("material {index}: {}", layers.join(", ")))
        })
        .collect();
    (!layered.is_empty()).then(|| {
        format!(
            "vkpath export: note: layers beyond metallic-roughness are in scene.json's {} ({}); a reader of the base factors alone renders them as opaque plastic",
            quoted_list(&LAYERS),
            layered.join("; ")
        )
    })
}

/// Names quoted and listed as a sentence says them: `"a", "b" and "c"`.
fn quoted_list(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|name| format!("\"{name}\"")).collect();
    match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => quoted.join(""),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_layers_note_names_the_layers_as_before() {
        // The note's words from before the layers were one list (scene::export::LAYERS).
        assert_eq!(
            quoted_list(&LAYERS),
            r#""transmission", "clearcoat", "sheen" and "unlit""#
        );
        assert_eq!(quoted_list(&["a"]), r#""a""#);
        assert_eq!(quoted_list(&[]), "");
    }
}
