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
    /// Its column: bytes from the start of its line (0: it starts the line).
    pub column: usize,
    /// Whether a conditional directive (`#if`, `#ifdef`, `#else`, `#endif`, …) stands
    /// between it and the structural token before it (set by `structural_tokens`).
    pub after_conditional: bool,
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
    let mut line_start = 0usize;
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
            line_start = i;
        } else if c == b'\\' && next == Some(b'\n') {
            // A line continuation: the directive (if any) goes on.
            line += 1;
            i += 2;
            line_start = i;
        } else if c.is_ascii_whitespace() {
            i += 1;
        } else if c == b'/' && next == Some(b'/') {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
        } else if c == b'/' && next == Some(b'*') {
            i += 2;
            while i < bytes.len() && !(bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/')) {
                if bytes[i] == b'\n' {
                    line += 1;
                    line_start = i + 1;
                }
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
                column: start - line_start,
                after_conditional: false,
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
    /// Braces still open at its end: a `{` never closed before a function definition that
    /// starts a later line (GLSL has no nested functions, so that definition is the next
    /// item), or before the end of the file. 0 where a preprocessor conditional stands
    /// inside (its branches may open a brace each).
    pub unclosed_braces: usize,
}

/// The structural tokens of a file: those outside preprocessor directives.
pub fn structural_tokens(tokens: &[Token]) -> Vec<Token> {
    let mut structure = Vec::with_capacity(tokens.len());
    let mut after_conditional = false;
    for (index, token) in tokens.iter().enumerate() {
        if token.in_directive {
            after_conditional |= token.starts_directive
                && tokens.get(index + 1).is_some_and(|word| {
                    word.in_directive
                        && matches!(
                            word.text.as_str(),
                            "if" | "ifdef" | "ifndef" | "else" | "elif" | "endif"
                        )
                });
            continue;
        }
        let mut token = token.clone();
        token.after_conditional = after_conditional;
        after_conditional = false;
        structure.push(token);
    }
    structure
}

/// Splits structural tokens into top-level items. A function definition starts at its
/// return type (what stands before it since the last item, a prose line or a Markdown
/// fence, is an item of its own); a `{` that is never closed ends its item before the next
/// definition that starts a line, or at the end of the file (`Item::unclosed_braces`).
pub fn top_level_items(tokens: &[Token]) -> Vec<Item> {
    let mut items = Vec::new();
    let mut first = 0;
    let mut i = 0;
    while i < tokens.len() {
        match tokens[i].text.as_str() {
            // A `for` header at file scope (a pasted loop) is one statement, not three
            // items: its semicolons are skipped.
            "for" if tokens.get(i + 1).is_some_and(|t| t.text == "(") => {
                if let Some(close) = bounded_close(tokens, i + 1) {
                    i = close;
                }
            }
            ";" => {
                items.push(classify(tokens, first, i));
                first = i + 1;
            }
            "{" => {
                let block = block_end(tokens, i);
                let head = (i > first && tokens[i - 1].text == ")")
                    .then(|| function_head(tokens, first, i))
                    .flatten();
                if let Some((start, name)) = head {
                    if start > first {
                        items.push(classify(tokens, first, start - 1));
                    }
                    items.push(Item {
                        kind: ItemKind::FunctionDefinition,
                        first: start,
                        last: block.last,
                        name: Some(name),
                        unclosed_braces: block.unclosed,
                    });
                    first = block.last + 1;
                } else if block.unclosed > 0 || i > first && tokens[i - 1].text == ")" {
                    // A block after a parenthesis that heads no function (`if (hit) { … }`
                    // at file scope) ends its item, as a function's body would.
                    let mut item = classify(tokens, first, block.last);
                    item.unclosed_braces = block.unclosed;
                    items.push(item);
                    first = block.last + 1;
                }
                i = block.last;
            }
            _ => {}
        }
        i += 1;
    }
    if first < tokens.len() {
        items.push(classify(tokens, first, tokens.len() - 1));
    }
    items
}

/// Where a block that opens at `open` ends: its closing `}`, else the token before a
/// function definition that starts a line inside it (no conditional directive between),
/// else the last token; with the braces left open there.
struct BlockEnd {
    last: usize,
    unclosed: usize,
}

fn block_end(tokens: &[Token], open: usize) -> BlockEnd {
    let mut depth = 0usize;
    let mut conditional = false;
    for (index, token) in tokens.iter().enumerate().skip(open) {
        conditional |= token.after_conditional;
        match token.text.as_str() {
            "{" => depth += 1,
            "}" => {
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    return BlockEnd {
                        last: index,
                        unclosed: 0,
                    };
                }
            }
            _ => {}
        }
        if index > open && token.column == 0 && !conditional && is_definition_header(tokens, index)
        {
            return BlockEnd {
                last: index - 1,
                unclosed: depth,
            };
        }
    }
    BlockEnd {
        last: tokens.len().saturating_sub(1),
        unclosed: if conditional { 0 } else { depth },
    }
}

