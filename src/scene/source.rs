//! Where a command's scene comes from: a file, the workshop's Cornell box, or the generated
//! scale-test scene of a given size.

use std::path::{Path, PathBuf};

use super::{meshes, Scene, SceneError};

/// Most triangles the generated scale-test scene may have (about 2 GB of scene data on the
/// host).
pub const MAX_GENERATED_TRIANGLES: usize = 20_000_000;

/// A scene, named but not yet loaded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneSource {
    /// A scene file (.gltf, .glb or .obj), see `Scene::load`.
    File(PathBuf),
    /// The workshop's Cornell box, see `Scene::builtin_cornell_box`.
    CornellBox,
    /// The scale-test scene of about this many triangles, see `meshes::scale_test_scene`.
    Generated(usize),
}

impl SceneSource {
    /// The source a command line names: the generated scene when `generated` is given, else
    /// the file, else the Cornell box.
    pub fn new(file: Option<&Path>, generated: Option<usize>) -> SceneSource {
        match (generated, file) {
            (Some(triangles), _) => SceneSource::Generated(triangles),
            (None, Some(path)) => SceneSource::File(path.to_path_buf()),
            (None, None) => SceneSource::CornellBox,
        }
    }

    /// Loads (or generates) the scene. Refuses more than `MAX_GENERATED_TRIANGLES`
    /// generated triangles before generating any.
    pub fn load(&self) -> Result<Scene, SceneError> {
        self.load_with(&super::files::LoadOptions::default())
    }

    /// `load` with options for reading files (see `Scene::load_with`).
    pub fn load_with(&self, options: &super::files::LoadOptions) -> Result<Scene, SceneError> {
        match self {
            SceneSource::File(path) => Scene::load_with(path, options),
            SceneSource::CornellBox => Scene::builtin_cornell_box(),
            SceneSource::Generated(triangles) if *triangles > MAX_GENERATED_TRIANGLES => {
                Err(SceneError::TooManyGeneratedTriangles {
                    requested: *triangles,
                    limit: MAX_GENERATED_TRIANGLES,
                })
            }
            SceneSource::Generated(triangles) => meshes::scale_test_scene(*triangles),
        }
    }

    /// What a report calls the scene: the file as given, "workshop Cornell box" or
    /// "generated scale-test scene".
    pub fn description(&self) -> String {
        match self {
            SceneSource::File(path) => path.display().to_string(),
            SceneSource::CornellBox => "workshop Cornell box".into(),
            SceneSource::Generated(_) => "generated scale-test scene".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_wins_then_file_then_cornell_box() {
        let file = Path::new("a.gltf");
        assert_eq!(
            SceneSource::new(Some(file), Some(10)),
            SceneSource::Generated(10)
        );
        assert_eq!(
            SceneSource::new(Some(file), None),
            SceneSource::File(file.into())
        );
        assert_eq!(SceneSource::new(None, None), SceneSource::CornellBox);
    }

    #[test]
    fn too_many_generated_triangles_are_refused_before_generating() {
        let error = SceneSource::Generated(MAX_GENERATED_TRIANGLES + 1)
            .load()
            .unwrap_err();
        assert_eq!(
            error.to_string(),
            format!(
                "--generated {}: at most {MAX_GENERATED_TRIANGLES} triangles",
                MAX_GENERATED_TRIANGLES + 1
            )
        );
    }

    #[test]
    fn the_cornell_box_loads_with_its_camera() {
        let scene = SceneSource::CornellBox.load().unwrap();
        assert!(scene.camera.is_some());
        assert!(!scene.triangles.is_empty());
    }
}
