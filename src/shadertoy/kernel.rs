//! Compiling one pass: `src/shadertoy/pass.comp` with its includes resolved to the user's
//! Common tab and pass, each prepared on its own by the intake that `vkpath check` uses too
//! (`crate::glsl_intake::prepare_with`, `shadertoy_intake_options`), so that every pass is
//! one compilation of the Common tab followed by that pass, as in ShaderToy, and the
//! compiler's messages name the user's files and lines.

use std::path::Path;

use crate::glsl_intake::{
    find_entry_point, prepare_with, EntryPoint, IntakeOptions, PreparedSource, LOOP_GUARD_NAMES,
};
use crate::shader_compiler::{compile_compute_shader, CompiledShader};
use crate::shadertoy::directives::rewrite_custom_uniforms;
use crate::shadertoy::discard::rewrite_discards;

/// Why a ShaderToy program's pass does not compile: one or more lines that name the user's
/// files and lines.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PassError {
    /// The tab has neither `mainImage` nor a page shader's `main()`.
    #[error(
        "{tab}: defines no mainImage(out vec4 fragColor, in vec2 fragCoord) (nor a page shader's main()); \
         if it is your Common tab, pass it first among the files (or with --common)"
    )]
    NoEntryPoint {
        /// The tab's name in messages.
        tab: String,
    },
    /// The tabs read what a pass cannot supply: one line per name (`UserTab::unavailable`).
    #[error("{0}")]
    Unavailable(String),
    /// The compiler's messages, rewritten to name the user's files and lines.
    #[error("{0}")]
    Compiler(String),
}

/// The pass kernel's source.
const PASS_KERNEL: &str = include_str!("pass.comp");
/// Its name in compiler messages.
const PASS_KERNEL_NAME: &str = "shadertoy_pass.comp";
/// The include that the Common tab becomes.
const COMMON_INCLUDE: &str = "shadertoy_common.glsl";
/// The include that the pass's tab becomes.
const PASS_INCLUDE: &str = "shadertoy_pass.glsl";
/// The kernel's workgroup size (`local_size_x/y` in pass.comp).
pub const SHADERTOY_WORKGROUP_SIZE: u32 = 8;
/// What a page shader's `main()` is renamed, for the kernel to call it once per pixel.
const PAGE_SHADER_MAIN: &str = "vkpath_user_main";
/// The colour a page shader writes when it declares no `out vec4` (its `gl_FragColor`,
/// which the intake renames).
const PAGE_SHADER_FRAG_COLOR: &str = "vkpath_FragColor";

/// The macros that make `iChannel0`–`3` cube maps in pass.comp.
const CUBE_CHANNEL_MACROS: [&str; 4] = [
    "VKPATH_CHANNEL0_CUBE",
    "VKPATH_CHANNEL1_CUBE",
    "VKPATH_CHANNEL2_CUBE",
    "VKPATH_CHANNEL3_CUBE",
];

/// ShaderToy's inputs, which the pass kernel declares (a tab that declares them itself, as
/// exported or page-shader files do, has its declarations dropped).
pub const SUPPLIED_INPUTS: [&str; 14] = [
    "iResolution",
    "iTime",
    "iTimeDelta",
    "iFrameRate",
    "iFrame",
    "iMouse",
    "iDate",
    "iSampleRate",
    "iChannelResolution",
    "iChannelTime",
    "iChannel0",
    "iChannel1",
    "iChannel2",
    "iChannel3",
];

