//! Glass (KHR_materials_transmission, _volume, _ior) rendered on the GPU against closed
//! forms: a smooth glass sphere in a white furnace stays white (energy conservation, with
//! mis, nee and cosine at a long path length), rough glass never exceeds it and loses only
//! what single scattering loses, an absorbing slab seen head-on transmits the series of
//! Beer-Lambert and exact Fresnel terms, and a thin-walled pane transmits (1 - F) of what is
//! behind it, tinted by its base colour.

use crate::common;

use glam::{Vec2, Vec3, Vec4};
use vkpath::camera::Camera;
use vkpath::lights::environment_source::EnvironmentSource;
use vkpath::scene::materials::{PbrMaterial, SceneMaterials, Transmission, TriangleShading};
use vkpath::scene::Triangle;
use vkpath::{Integrator, PixelFilter, RenderSettings, RenderedImage, Scene};

/// Triangles with flat normals and materials.
#[derive(Default)]
struct MeshScene {
    triangles: Vec<Triangle>,
    shading: Vec<TriangleShading>,
    materials: Vec<PbrMaterial>,
}

impl MeshScene {
    /// A material's index.
    fn material(&mut self, material: PbrMaterial) -> u32 {
        self.materials.push(material);
        self.materials.len() as u32 - 1
    }

