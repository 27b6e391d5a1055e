//! The intake of user GLSL ("paste anything"), shared by `vkpath check` and
//! `vkpath shadertoy`: a file as people publish it (a ShaderToy tab, a WebGL or desktop page
//! shader, a blog post's code blocks, just the functions) turned into GLSL that vkpath can
//! compile, with every line where the user wrote it so that compiler messages name the
//! user's lines.
//!
//! - `syntax`: a tokenizer and the top-level items of a file (functions, declarations);
//! - `paste`: the GLSL of a file published around it (a Markdown post's code blocks, a web
//!   page's shader tags, a script's template strings, notes with prose lines), the rest
//!   blanked on its lines;
//! - `functions`: the functions a file defines, with normalized signatures;
//! - `prepare`: what is dropped, renamed and supplied (`prepare_with` and its options).
//!
//! Why a hand-written reader and not a GLSL parser such as the `glsl-lang` crate (GLSL 4.6
//! with a preprocessor): what the intake must do is edit the user's text in place — blank an
//! item, rename a token, insert a loop guard — keeping every byte and line where it was, so
//! that the compiler's messages name the user's lines; and it must read files that are not
//! valid GLSL 4.6 (GLSL ES 1.0/3.0 page shaders, ShaderToy tabs that use `iTime` undeclared,
//! macros used before they are expanded, a stray line that does not compile), where a
//! parser fails on the first error and says nothing about the rest. The statement-level
//! work needs only the top-level items with their byte ranges, the identifiers each function
//! references, and the compiler (glslang, through shaderc) to say which item is wrong; the
//! tokenizer and item reader give exactly that, and glslang stays the judge of validity.
//!
//! `read_source_file` reads a file as published (byte-order mark, Windows line ends), and
//! `find_entry_point` tells a ShaderToy pass (`mainImage`) from a page shader (`main`) from
//! a file of functions (a Common tab, notes).

pub mod functions;
pub mod paste;
pub mod prepare;
pub mod syntax;

use std::path::Path;

pub use functions::{find_functions, FoundFunction, Signature};
pub use paste::{glsl_of_paste, PasteNote, PastedGlsl};
pub use prepare::{
    declared_globals, loop_guard_declarations, prepare, prepare_with, IntakeOptions,
    PreparedSource, Unavailable, UniformValue, LOOP_GUARD_NAMES, USER_LOOP_LIMIT,
};

/// The file name under which vkpath's kernels `#include` a user's prepared code.
pub const USER_FUNCTIONS_FILE: &str = "user_functions.glsl";

/// Reads a user's GLSL file as text: invalid UTF-8 replaced, a byte-order mark dropped and
/// Windows line ends made `\n` (published files come with either now and then).
pub fn read_source_file(path: &Path) -> std::io::Result<String> {
    let bytes = std::fs::read(path)?;
    Ok(normalize_text(&bytes))
}

/// See `read_source_file`.
pub fn normalize_text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes)
        .trim_start_matches('\u{feff}')
        .replace("\r\n", "\n")
}

/// The entry point a file defines, which says what kind of file it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EntryPoint {
    /// `void mainImage(out vec4 color, in vec2 fragCoord)`: a ShaderToy Image or Buffer pass.
    MainImage,
    /// `void main()`: a page (WebGL, desktop) or Vulkan shader.
    Main,
}