/// The intake options of a tab that runs in the pass kernel of a `width` x `height`
/// program: entry points kept (a page shader's `main` renamed `vkpath_user_main`),
/// ShaderToy's inputs and the loop guard declared by the kernel (once for the Common tab and
/// the pass), a uniform that stands for the resolution given the program's size, the
/// workshop's path length to an integer uniform that bounds the path loop; no renaming
/// against vkpath's path-tracing kernels, which a pass does not include.
pub fn shadertoy_intake_options(page_shader: bool, (width, height): (u32, u32)) -> IntakeOptions {
    IntakeOptions {
        keep_entry_points: true,
        supply_inputs: false,
        guard_loops: true,
        avoid_kernel_names: false,
        protected_functions: Vec::new(),
        bind_opaque: false,
        uniform_values: true,
        resolution: (width, height),
        caller_declares: SUPPLIED_INPUTS
            .iter()
            .chain(LOOP_GUARD_NAMES.iter())
            .map(|n| n.to_string())
            .collect(),
        renames: if page_shader {
            vec![("main".to_string(), PAGE_SHADER_MAIN.to_string())]
        } else {
            Vec::new()
        },
        caller_declares_loop_guard: true,
    }
}

/// A tab of the user's: its file and its prepared text.
#[derive(Clone, Debug)]
pub struct UserTab {
    /// The file as the user named it, for messages.
    pub display_name: String,
    /// The tab made ready for the kernel.
    pub prepared: PreparedSource,
    /// Whether the tab defines `mainImage`.
    pub has_main_image: bool,
    /// Whether the tab asks for VS Code Shader Toy's keyboard queries (`#iKeyboard`), which
    /// the kernel then declares (no key is ever down).
    pub keyboard: bool,
    /// For a page shader (`main()` and no `mainImage`): the expression of its colour, its
    /// `out vec4` variable or `vkpath_FragColor` (its `gl_FragColor`).
    pub page_shader_output: Option<String>,
}

impl UserTab {
    /// Prepares the text of `path` for a program of `resolution` (width, height) pixels.
    pub fn new(path: &Path, text: &str, resolution: (u32, u32)) -> UserTab {
        let entry = find_entry_point(text);
        let page_shader = entry == Some(EntryPoint::Main);
        // VS Code Shader Toy's custom uniforms, before the intake drops their lines.
        let (text, uniform_notes) = rewrite_custom_uniforms(text);
        let text = text.as_str();
        let mut prepared = prepare_with(text, &shadertoy_intake_options(page_shader, resolution));
        prepared.notes.extend(uniform_notes);
        // A fragment shader's `discard`, which a compute kernel lacks (see `discard`).
        prepared.text = rewrite_discards(&prepared.text).0;
        let page_shader_output = page_shader.then(|| {
            prepared
                .outputs
                .iter()
                .find(|(kind, _)| kind == "vec4")
                .map_or_else(
                    || PAGE_SHADER_FRAG_COLOR.to_string(),
                    |(_, name)| name.clone(),
                )
        });
        let mut tab = UserTab {
            display_name: path.display().to_string(),
            prepared,
            has_main_image: entry == Some(EntryPoint::MainImage),
            keyboard: false,
            page_shader_output,
        };
        let keyboard_line = text.lines().position(|line| {
            line.trim_start()
                .strip_prefix('#')
                .is_some_and(|rest| rest.trim_start().starts_with("iKeyboard"))
        });
        if let Some(index) = keyboard_line {
            tab.keyboard = true;
            tab.prepared.notes.push(format!(
                "line {}: #iKeyboard: isKeyDown, isKeyPressed, isKeyToggled, isKeyReleased and the Key_* codes are declared; no key is ever down (headless)",
                index + 1
            ));
        }
        if page_shader {
            tab.prepared.notes.push(
                "your main() runs once per pixel as a mainImage would (gl_FragCoord at pixel centres)"
                    .into(),
            );
        }
        tab
    }

    /// The notes of the intake, each naming the file ("tab.glsl:3: dropped …").
    pub fn notes(&self) -> Vec<String> {
        self.prepared
            .notes
            .iter()
            .map(|note| match note.strip_prefix("line ") {
                Some(rest) => format!("{}:{rest}", self.display_name),
                None => format!("{}: {note}", self.display_name),
            })
            .collect()
    }

