//! Scenes built in code that several integration tests render.

use glam::{Vec2, Vec3, Vec4};
use vkpath::scene::materials::{PbrMaterial, SceneMaterials, TriangleShading};
use vkpath::Scene;

/// A white metal (base colour 1, F = 1) of the given roughness.
pub fn white_metal(roughness: f32) -> PbrMaterial {
    PbrMaterial {
        metallic: 1.0,
        roughness,
        specular: 1.0,
        ..PbrMaterial::lambertian(Vec3::ONE, Vec3::ZERO, false)
    }
}

/// The test glTF's open box (`tests/data/emissive_quad.gltf`) with glossy glTF materials:
/// gold metal walls, a red plastic floor, both of `roughness`; no layered lobes.
pub fn glossy_box(roughness: f32) -> Scene {
    let mut scene =
        Scene::load(std::path::Path::new(&super::fixture("emissive_quad.gltf"))).unwrap();
    let shading: Vec<TriangleShading> = scene
        .triangles
        .iter()
        .map(|t| TriangleShading {
            material: if t.emission.max_element() > 0.0 {
                0
            } else if t.normal.y > 0.5 {
                1
            } else {
                2
            },
            normals: [t.normal; 3],
            tex_coords: [Vec2::ZERO; 3],
            tangents: [Vec4::ZERO; 3],
        })
        .collect();
    let light = scene
        .triangles
        .iter()
        .find(|t| t.emission.max_element() > 0.0)
        .unwrap();
    let mut plastic = PbrMaterial::lambertian(Vec3::new(0.7, 0.2, 0.2), Vec3::ZERO, false);
    plastic.specular = 1.0;
    plastic.roughness = roughness;
    let mut metal = white_metal(roughness);
    metal.base_color = Vec4::new(0.9, 0.8, 0.5, 1.0);
    scene.materials = Some(SceneMaterials {
        materials: vec![
            PbrMaterial::lambertian(Vec3::ZERO, light.emission, light.double_sided),
            plastic,
            metal,
        ],
        textures: Vec::new(),
        triangles: shading,
    });
    scene
}
