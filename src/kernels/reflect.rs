//! What a kernel's SPIR-V declares: its descriptor bindings (set, binding, descriptor type,
//! name) and its specialization-constant ids, read from the module's `OpDecorate`,
//! `OpVariable` and type instructions (SPIR-V 1.6 specification, 2.3 and 3.x). Only what
//! GLSL compute kernels declare is told apart: uniform and storage buffers, texel buffers,
//! storage and sampled images, samplers, acceleration structures. The tests use it to check each kernel's binding
//! table (`crate::kernels::bindings`) against every build.

use std::collections::HashMap;

use ash::vk;

/// A descriptor binding that a module declares.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeclaredBinding {
    /// The descriptor set.
    pub set: u32,
    /// The binding index.
    pub binding: u32,
    /// The descriptor type its variable's type implies (`None`: one this reader does not
    /// know).
    pub kind: Option<vk::DescriptorType>,
    /// The variable's name (`OpName`; empty without debug information).
    pub name: String,
    /// Whether the entry point uses it statically: whether a function of its static call
    /// tree loads, stores, indexes or passes the variable (what Vulkan's validation calls
    /// "statically used"). glslang keeps functions that nothing calls in unoptimized modules,
    /// and lists their variables in the entry point's interface too, so that is not enough.
    pub used: bool,
}

/// What a module declares.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Declarations {
    /// Its descriptor bindings, in the order of their variables.
    pub bindings: Vec<DeclaredBinding>,
    /// Its specialization-constant ids (`SpecId` decorations), ascending.
    pub spec_ids: Vec<u32>,
}

// Opcodes, decorations, storage classes and image dimensions (SPIR-V 1.6, 3.x).
const OP_NAME: u32 = 5;
const OP_ENTRY_POINT: u32 = 15;
const OP_FUNCTION: u32 = 54;
const OP_FUNCTION_END: u32 = 56;
const OP_FUNCTION_CALL: u32 = 57;
const OP_TYPE_IMAGE: u32 = 25;
const OP_TYPE_SAMPLER: u32 = 26;
const OP_TYPE_SAMPLED_IMAGE: u32 = 27;
const OP_TYPE_ARRAY: u32 = 28;
const OP_TYPE_RUNTIME_ARRAY: u32 = 29;
const OP_TYPE_POINTER: u32 = 32;
/// `OpTypeAccelerationStructureKHR` (SPV_KHR_ray_query).
const OP_TYPE_ACCELERATION_STRUCTURE: u32 = 5341;
const OP_VARIABLE: u32 = 59;
const OP_DECORATE: u32 = 71;
const DECORATION_SPEC_ID: u32 = 1;
const DECORATION_BLOCK: u32 = 2;
const DECORATION_BUFFER_BLOCK: u32 = 3;
const DECORATION_BINDING: u32 = 33;
const DECORATION_DESCRIPTOR_SET: u32 = 34;
const STORAGE_CLASS_UNIFORM_CONSTANT: u32 = 0;
const STORAGE_CLASS_UNIFORM: u32 = 2;
const STORAGE_CLASS_STORAGE_BUFFER: u32 = 12;
const DIM_BUFFER: u32 = 5;

/// A type that decides a descriptor type.
#[derive(Clone, Copy)]
enum Type {
    /// `OpTypeImage`: dimension and `Sampled` (1: sampled, 2: storage).
    Image {
        dim: u32,
        sampled: u32,
    },
    Sampler,
    /// `OpTypeAccelerationStructureKHR`.
    AccelerationStructure,
    /// `OpTypeSampledImage` of an image type.
    SampledImage(u32),
    /// An array of descriptors of the element type.
    Array(u32),
    /// `OpTypePointer` to a pointee (the storage class is the variable's).
    Pointer(u32),
}

/// Why words are not a SPIR-V module that `declarations` can read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SpirvError {
    /// No header, or not SPIR-V's magic number.
    #[error("not a SPIR-V module (no magic number)")]
    NoMagicNumber,
    /// An instruction whose length runs past the last word (or is 0).
    #[error("instruction at word {0} runs past the module's end")]
    Truncated(usize),
}

