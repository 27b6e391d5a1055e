//! Scenes built in code that several integration tests render.

use glam::{Vec2, Vec3, Vec4};
use vkpath::scene::materials::{PbrMaterial, SceneMaterials, TextureBinding, TriangleShading};
use vkpath::scene::textures::{Texture, TextureTransform, WrapMode};
use vkpath::scene::Triangle;
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

/// The test glTF's open box (`tests/data/emissive_quad.gltf`), its triangles' shading for
/// three materials (0 the emitting quad, 1 the floor, 2 the walls; flat normals, texture
/// coordinates from `tex_coords`) and its light triangle.
fn open_box(
    tex_coords: impl Fn(&Triangle) -> [Vec2; 3],
) -> (Scene, Vec<TriangleShading>, Triangle) {
    let scene = Scene::load(std::path::Path::new(&super::fixture("emissive_quad.gltf"))).unwrap();
    let shading = scene
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
            tex_coords: tex_coords(t),
            tangents: [Vec4::ZERO; 3],
        })
        .collect();
    let light = *scene
        .triangles
        .iter()
        .find(|t| t.emission.max_element() > 0.0)
        .unwrap();
    (scene, shading, light)
}

/// The test glTF's open box (`tests/data/emissive_quad.gltf`) with glossy glTF materials:
/// gold metal walls, a red plastic floor, both of `roughness`; no layered lobes.
pub fn glossy_box(roughness: f32) -> Scene {
    let (mut scene, shading, light) = open_box(|_| [Vec2::ZERO; 3]);
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
        ..Default::default()
    });
    scene
}

/// The test glTF's open box (`tests/data/emissive_quad.gltf`) with Lambertian glTF materials
/// (metallic and specular 0): the floor textured by a 4x4 sRGB checker of colours
/// (bilinear, repeated), the walls grey, the quad emitting. Texture coordinates are the
/// vertices' x and z, so the floor shows the texture about twice.
pub fn textured_lambertian_box() -> Scene {
    let (mut scene, shading, light) = open_box(|t| t.positions.map(|p| Vec2::new(p.x, p.z)));
    let mut floor = PbrMaterial::lambertian(Vec3::ONE, Vec3::ZERO, false);
    floor.base_color_texture = Some(TextureBinding::new(0, TextureTransform::identity()));
    let checker = Texture {
        width: 4,
        height: 4,
        texels: (0..16u8)
            .map(|i| [40 + i * 12, 230 - i * 9, (i % 3) * 100, 255])
            .collect(),
        wrap_s: WrapMode::Repeat,
        wrap_t: WrapMode::Repeat,
        nearest: false,
    };
    scene.materials = Some(SceneMaterials {
        materials: vec![
            PbrMaterial::lambertian(Vec3::ZERO, light.emission, light.double_sided),
            floor,
            PbrMaterial::lambertian(Vec3::splat(0.6), Vec3::ZERO, false),
        ],
        textures: vec![checker],
        triangles: shading,
        ..Default::default()
    });
    scene
}
