//! `scene_lights`' tests: each kind packed as its own module packs it, the digests kind by
//! kind, and the reuse counts' names.

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
    let lights = lights.with_light_tree(&reversed, LightKeys::STILL);
    assert_eq!(
        lights.selection_words(),
        gpu_light_index_words(&lights.emissive)
    );
}

#[test]
fn only_an_environment_map_that_gives_light_is_light_sampled() {
    let mut scene = Scene::builtin_cornell_box().unwrap();
    let samples = |scene: &Scene| SceneLights::new(scene, &scene.triangles).samples_environment();
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

#[test]
fn a_kind_is_kept_while_its_words_are_the_same() {
    let lit = |strength: f32| {
        let mut scene = Scene::builtin_cornell_box().unwrap();
        scene.environment = Some(Environment::constant(Vec3::splat(strength)));
        scene
    };
    let digest = |scene: &Scene| LightsDigest::of(scene, true);
    assert_eq!(digest(&lit(1.0)), digest(&lit(1.0)));
    assert_eq!(
        digest(&lit(1.0)).same(&digest(&lit(1.0))),
        SameLights::all()
    );
    // A brighter environment: the punctual lights (none) are still the same.
    let brighter = digest(&lit(1.0)).same(&digest(&lit(2.0)));
    assert_eq!(
        brighter,
        SameLights {
            environment: false,
            ..SameLights::all()
        }
    );
    let mut pointed = lit(1.0);
    pointed.punctual_lights =
        vec![PunctualLight::new(PunctualKind::Point, Vec3::ONE, 3.0, Mat4::IDENTITY).unwrap()];
    assert_eq!(
        digest(&lit(1.0)).same(&digest(&pointed)),
        SameLights {
            punctual: false,
            ..SameLights::all()
        }
    );
    // The workshop kernels read neither: every scene is alike to them.
    let workshop = |scene: &Scene| LightsDigest::of(scene, false);
    assert_eq!(workshop(&lit(1.0)), workshop(&pointed));
    assert_ne!(workshop(&lit(1.0)), digest(&lit(1.0)));
}

#[test]
fn reuse_is_named_kind_by_kind() {
    let before = LightReuse::default();
    let mut after = before;
    after.count(&KeptLightBuffers::default());
    assert_eq!(after.since(before).count(), 0);
    after.environment += 1;
    assert_eq!(after.since(before).collect::<Vec<_>>(), ["environment"]);
    after.punctual_lights += 1;
    assert_eq!(
        after.since(before).collect::<Vec<_>>(),
        ["environment", "punctual_lights"]
    );
}
