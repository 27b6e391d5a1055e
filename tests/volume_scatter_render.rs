//! KHR_materials_volume_scatter (a scattering medium inside a refracting glTF volume,
//! `Transmission::scattering`) rendered on lavapipe against closed forms, with
//! `SamplerKind::Pcg` (independent samples: per-pixel moments give honest standard errors).
//! The volumes are cubes of white glass of ior 1.001, nearly index-matched: ior 1 exactly is a
//! thin wall (`is_refracting()`: thickness above 0 and ior not 1), and at 1.001 Fresnel
//! reflects 2.5e-7 at normal incidence and the critical angle is 87.4 degrees.
//! - Unscattered light: with paths of 3 vertices (the entry, the exit, the environment), a
//!   path that scatters inside cannot reach the environment, so a cube of sigma_a and sigma_s
//!   seen head-on against an environment of 1 shows exp(-(sigma_a + sigma_s) d) per channel
//!   (the distance sampler's chromatic passing weights times Beer-Lambert); without the
//!   volume's medium it would show exp(-sigma_a d). (The furnaces below also pass where the
//!   volume does not scatter at all: this is the test that needs the scattering.)
//! - A white furnace: a non-absorbing chromatic volume (albedo 1) under an environment of 1
//!   shows 1 everywhere (cosine, nee, mis; g 0 and 0.7).
//! - The volume inside the global medium: the furnace box of tests/medium_render.rs (walls
//!   that emit 1 and reflect nothing, fog of albedo 1) around the scattering cube shows 1
//!   everywhere, which holds only if each refraction hands the path the right medium.

use crate::common;

use glam::{Vec2, Vec3, Vec4};
use vkpath::camera::Camera;
use vkpath::lights::environment_source::EnvironmentSource;
use vkpath::medium::Medium;
use vkpath::scene::materials::{PbrMaterial, SceneMaterials, Transmission, TriangleShading};
use vkpath::scene::Triangle;
use vkpath::{Integrator, RenderSettings, SamplerKind, Scene};

/// Triangles with flat normals and their materials.
#[derive(Default)]
struct MeshScene {
    triangles: Vec<Triangle>,
    shading: Vec<TriangleShading>,
    materials: Vec<PbrMaterial>,
}

impl MeshScene {
    fn material(&mut self, material: PbrMaterial) -> u32 {
        self.materials.push(material);
        self.materials.len() as u32 - 1
    }

    /// A quad a, b, c, d, counter-clockwise seen from its front.
    fn quad(&mut self, corners: [Vec3; 4], material: u32) {
        let pbr = self.materials[material as usize];
        for positions in [
            [corners[0], corners[1], corners[2]],
            [corners[0], corners[2], corners[3]],
        ] {
            let triangle = Triangle::new(
                positions,
                pbr.base_color.truncate(),
                pbr.emission,
                pbr.double_sided,
            )
            .unwrap();
            self.shading.push(TriangleShading {
                material,
                normals: [triangle.normal; 3],
                tex_coords: [Vec2::ZERO; 3],
                tangents: [Vec4::ZERO; 3],
            });
            self.triangles.push(triangle);
        }
    }

    /// The cube [-h, h]^3, its faces' fronts outward (or inward).
    fn cube(&mut self, h: f32, material: u32, inward: bool) {
        let c = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * h;
        let outward = [
            [
                c(-1., -1., -1.),
                c(-1., 1., -1.),
                c(1., 1., -1.),
                c(1., -1., -1.),
            ],
            [
                c(-1., -1., 1.),
                c(1., -1., 1.),
                c(1., 1., 1.),
                c(-1., 1., 1.),
            ],
            [
                c(-1., -1., -1.),
                c(1., -1., -1.),
                c(1., -1., 1.),
                c(-1., -1., 1.),
            ],
            [
                c(-1., 1., -1.),
                c(-1., 1., 1.),
                c(1., 1., 1.),
                c(1., 1., -1.),
            ],
            [
                c(-1., -1., -1.),
                c(-1., -1., 1.),
                c(-1., 1., 1.),
                c(-1., 1., -1.),
            ],
            [
                c(1., -1., -1.),
                c(1., 1., -1.),
                c(1., 1., 1.),
                c(1., -1., 1.),
            ],
        ];
        for [a, b, cc, d] in outward {
            self.quad(if inward { [a, d, cc, b] } else { [a, b, cc, d] }, material);
        }
    }

    fn build(self, camera: Camera, environment: Option<Vec3>) -> Scene {
        Scene {
            triangles: self.triangles,
            camera: Some(camera),
            warnings: Vec::new(),
            punctual_lights: Vec::new(),
            environment: None,
            cameras: Vec::new(),
            mesh_instances: Vec::new(),
            motion: None,
            materials: Some(SceneMaterials {
                materials: self.materials,
                textures: Vec::new(),
                triangles: self.shading,
                ..Default::default()
            }),
        }
        .with_environment(environment.map(EnvironmentSource::Background).as_ref())
        .unwrap()
    }
}