    /// One triangle, counter-clockwise from its front, with flat normals.
    fn triangle(&mut self, positions: [Vec3; 3], material: u32) {
        let pbr = self.materials[material as usize];
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

    /// A quad a, b, c, d (counter-clockwise from its front).
    fn quad(&mut self, corners: [Vec3; 4], material: u32) {
        self.triangle([corners[0], corners[1], corners[2]], material);
        self.triangle([corners[0], corners[2], corners[3]], material);
    }

    /// An outward-facing box between `low` and `high`.
    fn cuboid(&mut self, low: Vec3, high: Vec3, material: u32) {
        let corner = |x: usize, y: usize, z: usize| {
            Vec3::new([low.x, high.x][x], [low.y, high.y][y], [low.z, high.z][z])
        };
        let faces = [
            [
                corner(0, 0, 0),
                corner(0, 1, 0),
                corner(1, 1, 0),
                corner(1, 0, 0),
            ], // -z
            [
                corner(0, 0, 1),
                corner(1, 0, 1),
                corner(1, 1, 1),
                corner(0, 1, 1),
            ], // +z
            [
                corner(0, 0, 0),
                corner(1, 0, 0),
                corner(1, 0, 1),
                corner(0, 0, 1),
            ], // -y
            [
                corner(0, 1, 0),
                corner(0, 1, 1),
                corner(1, 1, 1),
                corner(1, 1, 0),
            ], // +y
            [
                corner(0, 0, 0),
                corner(0, 0, 1),
                corner(0, 1, 1),
                corner(0, 1, 0),
            ], // -x
            [
                corner(1, 0, 0),
                corner(1, 1, 0),
                corner(1, 1, 1),
                corner(1, 0, 1),
            ], // +x
        ];
        for face in faces {
            self.quad(face, material);
        }
    }

    /// A closed, outward-facing UV sphere of flat facets.
    fn sphere(&mut self, center: Vec3, radius: f32, segments: u32, rings: u32, material: u32) {
        let point = |ring: u32, segment: u32| {
            let theta = std::f32::consts::PI * ring as f32 / rings as f32;
            let phi = std::f32::consts::TAU * segment as f32 / segments as f32;
            center
                + radius
                    * Vec3::new(
                        theta.sin() * phi.cos(),
                        theta.cos(),
                        -theta.sin() * phi.sin(),
                    )
        };
        for ring in 0..rings {
            for segment in 0..segments {
                let (a, b) = (point(ring, segment), point(ring, segment + 1));
                let (c, d) = (point(ring + 1, segment), point(ring + 1, segment + 1));
                if ring != 0 {
                    self.triangle([a, c, b], material);
                }
                if ring != rings - 1 {
                    self.triangle([b, c, d], material);
                }
            }
        }
    }

    fn build(self, camera: Camera, background: Option<Vec3>) -> Scene {
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
        .with_environment(background.map(EnvironmentSource::Background).as_ref())
        .unwrap()
    }
}

/// White glass, a refracting volume of `ior` (no absorption unless `attenuation`).
fn glass(roughness: f32, ior: f32, attenuation: Vec3) -> PbrMaterial {
    let mut material = PbrMaterial::lambertian(Vec3::ONE, Vec3::ZERO, false);
    material.roughness = roughness;
    material.specular = 1.0;
    material.ior = ior;
    material.transmission = Transmission {
        factor: 1.0,
        thickness: 1.0,
        attenuation,
        ..Transmission::default()
    };
    material
}

use common::render_scene as render;

/// Mean and largest deviation from 1 of an image's red channel, and its pixels' largest value.
fn furnace_statistics(image: &RenderedImage) -> (f64, f64, f64) {
    let values: Vec<f64> = image.mean.iter().map(|p| f64::from(p[0])).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let worst = values.iter().map(|v| (v - 1.0).abs()).fold(0.0, f64::max);
    let largest = values.iter().copied().fold(f64::MIN, f64::max);
    (mean, worst, largest)
}

/// A faceted glass sphere of radius 1 filling most of a 24 x 24 view.
fn sphere_in_furnace(roughness: f32) -> Scene {
    sphere_in_furnace_with(roughness, 1.5)
}

fn sphere_in_furnace_with(roughness: f32, ior: f32) -> Scene {
    let mut builder = MeshScene::default();
    let material = builder.material(glass(roughness, ior, Vec3::ZERO));
    builder.sphere(
        Vec3::ZERO,
        1.0,
        SPHERE_SEGMENTS,
        SPHERE_SEGMENTS / 2,
        material,
    );
    let camera = Camera::look_at(Vec3::new(0.0, 0.3, 3.2), Vec3::ZERO, Vec3::Y, 0.75);
    builder.build(camera, Some(Vec3::ONE))
}

/// The path length of the furnace renders: refraction in and out and internal reflections.
const FURNACE_PATH_LENGTH: u32 = 16;
/// Facets around the furnace sphere's equator.
const SPHERE_SEGMENTS: u32 = 64;

#[test]
fn smooth_glass_in_a_white_furnace_stays_white() {
    // Every path that leaves the sphere sees radiance 1, and smooth glass loses nothing:
    // its weights are G2/G1 = 1 (alpha 10^-4) times the radiance scale 1/eta^2 of each
    // crossing, which the next crossing undoes, and Russian roulette divides that scale out
    // (survival 1). So no pixel may exceed 1, and what a pixel lacks is the light of paths
    // still inside the sphere after the last hit: a faceted sphere, unlike a round one,
    // totally reflects some rays that enter near its rim, which can then circle inside for
    // many hits (measured with cosine, 64 x 32 facets: the image mean is 0.9907 at path
    // length 16 and 0.9939 at 40; with ior 1.05, whose critical angle is 72 degrees,
    // 0.9980 and 0.99967). The loss must therefore shrink as paths grow longer.
    let scene = sphere_in_furnace(0.0);
    let settings = |integrator, max_path_length| RenderSettings {
        width: 24,
        height: 24,
        spp: 16,
        max_path_length,
        integrator,
        seed: 3,
        ..Default::default()
    };
    for integrator in [Integrator::Mis, Integrator::Nee, Integrator::PathTracing] {
        let image = render(&scene, settings(integrator, FURNACE_PATH_LENGTH));
        let (mean, worst, largest) = furnace_statistics(&image);
        println!("smooth glass, {integrator:?}, path length {FURNACE_PATH_LENGTH}: mean {mean:.6}, worst |L - 1| {worst:.2e}, largest {largest:.7}");
        // Float rounding only above 1 (G2/G1 and 1/eta^2 eta^2 are 1 within a few ulps).
        assert!(largest < 1.0 + 1e-4, "{integrator:?}: a pixel at {largest}");
        assert!(mean > 0.985, "{integrator:?}: mean {mean}");
    }
    let longer = render(&scene, settings(Integrator::PathTracing, 40));
    let (longer_mean, _, longer_largest) = furnace_statistics(&longer);
    let (shorter_mean, _, _) = furnace_statistics(&render(
        &scene,
        settings(Integrator::PathTracing, FURNACE_PATH_LENGTH),
    ));
    println!("smooth glass, cosine: mean {shorter_mean:.6} at path length {FURNACE_PATH_LENGTH}, {longer_mean:.6} at 40");
    assert!(longer_largest < 1.0 + 1e-4);
    assert!(
        longer_mean > shorter_mean,
        "{longer_mean} <= {shorter_mean}"
    );
}

#[test]
fn rough_glass_in_a_white_furnace_never_exceeds_one() {
    // A single-scattering microfacet BTDF loses the light that would scatter again among the
    // microfacets (no multiple-scattering compensation): the sphere's pixels stay below 1
    // (within noise) and lose more as the roughness grows.
    let mut previous_loss = 0.0;
    for roughness in [0.3f32, 0.7] {
        let image = render(
            &sphere_in_furnace(roughness),
            RenderSettings {
                width: 24,
                height: 24,
                spp: 64,
                max_path_length: FURNACE_PATH_LENGTH,
                integrator: Integrator::Mis,
                seed: 5,
                ..Default::default()
            },
        );
        let variance = image.variance_of_mean();
        let (mean, _, _) = furnace_statistics(&image);
        let worst_excess = image
            .mean
            .iter()
            .zip(&variance)
            .map(|(p, v)| (f64::from(p[0]) - 1.0) / f64::from(v[0]).sqrt().max(1e-9))
            .fold(f64::MIN, f64::max);
        let loss = 1.0 - mean;
        println!("rough glass {roughness}: image mean {mean:.4} (loss {loss:.4}), largest (L - 1) / sigma {worst_excess:.2}");
        // 576 pixels at 1%, Šidák-corrected, one-sided: z < 3.9.
        assert!(
            worst_excess < 3.9,
            "roughness {roughness}: a pixel above 1 by {worst_excess} sigma"
        );
        assert!(loss > previous_loss, "roughness {roughness}: loss {loss}");
        previous_loss = loss;
    }
}

/// Radiance through a glass slab of `thickness` seen head-on in front of an emitter of
/// radiance 1 (black elsewhere): the camera's 16 x 16 pixels all look through the slab's
/// middle within 0.6 degrees of its normal.
fn slab_render(material: PbrMaterial, thickness: f32, spp: u32) -> RenderedImage {
    let mut builder = MeshScene::default();
    let slab = builder.material(material);
    builder.cuboid(
        Vec3::new(-2.0, -2.0, -thickness),
        Vec3::new(2.0, 2.0, 0.0),
        slab,
    );
    let light = builder.material(PbrMaterial::lambertian(Vec3::ZERO, Vec3::ONE, false));
    let s = 4.0;
    builder.quad(
        [
            Vec3::new(-s, -s, -3.0),
            Vec3::new(s, -s, -3.0),
            Vec3::new(s, s, -3.0),
            Vec3::new(-s, s, -3.0),
        ],
        light,
    );
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 0.02);
    render(
        &builder.build(camera, None),
        RenderSettings {
            width: 16,
            height: 16,
            spp,
            max_path_length: FURNACE_PATH_LENGTH,
            integrator: Integrator::Mis,
            pixel_filter: PixelFilter::Center,
            seed: 9,
            ..Default::default()
        },
    )
}

