//! Compiling the embedded kernels at run time with a user's functions: `#include
//! "user_functions.glsl"` resolves to the user's prepared file (`crate::glsl_intake`),
//! the other includes to the embedded `glsl/` sources, and `USER_FUNCTIONS` plus
//! `USER_DEFINES_<NAME>` for each function taken from the user make the kernels use the
//! user's versions (the reference versions of the others stay).
//!
//! Each function is judged on its own: the kernel that judges one takes only that function
//! from the user's file, so a mistake in one function never fails another. Compiler
//! messages name the user's file and its lines. What the user's file defines, and which of
//! its functions a kernel takes, is `crate::check::user_functions`.

use crate::check::detect::WorkshopFunction;
use crate::shader_compiler::{compile_compute_shader, CompiledShader};
use crate::shaders::GLSL_SOURCES;

pub use crate::glsl_intake::USER_FUNCTIONS_FILE;

/// Why a kernel with a user's code does not compile.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CompileError {
    /// The kernel named is not among the embedded `glsl/` sources.
    #[error("{kernel_file} is not among the embedded GLSL sources")]
    NotEmbedded {
        /// The kernel's file name.
        kernel_file: String,
    },
    /// The compiler's messages (`file:line: error: …`, one a line), rewritten to name the
    /// user's file.
    #[error("{0}")]
    Compiler(String),
    /// Setting aside the functions that do not compile took more rounds than
    /// `UserFunctions::find_broken_functions` allows.
    #[error("{file}: too many functions do not compile")]
    TooManyBrokenFunctions {
        /// The user's file, as messages name it.
        file: String,
    },
}

/// The user's code as one kernel includes it: the prepared file with only `active` of its
/// workshop functions, between the prelude and the epilogue.
#[derive(Clone, Debug)]
pub struct UserCode {
    /// The text that `#include "user_functions.glsl"` resolves to.
    pub include: String,
    /// The workshop functions taken from the user.
    pub active: Vec<WorkshopFunction>,
    /// The user's file name, for messages.
    pub display_name: String,
}

impl UserCode {
    /// `USER_FUNCTIONS` and `USER_DEFINES_<NAME>` for each active function.
    pub fn macros(&self) -> Vec<(String, String)> {
        let mut macros = vec![("USER_FUNCTIONS".to_string(), "1".to_string())];
        macros.extend(
            self.active
                .iter()
                .map(|f| (f.user_defines_macro(), "1".to_string())),
        );
        macros
    }

    /// Rewrites compiler messages so that they name the user's file: the include's name
    /// becomes the user's file name (the lines are the user's, thanks to `#line`), and a
    /// message about vkpath's own files says that the user's file caused it, without naming
    /// them.
    pub fn rewrite_messages(&self, messages: &str) -> String {
        messages
            .lines()
            .map(|line| {
                if let Some(rest) = line.strip_prefix(&format!("{USER_FUNCTIONS_FILE}:")) {
                    format!("{}:{rest}", self.display_name)
                } else if let Some(position) = line.find(": error:").or_else(|| line.find(": warning:")) {
                    format!(
                        "{} (in vkpath's kernel code after your file; a name or macro of yours probably clashes with it){}",
                        self.display_name,
                        &line[position..]
                    )
                } else {
                    line.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    }
}

/// Compiles `glsl/<kernel_file>` from the embedded sources, with the user's code when
/// `user` is given, and `extra_macros` (e.g. `USE_BVH`). The SPIR-V is not optimized: the
/// kernels are small, and the driver optimizes anyway. On failure the error is the
/// compiler's messages, rewritten to name the user's file.
pub fn compile_kernel(
    kernel_file: &str,
    user: Option<&UserCode>,
    extra_macros: &[(&str, &str)],
) -> Result<CompiledShader, CompileError> {
    let source = embedded_source(kernel_file).ok_or_else(|| CompileError::NotEmbedded {
        kernel_file: kernel_file.to_string(),
    })?;
    // The user's file is included once; any other request for it (there is none in the
    // kernels) is refused rather than recursing.
    let included = std::cell::Cell::new(false);
    let resolve = |name: &str| -> Option<String> {
        match user {
            Some(user) if name == USER_FUNCTIONS_FILE => {
                (!included.replace(true)).then(|| user.include.clone())
            }
            _ => embedded_source(name).map(str::to_string),
        }
    };
    let user_macros = user.map(UserCode::macros).unwrap_or_default();
    let mut macros: Vec<(&str, &str)> = user_macros
        .iter()
        .map(|(name, value)| (name.as_str(), value.as_str()))
        .collect();
    macros.extend_from_slice(extra_macros);
    let rewrite = |text: String| match user {
        Some(user) => user.rewrite_messages(&text),
        None => text,
    };
    match compile_compute_shader(source, kernel_file, &resolve, &macros, false) {
        Ok(compiled) => Ok(CompiledShader {
            spirv: compiled.spirv,
            warnings: rewrite(compiled.warnings),
        }),
        Err(error) => Err(CompileError::Compiler(rewrite(error.to_string()))),
    }
}

/// The text of an embedded file of `glsl/`.
fn embedded_source(file_name: &str) -> Option<&'static str> {
    GLSL_SOURCES
        .iter()
        .find(|(name, _)| *name == file_name)
        .map(|(_, text)| *text)
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn reference_kernels_compile_without_a_user() {
        assert!(compile_kernel("probe_get_random_numbers.comp", None, &[]).is_ok());
        assert!(compile_kernel("no_such.comp", None, &[]).is_err());
    }
}
