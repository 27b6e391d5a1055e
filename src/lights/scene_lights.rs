//! Every light of a scene as the renderer uploads it: the emissive triangles (as a table
//! over the triangles in the order they are uploaded), the environment and the punctual
//! lights, with the words of each that the shaders read.

use super::emissive::EmissiveTriangles;
use super::environment::Environment;
use super::gpu_emissive::{
    gpu_light_bytes, gpu_light_bytes_with_tree, gpu_light_index_words, gpu_light_selection_words,
};
use super::gpu_environment::gpu_environment_words;
use super::gpu_punctual::gpu_punctual_light_words;
use super::light_tree::LightTree;
use super::punctual::PunctualLight;
use crate::scene::{Scene, Triangle};

/// The list of a scene's lights that the renderer uploads.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneLights<'a> {
    /// The emissive triangles, indexed in the order the triangles are uploaded (the BVH's
    /// leaf order when there is one).
    pub emissive: EmissiveTriangles,
    /// The light tree over them (`--light-selection tree`); `None`: the power CDF.
    pub tree: Option<LightTree>,
    /// What rays that leave the scene see; `None`: black.
    pub environment: Option<&'a Environment>,
    /// KHR_lights_punctual's lights.
    pub punctual: &'a [PunctualLight],
}

impl<'a> SceneLights<'a> {
    /// The lights of `scene`, whose triangles are uploaded as `triangles` (the scene's own
    /// or a reordering of them).
    pub fn new(scene: &'a Scene, triangles: &[Triangle]) -> SceneLights<'a> {
        SceneLights {
            emissive: EmissiveTriangles::new(triangles),
            tree: None,
            environment: scene.environment.as_ref(),
            punctual: &scene.punctual_lights,
        }
    }

    /// These lights with a light tree over the emissive triangles (none without them);
    /// `triangles` must be the ones this list was made with.
    pub fn with_light_tree(self, triangles: &[Triangle]) -> SceneLights<'a> {
        let tree = (!self.emissive.triangle_indices.is_empty())
            .then(|| LightTree::build(triangles, &self.emissive));
        SceneLights { tree, ..self }
    }

    /// The words of the selection buffer (`BINDING_LIGHT_SELECTION`), one per triangle this
    /// list was made with, in the same order: what MIS reads of each, its selection
    /// probability, or with a light tree its index in the light list.
    pub fn selection_words(&self) -> Vec<u32> {
        match &self.tree {
            None => gpu_light_selection_words(&self.emissive),
            Some(_) => gpu_light_index_words(&self.emissive),
        }
    }

    /// The bytes of the emissive triangles' texel buffer (`BINDING_LIGHTS`), with the tree's
    /// nodes where there is one.
    pub fn emissive_bytes(&self) -> Vec<u8> {
        match &self.tree {
            None => gpu_light_bytes(&self.emissive),
            Some(tree) => gpu_light_bytes_with_tree(&self.emissive, tree),
        }
    }

    /// The light searches' iterations per ray that the kernel counts (the loop bound,
    /// `get_light_search_iterations()` of `glsl/emissive_lights.glsl`): the power CDF's binary search
    /// (`crate::kernels::loops::light_search_iterations`), or with a tree two walks (a light
    /// sample's and an MIS weight's) of at most depth + 1 trips each.
    pub fn light_search_iterations(&self) -> u64 {
        match &self.tree {
            None => crate::kernels::loops::light_search_iterations(
                self.emissive.triangle_indices.len() as u64,
            ),
            Some(tree) => 2 * (u64::from(tree.depth) + 1),
        }
    }

    /// The words of the environment's texel buffer (`BINDING_ENVIRONMENT`).
    pub fn environment_words(&self) -> Vec<u32> {
        gpu_environment_words(self.environment)
    }

    /// Whether the environment gives light (`SCENE_HAS_ENVIRONMENT`; else its words say
    /// `ENVIRONMENT_NONE`).
    pub fn has_environment(&self) -> bool {
        self.environment.is_some_and(Environment::emits_light)
    }

    /// Whether next event estimation draws light samples from the environment
    /// (`SCENE_SAMPLES_ENVIRONMENT`): where it gives light and is a map. A constant
    /// environment is left to the paths' BSDF-sampled rays (`glsl/shared.h`).
    pub fn samples_environment(&self) -> bool {
        self.has_environment() && self.environment.is_some_and(|e| e.map.is_some())
    }

    /// The words of the punctual lights' texel buffer (`BINDING_PUNCTUAL_LIGHTS`).
    pub fn punctual_words(&self) -> Vec<u32> {
        gpu_punctual_light_words(self.punctual)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::environment::EnvironmentMap;
    use crate::lights::punctual::PunctualKind;
    use glam::{Mat4, Vec3};

    #[test]
    fn the_list_packs_each_kind_as_its_own_module_does() {
        let mut scene = Scene::builtin_cornell_box().unwrap();
        scene.environment = Some(Environment::constant(Vec3::splat(0.5)));
        scene.punctual_lights = vec![PunctualLight::new(
            PunctualKind::Point,
            Vec3::ONE,
            3.0,
            Mat4::from_translation(Vec3::Z),
        )
        .unwrap()];
        // Reversed, as a BVH might reorder them: the table follows the upload order.
        let reversed: Vec<Triangle> = scene.triangles.iter().rev().copied().collect();
        let lights = SceneLights::new(&scene, &reversed);
        assert_eq!(lights.emissive, EmissiveTriangles::new(&reversed));
        assert_ne!(lights.emissive, EmissiveTriangles::new(&scene.triangles));
        assert_eq!(lights.emissive_bytes(), gpu_light_bytes(&lights.emissive));
        assert_eq!(
            lights.environment_words(),
            gpu_environment_words(scene.environment.as_ref())
        );
        assert_eq!(
            lights.punctual_words(),
            gpu_punctual_light_words(&scene.punctual_lights)
        );
        assert_eq!(
            lights.selection_words(),
            gpu_light_selection_words(&lights.emissive)
        );
        assert_eq!(lights.selection_words().len(), reversed.len());
        let lights = lights.with_light_tree(&reversed);
        assert_eq!(
            lights.selection_words(),
            gpu_light_index_words(&lights.emissive)
        );
    }

    #[test]
    fn only_an_environment_map_that_gives_light_is_light_sampled() {
        let mut scene = Scene::builtin_cornell_box().unwrap();
        let samples =
            |scene: &Scene| SceneLights::new(scene, &scene.triangles).samples_environment();
        assert!(!samples(&scene), "no environment");
        scene.environment = Some(Environment::constant(Vec3::ONE));
        assert!(
            !samples(&scene),
            "a constant environment: BSDF sampling alone"
        );
        let map = |radiance: Vec3| EnvironmentMap {
            width: 2,
            height: 1,
            texels: vec![radiance; 2],
        };
        scene.environment = Some(Environment {
            map: Some(map(Vec3::ONE)),
            ..Environment::constant(Vec3::ZERO)
        });
        assert!(samples(&scene), "a map");
        scene.environment = Some(Environment {
            map: Some(map(Vec3::ZERO)),
            ..Environment::constant(Vec3::ZERO)
        });
        assert!(!samples(&scene), "a black map gives no light");
    }
}
