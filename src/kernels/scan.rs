//! A small scanner of GLSL text for the loop-limit test (`crate::kernels::loops`): which
//! files a kernel is made of, and where their loops are.

/// A loop found in GLSL text: the function it is in.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FoundLoop {
    /// The file.
    pub file: String,
    /// The enclosing function (empty outside any).
    pub function: String,
}

/// The loops (`for`, `while`, `do ... while`) of one GLSL file, with the function each is
/// in: comments and preprocessor lines are skipped, a function is a `name(...) {` at brace
/// depth 0, a `while` that closes a `do` is not a loop of its own, and a loop marked
/// `[[unroll]]` (a constant trip count, unrolled when compiled) is no loop at run time.
pub fn find_loops(file: &str, text: &str) -> Vec<FoundLoop> {
    let code = strip_comments_and_directives(text);
    let mut tokens: Vec<&str> = Vec::new();
    let mut start = None;
    for (i, ch) in code.char_indices() {
        let word = ch.is_ascii_alphanumeric() || ch == '_';
        match (word, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                tokens.push(&code[s..i]);
                start = None;
            }
            _ => {}
        }
        if !word && !ch.is_whitespace() {
            tokens.push(&code[i..i + ch.len_utf8()]);
        }
    }
    if let Some(s) = start {
        tokens.push(&code[s..]);
    }
    let mut loops = Vec::new();
    let (mut depth, mut function) = (0usize, String::new());
    let mut last_call_name = "";
    // Brace depths of the `do` bodies whose closing `while` is still to come.
    let mut open_dos: Vec<usize> = Vec::new();
    for (i, &token) in tokens.iter().enumerate() {
        let previous = if i > 0 { tokens[i - 1] } else { "" };
        match token {
            "(" if depth == 0 => last_call_name = previous,
            "{" => {
                if depth == 0 {
                    function = if previous == ")" {
                        last_call_name.to_string()
                    } else {
                        String::new()
                    };
                }
                depth += 1;
            }
            "}" => depth = depth.saturating_sub(1),
            "do" | "for" | "while" if depth > 0 => {
                if token == "while" && previous == "}" && open_dos.last() == Some(&depth) {
                    open_dos.pop();
                    continue;
                }
                if i >= 5 && tokens[i - 5..i] == ["[", "[", "unroll", "]", "]"] {
                    continue;
                }
                if token == "do" {
                    open_dos.push(depth);
                }
                loops.push(FoundLoop {
                    file: file.to_string(),
                    function: function.clone(),
                });
            }
            _ => {}
        }
    }
    loops
}

/// `text` without `//` and `/* */` comments and without preprocessor lines (continued ones
/// included), so that a loop in a comment or a macro's text does not count.
fn strip_comments_and_directives(text: &str) -> String {
    let mut without_comments = String::with_capacity(text.len());
    let mut rest = text;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix("//") {
            rest = after.find('\n').map_or("", |end| &after[end..]);
        } else if let Some(after) = rest.strip_prefix("/*") {
            rest = after.find("*/").map_or("", |end| &after[end + 2..]);
            without_comments.push(' ');
        } else {
            let ch = rest.chars().next().unwrap_or(' ');
            without_comments.push(ch);
            rest = &rest[ch.len_utf8()..];
        }
    }
    let mut code = String::with_capacity(without_comments.len());
    let mut continued = false;
    for line in without_comments.lines() {
        let directive = continued || line.trim_start().starts_with('#');
        continued = directive && line.trim_end().ends_with('\\');
        if !directive {
            code.push_str(line);
        }
        code.push('\n');
    }
    code
}

/// The files a kernel is made of: `source` and every file it includes, transitively (under
/// any macro), but `user_functions.glsl` (a user's code, guarded by `vkpath check`).
pub fn kernel_files(source: &str) -> Vec<&'static str> {
    let text_of = |name: &str| {
        crate::shaders::GLSL_SOURCES
            .iter()
            .find(|(file, _)| *file == name)
            .copied()
    };
    let mut files: Vec<&'static str> = Vec::new();
    let mut pending = vec![source.to_string()];
    while let Some(name) = pending.pop() {
        let Some((file, text)) = text_of(&name) else {
            continue;
        };
        if files.contains(&file) || file == "user_functions.glsl" {
            continue;
        }
        files.push(file);
        for line in text.lines() {
            if let Some(rest) = line.trim_start().strip_prefix("#include") {
                pending.push(rest.trim().trim_matches('"').to_string());
            }
        }
    }
    files
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scan_finds_loops_in_functions_only() {
        let text = "// for (a comment)\n#define X for (;;)\nstruct s_t { int a; };\n\
                    void f(int n) {\n    for (int i = 0; i != n; ++i) {}\n    do {\n        n--;\n    } while (n > 0);\n}\n\
                    int g() { while (true) { /* for */ } }\n";
        let found = find_loops("x.glsl", text);
        let names: Vec<&str> = found.iter().map(|l| l.function.as_str()).collect();
        assert_eq!(names, ["f", "f", "g"]);
    }

    #[test]
    fn loops_unrolled_when_compiled_are_not_counted() {
        let text = "void f(int n) {\n    [[unroll]] for (int k = 0; k != 4; ++k) {}\n    \
                    [[dont_unroll]] while (n > 0) n--;\n}\n";
        let found = find_loops("x.glsl", text);
        assert_eq!(found.len(), 1, "{found:?}");
    }
}
