//! `discard` in a pass: ShaderToy runs every pass as a fragment shader, where `discard`
//! ends the fragment and leaves its texel of the render target unwritten. A compute kernel
//! has no `discard`, so each one in the user's (prepared) code becomes a statement that
//! sets the kernel's `vkpath_discarded` and returns from the function it is in; the kernel
//! (`pass.comp`) then skips the pixel's `imageStore`, and its loop guard ends every loop
//! still running in the callers, so that the rest of the pixel's work finishes at once.
//!
//! The text keeps every line where it was (each replacement stays on the `discard`'s line),
//! so the compiler's messages still name the user's lines.

use crate::glsl_intake::find_functions;
use crate::glsl_intake::syntax::tokenize;

/// The kernel's flag that a `discard` ran (declared in `pass.comp`).
pub const DISCARD_FLAG: &str = "vkpath_discarded";

/// `text` with every `discard;` replaced by a block that sets `vkpath_discarded` and
/// returns: `return;` in a `void` function (and in a macro, or a function the finder does
/// not know, such as one returning an array), otherwise the value of an uninitialized local
/// of the function's return type (never used: the pixel is not stored). Returns the text and
/// how many were replaced.
pub fn rewrite_discards(text: &str) -> (String, usize) {
    let tokens = tokenize(text);
    let functions: Vec<_> = find_functions(text)
        .into_iter()
        .filter(|f| f.has_body)
        .collect();
    let mut out = String::with_capacity(text.len());
    let mut copied = 0;
    let mut count = 0;
    let mut index = 0;
    while index < tokens.len() {
        let token = &tokens[index];
        if token.text != "discard" {
            index += 1;
            continue;
        }
        // The statement's `;` goes into the block, so that `if (c) discard; else …` stays
        // one if-else statement.
        let end = match tokens.get(index + 1) {
            Some(next) if next.text == ";" && next.in_directive == token.in_directive => {
                index += 1;
                next.end
            }
            _ => token.end,
        };
        let return_type = (!token.in_directive)
            .then(|| {
                functions
                    .iter()
                    .find(|f| f.span.contains(&token.start))
                    .map(|f| declared_return_type(text, f.span.start, &f.name))
            })
            .flatten()
            .filter(|t| t != "void");
        let replacement = match return_type {
            None => format!("{{ {DISCARD_FLAG} = true; return; }}"),
            Some(return_type) => format!(
                "{{ {DISCARD_FLAG} = true; {return_type} vkpath_never_read; return vkpath_never_read; }}"
            ),
        };
        out.push_str(&text[copied..token.start]);
        out.push_str(&replacement);
        copied = end;
        count += 1;
        index += 1;
    }
    out.push_str(&text[copied..]);
    (out, count)
}

/// The return type of the function that starts at byte `start` of `text` and is named
/// `name`, as written (qualifiers kept, comments and line breaks dropped): the text before
/// its name.
fn declared_return_type(text: &str, start: usize, name: &str) -> String {
    let tokens = tokenize(&text[start..]);
    tokens
        .iter()
        .take_while(|t| t.text != name)
        .map(|t| t.text.as_str())
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_discard_returns_from_its_function_on_its_own_line() {
        let text = "void mainImage(out vec4 c, in vec2 p) {\n    if (p.x < 2.0) discard;\n    else c = vec4(1.0);\n}\n";
        let (out, count) = rewrite_discards(text);
        assert_eq!(count, 1);
        assert_eq!(
            out.lines().nth(1),
            Some("    if (p.x < 2.0) { vkpath_discarded = true; return; }")
        );
        assert_eq!(out.lines().count(), text.lines().count());
    }

    #[test]
    fn a_discard_in_a_function_with_a_value_returns_an_unread_one() {
        let text =
            "highp vec3 shade(float x) {\n    if (x < 0.0) discard ;\n    return vec3(x);\n}\n";
        let (out, count) = rewrite_discards(text);
        assert_eq!(count, 1);
        assert!(
            out.contains("{ vkpath_discarded = true; highp vec3 vkpath_never_read; return vkpath_never_read; }"),
            "{out}"
        );
    }

    #[test]
    fn comments_and_other_words_are_left_alone() {
        let text = "// discard this\nfloat discarded = 1.0;\n";
        assert_eq!(rewrite_discards(text), (text.to_string(), 0));
    }
}
