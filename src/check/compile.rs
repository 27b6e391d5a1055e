//! Compiling the embedded kernels at run time with a user's functions: `#include
//! "user_functions.glsl"` resolves to the user's file, the other includes to the embedded
//! `glsl/` sources, and `USER_FUNCTIONS` plus `USER_DEFINES_<NAME>` for every function the
//! file defines make the kernels use the user's versions (the reference versions of the
//! others stay, and call the user's). Compiler messages name the user's file and its lines.

use std::collections::BTreeSet;

use crate::check::detect::{find_definitions, Definition, WorkshopFunction};
use crate::shader_compiler::{compile_compute_shader, CompiledShader};
use crate::shaders::GLSL_SOURCES;

/// The file name under which the kernels include the user's functions.
pub const USER_FUNCTIONS_FILE: &str = "user_functions.glsl";

/// A user's GLSL file with its versions of workshop functions.
#[derive(Clone, Debug)]
pub struct UserFunctions {
    /// The file as the user named it, for messages.
    pub display_name: String,
    /// Its text.
    pub text: String,
    /// The workshop functions it defines, in order of appearance.
    pub definitions: Vec<Definition>,
}

impl UserFunctions {
    /// Finds the workshop functions that `text` defines.
    pub fn new(display_name: &str, text: String) -> UserFunctions {
        let definitions = find_definitions(&text);
        UserFunctions {
            display_name: display_name.to_string(),
            text,
            definitions,
        }
    }

    /// The distinct functions the file defines, in the workshop's order.
    pub fn functions(&self) -> Vec<WorkshopFunction> {
        let defined: BTreeSet<WorkshopFunction> =
            self.definitions.iter().map(|d| d.function).collect();
        defined.into_iter().collect()
    }

    /// Whether the file defines `function`.
    pub fn defines(&self, function: WorkshopFunction) -> bool {
        self.definitions.iter().any(|d| d.function == function)
    }

    /// The line of the file's first definition of `function` (0 if none).
    pub fn line_of(&self, function: WorkshopFunction) -> usize {
        self.definitions
            .iter()
            .find(|d| d.function == function)
            .map_or(0, |d| d.line)
    }

    /// `USER_FUNCTIONS` and `USER_DEFINES_<NAME>` for each defined function.
    pub fn macros(&self) -> Vec<(String, String)> {
        let mut macros = vec![("USER_FUNCTIONS".to_string(), "1".to_string())];
        macros.extend(
            self.functions()
                .into_iter()
                .map(|f| (f.user_defines_macro(), "1".to_string())),
        );
        macros
    }

    /// Replaces the include's name in compiler messages by the user's file name, so that
    /// `user_functions.glsl:12: error: ...` reads `their_file.glsl:12: error: ...`; the
    /// lines are the user's own, since the include is their file verbatim.
    pub fn rewrite_messages(&self, messages: &str) -> String {
        messages.replace(
            &format!("{USER_FUNCTIONS_FILE}:"),
            &format!("{}:", self.display_name),
        )
    }
}

/// Compiles `glsl/<kernel_file>` from the embedded sources, with the user's functions when
/// `user` is given, and `extra_macros` (e.g. `USE_BVH`). The SPIR-V is
/// not optimized: the kernels are small, and the driver optimizes anyway. On failure the
/// error is the compiler's messages, rewritten to name the user's file.
pub fn compile_kernel(
    kernel_file: &str,
    user: Option<&UserFunctions>,
    extra_macros: &[(&str, &str)],
) -> Result<CompiledShader, String> {
    let source = embedded_source(kernel_file)
        .ok_or_else(|| format!("{kernel_file} is not among the embedded GLSL sources"))?;
    let resolve = |name: &str| -> Option<String> {
        match user {
            Some(user) if name == USER_FUNCTIONS_FILE => Some(user.text.clone()),
            _ => embedded_source(name).map(str::to_string),
        }
    };
    let user_macros = user.map(UserFunctions::macros).unwrap_or_default();
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
        Err(messages) => Err(rewrite(messages)),
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
    fn user_functions_replace_the_reference_and_errors_name_their_file() {
        let user = UserFunctions::new(
            "mine.glsl",
            "vec3 sample_sphere(vec2 u) {\n    return vec3(0.0, 0.0, 1.0);\n}\n".into(),
        );
        assert_eq!(user.functions(), [WorkshopFunction::SampleSphere]);
        assert!(user
            .macros()
            .contains(&("USER_DEFINES_SAMPLE_SPHERE".into(), "1".into())));
        let compiled = compile_kernel("probe_sample_hemisphere.comp", Some(&user), &[]);
        assert!(compiled.is_ok(), "{:?}", compiled.err());

        let broken = UserFunctions::new(
            "mine.glsl",
            "vec3 sample_sphere(vec2 u) {\n    return vec3(0.0, 0.0, 1.0)\n}\n".into(),
        );
        let Err(error) = compile_kernel("probe_sample_sphere.comp", Some(&broken), &[]) else {
            panic!("a missing semicolon must not compile");
        };
        assert!(error.contains("mine.glsl:3:"), "{error}");
        assert!(!error.contains(USER_FUNCTIONS_FILE), "{error}");
    }

    #[test]
    fn reference_kernels_compile_without_a_user() {
        assert!(compile_kernel("probe_get_random_numbers.comp", None, &[]).is_ok());
        assert!(compile_kernel("no_such.comp", None, &[]).is_err());
    }
}
