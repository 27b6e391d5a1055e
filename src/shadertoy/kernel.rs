//! Compiling one pass: `src/shadertoy/pass.comp` with its includes resolved to the user's
//! Common tab and pass (each prepared by `intake`), so that the compiler's messages name the
//! user's files and lines.

use std::path::Path;

use crate::shader_compiler::{compile_compute_shader, CompiledShader};
use crate::shadertoy::intake::{prepare_tab, PreparedTab};

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

/// A tab of the user's: its file and its prepared text.
#[derive(Clone, Debug)]
pub struct UserTab {
    /// The file as the user named it, for messages.
    pub display_name: String,
    /// The tab made ready for the kernel.
    pub prepared: PreparedTab,
}

impl UserTab {
    /// Prepares the text of `path`.
    pub fn new(path: &Path, text: &str) -> UserTab {
        UserTab {
            display_name: path.display().to_string(),
            prepared: prepare_tab(text),
        }
    }

    /// What the kernel includes for this tab: the prelude, then the text from line 1.
    fn include(&self) -> String {
        format!("{}#line 1\n{}\n", self.prepared.prelude, self.prepared.text)
    }
}

/// Compiles a pass: `tab` (with `mainImage`, or a page shader's `main`) after `common`.
/// On failure the error is the compiler's messages, naming the user's files and lines.
pub fn compile_pass(common: Option<&UserTab>, tab: &UserTab) -> Result<CompiledShader, String> {
    if !tab.prepared.has_main_image && tab.prepared.page_shader_output.is_none() {
        return Err(format!(
            "{}: defines no mainImage(out vec4 fragColor, in vec2 fragCoord) (nor a page shader's main()); \
             if it is your Common tab, pass it with --common",
            tab.display_name
        ));
    }
    let resolve = |name: &str| -> Option<String> {
        match name {
            COMMON_INCLUDE => Some(common.map(UserTab::include).unwrap_or_default()),
            PASS_INCLUDE => Some(tab.include()),
            _ => None,
        }
    };
    let output = tab.prepared.page_shader_output.clone();
    let mut macros: Vec<(&str, &str)> = Vec::new();
    if let Some(output) = &output {
        macros.push(("VKPATH_PAGE_SHADER", "1"));
        macros.push(("VKPATH_PAGE_SHADER_OUTPUT", output.as_str()));
    }
    let rewrite = |messages: String| rewrite_messages(&messages, common, tab);
    match compile_compute_shader(PASS_KERNEL, PASS_KERNEL_NAME, &resolve, &macros, false) {
        Ok(compiled) => Ok(CompiledShader {
            spirv: compiled.spirv,
            warnings: rewrite(compiled.warnings),
        }),
        Err(messages) => Err(rewrite(messages)),
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
        UserTab::new(Path::new(name), text)
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
        assert!(compile_pass(Some(&common), &image).is_ok());
        let message = compile_pass(None, &image).err().expect("an error");
        assert!(message.starts_with("image.glsl:1:"), "{message}");
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
        let message = compile_pass(Some(&common), &image).err().expect("an error");
        assert!(message.contains("my/common.glsl:3:"), "{message}");
        let message = compile_pass(None, &tab("notes.glsl", "float f() { return 1.0; }\n"))
            .err()
            .expect("an error");
        assert!(
            message.contains("notes.glsl: defines no mainImage"),
            "{message}"
        );
        let message = compile_pass(None, &tab("bad.glsl", "void mainImage(vec2 p) { }\n"))
            .err()
            .expect("an error");
        assert!(
            message.starts_with("bad.glsl: in vkpath's code"),
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
            compile_pass(None, &page).is_ok(),
            "{:?}",
            compile_pass(None, &page).err()
        );
    }
}
