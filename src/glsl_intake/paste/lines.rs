//! Lines that are visibly not GLSL (prose, LaTeX, HTML, ellipses): what
//! `glsl_of_paste` blanks line by line.

/// The code of one line: its text with comments replaced by spaces (`in_block_comment` says
/// whether the line starts inside a `/* */` comment, and is updated), or empty for a
/// preprocessor directive.
pub(super) fn code_of_line(line: &str, in_block_comment: &mut bool) -> String {
    let bytes = line.as_bytes();
    let mut code = String::with_capacity(line.len());
    let mut i = 0;
    while i < bytes.len() {
        if *in_block_comment {
            if bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/') {
                *in_block_comment = false;
                code.push_str("  ");
                i += 2;
            } else {
                i += 1;
                code.push(' ');
            }
        } else if bytes[i] == b'/' && bytes.get(i + 1) == Some(&b'/') {
            break;
        } else if bytes[i] == b'/' && bytes.get(i + 1) == Some(&b'*') {
            *in_block_comment = true;
            code.push_str("  ");
            i += 2;
        } else {
            let length = line[i..].chars().next().map_or(1, char::len_utf8);
            code.push_str(&line[i..i + length]);
            i += length;
        }
    }
    if code.trim_start().starts_with('#') {
        // A directive (or a Markdown heading, which the intake drops as an unknown
        // directive, with its note).
        return String::new();
    }
    code
}

/// Why a line's code (comments blanked) is not GLSL, if it is visibly not.
pub(super) fn not_glsl(code: &str) -> Option<&'static str> {
    let trimmed = code.trim();
    if trimmed.is_empty() {
        return None;
    }
    let bytes = trimmed.as_bytes();
    if bytes[0] == b'<'
        && bytes
            .get(1)
            .is_some_and(|b| b.is_ascii_alphabetic() || *b == b'/' || *b == b'!')
        && trimmed.contains('>')
    {
        return Some("an HTML tag");
    }
    if trimmed
        .bytes()
        .all(|b| b == b'.' || b.is_ascii_whitespace())
        && trimmed.len() >= 2
    {
        return Some("an ellipsis");
    }
    let backslash_inside = trimmed
        .char_indices()
        .any(|(at, c)| c == '\\' && at + 1 < trimmed.len());
    if trimmed
        .chars()
        .any(|c| matches!(c, '`' | '$' | '@' | '\'' | '"') || !c.is_ascii())
        || backslash_inside
    {
        return Some("characters GLSL does not have");
    }
    let words = words_of(trimmed);
    // Three words in a row, none of them GLSL's, are a sentence: GLSL puts at most a type
    // and a name side by side (`triangle_t tri`) after its own qualifiers.
    let mut run = 0;
    let mut previous_end = None;
    let mut previous_word: Option<&str> = None;
    for (start, end, word) in &words {
        let adjacent = previous_end.is_some_and(|e: usize| trimmed[e..*start].trim().is_empty());
        run = match (adjacent, is_glsl_word(word)) {
            (_, true) => 0,
            (true, false) => run + 1,
            (false, false) => 1,
        };
        if run >= 3 {
            return Some("prose");
        }
        // A word that is no GLSL word before a number ("Exercise 1", "Step 2:"): GLSL never
        // writes a number right after a name.
        let number_after_name = adjacent
            && word.starts_with(|c: char| c.is_ascii_digit())
            && run >= 2
            && previous_word.is_some_and(|w: &str| !w.starts_with(|c: char| c.is_ascii_digit()));
        if number_after_name {
            return Some("prose");
        }
        previous_word = Some(word);
        previous_end = Some(*end);
    }
    // Words that end in ':' (a heading, "Result:") or '.' (a sentence's end).
    let last = trimmed.chars().last().unwrap_or(' ');
    let before_last = trimmed[..trimmed.len() - 1].trim_end();
    let ends_in_word = before_last.ends_with(|c: char| c.is_ascii_alphabetic());
    let first_word = words.first().map_or("", |w| w.2);
    if ends_in_word
        && (last == ':' && !trimmed.contains('?') && !matches!(first_word, "case" | "default")
            || last == '.' && !trimmed.contains(['=', '(', ';', '{', '}']))
    {
        return Some("prose");
    }
    None
}

/// The words (identifiers and numbers) of a line, each (start, end, text).
fn words_of(text: &str) -> Vec<(usize, usize, &str)> {
    let bytes = text.as_bytes();
    let mut words = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_' {
            let start = i;
            while i < bytes.len()
                && (bytes[i].is_ascii_alphanumeric()
                    || bytes[i] == b'_'
                    || bytes[i] == b'.' && bytes[start].is_ascii_digit())
            {
                i += 1;
            }
            words.push((start, i, &text[start..i]));
        } else {
            i += 1;
        }
    }
    words
}

/// Whether a word is GLSL's: a keyword, a qualifier or a built-in type
/// (`glsl_intake::is_glsl_word`), or a word of GLSL's statements and literals.
fn is_glsl_word(word: &str) -> bool {
    const STATEMENT_WORDS: [&str; 11] = [
        "if", "for", "while", "do", "switch", "default", "break", "continue", "true", "false",
        "else",
    ];
    crate::glsl_intake::is_glsl_word(word) || STATEMENT_WORDS.contains(&word)
}