    /// What the user's code reads that a pass cannot supply (a sampler uniform of a page
    /// shader, ray queries), as one error line per name, naming the file and line; a
    /// declaration that nothing reads is only dropped.
    fn unavailable(&self) -> Option<String> {
        let read: std::collections::BTreeSet<String> =
            crate::glsl_intake::syntax::tokenize(&self.prepared.text)
                .into_iter()
                .filter(|t| t.is_identifier())
                .map(|t| t.text)
                .collect();
        let lines: Vec<String> = self
            .prepared
            .unavailable
            .iter()
            .filter(|u| read.contains(&u.name))
            .map(|u| {
                format!(
                    "{}:{}: '{}' cannot be supplied by vkpath shadertoy (a pass reads textures through iChannel0-3, set with --channel)",
                    self.display_name, u.line, u.what
                )
            })
            .collect();
        (!lines.is_empty()).then(|| lines.join("\n"))
    }

    /// What the kernel includes for this tab: the prelude, then the text from line 1.
    fn include(&self) -> String {
        format!("{}#line 1\n{}\n", self.prepared.prelude, self.prepared.text)
    }
}

/// Compiles a pass: `tab` (with `mainImage`, or a page shader's `main`) after `common`, the
/// two prepared on their own and compiled as one, as ShaderToy prepends its Common tab to
/// every pass. The user's macros end after both (their epilogues), so that they cannot
/// change the kernel's own code. On failure the error is the compiler's messages, naming the
/// user's files and lines.
///
/// `cube_channels[N]` makes `iChannelN` a `samplerCube` (a cube-map channel) instead of a
/// `sampler2D`.
pub fn compile_pass(
    common: Option<&UserTab>,
    tab: &UserTab,
    cube_channels: [bool; 4],
) -> Result<CompiledShader, PassError> {
    if !tab.has_main_image && tab.page_shader_output.is_none() {
        return Err(PassError::NoEntryPoint {
            tab: tab.display_name.clone(),
        });
    }
    if let Some(message) = common
        .and_then(UserTab::unavailable)
        .or_else(|| tab.unavailable())
    {
        return Err(PassError::Unavailable(message));
    }
    let epilogues = format!(
        "{}{}",
        common.map_or("", |c| c.prepared.epilogue.as_str()),
        tab.prepared.epilogue
    );
    let resolve = |name: &str| -> Option<String> {
        match name {
            COMMON_INCLUDE => Some(common.map(UserTab::include).unwrap_or_default()),
            PASS_INCLUDE => Some(format!("{}{epilogues}", tab.include())),
            _ => None,
        }
    };
    let output = tab.page_shader_output.clone();
    let mut macros: Vec<(&str, &str)> = Vec::new();
    if let Some(output) = &output {
        macros.push(("VKPATH_PAGE_SHADER", "1"));
        macros.push(("VKPATH_PAGE_SHADER_OUTPUT", output.as_str()));
    }
    for (channel, _) in cube_channels.iter().enumerate().filter(|(_, cube)| **cube) {
        macros.push((CUBE_CHANNEL_MACROS[channel], "1"));
    }
    if common.is_some_and(|c| c.keyboard) || tab.keyboard {
        macros.push(("VKPATH_KEYBOARD", "1"));
    }
    let rewrite = |messages: String| rewrite_messages(&messages, common, tab);
    match compile_compute_shader(PASS_KERNEL, PASS_KERNEL_NAME, &resolve, &macros, false) {
        Ok(compiled) => Ok(CompiledShader {
            spirv: compiled.spirv,
            warnings: rewrite(compiled.warnings),
        }),
        Err(error) => Err(PassError::Compiler(with_missing_tab_hint(
            rewrite(error.to_string()),
            common,
            tab,
        ))),
    }
}

