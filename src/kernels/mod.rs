//! The kernels as data: each compute kernel of `glsl/` is declared once here — its source,
//! its builds (`builds`), the specialization constants it declares, its push-constant size and
//! its binding table (`bindings`) — and its pipeline, descriptor-set layout and descriptor
//! writes are derived from that declaration. The tests reflect every build's SPIR-V
//! (`reflect`) against it, and the path tracer's loop-limit bound is derived from the
//! description of its loops (`loops`).

pub mod bindings;
pub mod builds;
pub mod catalog;
pub mod loops;
pub mod push_constants;
pub mod reflect;
pub mod scan;
pub mod specialization;
pub mod variant;

use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result};
use crate::shaders;
use crate::vk::TexelBufferView;
use crate::vk::{
    spirv_words, AccelerationStructure, Buffer, ComputePipeline, Context, DescriptorSet,
    StorageImage,
};
pub use bindings::{Binding, Resource};
pub use catalog::*;

/// A range of specialization-constant ids that a kernel declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpecConstants {
    /// The first id (a `SPEC_*` of `glsl/shared.h`).
    pub first_id: u32,
    /// How many consecutive ids (1 but for arrays such as the constant triangles).
    pub count: u32,
}

impl SpecConstants {
    /// The single constant `id`.
    pub const fn one(id: u32) -> SpecConstants {
        SpecConstants {
            first_id: id,
            count: 1,
        }
    }

    /// Whether `id` is among these.
    pub fn contains(self, id: u32) -> bool {
        id >= self.first_id && id - self.first_id < self.count
    }
}

/// One compute kernel, `glsl/<source>`: what it is built from, what it declares and binds.
#[derive(Debug)]
pub struct Kernel {
    /// The kernel's file in `glsl/` (and in `shaders::GLSL_SOURCES`).
    pub source: &'static str,
    /// Its binding table (set 0).
    pub bindings: &'static [Binding],
    /// The specialization constants it declares (in any of its builds).
    pub specialization: &'static [SpecConstants],
    /// Bytes of its push-constant block (0: none).
    pub push_constant_size: u32,
}

/// One build of a kernel: its name and the macros it is compiled with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Build {
    /// The build's name (the stem of the source for the plain build).
    pub name: &'static str,
    /// The macros defined for it.
    pub macros: &'static [(&'static str, &'static str)],
}

impl Build {
    /// Whether the build defines `macro_name`.
    pub fn defines(&self, macro_name: &str) -> bool {
        self.macros.iter().any(|(name, _)| *name == macro_name)
    }

    /// The SPIR-V embedded for this build.
    pub fn embedded_spirv(&self) -> Result<Vec<u32>> {
        let bytes = shaders::SPIRV
            .iter()
            .find(|(name, _)| *name == self.name)
            .map(|(_, bytes)| *bytes)
            .ok_or_else(|| {
                Error::MissingInput(format!("the kernel build {} is not embedded", self.name))
            })?;
        Ok(spirv_words(bytes)?)
    }
}

