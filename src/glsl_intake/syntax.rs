//! Just enough GLSL syntax for `vkpath check` to read files the way people publish them:
//! a tokenizer that keeps each token's line and byte range, and a reader of the top-level
//! items of a file (function definitions and prototypes, declarations, structs). It does not
//! type-check or expand macros; the compiler does that later.

/// A token of GLSL: an identifier or number, or one punctuation character.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// The token's text.
    pub text: String,
    /// The line where it stands (from 1).
    pub line: usize,
    /// Its byte range in the source.
    pub start: usize,
    /// See `start`.
    pub end: usize,
    /// Whether it stands in a preprocessor directive (these tokens are kept for renaming
    /// inside macro bodies, and left out of the structure).
    pub in_directive: bool,
    /// Whether it is the `#` that starts a directive (the first token of a logical line;
    /// a `#` or `##` inside a directive, also on a continuation line, is not).
    pub starts_directive: bool,
}

impl Token {
    /// Whether the token is an identifier (or keyword).
    pub fn is_identifier(&self) -> bool {
        self.text
            .starts_with(|c: char| c.is_alphabetic() || c == '_')
    }
}

/// Splits `source` into tokens, dropping comments and whitespace. Tokens of preprocessor
/// directives are marked `in_directive`.
pub fn tokenize(source: &str) -> Vec<Token> {
    let bytes = source.as_bytes();
    let mut tokens = Vec::new();
    let (mut i, mut line) = (0usize, 1usize);
    let mut at_line_start = true;
    let mut in_directive = false;
    while i < bytes.len() {
        let c = bytes[i];
        let next = bytes.get(i + 1).copied();
        if c == b'\n' {
            line += 1;
            at_line_start = true;
            in_directive = false;
            i += 1;
        } else if c == b'\\' && next == Some(b'\n') {
            // A line continuation: the directive (if any) goes on.
            line += 1;
            i += 2;
        } else if c.is_ascii_whitespace() {
            i += 1;
        } else if c == b'/' && next == Some(b'/') {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
        } else if c == b'/' && next == Some(b'*') {
            i += 2;
            while i < bytes.len() && !(bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/')) {
                line += usize::from(bytes[i] == b'\n');
                i += 1;
            }
            i = (i + 2).min(bytes.len());
        } else {
            let starts_directive = c == b'#' && at_line_start;
            in_directive |= starts_directive;
            let start = i;
            if c.is_ascii_alphanumeric()
                || c == b'_'
                || c == b'.' && next.is_some_and(|n| n.is_ascii_digit())
            {
                // Identifiers and numbers (with their suffixes and exponents: 1.0e-3, 2u).
                let numeric = !(c.is_ascii_alphabetic() || c == b'_');
                while i < bytes.len() {
                    let b = bytes[i];
                    let exponent_sign =
                        numeric && (b == b'+' || b == b'-') && matches!(bytes[i - 1], b'e' | b'E');
                    if b.is_ascii_alphanumeric()
                        || b == b'_'
                        || numeric && b == b'.'
                        || exponent_sign
                    {
                        i += 1;
                    } else {
                        break;
                    }
                }
            } else {
                // One character (a multi-byte one whole).
                i += source[i..].chars().next().map_or(1, char::len_utf8);
            }
            tokens.push(Token {
                text: source[start..i].to_string(),
                line,
                start,
                end: i,
                in_directive,
                starts_directive,
            });
            at_line_start = false;
        }
    }
    tokens
}

/// What a top-level item of a GLSL file is.
#[derive(Clone, Debug, PartialEq)]
pub enum ItemKind {
    /// `type name(parameters) { body }`
    FunctionDefinition,
    /// `type name(parameters);`
    FunctionPrototype,
    /// Anything else ending in `;`: a global variable or constant, a struct, a block, a
    /// precision statement, a layout declaration.
    Declaration,
}

/// A top-level item: the indices of its first and last token in the token list.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    /// What it is.
    pub kind: ItemKind,
    /// Index of its first token (of the structural tokens given to `top_level_items`).
    pub first: usize,
    /// Index of its last token (`;` or the body's `}`).
    pub last: usize,
    /// For functions, the index of the name token.
    pub name: Option<usize>,
}

/// The structural tokens of a file: those outside preprocessor directives.
pub fn structural_tokens(tokens: &[Token]) -> Vec<Token> {
    tokens.iter().filter(|t| !t.in_directive).cloned().collect()
}

