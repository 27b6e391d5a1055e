//! The top-level items of a pasted file that GLSL cannot have at file scope (statements,
//! words alone) and braces never closed: what `glsl_of_paste` does after the lines.

use super::PasteNote;

/// The top-level items of `text` that are no declaration are blanked (a statement such as
/// the slides' `seed = ...;` or an unfinished `if (hit) {` pasted at file scope, a fence, a
/// word alone: GLSL allows none of them there), and the braces another item leaves open
/// (`Item::unclosed_braces`: a function without its last `}`) are closed at its end, each
/// with a note; in one pass, so that check's compile rounds are spared one round each and
/// the definitions after an open brace are read as the file's own.
pub(super) fn close_braces_and_drop_statements(text: &str, notes: &mut Vec<PasteNote>) -> String {
    use crate::glsl_intake::syntax::{structural_tokens, tokenize, top_level_items, ItemKind};
    let tokens = tokenize(text);
    let macros: Vec<&str> = tokens
        .windows(3)
        .filter(|w| w[0].starts_directive && w[1].text == "define")
        .map(|w| w[2].text.as_str())
        .collect();
    let structure = structural_tokens(&tokens);
    // (byte range, replacement), in order.
    let mut edits: Vec<(std::ops::Range<usize>, String)> = Vec::new();
    for item in top_level_items(&structure) {
        let item_tokens = &structure[item.first..=item.last];
        let range = item_tokens[0].start..item_tokens[item_tokens.len() - 1].end;
        let next = match structure.get(item.last + 1) {
            Some(token) => format!("the definition at line {}", token.line),
            None => match hidden_definition(&structure, item.first, item.last) {
                // Not at the start of its line, a definition inside is no sign of where the
                // brace should have closed: it stays inside, unread.
                Some((name, line)) => format!(
                    "the end of the file, so the definition of {name} at line {line} stands inside it and is not read (close the '{{', or start the definition at the beginning of its line)"
                ),
                None => "the end of the file".into(),
            },
        };
        if item.kind == ItemKind::Declaration && !is_declaration(item_tokens, &macros) {
            let written: Vec<&str> = text[range.clone()].split_whitespace().collect();
            let written = written.join(" ");
            let quoted: String = written.chars().take(50).collect();
            let cut = if quoted.len() < written.len() {
                "…"
            } else {
                ""
            };
            let open = if item.unclosed_braces > 0 {
                format!("; its '{{' is never closed before {next}")
            } else {
                String::new()
            };
            notes.push(PasteNote {
                line: item_tokens[0].line,
                text: format!(
                    "dropped '{quoted}{cut}' (a statement or text outside any function, which GLSL does not allow there{open})"
                ),
            });
            let blank: String = text[range.clone()]
                .chars()
                .map(|c| if c == '\n' { '\n' } else { ' ' })
                .collect();
            edits.push((range, blank));
            continue;
        }
        if item.unclosed_braces == 0 {
            continue;
        }
        // The outermost `{` left open: the bottom of the stack of open braces.
        let mut open: Vec<usize> = Vec::new();
        for (index, token) in item_tokens.iter().enumerate() {
            match token.text.as_str() {
                "{" => open.push(index),
                "}" => {
                    open.pop();
                }
                _ => {}
            }
        }
        let Some(&outermost) = open.first() else {
            continue;
        };
        notes.push(PasteNote {
            line: item_tokens[outermost].line,
            text: format!(
                "this '{{' is never closed before {next}; check closes it there, so that what follows is read as your own functions"
            ),
        });
        edits.push((range.end..range.end, "}".repeat(item.unclosed_braces)));
    }
    if edits.is_empty() {
        return text.to_string();
    }
    let mut result = String::with_capacity(text.len() + edits.len());
    let mut position = 0;
    for (range, replacement) in edits {
        result.push_str(&text[position..range.start]);
        result.push_str(&replacement);
        position = range.end;
    }
    result.push_str(&text[position..]);
    result
}

/// The first function definition (name, line) among `tokens[first..=last]` after its first
/// token, if any.
fn hidden_definition(
    tokens: &[crate::glsl_intake::syntax::Token],
    first: usize,
    last: usize,
) -> Option<(String, usize)> {
    (first + 1..=last)
        .filter(|&at| crate::glsl_intake::syntax::is_definition_header(tokens, at))
        .find_map(|at| {
            let name = tokens[at..=last]
                .windows(2)
                .find(|pair| pair[1].text == "(")
                .map(|pair| &pair[0])?;
            Some((name.text.clone(), name.line))
        })
}

/// Whether the tokens of a top-level item without a body begin as a declaration does: a
/// qualifier or `struct`, two names (`float x`, `triangle_t tri`), an array type (`float[3]
/// x`), or a macro of the user's (`macros`, which may expand to anything).
fn is_declaration(tokens: &[crate::glsl_intake::syntax::Token], macros: &[&str]) -> bool {
    const STARTS: [&str; 24] = [
        "struct",
        "layout",
        "const",
        "shared",
        "attribute",
        "varying",
        "subroutine",
        "coherent",
        "readonly",
        "writeonly",
        "uniform",
        "in",
        "out",
        "buffer",
        "flat",
        "smooth",
        "noperspective",
        "centroid",
        "invariant",
        "highp",
        "mediump",
        "lowp",
        "precise",
        "precision",
    ];
    let Some(head) = tokens.first() else {
        return true;
    };
    let second = tokens.get(1);
    head.text == ";"
        || STARTS.contains(&head.text.as_str())
        || macros.contains(&head.text.as_str())
        || head.is_identifier()
            && !crate::glsl_intake::syntax::is_statement_word(&head.text)
            && second.is_some_and(|t| t.is_identifier() || t.text == "[")
}
