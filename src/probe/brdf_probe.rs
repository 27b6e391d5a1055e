//! The BRDF probe (`glsl/probe_brdf.comp`): runs the glTF BRDF of `glsl/brdf.glsl` and its
//! sampling on a buffer of inputs, so that tests can compare them with their Rust twins
//! (`crate::cpu::brdf`). It binds only its inputs and outputs (no scene);
//! `BrdfProbeOutput::cpu` is the kernel's `main` on the CPU.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3, Vec4};

use crate::cpu::brdf::{
    get_base_material, get_brdf, get_brdf_density, get_brdf_mirror_probability,
    get_brdf_mirror_weight, get_ggx_alpha, get_specular_probability, sample_brdf,
    sample_ggx_visible_normal, MaterialSample,
};
use crate::cpu::fresnel::{
    get_dielectric_fresnel, get_dielectric_schlick_fresnel, get_metal_schlick_fresnel,
};
use crate::error::Result;
use crate::kernels;
use crate::probe::runner::Probe;
use crate::vk::Context;

/// `probe_input_t` of `glsl/probe_brdf.comp` (96 bytes): one material, frame and pair of
/// random numbers.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct BrdfProbeInput {
    /// rgb: `material_t.base_color` (linear RGB); a: metallic.
    pub base_color_metallic: [f32; 4],
    /// rgb: `material_t.specular_color` (linear RGB); a: specular.
    pub specular_color_specular: [f32; 4],
    /// x: perceptual roughness; y: ior; zw: the random numbers (u_0, u_1) in [0, 1)^2.
    pub roughness_ior_randoms: [f32; 4],
    /// xyz: unit shading normal, world space; w: 0.
    pub normal: [f32; 4],
    /// xyz: unit view direction (towards the viewer), world space; w: 0.
    pub view: [f32; 4],
    /// xyz: unit light direction (towards the light), world space; w: 0.
    pub light: [f32; 4],
}

impl BrdfProbeInput {
    /// The input for one evaluation of every function with these arguments.
    pub fn new(
        material: &MaterialSample,
        random_numbers: Vec2,
        normal: Vec3,
        view: Vec3,
        light: Vec3,
    ) -> BrdfProbeInput {
        BrdfProbeInput {
            base_color_metallic: material.base_color.extend(material.metallic).into(),
            specular_color_specular: material.specular_color.extend(material.specular).into(),
            roughness_ior_randoms: [
                material.roughness,
                material.ior,
                random_numbers.x,
                random_numbers.y,
            ],
            normal: normal.extend(0.0).into(),
            view: view.extend(0.0).into(),
            light: light.extend(0.0).into(),
        }
    }

    /// The material, as the kernel unpacks it into a `material_t`.
    pub fn material(&self) -> MaterialSample {
        let [r, g, b, metallic] = self.base_color_metallic;
        let [sr, sg, sb, specular] = self.specular_color_specular;
        get_base_material(
            Vec3::new(r, g, b),
            metallic,
            self.roughness_ior_randoms[0],
            specular,
            Vec3::new(sr, sg, sb),
            self.roughness_ior_randoms[1],
        )
    }

    /// The random numbers (u_0, u_1).
    pub fn random_numbers(&self) -> Vec2 {
        Vec2::new(self.roughness_ior_randoms[2], self.roughness_ior_randoms[3])
    }

    /// The shading normal.
    pub fn normal(&self) -> Vec3 {
        Vec4::from_array(self.normal).truncate()
    }

    /// The view direction.
    pub fn view(&self) -> Vec3 {
        Vec4::from_array(self.view).truncate()
    }

    /// The light direction.
    pub fn light(&self) -> Vec3 {
        Vec4::from_array(self.light).truncate()
    }

    /// The view as `sample_ggx_visible_normal` receives it in the kernel: a shading-frame
    /// vector above the surface, (view.x, view.y, |view.z|).
    pub fn local_view(&self) -> Vec3 {
        let view = self.view();
        Vec3::new(view.x, view.y, view.z.abs())
    }
}

/// `probe_output_t` of `glsl/probe_brdf.comp` (96 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct BrdfProbeOutput {
    /// rgb: `get_brdf(material, normal, view, light)`; a: `get_brdf_density` of the same.
    pub brdf: [f32; 4],
    /// xyz: `sample_brdf(randoms, material, normal, view)`; w: `get_brdf_density` there.
    pub sampled: [f32; 4],
    /// xyz: `sample_ggx_visible_normal(randoms, get_ggx_alpha(roughness), local_view)`;
    /// w: `get_specular_probability(material, dot(normal, view))`.
    pub visible_normal: [f32; 4],
    /// rgb: `get_brdf_mirror_weight(material, normal, view)` where the mirror probability is
    /// above 0, else 0; a: `get_brdf_mirror_probability(material, normal, view)`.
    pub mirror: [f32; 4],
    /// rgb: `get_dielectric_schlick_fresnel(material, dot(normal, view))`;
    /// a: `get_dielectric_fresnel(dot(normal, view), material.ior)`.
    pub fresnel: [f32; 4],
    /// rgb: `get_metal_schlick_fresnel(material, dot(normal, view))`; a: 0.
    pub metal_fresnel: [f32; 4],
}