/// Reads the declarations of a SPIR-V module (words, header included).
pub fn declarations(spirv: &[u32]) -> Result<Declarations, SpirvError> {
    if spirv.len() < 5 || spirv[0] != 0x0723_0203 {
        return Err(SpirvError::NoMagicNumber);
    }
    let mut names: HashMap<u32, String> = HashMap::new();
    let mut decorations: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    let mut types: HashMap<u32, Type> = HashMap::new();
    let mut variables: Vec<(u32, u32, u32)> = Vec::new(); // (id, pointer type, storage class)
    let mut spec_ids = Vec::new();
    let mut entry_point = None;
    // Per function: the ids its instructions take as pointers, and the functions it calls.
    let mut functions: HashMap<u32, (Vec<u32>, Vec<u32>)> = HashMap::new();
    let mut current_function = None;
    let mut index = 5;
    while index < spirv.len() {
        let (length, opcode) = ((spirv[index] >> 16) as usize, spirv[index] & 0xffff);
        let Some(operands) = spirv.get(index + 1..index + length).filter(|_| length > 0) else {
            return Err(SpirvError::Truncated(index));
        };
        let word = |i: usize| operands.get(i).copied().unwrap_or(0);
        match opcode {
            OP_NAME => {
                let bytes: Vec<u8> = operands
                    .get(1..)
                    .unwrap_or_default()
                    .iter()
                    .flat_map(|w| w.to_le_bytes())
                    .take_while(|&b| b != 0)
                    .collect();
                names.insert(word(0), String::from_utf8_lossy(&bytes).into_owned());
            }
            OP_ENTRY_POINT => entry_point = Some(word(1)),
            OP_FUNCTION => current_function = Some(word(1)),
            OP_FUNCTION_END => current_function = None,
            OP_DECORATE => {
                if word(1) == DECORATION_SPEC_ID {
                    spec_ids.push(word(2));
                }
                decorations
                    .entry(word(0))
                    .or_default()
                    .push((word(1), word(2)));
            }
            OP_TYPE_IMAGE => {
                types.insert(
                    word(0),
                    Type::Image {
                        dim: word(2),
                        sampled: word(6),
                    },
                );
            }
            OP_TYPE_SAMPLER => {
                types.insert(word(0), Type::Sampler);
            }
            OP_TYPE_ACCELERATION_STRUCTURE => {
                types.insert(word(0), Type::AccelerationStructure);
            }
            OP_TYPE_SAMPLED_IMAGE => {
                types.insert(word(0), Type::SampledImage(word(1)));
            }
            OP_TYPE_ARRAY | OP_TYPE_RUNTIME_ARRAY => {
                types.insert(word(0), Type::Array(word(1)));
            }
            OP_TYPE_POINTER => {
                types.insert(word(0), Type::Pointer(word(2)));
            }
            OP_VARIABLE if current_function.is_none() => {
                variables.push((word(1), word(0), word(2)))
            }
            _ => {}
        }
        if let Some(function) = current_function {
            let (pointers, callees) = functions.entry(function).or_default();
            if opcode == OP_FUNCTION_CALL {
                callees.push(word(2));
            }
            pointers.extend(pointer_operands(opcode, operands));
        }
        index += length;
    }
    let decoration = |id: u32, which: u32| {
        decorations
            .get(&id)
            .and_then(|list| list.iter().find(|(d, _)| *d == which))
            .map(|&(_, value)| value)
    };
    let has = |id: u32, which: u32| {
        decorations
            .get(&id)
            .is_some_and(|l| l.iter().any(|(d, _)| *d == which))
    };
    // The ids used by the entry point's static call tree.
    let mut used_ids: Vec<u32> = Vec::new();
    let mut reached: Vec<u32> = entry_point.into_iter().collect();
    let mut next = 0;
    while let Some(&function) = reached.get(next) {
        next += 1;
        if let Some((pointers, callees)) = functions.get(&function) {
            used_ids.extend(pointers);
            for callee in callees {
                if !reached.contains(callee) {
                    reached.push(*callee);
                }
            }
        }
    }
    let mut bindings = Vec::new();
    for (id, pointer, storage) in variables {
        let (Some(set), Some(binding)) = (
            decoration(id, DECORATION_DESCRIPTOR_SET),
            decoration(id, DECORATION_BINDING),
        ) else {
            continue;
        };
        let mut pointee = match types.get(&pointer) {
            Some(Type::Pointer(pointee)) => *pointee,
            _ => 0,
        };
        while let Some(Type::Array(element)) = types.get(&pointee) {
            pointee = *element;
        }
        let kind = match (storage, types.get(&pointee)) {
            (STORAGE_CLASS_STORAGE_BUFFER, _) => Some(vk::DescriptorType::STORAGE_BUFFER),
            (STORAGE_CLASS_UNIFORM, _) if has(pointee, DECORATION_BUFFER_BLOCK) => {
                Some(vk::DescriptorType::STORAGE_BUFFER)
            }
            (STORAGE_CLASS_UNIFORM, _) if has(pointee, DECORATION_BLOCK) => {
                Some(vk::DescriptorType::UNIFORM_BUFFER)
            }
            (STORAGE_CLASS_UNIFORM_CONSTANT, Some(&t)) => descriptor_type(t, &types),
            _ => None,
        };
        bindings.push(DeclaredBinding {
            set,
            binding,
            kind,
            name: names.get(&id).cloned().unwrap_or_default(),
            used: entry_point.is_none() || used_ids.contains(&id),
        });
    }
    spec_ids.sort_unstable();
    spec_ids.dedup();
    Ok(Declarations { bindings, spec_ids })
}

