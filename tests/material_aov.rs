//! `--aov material` (vkpath::render::aov, INTEGRATOR_MATERIAL) against a CPU lookup of the
//! metallic-roughness texture: a quad with a small metallic-roughness texture (roughness in
//! G, metallic in B, different patterns; R and A junk that must be ignored), seen head-on at
//! 1 spp through pixel centres, must show at each pixel the factors times the CPU twin's
//! lookup (`vkpath::cpu::textures::sample_texture`) at the hit's uv, bilinear and nearest;
//! the workshop's Lambertian triangles show (0, 1, 0) in both kernels. This is the probe of
//! the metallic and roughness that the BRDF really gets at the camera's hits.

use crate::common;

use glam::{UVec4, Vec2, Vec3, Vec4};
use vkpath::camera::Camera;
use vkpath::cpu::textures::{sample_texture, unpack_texture_slot};
use vkpath::render::aov::{render_aov, Aov};
use vkpath::render::gpu_textures::GpuTextureSlot;
use vkpath::scene::materials::{PbrMaterial, SceneMaterials, TextureBinding, TriangleShading};
use vkpath::scene::textures::{Texture, TextureTransform, WrapMode};
use vkpath::scene::Triangle;
use vkpath::{PixelFilter, RenderSettings, Scene};

const WIDTH: u32 = 48;
const HEIGHT: u32 = 48;
const METALLIC_FACTOR: f32 = 0.8;
const ROUGHNESS_FACTOR: f32 = 0.9;

/// Largest difference allowed between the AOV and the CPU lookup on bilinear textures. The
/// lookups themselves agree bit for bit on linear textures (tests/texture_twins.rs); the
/// hit's uv differs from the CPU's by the rounding of the ray, the intersection and the
/// barycentrics (a few dozen ulps of numbers below 2: ~5e-6), which moves a bilinear value by
/// at most its gradient, one full texel step (1) per texel, 5 texels per unit of u here:
/// 2.5e-5. 1e-4 leaves a margin of 4; the measured difference is printed (lavapipe: 4.2e-7).
const BILINEAR_TOLERANCE: f32 = 1.0e-4;

/// Nearest textures: a texel times a factor, the same float product on both sides, so no
/// difference at all, except at pixels whose uv lies within rounding of a texel edge, which
/// are left out (closer than EDGE_MARGIN in texels).
const NEAREST_TOLERANCE: f32 = 0.0;
const EDGE_MARGIN: f32 = 1.0e-3;

/// A 5x3 metallic-roughness texture (not square, so that a transposed lookup is caught): G
/// (roughness) rises along x, B (metallic) alternates by row and column, R and A are
/// junk that the lookup must ignore.
fn metallic_roughness_texture(nearest: bool) -> Texture {
    let (width, height) = (5u32, 3u32);
    let texels = (0..height)
        .flat_map(|y| {
            (0..width).map(move |x| {
                let roughness = 30 + 50 * x as u8 + 7 * y as u8;
                let metallic = if (x + y) % 2 == 0 {
                    255
                } else {
                    40 + 60 * y as u8
                };
                [200 - 20 * x as u8, roughness, metallic, 90]
            })
        })
        .collect();
    Texture {
        width,
        height,
        texels,
        wrap_s: WrapMode::Repeat,
        wrap_t: WrapMode::MirroredRepeat,
        nearest,
    }
}

/// A scene of one quad in the plane z = 0, corners (±1, ±1), uv (0, 1) at (-1, -1) and
/// (1, 0) at (1, 1) (glTF's v downwards), with `material`; or the workshop's kernels'
/// Lambertian triangles when `material` is None.
fn quad_scene(material: Option<(PbrMaterial, Vec<Texture>)>, camera: Camera) -> Scene {
    let corners = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ];
    let uv = [
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(1.0, 0.0),
        Vec2::ZERO,
    ];
    let (mut triangles, mut shading) = (Vec::new(), Vec::new());
    for [i, j, k] in [[0, 1, 2], [0, 2, 3]] {
        let triangle = Triangle::new(
            [corners[i], corners[j], corners[k]],
            Vec3::splat(0.5),
            Vec3::ZERO,
            false,
        )
        .unwrap();
        shading.push(TriangleShading {
            material: 0,
            normals: [triangle.normal; 3],
            tex_coords: [uv[i], uv[j], uv[k]],
            tangents: [Vec4::ZERO; 3],
        });
        triangles.push(triangle);
    }
    Scene {
        triangles,
        camera: Some(camera),
        warnings: Vec::new(),
        punctual_lights: Vec::new(),
        environment: None,
        cameras: Vec::new(),
        mesh_instances: Vec::new(),
        motion: None,
        materials: material.map(|(material, textures)| SceneMaterials {
            materials: vec![material],
            textures,
            triangles: shading,
            ..Default::default()
        }),
    }
}

fn camera() -> (Vec3, Camera) {
    let position = Vec3::new(0.0, 0.0, 2.2);
    (
        position,
        Camera::look_at(position, Vec3::ZERO, Vec3::Y, 1.0),
    )
}

/// The material AOV at 1 spp through pixel centres, with the validation layer watching.
fn render_material_aov(scene: &Scene) -> Vec<[f32; 3]> {
    let context = common::validated_context();
    let settings = RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        spp: 1,
        pixel_filter: PixelFilter::Center,
        ..Default::default()
    };
    let pixels = render_aov(
        &context,
        scene,
        &scene.camera.unwrap(),
        &settings,
        Aov::Material,
    )
    .unwrap();
    common::assert_validation_silent(&context);
    pixels
}

