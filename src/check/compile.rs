//! Compiling the embedded kernels at run time with a user's functions: `#include
//! "user_functions.glsl"` resolves to the user's prepared file (`crate::glsl_intake`),
//! the other includes to the embedded `glsl/` sources, and `USER_FUNCTIONS` plus
//! `USER_DEFINES_<NAME>` for each function taken from the user make the kernels use the
//! user's versions (the reference versions of the others stay).
//!
//! Each function is judged on its own: the kernel that judges one takes only that function
//! from the user's file, so a mistake in one function never fails another. Compiler
//! messages name the user's file and its lines.

use std::collections::BTreeSet;
use std::ops::Range;

use crate::check::detect::{find_functions, Definition, FoundFunction, WorkshopFunction};
use crate::glsl_intake::{prepare_with, IntakeOptions, PreparedSource};
use crate::shader_compiler::{compile_compute_shader, CompiledShader};
use crate::shaders::GLSL_SOURCES;

pub use crate::glsl_intake::USER_FUNCTIONS_FILE;

/// The intake options of `check`: the user's code goes into vkpath's kernels, its entry
/// points are dropped, and the workshop functions keep their signatures (a definition with
/// other parameters is renamed `user_<name>` and listed as not judged).
pub fn check_intake_options() -> IntakeOptions {
    IntakeOptions {
        protected_functions: WorkshopFunction::ALL
            .iter()
            .filter_map(|f| Some((f.name().to_string(), f.signature()?)))
            .collect(),
        ..IntakeOptions::default()
    }
}

/// How many rounds of dropping functions that do not compile are tried before the whole
/// file is reported as not compiling.
const MAX_COMPILE_ROUNDS: usize = 12;

/// A workshop name in the user's file that cannot be judged, and why.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct NotJudged {
    /// The function's name.
    pub function: String,
    /// Its line in the user's file.
    pub line: usize,
    /// Why it is not judged.
    pub reason: String,
}

/// A function of the user's file that does not compile: dropped, with the compiler's words.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BrokenFunction {
    /// The function's name.
    pub name: String,
    /// Its line in the user's file.
    pub line: usize,
    /// The compiler's messages about it (naming the user's file and lines).
    pub messages: String,
}

/// A user's GLSL file with its versions of workshop functions.
#[derive(Clone, Debug)]
pub struct UserFunctions {
    /// The file as the user named it, for messages.
    pub display_name: String,
    /// Its text as written.
    pub text: String,
    /// The text made ready for the kernels.
    pub prepared: PreparedSource,
    /// The workshop functions it defines with the workshop's signatures, in order of
    /// appearance (those that do not compile included).
    pub definitions: Vec<Definition>,
    /// Workshop names it uses for something else.
    pub not_judged: Vec<NotJudged>,
    /// Functions dropped because they do not compile.
    pub broken: Vec<BrokenFunction>,
    /// The compiler's warnings about the file (once it compiles).
    pub compile_warnings: String,
    /// The compiler's messages when an error lies outside every function, so that nothing
    /// can be judged.
    pub compile_errors: Option<String>,
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

impl UserFunctions {
    /// Reads `text`: prepares it and finds the workshop functions it defines.
    pub fn new(display_name: &str, text: String) -> UserFunctions {
        let prepared = prepare_with(&text, &check_intake_options());
        let mut definitions = Vec::new();
        let mut not_judged = Vec::new();
        for (name, line, signature) in &prepared.renamed_functions {
            let Some(function) = WorkshopFunction::from_name(name) else {
                continue;
            };
            not_judged.push(NotJudged {
                function: function.name().to_string(),
                line: *line,
                reason: format!(
                    "its parameters are {signature} but the workshop's {} is {}; it is kept as your own user_{} and not judged",
                    function.name(),
                    function
                        .signature()
                        .map_or_else(|| "unknown".to_string(), |s| s.to_string()),
                    function.name()
                ),
            });
        }
        for found in find_functions(&prepared.text)
            .into_iter()
            .filter(|f| f.has_body)
        {
            let Some(function) = WorkshopFunction::from_name(&found.name) else {
                continue;
            };
            let definition = Definition {
                function,
                line: found.line,
                signature: found.signature,
            };
            if definition.has_workshop_signature() {
                definitions.push(definition);
            } else {
                // A second definition of the name with other parameters, beside one with
                // the workshop's: GLSL takes it as an overload.
                not_judged.push(NotJudged {
                    function: function.name().to_string(),
                    line: found.line,
                    reason: format!(
                        "this overload takes {} rather than the workshop's parameters; it is kept and not judged",
                        definition.signature
                    ),
                });
            }
        }
        if prepared.other_triangle_struct.is_some() {
            for entry in &mut not_judged {
                if entry.reason.contains("user_triangle_t") {
                    entry
                        .reason
                        .push_str(" (your triangle_t differs from the workshop's)");
                }
            }
        }
        not_judged.sort_by_key(|n| n.line);
        UserFunctions {
            display_name: display_name.to_string(),
            text,
            prepared,
            definitions,
            not_judged,
            broken: Vec::new(),
            compile_warnings: String::new(),
            compile_errors: None,
        }
    }

