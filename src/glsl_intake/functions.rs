//! The functions a GLSL file defines or declares at global scope, with their normalized
//! signatures (return type, parameter qualifiers and types).

use crate::glsl_intake::syntax::{
    matching, structural_tokens, tokenize, top_level_items, ItemKind, Token,
};

/// A function's return type and parameter types, normalized: `in`, `const` and precision
/// qualifiers dropped (they do not change what GLSL calls the function's signature),
/// `out` and `inout` kept, parameter names dropped.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Signature {
    /// The return type, e.g. `vec3`.
    pub return_type: String,
    /// Each parameter's qualifier and type, e.g. `inout uvec2`.
    pub parameters: Vec<String>,
}

impl std::fmt::Display for Signature {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({})", self.return_type, self.parameters.join(", "))
    }
}

/// A function defined or declared at global scope.
#[derive(Clone, Debug, PartialEq)]
pub struct FoundFunction {
    /// Its name.
    pub name: String,
    /// The line of its name (from 1).
    pub line: usize,
    /// The line of its last token (the body's `}` or the prototype's `;`).
    pub last_line: usize,
    /// Its signature.
    pub signature: Signature,
    /// Whether it is a definition (with a body) rather than a prototype.
    pub has_body: bool,
    /// Byte range of the whole function (from its return type to its `}` or `;`).
    pub span: std::ops::Range<usize>,
}

/// Every function defined or declared at global scope of `source`.
pub fn find_functions(source: &str) -> Vec<FoundFunction> {
    let tokens = structural_tokens(&tokenize(source));
    top_level_items(&tokens)
        .into_iter()
        .filter_map(|item| {
            let name = item.name?;
            let close = matching(&tokens, name + 1, "(", ")")?;
            Some(FoundFunction {
                name: tokens[name].text.clone(),
                line: tokens[name].line,
                last_line: tokens[item.last].line,
                signature: Signature {
                    return_type: tokens[name - 1].text.clone(),
                    parameters: parameters(&tokens[name + 2..close]),
                },
                has_body: item.kind == ItemKind::FunctionDefinition,
                span: tokens[item.first].start..tokens[item.last].end,
            })
        })
        .collect()
}

/// Qualifiers that do not change a function's signature.
const IGNORED_QUALIFIERS: [&str; 5] = ["in", "const", "highp", "mediump", "lowp"];

/// One parameter's normalized type: the tokens without ignored qualifiers and without the
/// name (the last identifier, when more than the type remains).
fn normalize_parameter(tokens: &[Token]) -> String {
    let mut words: Vec<&str> = tokens
        .iter()
        .map(|t| t.text.as_str())
        .filter(|t| !IGNORED_QUALIFIERS.contains(t))
        .collect();
    let qualifiers = words
        .iter()
        .take_while(|w| **w == "out" || **w == "inout")
        .count();
    if words.len() > qualifiers + 1 {
        words.pop();
    }
    words.join(" ")
}

/// The normalized parameters of a parameter list (the tokens between its parentheses).
fn parameters(tokens: &[Token]) -> Vec<String> {
    let mut parameters = Vec::new();
    let mut depth = 0usize;
    let mut start = 0;
    for (index, token) in tokens.iter().enumerate() {
        match token.text.as_str() {
            "(" | "[" => depth += 1,
            ")" | "]" => depth = depth.saturating_sub(1),
            "," if depth == 0 => {
                parameters.push(normalize_parameter(&tokens[start..index]));
                start = index + 1;
            }
            _ => {}
        }
    }
    if start < tokens.len() {
        parameters.push(normalize_parameter(&tokens[start..]));
    }
    // `(void)` declares no parameters.
    if parameters == ["void"] {
        parameters.clear();
    }
    parameters
}
