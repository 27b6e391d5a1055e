//! The Fresnel room's twins by hand: the exact dielectric's reflectance at normal and
//! grazing incidence, Brewster's angle and total internal reflection; Schlick's end points;
//! the base's two terms at glTF's defaults.

use glam::Vec3;

use super::*;

#[test]
fn fresnel_by_hand() {
    // Normal incidence: ((n - 1) / (n + 1))^2, 0.04 for glass, from either side.
    assert!((get_dielectric_fresnel(1.0, 1.5) - 0.04).abs() < 1e-6);
    assert!((get_dielectric_fresnel(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
    assert!((get_dielectric_fresnel(1.0, 1.33) - (0.33f32 / 2.33).powi(2)).abs() < 1e-6);
    // Total internal reflection beyond the critical angle asin(1 / 1.5) = 41.8 degrees.
    let beyond = 45.0f32.to_radians().cos();
    assert_eq!(get_dielectric_fresnel(beyond, 1.0 / 1.5), 1.0);
    let before = 40.0f32.to_radians().cos();
    assert!(get_dielectric_fresnel(before, 1.0 / 1.5) < 1.0);
    // Grazing incidence reflects everything; Brewster's angle atan(1.5) has R_p = 0, so
    // R = R_s / 2, with R_s = ((cos_i - n cos_t) / (cos_i + n cos_t))^2.
    assert!((get_dielectric_fresnel(0.0, 1.5) - 1.0).abs() < 1e-6);
    let brewster = 1.5f32.atan();
    let (cos_i, sin_t) = (brewster.cos(), brewster.sin() / 1.5);
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    let r_s = ((cos_i - 1.5 * cos_t) / (cos_i + 1.5 * cos_t)).powi(2);
    assert!((get_dielectric_fresnel(cos_i, 1.5) - r_s / 2.0).abs() < 1e-6);
    // A negative cosine is the same interface seen from the other side.
    assert_eq!(
        get_dielectric_fresnel(-0.7, 1.5),
        get_dielectric_fresnel(0.7, 1.0 / 1.5)
    );
}

#[test]
fn fresnel_and_f0_by_hand() {
    let material = MaterialSample::gltf(Vec3::ONE, 0.0, 1.0);
    let f0 = get_dielectric_f0(&material);
    assert!((f0 - Vec3::splat(0.04)).abs().max_element() < 1e-7);
    assert_eq!(get_schlick_fresnel(f0, Vec3::ONE, 1.0), f0);
    assert_eq!(get_schlick_fresnel(f0, Vec3::ONE, 0.0), Vec3::ONE);
    let half_way = get_schlick_fresnel(Vec3::ZERO, Vec3::ONE, 0.5);
    assert!((half_way.x - 1.0 / 32.0).abs() < 1e-7);
}

#[test]
fn the_base_terms_are_schlicks_with_the_materials_end_points() {
    // glTF's defaults: the dielectric goes from 0.04 at normal incidence to specular (1) at
    // grazing; the metal from its base colour to 1; specular 0 switches the dielectric off
    // (the Lambertian case get_lambert_brdf() relies on: exact zeros).
    let color = Vec3::new(0.9, 0.5, 0.2);
    let material = MaterialSample::gltf(color, 1.0, 0.5);
    assert_eq!(get_metal_schlick_fresnel(&material, 1.0), color);
    assert_eq!(get_metal_schlick_fresnel(&material, 0.0), Vec3::ONE);
    assert!(
        (get_dielectric_schlick_fresnel(&material, 1.0) - Vec3::splat(0.04))
            .abs()
            .max_element()
            < 1e-7
    );
    assert_eq!(get_dielectric_schlick_fresnel(&material, 0.0), Vec3::ONE);
    let lambertian = MaterialSample {
        specular: 0.0,
        ..material
    };
    for cosine in [0.0, 0.3, 1.0] {
        assert_eq!(
            get_dielectric_schlick_fresnel(&lambertian, cosine),
            Vec3::ZERO
        );
    }
    // |v.h| enters: a cosine from below the surface gives the same reflectance.
    assert_eq!(
        get_dielectric_schlick_fresnel(&material, -0.3),
        get_dielectric_schlick_fresnel(&material, 0.3)
    );
}