/// The image's mean and the standard error of that mean (pixels independent).
fn image_mean(image: &RenderedImage, channel: usize) -> (f64, f64) {
    let n = image.mean.len() as f64;
    let mean = image
        .mean
        .iter()
        .map(|p| f64::from(p[channel]))
        .sum::<f64>()
        / n;
    let variance = image
        .variance_of_mean()
        .iter()
        .map(|v| f64::from(v[channel]))
        .sum::<f64>()
        / (n * n);
    (mean, variance.sqrt())
}

#[test]
fn an_absorbing_slab_transmits_beer_lambert_and_fresnel_at_normal_incidence() {
    // At normal incidence each face reflects F = ((n - 1) / (n + 1))^2 = 0.04 and the slab
    // keeps tau = exp(-sigma d) per crossing; the light that reaches the camera crosses once,
    // or three times after two internal reflections, ...: (1 - F)^2 tau / (1 - F^2 tau^2).
    // The red channel absorbs (sigma d = 0.7), green not at all, blue strongly (2.0).
    let thickness = 0.5;
    let sigma = Vec3::new(0.7, 0.0, 2.0) / thickness;
    let image = slab_render(glass(0.0, 1.5, sigma), thickness, 256);
    let fresnel = 0.04f64;
    for (channel, optical_depth) in [(0usize, 0.7f64), (1, 0.0), (2, 2.0)] {
        let tau = (-optical_depth).exp();
        let expected = (1.0 - fresnel).powi(2) * tau / (1.0 - fresnel * fresnel * tau * tau);
        let (mean, error) = image_mean(&image, channel);
        println!("slab channel {channel}: {mean:.5} +- {error:.5}, closed form {expected:.5}");
        // 3 channels at 1%: |z| < 3 (and the error is small: a reflection or a
        // transmission per crossing, 256 x 256 samples).
        assert!(
            (mean - expected).abs() < 3.0 * error + 1e-4,
            "channel {channel}: {mean} vs {expected}"
        );
    }
}