/// A resource for one binding, as the host holds it.
#[derive(Clone, Copy)]
pub enum Bound<'a> {
    /// A (uniform or storage) buffer, bound whole.
    Buffer(&'a Buffer),
    /// A uniform texel buffer's view.
    TexelBuffer(&'a TexelBufferView),
    /// A storage image in GENERAL layout.
    StorageImage(&'a StorageImage),
    /// A top-level acceleration structure.
    AccelerationStructure(&'a AccelerationStructure),
}

impl Kernel {
    /// The kernel's file name without `.comp`.
    pub fn stem(&self) -> &'static str {
        self.source.strip_suffix(".comp").unwrap_or(self.source)
    }

    /// Every build of the kernel: the plain one, then those of `builds::EXTRA_BUILDS`.
    pub fn builds(&self) -> Vec<Build> {
        let stem = self.stem();
        let mut all = vec![Build {
            name: stem,
            macros: &[],
        }];
        all.extend(
            builds::EXTRA_BUILDS
                .iter()
                .filter(|build| build.source == stem)
                .map(|build| Build {
                    name: build.name,
                    macros: build.macros,
                }),
        );
        all
    }

    /// The build that defines exactly `macros` (in any order).
    pub fn build_with(&self, macros: &[&str]) -> Result<Build> {
        self.builds()
            .into_iter()
            .find(|build| {
                build.macros.len() == macros.len() && macros.iter().all(|m| build.defines(m))
            })
            .ok_or_else(|| {
                Error::MissingInput(format!(
                    "{} has no build with the macros {macros:?}",
                    self.source
                ))
            })
    }

    /// The rows of the binding table that `build` declares.
    pub fn bindings_of(&self, build: &Build) -> Vec<Binding> {
        self.bindings
            .iter()
            .filter(|row| row.only_with.is_none_or(|m| build.defines(m)))
            .copied()
            .collect()
    }

    /// Whether the kernel declares specialization constant `id`.
    pub fn declares_spec_constant(&self, id: u32) -> bool {
        self.specialization.iter().any(|range| range.contains(id))
    }

    /// Creates the pipeline of `build` from `spirv` (its embedded SPIR-V, or the same
    /// source compiled at run time with the build's macros and others that bind nothing
    /// else), with the descriptor-set layout of the build's rows and the kernel's push
    /// constants. Every specialization constant must be one that the kernel declares.
    pub fn pipeline(
        &'static self,
        context: &Arc<Context>,
        build: &Build,
        spirv: &[u32],
        specialization: &[(u32, u32)],
    ) -> Result<KernelPipeline> {
        if let Some((id, _)) = specialization
            .iter()
            .find(|(id, _)| !self.declares_spec_constant(*id))
        {
            return Err(Error::InvalidSettings(format!(
                "{} declares no specialization constant {id}",
                self.source
            )));
        }
        let rows = self.bindings_of(build);
        let layout: Vec<(u32, vk::DescriptorType)> =
            rows.iter().map(|row| (row.binding, row.kind)).collect();
        let pipeline = ComputePipeline::new(
            context,
            spirv,
            &layout,
            self.push_constant_size,
            specialization,
        )?;
        Ok(KernelPipeline {
            kernel: self,
            rows,
            pipeline,
        })
    }
}

/// A kernel's compute pipeline, with the binding rows of its build.
pub struct KernelPipeline {
    kernel: &'static Kernel,
    rows: Vec<Binding>,
    /// The pipeline.
    pub pipeline: ComputePipeline,
}

impl KernelPipeline {
    /// The kernel.
    pub fn kernel(&self) -> &'static Kernel {
        self.kernel
    }

    /// Whether the build binds `resource`.
    pub fn binds(&self, resource: Resource) -> bool {
        self.rows.iter().any(|row| row.resource == resource)
    }

    /// Allocates a descriptor set and writes every row of the build into it, with the
    /// resources that `resource` gives; a resource it does not have, or of another kind than
    /// its row's descriptor type, is an error that names it.
    pub fn descriptor_set<'a>(
        &self,
        resource: impl Fn(Resource) -> Option<Bound<'a>>,
    ) -> Result<DescriptorSet> {
        let set = self.pipeline.allocate_descriptor_set()?;
        for row in &self.rows {
            let missing = || {
                Error::MissingInput(format!(
                    "{} binds {:?} at binding {} as {:?}, which the host did not provide as such",
                    self.kernel.source, row.resource, row.binding, row.kind
                ))
            };
            match (resource(row.resource).ok_or_else(missing)?, row.kind) {
                (Bound::TexelBuffer(view), vk::DescriptorType::UNIFORM_TEXEL_BUFFER) => {
                    set.write_texel_buffer(row.binding, view)
                }
                (
                    Bound::Buffer(buffer),
                    vk::DescriptorType::UNIFORM_BUFFER | vk::DescriptorType::STORAGE_BUFFER,
                ) => set.write_buffer(row.binding, row.kind, buffer),
                (Bound::StorageImage(image), vk::DescriptorType::STORAGE_IMAGE) => {
                    set.write_storage_image(row.binding, image)
                }
                (
                    Bound::AccelerationStructure(structure),
                    vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
                ) => set.write_acceleration_structure(row.binding, structure),
                _ => return Err(missing()),
            }
        }
        Ok(set)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::variant::{
        path_tracer_variant, KernelSource, SceneSummary, Traversal, VariantSettings,
    };

    #[test]
    fn every_path_tracer_build_is_embedded() {
        // Which build a render takes is variant::tests' matter
        for build in PATH_TRACER.builds() {
            assert!(build.embedded_spirv().is_ok(), "{}", build.name);
        }
        assert!(PATH_TRACER.build_with(&["NO_SUCH_MACRO"]).is_err());
    }

    #[test]
    fn rows_and_constants_follow_the_build() {
        let plain_build = |traversal| {
            let scene = SceneSummary::default();
            path_tracer_variant(
                &scene,
                &VariantSettings::default(),
                traversal,
                KernelSource::Given,
            )
            .unwrap()
            .build
        };
        let (bvh, plain) = (plain_build(Traversal::Bvh), plain_build(Traversal::Linear));
        let binds = |build: &Build, resource| {
            PATH_TRACER
                .bindings_of(build)
                .iter()
                .any(|row| row.resource == resource)
        };
        assert!(binds(&bvh, Resource::BvhNodes));
        assert!(!binds(&plain, Resource::BvhNodes));
        assert!(!binds(&bvh, Resource::Materials));
        assert!(binds(&plain, Resource::Accumulation));
        assert!(PATH_TRACER.declares_spec_constant(crate::contract::SPEC_CONSTANT_TRIANGLES + 575));
        assert!(!PATH_TRACER.declares_spec_constant(crate::contract::SPEC_CONSTANT_TRIANGLES + 576));
        assert!(!PROBE_BRDF.declares_spec_constant(crate::contract::SPEC_SAMPLE_COUNT));
    }
}