/// Words that begin a statement or declaration, never a function definition.
const NOT_A_DEFINITION: [&str; 21] = [
    "if",
    "for",
    "while",
    "switch",
    "return",
    "else",
    "do",
    "case",
    "default",
    "struct",
    "layout",
    "precision",
    "uniform",
    "buffer",
    "in",
    "out",
    "inout",
    "const",
    "discard",
    "break",
    "continue",
];

/// Whether a word begins a statement (`if`, `for`, `return`, …) rather than a declaration.
pub fn is_statement_word(word: &str) -> bool {
    matches!(
        word,
        "if" | "for"
            | "while"
            | "switch"
            | "return"
            | "else"
            | "do"
            | "case"
            | "default"
            | "discard"
            | "break"
            | "continue"
    )
}

/// Whether a function definition starts at `at`: two or more identifiers (qualifiers, the
/// return type, the name), `(`, parameters closed within a few hundred tokens, `{`.
pub fn is_definition_header(tokens: &[Token], at: usize) -> bool {
    let mut end = at;
    while end < tokens.len() && end - at < 6 && tokens[end].is_identifier() {
        end += 1;
    }
    if end - at < 2
        || tokens.get(end).is_none_or(|t| t.text != "(")
        || NOT_A_DEFINITION.contains(&tokens[at].text.as_str())
        || NOT_A_DEFINITION.contains(&tokens[end - 1].text.as_str())
    {
        return false;
    }
    let mut depth = 0usize;
    for index in end..tokens.len().min(end + 256) {
        match tokens[index].text.as_str() {
            "(" => depth += 1,
            ")" => {
                depth -= 1;
                if depth == 0 {
                    return tokens.get(index + 1).is_some_and(|t| t.text == "{");
                }
            }
            ";" | "{" | "}" => return false,
            _ => {}
        }
    }
    false
}

/// The `)` that closes the `(` at `open` within a few hundred tokens and before any brace.
fn bounded_close(tokens: &[Token], open: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (index, token) in tokens.iter().enumerate().skip(open).take(256) {
        match token.text.as_str() {
            "(" => depth += 1,
            ")" => {
                depth -= 1;
                if depth == 0 {
                    return Some(index);
                }
            }
            "{" | "}" => return None,
            _ => {}
        }
    }
    None
}

/// Qualifiers that may stand before a function's return type, on another line.
const RETURN_QUALIFIERS: [&str; 5] = ["highp", "mediump", "lowp", "precise", "invariant"];