/// The names that the compiler's `messages` call undeclared (an undeclared identifier, a
/// function without a matching overload) and that none of `texts` declares at global scope
/// (a `user_` prefix, the intake's rename, ignored), as "'a' is" or "'a', 'b' are"; `None`
/// when there are none. Such a name usually lives in a tab the user did not pass (the
/// Common tab).
pub fn undefined_names(messages: &str, texts: &[&str]) -> Option<String> {
    let declared: Vec<std::collections::BTreeSet<String>> =
        texts.iter().map(|t| prepare::declared_globals(t)).collect();
    let is_declared = |name: &str| declared.iter().any(|d| d.contains(name));
    let mut missing: Vec<String> = Vec::new();
    for line in messages.lines() {
        let Some(error) = line.split(": error:").nth(1) else {
            continue;
        };
        let undeclared = error.contains("undeclared identifier")
            || error.contains("no matching overloaded function found");
        let name = error
            .trim()
            .strip_prefix('\'')
            .and_then(|r| r.split('\'').next());
        if let (true, Some(name)) = (undeclared, name) {
            let base = name.strip_prefix("user_").unwrap_or(name);
            if !name.is_empty()
                && !is_declared(name)
                && !is_declared(base)
                && !missing.iter().any(|m| m == name)
            {
                missing.push(name.to_string());
            }
        }
    }
    match missing.len() {
        0 => None,
        1 => Some(format!("'{}' is", missing[0])),
        _ => Some(format!(
            "{} are",
            missing
                .iter()
                .map(|m| format!("'{m}'"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// The names used as types on the lines where the compiler's `messages` report "syntax
/// error, unexpected IDENTIFIER" (a name followed by a name, as in `triangle_t tri`) that
/// are no GLSL word and that none of `texts` declares: a struct of a tab the user did not
/// pass, most likely. `tabs` are (the name the messages give, the text they number).
pub fn undeclared_types(messages: &str, tabs: &[(&str, &str)], texts: &[&str]) -> Vec<String> {
    let declared: Vec<std::collections::BTreeSet<String>> =
        texts.iter().map(|t| prepare::declared_globals(t)).collect();
    let mut missing: Vec<String> = Vec::new();
    for message in messages.lines() {
        if !message.contains("syntax error, unexpected IDENTIFIER") {
            continue;
        }
        let place = tabs.iter().find_map(|(name, text)| {
            let rest = message.strip_prefix(name)?.strip_prefix(':')?;
            let line: usize = rest.split(':').next()?.trim().parse().ok()?;
            Some((*text, line))
        });
        let Some((text, line)) = place else {
            continue;
        };
        let tokens: Vec<syntax::Token> = syntax::tokenize(text)
            .into_iter()
            .filter(|t| t.line == line && !t.in_directive)
            .collect();
        for pair in tokens.windows(2) {
            let name = pair[0].text.as_str();
            if pair[0].is_identifier()
                && pair[1].is_identifier()
                && !is_glsl_word(name)
                && !declared.iter().any(|d| d.contains(name))
                && !missing.iter().any(|m| m == name)
            {
                missing.push(name.to_string());
            }
        }
    }
    missing
}

/// Whether a word is GLSL's own: a keyword, a qualifier or a built-in type.
pub(crate) fn is_glsl_word(word: &str) -> bool {
    const WORDS: [&str; 40] = [
        "void",
        "bool",
        "int",
        "uint",
        "float",
        "double",
        "in",
        "out",
        "inout",
        "const",
        "uniform",
        "buffer",
        "shared",
        "highp",
        "mediump",
        "lowp",
        "precise",
        "invariant",
        "flat",
        "smooth",
        "noperspective",
        "centroid",
        "sample",
        "patch",
        "coherent",
        "volatile",
        "restrict",
        "readonly",
        "writeonly",
        "return",
        "else",
        "case",
        "struct",
        "layout",
        "precision",
        "attribute",
        "varying",
        "discard",
        "atomic_uint",
        "subroutine",
    ];
    let families = [
        "vec",
        "ivec",
        "uvec",
        "bvec",
        "dvec",
        "mat",
        "dmat",
        "sampler",
        "isampler",
        "usampler",
        "image",
        "iimage",
        "uimage",
        "texture",
        "itexture",
        "utexture",
        "subpassInput",
    ];
    WORDS.contains(&word)
        || families.iter().any(|family| {
            word.strip_prefix(family).is_some_and(|rest| {
                rest.starts_with(|c: char| c.is_ascii_digit() || c.is_ascii_uppercase())
            })
        })
}

/// The entry point that `source` defines (a definition at global scope), `mainImage` first;
/// `None` for a file of functions only (a ShaderToy Common tab, notes).
pub fn find_entry_point(source: &str) -> Option<EntryPoint> {
    let found = find_functions(source);
    let defines = |name: &str| found.iter().any(|f| f.has_body && f.name == name);
    if defines("mainImage") {
        Some(EntryPoint::MainImage)
    } else if defines("main") {
        Some(EntryPoint::Main)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entry_points_tell_passes_from_common_tabs() {
        assert_eq!(
            find_entry_point("void mainImage(out vec4 c, in vec2 p) { c = vec4(p, 0, 1); }"),
            Some(EntryPoint::MainImage)
        );
        assert_eq!(
            find_entry_point("out vec4 c;\nvoid main() { c = vec4(1); }"),
            Some(EntryPoint::Main)
        );
        assert_eq!(
            find_entry_point("// void main() {}\nfloat f(float x) { return x; }"),
            None
        );
        assert_eq!(normalize_text(b"\xef\xbb\xbfa\r\nb"), "a\nb");
    }

    #[test]
    fn a_pass_keeps_its_entry_point_when_asked() {
        let source = "void mainImage(out vec4 c, in vec2 p) { c = vec4(iTime); }\n";
        let kept = prepare_with(
            source,
            &IntakeOptions {
                keep_entry_points: true,
                supply_inputs: false,
                guard_loops: false,
                ..IntakeOptions::default()
            },
        );
        assert_eq!(kept.text, source);
        assert!(!kept.prelude.contains("iTime"), "{}", kept.prelude);
        let dropped = prepare(source);
        assert!(dropped.text.trim().is_empty());
    }
}