/// White smooth glass of ior 1.001 enclosing a medium of `absorption` and `scattering` per
/// unit length with Henyey-Greenstein `anisotropy`.
fn scattering_glass(absorption: Vec3, scattering: Vec3, anisotropy: f32) -> PbrMaterial {
    let mut material = PbrMaterial::lambertian(Vec3::ONE, Vec3::ZERO, false);
    material.roughness = 0.0;
    material.specular = 1.0;
    material.ior = 1.001;
    material.transmission = Transmission {
        factor: 1.0,
        thickness: 1.0,
        attenuation: absorption,
        scattering,
        anisotropy,
        ..Transmission::default()
    };
    material
}

fn settings(integrator: Integrator, max_path_length: u32, spp: u32) -> RenderSettings {
    RenderSettings {
        width: 16,
        height: 16,
        spp,
        samples_per_frame: spp,
        integrator,
        sampler: SamplerKind::Pcg,
        max_path_length,
        russian_roulette_start: 2,
        seed: 7,
        ..Default::default()
    }
}

#[test]
fn unscattered_light_through_a_scattering_volume_is_exp_minus_sigma_t_d() {
    let absorption = Vec3::new(0.1, 0.05, 0.0);
    let scattering = Vec3::new(0.2, 0.5, 1.0);
    let mut builder = MeshScene::default();
    let glass = builder.material(scattering_glass(absorption, scattering, 0.5));
    builder.cube(1.0, glass, false);
    // Head-on through the cube (d = 2) within 0.3 degrees of its axis
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 0.01);
    let scene = builder.build(camera, Some(Vec3::ONE));
    let expected = (-(absorption + scattering) * 2.0).exp();
    // mis only: no light samples are taken inside glass, so cosine, nee and mis estimate
    // this alike (the furnace below runs all three)
    let spp = 256;
    let image = common::render_scene(&scene, settings(Integrator::Mis, 3, spp));
    common::assert_mean(&image, spp, expected, "unscattered");
}

#[test]
fn a_scattering_volume_in_a_white_furnace_stays_white() {
    // Albedo 1 per channel, a different density in each. Paths of 32 vertices: a segment
    // inside the cube (at most 2 sqrt(3) long) scatters with probability at most
    // 1 - exp(-0.35 * 3.46) = 0.70, so a path is cut short with probability at most
    // 0.70^29 = 3e-5, far below the test's resolution.
    let scattering = Vec3::new(0.15, 0.25, 0.35);
    for (anisotropy, integrators) in [
        (
            0.0,
            &[Integrator::Cosine, Integrator::Nee, Integrator::Mis][..],
        ),
        (0.7, &[Integrator::Mis][..]),
    ] {
        let mut builder = MeshScene::default();
        let glass = builder.material(scattering_glass(Vec3::ZERO, scattering, anisotropy));
        builder.cube(1.0, glass, false);
        let camera = Camera::look_at(Vec3::new(0.6, 0.8, 3.0), Vec3::ZERO, Vec3::Y, 0.9);
        let scene = builder.build(camera, Some(Vec3::ONE));
        for &integrator in integrators {
            let spp = 64;
            let image = common::render_scene(&scene, settings(integrator, 32, spp));
            common::assert_mean(
                &image,
                spp,
                Vec3::ONE,
                &format!("volume furnace g {anisotropy} {integrator:?}"),
            );
        }
    }
}

#[test]
fn a_scattering_volume_inside_fog_stays_white() {
    // The furnace box [-1, 1]^3 (inward walls: albedo 0, emission 1) full of fog of albedo 1,
    // the scattering cube [-0.4, 0.4]^3 inside it. Paths of 48 vertices (64 would loop more
    // than llvmpipe allows one invocation over these 24 triangles): a segment scatters with
    // probability at most 1 - exp(-0.4 * 3.46) = 0.75 (fog) or 1 - exp(-0.8 * 1.39) = 0.67
    // (cube), so a path is cut short with probability at most 0.75^44 = 3e-6.
    let mut builder = MeshScene::default();
    let wall = builder.material(PbrMaterial::lambertian(Vec3::ZERO, Vec3::ONE, false));
    builder.cube(1.0, wall, true);
    let glass = builder.material(scattering_glass(Vec3::ZERO, Vec3::new(0.8, 0.5, 0.3), -0.3));
    builder.cube(0.4, glass, false);
    let camera = Camera::look_at(Vec3::new(0.1, -0.9, 0.15), Vec3::ZERO, Vec3::Z, 1.0);
    let scene = builder.build(camera, None);
    let fog = Medium {
        absorption: Vec3::ZERO,
        scattering: Vec3::new(0.4, 0.3, 0.2),
        anisotropy: 0.3,
    };
    // mis: its light samples at fog vertices and MIS against the phase function (the
    // furnaces above cover cosine and nee)
    let spp = 32;
    let image = common::render_scene(
        &scene,
        RenderSettings {
            medium: Some(fog),
            ..settings(Integrator::Mis, 48, spp)
        },
    );
    common::assert_mean(&image, spp, Vec3::ONE, "volume in fog");
}