#[test]
fn a_thin_pane_transmits_one_minus_f_of_what_is_behind_it() {
    // Thin-walled (no volume): light passes straight through, weighted by (1 - F) and the
    // base colour; Schlick's F at normal incidence is F0 = 0.04 (ior 1.5). What the front
    // reflects sees the black background.
    let mut pane = glass(0.0, 1.5, Vec3::ZERO);
    pane.transmission.thickness = 0.0;
    pane.base_color = Vec4::new(0.9, 0.6, 0.3, 1.0);
    pane.double_sided = true;
    let mut builder = MeshScene::default();
    let pane_material = builder.material(pane);
    let s = 2.0;
    builder.quad(
        [
            Vec3::new(-s, -s, 0.0),
            Vec3::new(s, -s, 0.0),
            Vec3::new(s, s, 0.0),
            Vec3::new(-s, s, 0.0),
        ],
        pane_material,
    );
    let light = builder.material(PbrMaterial::lambertian(Vec3::ZERO, Vec3::ONE, false));
    let l = 4.0;
    builder.quad(
        [
            Vec3::new(-l, -l, -3.0),
            Vec3::new(l, -l, -3.0),
            Vec3::new(l, l, -3.0),
            Vec3::new(-l, l, -3.0),
        ],
        light,
    );
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 0.02);
    for integrator in [Integrator::Mis, Integrator::Nee, Integrator::PathTracing] {
        let image = render(
            &builder_clone(&builder).build(camera, None),
            RenderSettings {
                width: 16,
                height: 16,
                spp: 64,
                max_path_length: 4,
                integrator,
                pixel_filter: PixelFilter::Center,
                seed: 2,
                ..Default::default()
            },
        );
        for (channel, tint) in [(0usize, 0.9f64), (1, 0.6), (2, 0.3)] {
            let expected = 0.96 * tint;
            let (mean, error) = image_mean(&image, channel);
            println!("thin pane, {integrator:?}, channel {channel}: {mean:.5} +- {error:.5}, closed form {expected:.5}");
            assert!(
                (mean - expected).abs() < 3.0 * error + 2e-3,
                "{integrator:?} channel {channel}: {mean} vs {expected}"
            );
        }
    }
}

/// A copy of a scene under construction (each render consumes one).
fn builder_clone(builder: &MeshScene) -> MeshScene {
    MeshScene {
        triangles: builder.triangles.clone(),
        shading: builder.shading.clone(),
        materials: builder.materials.clone(),
    }
}

/// Radiance of the emissive checkerboard behind `smooth_pane_over_tiles`: tile (i, j) of
/// side `TILE_SIDE` (world units, z = -3) is bright where i + j is even.
const BRIGHT_TILE: f32 = 1.0;
/// The dark tiles' radiance: 5 % of the bright ones', so that light leaking across an edge
/// shows as a large relative error.
const DARK_TILE: f32 = 0.05;
/// A tile is 2 pixels wide (the camera's pixel is 2e-3 wide at z = -3), so every pixel
/// touches a tile edge and its centre lies half a pixel (1e-3, 3.3e-4 rad seen from the pane)
/// from one.
const TILE_SIDE: f32 = 4e-3;
/// Tiles on each side of the axis: 8 cover the view, 2 more beyond each edge.
const TILES_PER_SIDE: i32 = 6;