/// The first token and the name of the function whose parameter list ends just before the
/// `{` at `brace`, within `first..brace`: `type name (...)`, with the qualifiers before the
/// type (and words on the type's own line, such as a macro the user defined); `None` when
/// what precedes the `{` is no function head (`if (hit) {`).
fn function_head(tokens: &[Token], first: usize, brace: usize) -> Option<(usize, usize)> {
    let mut depth = 0usize;
    let mut open = None;
    for index in (first..brace).rev() {
        match tokens[index].text.as_str() {
            ")" => depth += 1,
            "(" => {
                depth = depth.checked_sub(1)?;
                if depth == 0 {
                    open = Some(index);
                    break;
                }
            }
            _ => {}
        }
    }
    let open = open?;
    let name = open.checked_sub(1).filter(|&n| n > first)?;
    let type_index = name - 1;
    let (name_token, type_token) = (&tokens[name], &tokens[type_index]);
    if !name_token.is_identifier()
        || !type_token.is_identifier()
        || NOT_A_DEFINITION.contains(&name_token.text.as_str())
        || NOT_A_DEFINITION.contains(&type_token.text.as_str())
    {
        return None;
    }
    let mut start = type_index;
    while start > first {
        let before = &tokens[start - 1];
        let qualifier = RETURN_QUALIFIERS.contains(&before.text.as_str());
        let same_line = before.is_identifier()
            && before.line == tokens[type_index].line
            && !NOT_A_DEFINITION.contains(&before.text.as_str());
        if !(qualifier || same_line) {
            break;
        }
        start -= 1;
    }
    Some((start, name))
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

/// An item from `first` to `last` that has no body: a prototype when an identifier followed
/// by `(` stands at parenthesis depth 0 with a type before it, and its parameter list closes
/// the item (before the `;`); else a declaration.
fn classify(tokens: &[Token], first: usize, last: usize) -> Item {
    let declaration = Item {
        kind: ItemKind::Declaration,
        first,
        last,
        name: None,
        unclosed_braces: 0,
    };
    let Some(open) = (first + 1..last).find(|&i| tokens[i].text == "(") else {
        return declaration;
    };
    let is_function = tokens[open - 1].is_identifier()
        && open - 1 > first
        && tokens[open - 2].is_identifier()
        && tokens[first].text != "layout"
        && tokens[last].text == ";"
        && matching(tokens, open, "(", ")") == Some(last - 1);
    if !is_function {
        return declaration;
    }
    Item {
        kind: ItemKind::FunctionPrototype,
        first,
        last,
        name: Some(open - 1),
        unclosed_braces: 0,
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

    /// (kind, name, first line, unclosed braces) of each item of `source`.
    fn outline(source: &str) -> Vec<(ItemKind, Option<String>, usize, usize)> {
        let tokens = structural_tokens(&tokenize(source));
        top_level_items(&tokens)
            .iter()
            .map(|item| {
                (
                    item.kind.clone(),
                    item.name.map(|n| tokens[n].text.clone()),
                    tokens[item.first].line,
                    item.unclosed_braces,
                )
            })
            .collect()
    }

    #[test]
    fn a_definition_starts_at_its_type_whatever_stands_before_it() {
        // A fence, then prose with balanced braces (LaTeX), then a definition.
        let items = outline(
            "```glsl\nvec3 f(vec2 u) { return vec3(u, 0.0); }\nThe sum $$2{\\pi}\\frac{1}{N}$$ is\nhighp\nvec2 g(vec2 u) { return u; }\n",
        );
        assert_eq!(
            items,
            [
                (ItemKind::Declaration, None, 1, 0),
                (ItemKind::FunctionDefinition, Some("f".into()), 2, 0),
                (ItemKind::Declaration, None, 3, 0),
                (ItemKind::FunctionDefinition, Some("g".into()), 4, 0),
            ]
        );
    }

    #[test]
    fn an_unclosed_brace_ends_before_the_next_definition_at_a_line_start() {
        let source = "if (hit) {\n    // ...\nvec3 f(vec2 u) {\n    if (u.x > 0.0) {\n        return vec3(1.0);\n}\nvec2 g(vec2 u) { return u; }\n";
        assert_eq!(
            outline(source),
            [
                (ItemKind::Declaration, None, 1, 1),
                (ItemKind::FunctionDefinition, Some("f".into()), 3, 1),
                (ItemKind::FunctionDefinition, Some("g".into()), 7, 0),
            ]
        );
        // Indented, or behind a conditional directive, a header is no sign of an open brace.
        let indented = "if (hit) {\n    vec3 f(vec2 u) { return vec3(u, 0.0); }\n";
        assert_eq!(outline(indented).len(), 1);
        let conditional = "#if A\nvec3 f(vec2 u) {\n#else\nvec3 f(vec2 u, float k) {\n#endif\n    return vec3(u, 0.0);\n}\n";
        assert_eq!(
            outline(conditional),
            [(ItemKind::FunctionDefinition, Some("f".into()), 2, 0)]
        );
    }
}