/// Splits structural tokens into top-level items. Unbalanced braces end the last item at
/// the end of the file.
pub fn top_level_items(tokens: &[Token]) -> Vec<Item> {
    let mut items = Vec::new();
    let mut first = 0;
    let mut i = 0;
    while i < tokens.len() {
        match tokens[i].text.as_str() {
            ";" => {
                items.push(classify(tokens, first, i, false));
                first = i + 1;
            }
            "{" => {
                let close = matching(tokens, i, "{", "}").unwrap_or(tokens.len() - 1);
                let is_function = i > first && tokens[i - 1].text == ")";
                if is_function {
                    items.push(classify(tokens, first, close, true));
                    first = close + 1;
                }
                i = close;
            }
            _ => {}
        }
        i += 1;
    }
    if first < tokens.len() {
        items.push(classify(tokens, first, tokens.len() - 1, false));
    }
    items
}

/// The index of the token that closes the bracket opened at `open`.
pub fn matching(tokens: &[Token], open: usize, opening: &str, closing: &str) -> Option<usize> {
    let mut depth = 0usize;
    for (index, token) in tokens.iter().enumerate().skip(open) {
        if token.text == opening {
            depth += 1;
        } else if token.text == closing {
            depth -= 1;
            if depth == 0 {
                return Some(index);
            }
        }
    }
    None
}

/// An item from `first` to `last`: a function when an identifier followed by `(` stands at
/// parenthesis depth 0 with a type before it, and its parameter list closes the item (before
/// the body or the `;`).
fn classify(tokens: &[Token], first: usize, last: usize, has_body: bool) -> Item {
    let declaration = Item {
        kind: ItemKind::Declaration,
        first,
        last,
        name: None,
    };
    let end = if has_body {
        // The `{` follows the `)`.
        match (first..=last).find(|&i| tokens[i].text == "{") {
            Some(brace) => brace,
            None => return declaration,
        }
    } else {
        last
    };
    let Some(open) = (first + 1..end).find(|&i| tokens[i].text == "(") else {
        return declaration;
    };
    let is_function = tokens[open - 1].is_identifier()
        && open - 1 > first
        && tokens[open - 2].is_identifier()
        && tokens[first].text != "layout"
        && matching(tokens, open, "(", ")") == Some(end - 1);
    if !is_function {
        return declaration;
    }
    Item {
        kind: if has_body {
            ItemKind::FunctionDefinition
        } else {
            ItemKind::FunctionPrototype
        },
        first,
        last,
        name: Some(open - 1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_keep_lines_ranges_and_directives() {
        let source = "#define A(x) \\\n  x + 1.5e-3\nfloat f; // c\n/* a\nb */ int g = 2u;";
        let tokens = tokenize(source);
        let texts: Vec<&str> = tokens.iter().map(|t| t.text.as_str()).collect();
        assert_eq!(
            texts,
            [
                "#", "define", "A", "(", "x", ")", "x", "+", "1.5e-3", "float", "f", ";", "int",
                "g", "=", "2u", ";"
            ]
        );
        assert!(tokens[..9].iter().all(|t| t.in_directive));
        assert!(tokens[0].starts_directive && !tokens[1..].iter().any(|t| t.starts_directive));
        assert!(tokens[9..].iter().all(|t| !t.in_directive));
        assert_eq!(tokens[8].line, 2);
        assert_eq!(tokens[12].line, 5);
        assert_eq!(&source[tokens[10].start..tokens[10].end], "f");
    }

    #[test]
    fn items_are_functions_prototypes_and_declarations() {
        let source = "precision highp float;\nstruct s { vec3 a; } ;\nvec3 f(vec2 u) { if (u.x > 0.0) { return vec3(1); } return vec3(0); }\n\
            vec2 g(inout uvec2 s);\nconst float x = max(1.0, 2.0);\nlayout(location = 0) out vec4 c;\n";
        let tokens = structural_tokens(&tokenize(source));
        let items = top_level_items(&tokens);
        let kinds: Vec<(ItemKind, Option<&str>)> = items
            .iter()
            .map(|item| {
                (
                    item.kind.clone(),
                    item.name.map(|n| tokens[n].text.as_str()),
                )
            })
            .collect();
        assert_eq!(
            kinds,
            [
                (ItemKind::Declaration, None),
                (ItemKind::Declaration, None),
                (ItemKind::FunctionDefinition, Some("f")),
                (ItemKind::FunctionPrototype, Some("g")),
                (ItemKind::Declaration, None),
                (ItemKind::Declaration, None),
            ]
        );
        assert_eq!(tokens[items[2].last].text, "}");
        assert_eq!(tokens[items[2].last].line, 3);
    }
}