    /// The distinct workshop functions the file defines (with the workshop's signature), in
    /// the workshop's order.
    pub fn functions(&self) -> Vec<WorkshopFunction> {
        let defined: BTreeSet<WorkshopFunction> =
            self.definitions.iter().map(|d| d.function).collect();
        defined.into_iter().collect()
    }

    /// The functions that compile and can be judged.
    pub fn judged_functions(&self) -> Vec<WorkshopFunction> {
        self.functions()
            .into_iter()
            .filter(|f| !self.broken.iter().any(|b| b.name == f.name()))
            .collect()
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

    /// The code a kernel includes to take `active` from the user (the user's other workshop
    /// functions and the functions that do not compile are left out; its helpers stay).
    pub fn code(&self, active: &[WorkshopFunction]) -> UserCode {
        let mut left_out: Vec<Range<usize>> = Vec::new();
        for found in find_functions(&self.prepared.text) {
            let workshop = WorkshopFunction::from_name(&found.name);
            let inactive = workshop.is_some_and(|f| !active.contains(&f));
            let broken = self.broken.iter().any(|b| b.name == found.name);
            if inactive || broken {
                left_out.push(found.span.clone());
            }
        }
        let mut text = self.prepared.text.clone();
        for range in left_out {
            let blank: String = text[range.clone()]
                .chars()
                .map(|c| if c == '\n' { '\n' } else { ' ' })
                .collect();
            text.replace_range(range, &blank);
        }
        UserCode {
            include: format!(
                "{}#line 1\n{}{}",
                self.prepared.prelude, text, self.prepared.epilogue
            ),
            active: active.to_vec(),
            display_name: self.display_name.clone(),
        }
    }

    /// The code with every judged function taken from the user, as the file runs on its own.
    pub fn whole(&self) -> UserCode {
        self.code(&self.judged_functions())
    }

    /// Compiles the file with all its functions; functions whose code the compiler rejects
    /// are dropped (recorded in `broken`, with the compiler's messages) and the rest compiled
    /// again. Returns the compiler's warnings, or its messages when an error lies outside
    /// every function (then nothing can be judged).
    pub fn find_broken_functions(&mut self) -> Result<String, String> {
        for _ in 0..MAX_COMPILE_ROUNDS {
            let code = self.whole();
            let messages = match compile_kernel("probe_get_random_numbers.comp", Some(&code), &[]) {
                Ok(compiled) => return Ok(compiled.warnings),
                Err(messages) => messages,
            };
            let functions = find_functions(&self.prepared.text);
            let mut newly_broken: Vec<BrokenFunction> = Vec::new();
            let mut outside = false;
            for message in messages.lines().filter(|l| l.contains(": error:")) {
                let Some(line) = self.error_line(message) else {
                    outside = true;
                    continue;
                };
                match enclosing(&functions, &self.prepared.text, line) {
                    Some(found) if !self.broken.iter().any(|b| b.name == found.name) => {
                        match newly_broken.iter_mut().find(|b| b.name == found.name) {
                            Some(broken) => {
                                broken.messages.push_str(message);
                                broken.messages.push('\n');
                            }
                            None => newly_broken.push(BrokenFunction {
                                name: found.name.clone(),
                                line: found.line,
                                messages: format!("{message}\n"),
                            }),
                        }
                    }
                    _ => outside = true,
                }
            }
            if outside || newly_broken.is_empty() {
                return Err(messages);
            }
            self.broken.extend(newly_broken);
        }
        Err(format!(
            "{}: too many functions do not compile",
            self.display_name
        ))
    }

    /// The user's line that a compiler message names, if it names the user's file.
    fn error_line(&self, message: &str) -> Option<usize> {
        let rest = message.strip_prefix(&format!("{}:", self.display_name))?;
        rest.split(':').next()?.trim().parse().ok()
    }
}

/// The function (defined at global scope) whose text covers `line`.
fn enclosing<'a>(
    functions: &'a [FoundFunction],
    text: &str,
    line: usize,
) -> Option<&'a FoundFunction> {
    functions.iter().filter(|f| f.has_body).find(|f| {
        let first_line = text[..f.span.start].matches('\n').count() + 1;
        (first_line..=f.last_line).contains(&line)
    })
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
) -> Result<CompiledShader, String> {
    let source = embedded_source(kernel_file)
        .ok_or_else(|| format!("{kernel_file} is not among the embedded GLSL sources"))?;
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
        let code = user.whole();
        assert!(code
            .macros()
            .contains(&("USER_DEFINES_SAMPLE_SPHERE".into(), "1".into())));
        let compiled = compile_kernel("probe_sample_hemisphere.comp", Some(&code), &[]);
        assert!(compiled.is_ok(), "{:?}", compiled.err());

        let mut broken = UserFunctions::new(
            "mine.glsl",
            "#version 300 es\nvec3 sample_sphere(vec2 u) {\n    return vec3(0.0, 0.0, 1.0)\n}\n"
                .into(),
        );
        let Err(error) = compile_kernel("probe_sample_sphere.comp", Some(&broken.whole()), &[])
        else {
            panic!("a missing semicolon must not compile");
        };
        assert!(error.contains("mine.glsl:4:"), "{error}");
        assert!(!error.contains(USER_FUNCTIONS_FILE), "{error}");
        // The function is dropped, and with it nothing is left to judge.
        assert!(broken.find_broken_functions().is_ok());
        assert_eq!(broken.broken.len(), 1);
        assert!(broken.judged_functions().is_empty());
    }

    #[test]
    fn one_function_that_does_not_compile_leaves_the_others() {
        let mut user = UserFunctions::new(
            "tab.glsl",
            "vec3 sample_sphere(vec2 u) {\n    return vec3(0.0, 0.0, 1.0);\n}\n\
             vec3 sample_hemisphere(vec2 u, vec3 n) {\n    return undefined_name;\n}\n"
                .into(),
        );
        assert!(user.find_broken_functions().is_ok());
        assert_eq!(user.judged_functions(), [WorkshopFunction::SampleSphere]);
        assert_eq!(user.broken[0].name, "sample_hemisphere");
        assert!(
            user.broken[0].messages.contains("tab.glsl:5:"),
            "{:?}",
            user.broken
        );
    }

    #[test]
    fn each_kernel_takes_only_the_function_it_judges() {
        let user = UserFunctions::new(
            "tab.glsl",
            "vec3 sample_sphere(vec2 u) { return vec3(0.0, 0.0, 1.0); }\n\
             vec3 sample_hemisphere(vec2 u, vec3 n) { return sample_sphere(u); }\n"
                .into(),
        );
        let code = user.code(&[WorkshopFunction::SampleHemisphere]);
        assert!(!code.include.contains("return vec3(0.0, 0.0, 1.0)"));
        assert!(code.include.contains("return sample_sphere(u)"));
        assert!(compile_kernel("probe_sample_hemisphere.comp", Some(&code), &[]).is_ok());
    }

    #[test]
    fn reference_kernels_compile_without_a_user() {
        assert!(compile_kernel("probe_get_random_numbers.comp", None, &[]).is_ok());
        assert!(compile_kernel("no_such.comp", None, &[]).is_err());
    }
}