impl BrdfProbeOutput {
    /// What the kernel computes for `input`, computed by the Rust twins.
    pub fn cpu(input: &BrdfProbeInput) -> BrdfProbeOutput {
        let material = input.material();
        let (normal, view, light) = (input.normal(), input.view(), input.light());
        let random_numbers = input.random_numbers();
        let brdf = get_brdf(&material, normal, view, light);
        let density = get_brdf_density(&material, normal, view, light);
        let sampled = sample_brdf(random_numbers, &material, normal, view);
        let sampled_density = get_brdf_density(&material, normal, view, sampled);
        let visible_normal = sample_ggx_visible_normal(
            random_numbers,
            get_ggx_alpha(material.roughness),
            input.local_view(),
        );
        let specular_probability = get_specular_probability(&material, normal.dot(view));
        let mirror_probability = get_brdf_mirror_probability(&material, normal, view);
        let mirror_weight = if mirror_probability > 0.0 {
            get_brdf_mirror_weight(&material, normal, view)
        } else {
            Vec3::ZERO
        };
        let normal_dot_view = normal.dot(view);
        let dielectric_fresnel = get_dielectric_schlick_fresnel(&material, normal_dot_view);
        let exact_fresnel = get_dielectric_fresnel(normal_dot_view, material.ior);
        let metal_fresnel = get_metal_schlick_fresnel(&material, normal_dot_view);
        BrdfProbeOutput {
            brdf: brdf.extend(density).into(),
            sampled: sampled.extend(sampled_density).into(),
            visible_normal: visible_normal.extend(specular_probability).into(),
            mirror: mirror_weight.extend(mirror_probability).into(),
            fresnel: dielectric_fresnel.extend(exact_fresnel).into(),
            metal_fresnel: metal_fresnel.extend(0.0).into(),
        }
    }

    /// `get_brdf_mirror_weight` (0 where the mirror probability is 0).
    pub fn mirror_weight(&self) -> Vec3 {
        Vec4::from_array(self.mirror).truncate()
    }

    /// `get_brdf_mirror_probability`.
    pub fn mirror_probability(&self) -> f32 {
        self.mirror[3]
    }

    /// `get_brdf`'s value.
    pub fn brdf(&self) -> Vec3 {
        Vec4::from_array(self.brdf).truncate()
    }

    /// `get_brdf_density` at the input's light direction.
    pub fn density(&self) -> f32 {
        self.brdf[3]
    }

    /// The direction `sample_brdf` returned.
    pub fn sampled(&self) -> Vec3 {
        Vec4::from_array(self.sampled).truncate()
    }

    /// `get_brdf_density` at the sampled direction.
    pub fn sampled_density(&self) -> f32 {
        self.sampled[3]
    }

    /// The half vector `sample_ggx_visible_normal` returned.
    pub fn visible_normal(&self) -> Vec3 {
        Vec4::from_array(self.visible_normal).truncate()
    }

    /// `get_specular_probability`'s value.
    pub fn specular_probability(&self) -> f32 {
        self.visible_normal[3]
    }

    /// The Fresnel room's terms at n.v: `get_dielectric_schlick_fresnel` (rgb), then
    /// `get_metal_schlick_fresnel` (rgb), then `get_dielectric_fresnel` with the material's ior.
    pub fn fresnel_terms(&self) -> [f32; 7] {
        let [d0, d1, d2, exact] = self.fresnel;
        let [m0, m1, m2, _] = self.metal_fresnel;
        [d0, d1, d2, m0, m1, m2, exact]
    }
}

/// Runs the BRDF probe.
pub struct BrdfProbeRunner {
    probe: Probe,
}

impl BrdfProbeRunner {
    /// Creates the kernel's pipeline.
    pub fn new(context: &Arc<Context>) -> Result<BrdfProbeRunner> {
        Ok(BrdfProbeRunner {
            probe: Probe::embedded(context, &kernels::PROBE_BRDF, &[], "the glTF BRDF")?,
        })
    }

    /// Evaluates the BRDF functions on every input and returns the outputs in order.
    pub fn run(&self, inputs: &[BrdfProbeInput]) -> Result<Vec<BrdfProbeOutput>> {
        self.probe.run(|_| None, inputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn structs_match_the_std430_declarations() {
        // vec4 base_color_metallic; vec4 specular_color_specular; vec4 roughness_ior_randoms;
        // vec4 normal; vec4 view; vec4 light
        assert_eq!(size_of::<BrdfProbeInput>(), 96);
        assert_eq!(offset_of!(BrdfProbeInput, specular_color_specular), 16);
        assert_eq!(offset_of!(BrdfProbeInput, roughness_ior_randoms), 32);
        assert_eq!(offset_of!(BrdfProbeInput, normal), 48);
        assert_eq!(offset_of!(BrdfProbeInput, view), 64);
        assert_eq!(offset_of!(BrdfProbeInput, light), 80);
        // vec4 brdf; vec4 sampled; vec4 visible_normal
        assert_eq!(size_of::<BrdfProbeOutput>(), 96);
        assert_eq!(offset_of!(BrdfProbeOutput, sampled), 16);
        assert_eq!(offset_of!(BrdfProbeOutput, visible_normal), 32);
        assert_eq!(offset_of!(BrdfProbeOutput, mirror), 48);
        assert_eq!(offset_of!(BrdfProbeOutput, fresnel), 64);
        assert_eq!(offset_of!(BrdfProbeOutput, metal_fresnel), 80);
    }

    #[test]
    fn inputs_round_trip_their_arguments() {
        let mut material = MaterialSample::gltf(Vec3::new(0.1, 0.2, 0.3), 0.25, 0.5);
        material.specular = 0.75;
        material.specular_color = Vec3::new(0.4, 0.5, 0.6);
        material.ior = 2.0;
        let input = BrdfProbeInput::new(
            &material,
            Vec2::new(0.125, 0.875),
            Vec3::Z,
            Vec3::new(0.0, 0.6, -0.8),
            Vec3::X,
        );
        assert_eq!(input.material(), material);
        assert_eq!(input.random_numbers(), Vec2::new(0.125, 0.875));
        assert_eq!((input.normal(), input.light()), (Vec3::Z, Vec3::X));
        assert_eq!(input.local_view(), Vec3::new(0.0, 0.6, 0.8));
    }
}