/// A smooth (roughness 0) thin-walled white pane (ior 1.5) at z = 0 in front of an emissive
/// checkerboard at z = -3, seen head-on from z = 2 by a 16 x 16 camera whose pixels are 2e-3
/// wide at the tiles.
fn smooth_pane_over_tiles() -> Scene {
    let mut pane = glass(0.0, 1.5, Vec3::ZERO);
    pane.transmission.thickness = 0.0;
    pane.double_sided = true;
    let mut builder = MeshScene::default();
    let pane_material = builder.material(pane);
    let s = 2.0;
    builder.quad(
        [
            Vec3::new(-s, -s, 0.0),
            Vec3::new(s, -s, 0.0),
            Vec3::new(s, s, 0.0),
            Vec3::new(-s, s, 0.0),
        ],
        pane_material,
    );
    let bright = builder.material(PbrMaterial::lambertian(
        Vec3::ZERO,
        Vec3::splat(BRIGHT_TILE),
        false,
    ));
    let dark = builder.material(PbrMaterial::lambertian(
        Vec3::ZERO,
        Vec3::splat(DARK_TILE),
        false,
    ));
    for i in -TILES_PER_SIDE..TILES_PER_SIDE {
        for j in -TILES_PER_SIDE..TILES_PER_SIDE {
            let (x, y) = (i as f32 * TILE_SIDE, j as f32 * TILE_SIDE);
            let material = if (i + j).rem_euclid(2) == 0 {
                bright
            } else {
                dark
            };
            builder.quad(
                [
                    Vec3::new(x, y, -3.0),
                    Vec3::new(x + TILE_SIDE, y, -3.0),
                    Vec3::new(x + TILE_SIDE, y + TILE_SIDE, -3.0),
                    Vec3::new(x, y + TILE_SIDE, -3.0),
                ],
                material,
            );
        }
    }
    // Pixel height at z = -3: 5 * 2 tan(fov / 2) / 16 = 2e-3.
    let fov = 2.0 * (2e-3f32 * 16.0 / 10.0).atan();
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, fov);
    builder.build(camera, None)
}

#[test]
fn a_smooth_thin_pane_transmits_one_minus_f_at_every_pixel_tile_edges_included() {
    // Roughness 0 is a delta lobe: every camera ray (pixel centres) goes straight through
    // the pane to the tile behind its pixel centre, with probability 1 - P_r and weight
    // (1 - F) / (1 - P_r) = 1 (white: P_r = F = F0 = 0.04 head-on), or reflects (weight 1,
    // into the black background). So each pixel's mean is (1 - F) Le = 0.96 Le of its tile
    // exactly, and a sample is Le or 0: the mean of n samples has sigma
    // Le sqrt(0.96 * 0.04 / n). A GGX lobe of alpha 1e-4 in place of the delta spreads
    // light over a few 1e-4 rad, which at 3.3e-4 rad from an edge moved dark pixels next to
    // bright ones by several times their own radiance.
    let scene = smooth_pane_over_tiles();
    let spp = 256u32;
    let sigma_per_radiance = (0.96f64 * 0.04 / f64::from(spp)).sqrt();
    for integrator in [
        Integrator::Mis,
        Integrator::Nee,
        Integrator::Cosine,
        Integrator::PathTracing,
    ] {
        let image = render(
            &scene,
            RenderSettings {
                width: 16,
                height: 16,
                spp,
                max_path_length: 4,
                integrator,
                pixel_filter: PixelFilter::Center,
                seed: 4,
                ..Default::default()
            },
        );
        let mut worst_z = 0.0f64;
        for (index, pixel) in image.mean.iter().enumerate() {
            let (column, row) = ((index % 16) as i32, (index / 16) as i32);
            // Pixel (0, 0) is the top left; the tile behind a pixel centre is 2 pixels wide.
            let (i, j) = ((column - 8).div_euclid(2), (7 - row).div_euclid(2));
            let radiance = if (i + j).rem_euclid(2) == 0 {
                BRIGHT_TILE
            } else {
                DARK_TILE
            };
            let expected = 0.96 * f64::from(radiance);
            let sigma = f64::from(radiance) * sigma_per_radiance;
            for (channel, &value) in pixel.iter().take(3).enumerate() {
                let z = (f64::from(value) - expected) / sigma;
                worst_z = worst_z.max(z.abs());
                // 256 pixels (the channels are equal): a count of reflections among 256
                // samples is binomial (mean 10.2, sd 3.1); 5 sd (26 or more, Poisson tail
                // 2e-5 per pixel) keeps a false alarm below 1 % for the image.
                assert!(
                    z.abs() < 5.0,
                    "{integrator:?}: pixel ({column}, {row}) channel {channel}: {value} vs (1 - F) Le = {expected} ({z:.1} sigma)"
                );
            }
        }
        println!("smooth pane over tiles, {integrator:?}: worst |z| {worst_z:.2}");
    }
}
