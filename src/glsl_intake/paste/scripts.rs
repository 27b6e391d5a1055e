//! GLSL in JavaScript/TypeScript: template strings, their `${...}`, and whether their text
//! is GLSL.

/// Whether a backtick after `before` opens a template string of a script (not inline code
/// in prose): it follows `=`, `(`, `,`, `:`, `[`, `?`, `+`, `{`, `return` or a comment
/// (`/* glsl */`), or a tag written against it (`glsl\``).
pub(super) fn in_script_expression(before: &str) -> bool {
    let tagged = before.ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_');
    let trimmed = before.trim_end();
    tagged
        || trimmed.ends_with(['=', '(', ',', ':', '[', '?', '+', '{'])
        || trimmed.ends_with("return")
        || trimmed.ends_with("*/")
}

/// Whether a string's text looks like GLSL: a function definition (`type name(...) {`), a
/// `#version`, a `precision` statement or `gl_FragColor`/`mainImage`.
pub(super) fn looks_like_glsl(text: &str) -> bool {
    if text.contains("#version")
        || text.contains("precision highp")
        || text.contains("precision mediump")
        || text.contains("gl_FragColor")
        || text.contains("mainImage")
        || text.contains("void main")
    {
        return true;
    }
    let tokens =
        crate::glsl_intake::syntax::structural_tokens(&crate::glsl_intake::syntax::tokenize(text));
    crate::glsl_intake::syntax::top_level_items(&tokens)
        .iter()
        .any(|item| item.kind == crate::glsl_intake::syntax::ItemKind::FunctionDefinition)
}

/// The template strings of a script: each string's text (between its backticks) and the
/// `${...}` substitutions in it, as byte ranges of `script`. Comments and quoted strings
/// are skipped.
pub(super) fn template_strings(
    script: &str,
) -> Vec<(std::ops::Range<usize>, Vec<std::ops::Range<usize>>)> {
    let bytes = script.as_bytes();
    let mut strings = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i < bytes.len() && !(bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/')) {
                    i += 1;
                }
                i += 2;
            }
            quote @ (b'\'' | b'"') => {
                i += 1;
                while i < bytes.len() && bytes[i] != quote && bytes[i] != b'\n' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
            }
            b'`' => {
                let start = i + 1;
                let mut holes = Vec::new();
                i = start;
                while i < bytes.len() && bytes[i] != b'`' {
                    if bytes[i] == b'\\' {
                        i += 2;
                    } else if bytes[i] == b'$' && bytes.get(i + 1) == Some(&b'{') {
                        let hole_start = i;
                        let mut depth = 0usize;
                        while i < bytes.len() {
                            match bytes[i] {
                                b'{' => depth += 1,
                                b'}' => {
                                    depth -= 1;
                                    if depth == 0 {
                                        break;
                                    }
                                }
                                _ => {}
                            }
                            i += 1;
                        }
                        holes.push(hole_start..(i + 1).min(bytes.len()));
                        i += 1;
                    } else {
                        i += 1;
                    }
                }
                let end = i.min(bytes.len());
                strings.push((start..end, holes));
                i += 1;
            }
            _ => i += 1,
        }
    }
    strings
}