/// The camera ray through pixel (x, y) (rows top-down) with the centre pixel filter.
fn pixel_ray(camera: &Camera, x: u32, y: u32) -> Vec3 {
    let plane = camera.image_plane(WIDTH as f32 / HEIGHT as f32);
    let u = (x as f32 + 0.5) / WIDTH as f32;
    let v = ((HEIGHT - 1 - y) as f32 + 0.5) / HEIGHT as f32;
    (plane.left_bottom + u * plane.right + v * plane.up - plane.camera_position).normalize()
}

/// Renders the quad with the texture and compares every pixel with the CPU lookup;
/// returns (compared pixels on the quad, pixels left out at edges, largest difference).
fn compare_with_cpu_lookup(nearest: bool, transform: TextureTransform) -> (u32, u32, f32) {
    let texture = metallic_roughness_texture(nearest);
    let mut material = PbrMaterial::lambertian(Vec3::splat(0.5), Vec3::ZERO, false);
    material.metallic = METALLIC_FACTOR;
    material.roughness = ROUGHNESS_FACTOR;
    material.specular = 1.0;
    material.metallic_roughness_texture = Some(TextureBinding::new(0, transform));
    let (position, camera) = camera();
    let scene = quad_scene(Some((material, vec![texture.clone()])), camera);
    let pixels = render_material_aov(&scene);
    // The slot as the renderer uploads it: metallic-roughness textures are linear (glTF
    // 2.0, 3.9.4), never sRGB.
    let words = GpuTextureSlot::new(0, &texture, false, &transform).to_texels();
    let slot = unpack_texture_slot(
        UVec4::from(words[0]),
        UVec4::from(words[1]),
        UVec4::from(words[2]),
    );
    let size = Vec2::new(texture.width as f32, texture.height as f32);
    let (mut compared, mut left_out, mut worst) = (0, 0, 0.0f32);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let direction = pixel_ray(&camera, x, y);
            let hit = position + (-position.z / direction.z) * direction;
            let actual = Vec3::from(pixels[(y * WIDTH + x) as usize]);
            let inside = hit.x.abs().max(hit.y.abs());
            if (inside - 1.0).abs() < 1.0e-4 {
                left_out += 1; // on the quad's edge: an ulp decides hit or miss
                continue;
            }
            let expected = if inside < 1.0 {
                let uv = Vec2::new((hit.x + 1.0) / 2.0, (1.0 - hit.y) / 2.0);
                if nearest {
                    // The transformed uv in texels: near an integer, an ulp picks the texel.
                    let [row0, row1] = transform.matrix;
                    let transformed = Vec2::new(
                        row0[0] * uv.x + row0[1] * uv.y + row0[2],
                        row1[0] * uv.x + row1[1] * uv.y + row1[2],
                    ) * size;
                    let distance = (transformed - transformed.round()).abs().min_element();
                    if distance < EDGE_MARGIN {
                        left_out += 1;
                        continue;
                    }
                }
                compared += 1;
                let texel = sample_texture(&texture.texels, &slot, uv);
                // glTF: roughness in G, metallic in B, each times its factor.
                Vec3::new(METALLIC_FACTOR * texel.z, ROUGHNESS_FACTOR * texel.y, 0.0)
            } else {
                Vec3::ZERO // the ray escapes
            };
            worst = worst.max((actual - expected).abs().max_element());
        }
    }
    (compared, left_out, worst)
}

#[test]
fn material_aov_shows_the_bilinear_metallic_roughness_lookup() {
    let (compared, left_out, worst) = compare_with_cpu_lookup(false, TextureTransform::identity());
    println!("bilinear: {compared} pixels on the quad ({left_out} left out at its edge), largest difference {worst:e}");
    assert!(compared > 900, "{compared}");
    assert!(worst <= BILINEAR_TOLERANCE, "largest difference {worst}");
}

#[test]
fn material_aov_shows_the_nearest_metallic_roughness_lookup_with_a_transform() {
    // KHR_texture_transform on the metallic-roughness slot: offset, rotation, tiling 1.5.
    let transform = TextureTransform::from_gltf([0.1, -0.2], 0.3, [1.5, 1.5]);
    let (compared, left_out, worst) = compare_with_cpu_lookup(true, transform);
    println!("nearest: {compared} pixels on the quad ({left_out} left out at edges), largest difference {worst:e}");
    assert!(compared > 900, "{compared}");
    assert!(worst <= NEAREST_TOLERANCE, "largest difference {worst}");
}

#[test]
fn lambertian_triangles_show_metallic_0_roughness_1_in_both_kernels() {
    // The workshop's kernels (no glTF materials: their triangles carry no metallic or
    // roughness) report glTF's Lambertian material, metallic 0 and roughness 1, which is
    // what the material kernels report for PbrMaterial::lambertian.
    let (_, camera) = camera();
    let lambertian = PbrMaterial::lambertian(Vec3::splat(0.5), Vec3::ZERO, false);
    for material in [None, Some((lambertian, Vec::new()))] {
        let kernels = if material.is_some() {
            "material"
        } else {
            "workshop"
        };
        let scene = quad_scene(material, camera);
        assert_eq!(scene.needs_material_kernels(), kernels == "material");
        let pixels = render_material_aov(&scene);
        let hits = pixels.iter().filter(|p| **p == [0.0, 1.0, 0.0]).count();
        let misses = pixels.iter().filter(|p| **p == [0.0; 3]).count();
        println!("{kernels} kernels: {hits} hits, {misses} misses");
        assert_eq!(hits + misses, pixels.len(), "{kernels} kernels");
        assert!(
            hits > 900 && misses > 400,
            "{kernels} kernels: {hits} {misses}"
        );
    }
}
