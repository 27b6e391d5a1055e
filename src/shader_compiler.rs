//! GLSL to SPIR-V with shaderc, shared by `build.rs` (the embedded kernels) and the library
//! (run-time compilation for `vkpath check`), so both compile with the same options.
//! `#include "x"` is resolved by a caller-supplied function, never from arbitrary paths.

/// A compute shader compiled to SPIR-V, with the compiler's warnings.
pub struct CompiledShader {
    /// The SPIR-V words.
    pub spirv: Vec<u32>,
    /// Warnings as shaderc printed them (`file:line: warning: ...`), empty when there are none.
    pub warnings: String,
}

/// Why a shader did not compile: shaderc could not be set up, or its messages.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ShaderError {
    /// shaderc could not create a compiler.
    #[error("shaderc: cannot create a compiler: {0}")]
    CreateCompiler(shaderc::Error),
    /// shaderc could not create compile options.
    #[error("shaderc: cannot create compile options: {0}")]
    CreateOptions(shaderc::Error),
    /// The source did not compile: shaderc's messages, which name file and line.
    #[error("{0}")]
    Compile(shaderc::Error),
}

/// Compiles one GLSL compute shader for Vulkan 1.2.
///
/// `resolve_include` maps an include's name (as written between the quotes) to its text; a
/// `None` makes the include an error that names the including file and line. `macros` are
/// `#define`d before the source is read. With `optimize`, SPIR-V is optimized for
/// performance. On failure the error is shaderc's message, which names file and line.
pub fn compile_compute_shader(
    source: &str,
    file_name: &str,
    resolve_include: &dyn Fn(&str) -> Option<String>,
    macros: &[(&str, &str)],
    optimize: bool,
) -> Result<CompiledShader, ShaderError> {
    let compiler = shaderc::Compiler::new().map_err(ShaderError::CreateCompiler)?;
    let mut options = shaderc::CompileOptions::new().map_err(ShaderError::CreateOptions)?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_source_language(shaderc::SourceLanguage::GLSL);
    options.set_optimization_level(if optimize {
        shaderc::OptimizationLevel::Performance
    } else {
        shaderc::OptimizationLevel::Zero
    });
    options.set_generate_debug_info();
    for (name, value) in macros {
        options.add_macro_definition(name, Some(value));
    }
    options.set_include_callback(|requested, _kind, requesting, _depth| {
        resolve_include(requested)
            .map(|content| shaderc::ResolvedInclude {
                resolved_name: requested.to_string(),
                content,
            })
            .ok_or_else(|| format!("{requesting}: cannot include \"{requested}\""))
    });
    let artifact = compiler
        .compile_into_spirv(
            source,
            shaderc::ShaderKind::Compute,
            file_name,
            "main",
            Some(&options),
        )
        .map_err(ShaderError::Compile)?;
    Ok(CompiledShader {
        spirv: artifact.as_binary().to_vec(),
        warnings: artifact.get_warning_messages(),
    })
}