/// `messages` with a last line when they call names undeclared that neither tab declares:
/// a type or function of the Common tab, most likely, when none was given.
fn with_missing_tab_hint(messages: String, common: Option<&UserTab>, tab: &UserTab) -> String {
    let texts: Vec<&str> = common
        .map(|c| c.prepared.text.as_str())
        .into_iter()
        .chain([tab.prepared.text.as_str()])
        .collect();
    let tabs: Vec<(&str, &str)> = common
        .into_iter()
        .chain([tab])
        .map(|t| (t.display_name.as_str(), t.prepared.text.as_str()))
        .collect();
    let types = crate::glsl_intake::undeclared_types(&messages, &tabs, &texts);
    let types = match types.len() {
        0 => None,
        1 => Some(format!("'{}' is", types[0])),
        _ => Some(format!(
            "{} are",
            types
                .iter()
                .map(|t| format!("'{t}'"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
    };
    let missing = crate::glsl_intake::undefined_names(&messages, &texts).or(types);
    match missing {
        Some(missing) if common.is_none() => format!(
            "{messages}\n{}: {missing} not defined in any of your files; if your program has a Common tab, pass it first",
            tab.display_name
        ),
        Some(missing) => format!(
            "{messages}\n{}: {missing} not defined in any of your files (nor in the Common tab {})",
            tab.display_name,
            common.map_or("", |c| c.display_name.as_str())
        ),
        None => messages,
    }
}

/// Compiler messages with the includes' names replaced by the user's files; a message
/// about the kernel's own code names the pass's file and says so. Continuation lines stay
/// indented under their message.
fn rewrite_messages(messages: &str, common: Option<&UserTab>, tab: &UserTab) -> String {
    messages
        .lines()
        // shaderc's first line ("3 compilation errors:") says nothing the caller does not.
        .filter(|line| !line.trim().is_empty() && !line.trim_end().ends_with("compilation error:") && !line.trim_end().ends_with("compilation errors:"))
        .map(|line| {
            if let Some(rest) = line.strip_prefix(&format!("{PASS_INCLUDE}:")) {
                format!("{}:{rest}", tab.display_name)
            } else if let Some(rest) = line.strip_prefix(&format!("{COMMON_INCLUDE}:")) {
                let name = common.map_or("Common", |c| c.display_name.as_str());
                format!("{name}:{rest}")
            } else if let Some(rest) = line.strip_prefix(&format!("{PASS_KERNEL_NAME}:")) {
                let message = rest.split_once(':').map_or(rest, |(_, m)| m);
                format!(
                    "{}: in vkpath's code around your pass (its mainImage must be void mainImage(out vec4, in vec2); a name of yours may clash with vkpath_*):{message}",
                    tab.display_name
                )
            } else if line.contains(" error") && !line.starts_with(' ') {
                line.to_string()
            } else {
                format!("    {}", line.trim_start())
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tab(name: &str, text: &str) -> UserTab {
        UserTab::new(Path::new(name), text, (16, 8))
    }

    #[test]
    fn a_tab_compiles_after_its_common_tab() {
        let common = tab(
            "common.glsl",
            "vec3 shade(vec2 uv) { return vec3(uv, 0.0); }\n",
        );
        let image = tab(
            "image.glsl",
            "void mainImage(out vec4 c, in vec2 p) { c = vec4(shade(p / iResolution.xy), 1.0) + texture(iChannel0, p); }\n",
        );
        assert!(compile_pass(Some(&common), &image, [false; 4]).is_ok());
        let message = compile_pass(None, &image, [false; 4])
            .err()
            .expect("an error")
            .to_string();
        assert!(message.starts_with("image.glsl:1:"), "{message}");
        assert!(
            message.ends_with("image.glsl: 'shade' is not defined in any of your files; if your program has a Common tab, pass it first"),
            "{message}"
        );
    }

    #[test]
    fn a_type_of_the_common_tab_is_named_when_the_tab_is_missing() {
        // The compiler says only "syntax error, unexpected IDENTIFIER" at the parameter.
        let common = tab("common.glsl", "struct hit_t {\n    float t;\n};\n");
        let image = tab(
            "image.glsl",
            "// uses the Common tab's type\nfloat distance_of(hit_t hit) { return hit.t; }\n\
             void mainImage(out vec4 c, in vec2 p) { hit_t h; h.t = p.x; c = vec4(distance_of(h)); }\n",
        );
        assert!(compile_pass(Some(&common), &image, [false; 4]).is_ok());
        let message = compile_pass(None, &image, [false; 4])
            .err()
            .expect("an error")
            .to_string();
        assert!(message.starts_with("image.glsl:2:"), "{message}");
        assert!(
            message.ends_with("image.glsl: 'hit_t' is not defined in any of your files; if your program has a Common tab, pass it first"),
            "{message}"
        );
    }

    #[test]
    fn errors_name_the_users_file_and_line() {
        let common = tab(
            "my/common.glsl",
            "\n\nfloat broken() { return undefined_thing; }\n",
        );
        let image = tab(
            "image.glsl",
            "void mainImage(out vec4 c, in vec2 p) { c = vec4(1.0); }\n",
        );
        let message = compile_pass(Some(&common), &image, [false; 4])
            .err()
            .expect("an error")
            .to_string();
        assert!(message.contains("my/common.glsl:3:"), "{message}");
        let message = compile_pass(
            None,
            &tab("notes.glsl", "float f() { return 1.0; }\n"),
            [false; 4],
        )
        .err()
        .expect("an error")
        .to_string();
        assert!(
            message.contains("notes.glsl: defines no mainImage"),
            "{message}"
        );
        let message = compile_pass(
            None,
            &tab("bad.glsl", "void mainImage(vec2 p) { }\n"),
            [false; 4],
        )
        .err()
        .expect("an error")
        .to_string();
        assert!(
            message.starts_with("bad.glsl: in vkpath's code"),
            "{message}"
        );
    }

    #[test]
    fn a_tab_keeps_its_own_triangle_struct() {
        // check replaces the workshop's struct with vkpath's; a pass has no other to use.
        let image = tab(
            "tab.glsl",
            "struct triangle_t {\n    vec3 positions[3];\n    vec3 normal;\n    vec3 color;\n    vec3 emission;\n};\n\
             void mainImage(out vec4 c, in vec2 p) { triangle_t t; t.color = vec3(1.0); c = vec4(t.color, 1.0); }\n",
        );
        let compiled = compile_pass(None, &image, [false; 4]);
        assert!(compiled.is_ok(), "{:?}", compiled.err());
    }

    #[test]
    fn a_sampler_without_data_is_an_error_only_where_it_is_read() {
        let unused = tab(
            "page.glsl",
            "uniform sampler2D u_unused;\nout vec4 color;\nvoid main() { color = vec4(1.0); }\n",
        );
        assert!(compile_pass(None, &unused, [false; 4]).is_ok());
        let read = tab(
            "page.glsl",
            "uniform sampler2D u_scene;\nout vec4 color;\nvoid main() { color = texture(u_scene, vec2(0.5)); }\n",
        );
        let message = compile_pass(None, &read, [false; 4])
            .err()
            .expect("an error")
            .to_string();
        assert!(
            message.starts_with("page.glsl:1: 'uniform sampler2D u_scene' cannot be supplied"),
            "{message}"
        );
    }

    #[test]
    fn a_page_shader_compiles() {
        let page = tab(
            "page.glsl",
            "#version 300 es\nprecision highp float;\nuniform vec2 u_resolution;\nout vec4 color;\nvoid main() { color = vec4(gl_FragCoord.xy, 0.0, 1.0); }\n",
        );
        assert!(
            compile_pass(None, &page, [false; 4]).is_ok(),
            "{:?}",
            compile_pass(None, &page, [false; 4]).err()
        );
    }
}