/// The operands of an instruction inside a function that are pointers (or, for calls,
/// arguments), which is how a function uses a global variable: `OpLoad`, `OpStore`,
/// `OpCopyMemory`, the access chains, `OpArrayLength`, `OpImageTexelPointer`, the atomics and
/// `OpFunctionCall`'s arguments.
fn pointer_operands(opcode: u32, operands: &[u32]) -> &[u32] {
    let range = match opcode {
        // OpImageTexelPointer, OpLoad, OpAccessChain .. OpPtrAccessChain, OpArrayLength:
        // result type, result, pointer.
        60 | 61 | 65..=68 => 2..3,
        // OpStore, OpCopyMemory: pointer(s) first.
        62 | 63 => 0..2,
        // OpFunctionCall: result type, result, function, arguments.
        OP_FUNCTION_CALL => 3..operands.len(),
        // OpAtomicStore: pointer first; the other atomics: result type, result, pointer.
        228 => 0..1,
        227..=242 => 2..3,
        _ => 0..0,
    };
    operands.get(range).unwrap_or_default()
}

/// The descriptor type of a `UniformConstant` variable of type `t`.
fn descriptor_type(t: Type, types: &HashMap<u32, Type>) -> Option<vk::DescriptorType> {
    match t {
        Type::Sampler => Some(vk::DescriptorType::SAMPLER),
        Type::AccelerationStructure => Some(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR),
        Type::Image { dim, sampled } => Some(match (dim == DIM_BUFFER, sampled) {
            (true, 2) => vk::DescriptorType::STORAGE_TEXEL_BUFFER,
            (true, _) => vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
            (false, 2) => vk::DescriptorType::STORAGE_IMAGE,
            (false, _) => vk::DescriptorType::SAMPLED_IMAGE,
        }),
        // GLSL's samplerBuffer is a sampled image of a buffer image: a uniform texel buffer.
        Type::SampledImage(image) => match types.get(&image) {
            Some(Type::Image {
                dim: DIM_BUFFER, ..
            }) => Some(vk::DescriptorType::UNIFORM_TEXEL_BUFFER),
            Some(Type::Image { .. }) => Some(vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
            _ => None,
        },
        Type::Array(_) | Type::Pointer(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::{Build, Kernel, ALL_KERNELS};

    #[test]
    fn words_that_are_not_a_module_are_refused_in_one_line() {
        assert_eq!(
            declarations(&[]).unwrap_err().to_string(),
            "not a SPIR-V module (no magic number)"
        );
        // The header, then an instruction of 3 words with 1 left
        let cut = [0x0723_0203, 0x0001_0000, 0, 8, 0, 3 << 16];
        assert_eq!(
            declarations(&cut).unwrap_err().to_string(),
            "instruction at word 5 runs past the module's end"
        );
    }

    /// A module's declarations, failing the test with the build's name.
    fn declared(build: &Build) -> Declarations {
        let spirv = build.embedded_spirv().expect("every build is embedded");
        declarations(&spirv).unwrap_or_else(|e| panic!("{}: {e}", build.name))
    }

    /// What is wrong between `kernel`'s table and what `build` declares.
    fn mismatches(kernel: &Kernel, build: &Build, declared: &Declarations) -> Vec<String> {
        let rows = kernel.bindings_of(build);
        let mut problems = Vec::new();
        for binding in declared.bindings.iter().filter(|b| b.used) {
            let row = rows.iter().find(|row| row.binding == binding.binding);
            match row {
                _ if binding.set != 0 => problems.push(format!(
                    "{} declares {} in set {}, the host binds set 0 only",
                    build.name, binding.name, binding.set
                )),
                None => problems.push(format!(
                    "{} uses binding {} ({}, {:?}), which its table lacks",
                    build.name, binding.binding, binding.name, binding.kind
                )),
                Some(row) if Some(row.kind) != binding.kind => problems.push(format!(
                    "{}: binding {} ({}) is {:?} in the SPIR-V, {:?} in the table",
                    build.name, binding.binding, binding.name, binding.kind, row.kind
                )),
                Some(_) => {}
            }
        }
        for id in &declared.spec_ids {
            if !kernel.declares_spec_constant(*id) {
                problems.push(format!(
                    "{} declares specialization constant {id}, which the kernel's list lacks",
                    build.name
                ));
            }
        }
        // Every binding the kernel uses must be in the table, as the SPIR-V types it; a row
        // may name a binding that the build declares but does not use (the layout then has
        // one more binding than needed, which Vulkan allows). Optimized SPIR-V (release
        // builds) drops what a build never reads, so that a row or constant the shader
        // declares but does not use is missing there; unoptimized builds
        // (`VKPATH_UNOPTIMIZED_KERNELS=1`, `crate::shaders::KERNELS_OPTIMIZED` false) keep
        // every declaration, so there the table must not name a binding the build does not
        // declare at all.
        if !crate::shaders::KERNELS_OPTIMIZED {
            for row in &rows {
                if !declared.bindings.iter().any(|b| b.binding == row.binding) {
                    problems.push(format!(
                        "{}'s table binds {:?} at {}, which the kernel does not declare",
                        build.name, row.resource, row.binding
                    ));
                }
            }
        }
        problems
    }

    #[test]
    fn every_build_declares_what_its_binding_table_says() {
        let mut problems = Vec::new();
        for kernel in ALL_KERNELS {
            for build in kernel.builds() {
                problems.extend(mismatches(kernel, &build, &declared(&build)));
            }
        }
        assert!(problems.is_empty(), "{}", problems.join("\n"));
    }

    #[test]
    fn a_missing_or_mistyped_row_is_found() {
        use crate::kernels::bindings::PATH_TRACER;
        let build = crate::kernels::PATH_TRACER.builds()[0];
        let declared = declared(&build);
        let kernel = |rows: &'static [crate::kernels::Binding]| Kernel {
            bindings: rows,
            ..crate::kernels::PATH_TRACER
        };
        let without_lights: Vec<_> = PATH_TRACER
            .iter()
            .filter(|row| row.binding != crate::contract::BINDING_LIGHTS)
            .copied()
            .collect();
        let problems = mismatches(&kernel(without_lights.leak()), &build, &declared);
        assert!(
            problems.iter().any(|p| p.contains("which its table lacks")),
            "{problems:?}"
        );
        let mut mistyped = PATH_TRACER.to_vec();
        mistyped[0].kind = vk::DescriptorType::STORAGE_BUFFER;
        let problems = mismatches(&kernel(mistyped.leak()), &build, &declared);
        assert!(
            problems.iter().any(|p| p.contains("in the table")),
            "{problems:?}"
        );
    }

    #[test]
    fn every_kernel_source_is_declared() {
        for (file, _) in crate::shaders::GLSL_SOURCES {
            if file.ends_with(".comp") {
                assert!(
                    ALL_KERNELS.iter().any(|kernel| kernel.source == *file),
                    "glsl/{file} has no declaration in crate::kernels::catalog"
                );
            }
        }
    }

    #[test]
    fn descriptor_types_are_told_apart() {
        let path_tracer = declared(&crate::kernels::PATH_TRACER.builds()[0]);
        let kind = |binding| {
            path_tracer
                .bindings
                .iter()
                .find(|b| b.binding == binding)
                .and_then(|b| b.kind)
        };
        use crate::contract as c;
        assert_eq!(
            kind(c::BINDING_TRIANGLES),
            Some(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)
        );
        assert_eq!(
            kind(c::BINDING_RENDER_UNIFORMS),
            Some(vk::DescriptorType::UNIFORM_BUFFER)
        );
        assert_eq!(
            kind(c::BINDING_ACCUMULATION),
            Some(vk::DescriptorType::STORAGE_IMAGE)
        );
        let probe = declared_probe();
        assert!(probe
            .bindings
            .iter()
            .any(|b| b.kind == Some(vk::DescriptorType::STORAGE_BUFFER)));
        assert!(path_tracer.bindings.iter().all(|b| b.used));
        assert!(path_tracer.spec_ids.contains(&c::SPEC_SAMPLE_COUNT));
        if crate::shaders::KERNELS_OPTIMIZED {
            // Optimized SPIR-V keeps no binding that a kernel does not read.
            return;
        }
        // The sample display includes scene.glsl but traces no rays: unoptimized, it
        // declares the triangles and uniforms and does not use them.
        let display = declared(&crate::kernels::EXERCISE_SAMPLES.builds()[0]);
        let triangles = display
            .bindings
            .iter()
            .find(|b| b.binding == c::BINDING_TRIANGLES)
            .expect("declared");
        assert!(!triangles.used);
    }

    fn declared_probe() -> Declarations {
        declared(&crate::kernels::PROBE_BRDF.builds()[0])
    }
}
