//! The GLSL of a file as attendees publish it around their code: a Markdown post or README
//! (front matter, prose, fenced code blocks, HTML), a web page whose shaders sit in
//! `<script type="x-shader/...">` tags, a JavaScript/TypeScript file whose shaders are
//! template strings, or notes with prose lines between the functions.
//!
//! `glsl_of_paste` blanks what is visibly not GLSL and keeps every line where it was (a
//! blanked line stays as an empty line, a blanked span as spaces), so that the compiler's
//! messages still name the user's lines. What it drops is said in notes, one per kind of
//! thing dropped. A file of plain GLSL comes back unchanged: every rule here needs a sign
//! that GLSL never shows (a fence line, a front-matter line 1, a backtick outside comments,
//! a character GLSL does not have, three words in a row that are no GLSL).

mod items;
mod lines;
mod scripts;

use items::close_braces_and_drop_statements;
use lines::{code_of_line, not_glsl};
use scripts::{in_script_expression, looks_like_glsl, template_strings};

/// A note of `glsl_of_paste`: the line it is about (from 1, of the file given) and what was
/// done, without the place ("dropped ...").
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PasteNote {
    /// The line (from 1).
    pub line: usize,
    /// What was done there.
    pub text: String,
}

/// A file's GLSL with what is visibly not GLSL blanked (see the module documentation).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PastedGlsl {
    /// The text: the same lines, what is not GLSL blanked.
    pub text: String,
    /// What was dropped, in the order of the file.
    pub notes: Vec<PasteNote>,
    /// Whether the GLSL was read from JavaScript/TypeScript template strings.
    pub from_script_strings: bool,
}

/// Fence languages whose blocks are GLSL, or may be (a block without a language, the C-like
/// names people give GLSL for its highlighting).
const GLSL_FENCES: [&str; 19] = [
    "",
    "glsl",
    "glsl450",
    "glslang",
    "gl",
    "opengl",
    "webgl",
    "shader",
    "shadertoy",
    "frag",
    "vert",
    "comp",
    "fs",
    "vs",
    "c",
    "cpp",
    "c++",
    "cc",
    "h",
];

/// Fence languages whose blocks are scripts that may hold GLSL in template strings.
const SCRIPT_FENCES: [&str; 9] = [
    "js",
    "javascript",
    "ts",
    "typescript",
    "jsx",
    "tsx",
    "html",
    "svelte",
    "vue",
];

/// Reads `text` (a whole file) as `glsl_of_paste` says.
pub fn glsl_of_paste(text: &str) -> PastedGlsl {
    let lines = line_ranges(text);
    let mut state = Paste {
        text,
        lines: &lines,
        keep: vec![true; text.len()],
        notes: Vec::new(),
        from_script_strings: false,
    };
    state.drop_front_matter();
    if !state.read_fenced_blocks() && !state.read_shader_script_tags() {
        let whole = 0..text.len();
        state.read_script_strings(whole);
    }
    state.drop_lines_that_are_not_glsl();
    let bytes: Vec<u8> = text
        .bytes()
        .zip(&state.keep)
        .map(|(b, &keep)| if keep || b == b'\n' { b } else { b' ' })
        .collect();
    let mut result = String::from_utf8_lossy(&bytes).into_owned();
    if !state.notes.is_empty() {
        // Lines blanked whole are left empty rather than full of spaces.
        result = result
            .split('\n')
            .map(|line| if line.trim().is_empty() { "" } else { line })
            .collect::<Vec<_>>()
            .join("\n");
    }
    let mut notes = state.notes;
    let result = close_braces_and_drop_statements(&result, &mut notes);
    notes.sort_by_key(|n| n.line);
    PastedGlsl {
        text: result,
        notes,
        from_script_strings: state.from_script_strings,
    }
}

/// The byte range of each line, without its `\n`.
fn line_ranges(text: &str) -> Vec<std::ops::Range<usize>> {
    let mut ranges = Vec::new();
    let mut start = 0;
    for (at, _) in text.match_indices('\n') {
        ranges.push(start..at);
        start = at + 1;
    }
    ranges.push(start..text.len());
    ranges
}

/// A fence line: its character (`` ` `` or `~`), its length and its language (the first word
/// of its info string, lower case).
struct Fence {
    character: u8,
    length: usize,
    language: String,
}

/// The fence that `line` is, if it is one (up to three spaces, then three or more backticks
/// or tildes).
fn fence(line: &str) -> Option<Fence> {
    let indent = line.len() - line.trim_start_matches(' ').len();
    if indent > 3 {
        return None;
    }
    let rest = &line[indent..];
    let character = *rest.as_bytes().first()?;
    if character != b'`' && character != b'~' {
        return None;
    }
    let length = rest.bytes().take_while(|&b| b == character).count();
    if length < 3 {
        return None;
    }
    let info = rest[length..].trim();
    if character == b'`' && info.contains('`') {
        return None;
    }
    let language = info
        .trim_start_matches('{')
        .trim_start_matches('.')
        .split(|c: char| c.is_whitespace() || c == ',' || c == '}' || c == '{')
        .next()
        .unwrap_or_default()
        .to_ascii_lowercase();
    Some(Fence {
        character,
        length,
        language,
    })
}

/// `glsl_of_paste` at work: which bytes are kept, and the notes.
struct Paste<'a> {
    text: &'a str,
    lines: &'a [std::ops::Range<usize>],
    keep: Vec<bool>,
    notes: Vec<PasteNote>,
    from_script_strings: bool,
}

impl Paste<'_> {
    /// Blanks `range`.
    fn drop_range(&mut self, range: std::ops::Range<usize>) {
        for keep in &mut self.keep[range] {
            *keep = false;
        }
    }

    /// Blanks lines `first..=last` (indices from 0).
    fn drop_lines(&mut self, first: usize, last: usize) {
        let range = self.lines[first].start..self.lines[last].end;
        self.drop_range(range);
    }

    /// Whether any byte of line `index` is still kept.
    fn line_is_kept(&self, index: usize) -> bool {
        self.keep[self.lines[index].clone()].iter().any(|&k| k)
    }

    fn note(&mut self, index: usize, text: String) {
        self.notes.push(PasteNote {
            line: index + 1,
            text,
        });
    }

    /// YAML (`---`) or TOML (`+++`) front matter from line 1 to its closing line.
    fn drop_front_matter(&mut self) {
        let line = |i: usize| self.text[self.lines[i].clone()].trim_end();
        let opening = line(0);
        if opening != "---" && opening != "+++" {
            return;
        }
        let closes = |l: &str| l == opening || opening == "---" && l == "...";
        let Some(end) = (1..self.lines.len()).find(|&i| closes(line(i))) else {
            return;
        };
        self.drop_lines(0, end);
        self.note(
            0,
            format!(
                "dropped the front matter ('{opening}', {} lines): not GLSL",
                end + 1
            ),
        );
    }

    /// Markdown: when the file has a fenced code block with something in it, only the
    /// blocks are read (those of GLSL; the template strings of script blocks); the prose,
    /// HTML and other blocks around them are dropped. Returns whether the file is Markdown.
    fn read_fenced_blocks(&mut self) -> bool {
        // (opening line, closing line or the end, language)
        let mut blocks: Vec<(usize, usize, String)> = Vec::new();
        let mut index = 0;
        while index < self.lines.len() {
            if !self.line_is_kept(index) {
                index += 1;
                continue;
            }
            let Some(open) = fence(&self.text[self.lines[index].clone()]) else {
                index += 1;
                continue;
            };
            let close = (index + 1..self.lines.len()).find(|&i| {
                fence(&self.text[self.lines[i].clone()]).is_some_and(|f| {
                    f.character == open.character
                        && f.length >= open.length
                        && f.language.is_empty()
                        && self.text[self.lines[i].clone()]
                            .trim()
                            .bytes()
                            .all(|b| b == open.character)
                })
            });
            let end = close.unwrap_or(self.lines.len());
            blocks.push((index, end, open.language));
            index = end + 1;
        }
        let has_code = blocks.iter().any(|(open, end, _)| {
            (open + 1..*end).any(|i| !self.text[self.lines[i].clone()].trim().is_empty())
        });
        if !has_code {
            // A stray fence (a closing one pasted after the code): that line alone.
            for (open, end, _) in blocks {
                self.drop_lines(open, open);
                if end < self.lines.len() {
                    self.drop_lines(end, end);
                }
                self.note(open, "dropped a Markdown fence line (```): not GLSL".into());
            }
            return false;
        }
        let total_lines = self.lines.len();
        let mut kept_blocks = 0;
        let mut code_lines = 0;
        let mut next = 0;
        for (open, end, language) in &blocks {
            if next < *open {
                self.drop_lines(next, open - 1);
            }
            self.drop_lines(*open, *open);
            if *end < total_lines {
                self.drop_lines(*end, *end);
            }
            next = end + 1;
            if *open + 1 >= *end {
                continue;
            }
            let body = self.lines[open + 1].start..self.lines[end - 1].end;
            if GLSL_FENCES.contains(&language.as_str()) {
                kept_blocks += 1;
                code_lines += end - open - 1;
            } else if SCRIPT_FENCES.contains(&language.as_str()) {
                if !self.read_script_strings(body.clone()) {
                    self.drop_range(body);
                    self.note(
                        *open,
                        format!("dropped a ```{language} block: it holds no GLSL template string"),
                    );
                }
            } else {
                self.drop_range(body);
                self.note(*open, format!("dropped a ```{language} block: not GLSL"));
            }
        }
        if next < total_lines {
            self.drop_lines(next, total_lines - 1);
        }
        let first = blocks.first().map_or(0, |b| b.0);
        self.note(
            first,
            format!(
                "read as Markdown: the {code_lines} lines of its {kept_blocks} GLSL code block{} are read; the text around {} (prose, headings, HTML, fence lines) is dropped",
                if kept_blocks == 1 { "" } else { "s" },
                if kept_blocks == 1 { "it" } else { "them" }
            ),
        );
        true
    }

    /// A web page: when it has `<script type="x-shader/...">` (or a type naming GLSL) tags,
    /// only their contents are read. Returns whether it has such tags.
    fn read_shader_script_tags(&mut self) -> bool {
        let lower = self.text.to_ascii_lowercase();
        let mut scripts: Vec<std::ops::Range<usize>> = Vec::new();
        let mut from = 0;
        while let Some(at) = lower[from..].find("<script").map(|at| from + at) {
            let Some(tag_end) = lower[at..].find('>').map(|e| at + e + 1) else {
                break;
            };
            let tag = &lower[at..tag_end];
            let end = lower[tag_end..]
                .find("</script")
                .map_or(lower.len(), |e| tag_end + e);
            if tag.contains("shader") || tag.contains("glsl") {
                scripts.push(tag_end..end);
            }
            from = end.max(tag_end);
        }
        if scripts.is_empty() {
            return false;
        }
        let mut next = 0;
        for script in &scripts {
            self.drop_range(next..script.start);
            next = script.end;
        }
        self.drop_range(next..self.text.len());
        let first = self.line_of(scripts[0].start);
        self.note(
            first,
            format!(
                "read as a web page: the GLSL of its {} shader <script> tag{} is read; the HTML and JavaScript around {} are dropped",
                scripts.len(),
                if scripts.len() == 1 { "" } else { "s" },
                if scripts.len() == 1 { "it" } else { "them" }
            ),
        );
        true
    }

    /// The line (from 0) of byte `at`.
    fn line_of(&self, at: usize) -> usize {
        self.lines.partition_point(|l| l.end < at)
    }

    /// JavaScript/TypeScript: when `range` holds template strings (`` `...` ``, outside
    /// comments and quotes) whose text looks like GLSL, only their text is read (each
    /// `${...}` blanked); the script around them is dropped. Returns whether it found any.
    fn read_script_strings(&mut self, range: std::ops::Range<usize>) -> bool {
        let strings = template_strings(&self.text[range.clone()]);
        let glsl: Vec<(std::ops::Range<usize>, Vec<std::ops::Range<usize>>)> = strings
            .into_iter()
            .filter(|(body, _)| {
                in_script_expression(&self.text[range.start..range.start + body.start - 1])
                    && looks_like_glsl(&self.text[range.start + body.start..range.start + body.end])
            })
            .map(|(body, holes)| {
                let shift = |r: std::ops::Range<usize>| range.start + r.start..range.start + r.end;
                (shift(body), holes.into_iter().map(shift).collect())
            })
            .collect();
        if glsl.is_empty() {
            return false;
        }
        let mut next = range.start;
        let mut holes_count = 0;
        for (body, holes) in &glsl {
            self.drop_range(next..body.start);
            next = body.end;
            for hole in holes {
                self.drop_range(hole.clone());
            }
            holes_count += holes.len();
        }
        self.drop_range(next..range.end);
        self.from_script_strings = true;
        let first = self.line_of(glsl[0].0.start);
        self.note(
            first,
            format!(
                "GLSL inside a JS/TS template string: the text of its {} GLSL string{} is read{}; the script around {} is dropped",
                glsl.len(),
                if glsl.len() == 1 { "" } else { "s" },
                if holes_count > 0 {
                    format!(", each of the {holes_count} ${{...}} in {} blanked", if glsl.len() == 1 { "it" } else { "them" })
                } else {
                    String::new()
                },
                if glsl.len() == 1 { "it" } else { "them" }
            ),
        );
        true
    }

    /// Lines outside comments and directives that GLSL cannot have: a character GLSL does not
    /// use (`` ` ``, `$`, `@`, `'`, `"`, a backslash, anything not ASCII), an HTML tag or
    /// comment at the start of the line, a line of dots (`...`), a sentence (three words
    /// in a row that are no GLSL words, or words ending in `:` or `.`).
    fn drop_lines_that_are_not_glsl(&mut self) {
        // (first line, last line, why, the first line's text) of each run of dropped lines.
        let mut runs: Vec<(usize, usize, &'static str, String)> = Vec::new();
        let mut in_block_comment = false;
        let mut in_html_comment = false;
        let mut in_directive = false;
        for index in 0..self.lines.len() {
            if !self.line_is_kept(index) {
                continue;
            }
            let range = self.lines[index].clone();
            // The line as kept (what an extraction dropped is not read).
            let line: String = self.text[range.clone()]
                .chars()
                .zip(self.text[range.clone()].char_indices())
                .map(|(c, (at, _))| if self.keep[range.start + at] { c } else { ' ' })
                .collect();
            let line = line.as_str();
            // A directive goes on after a line that ends in a backslash.
            let continues = in_directive;
            in_directive = (continues || line.trim_start().starts_with('#'))
                && line.trim_end().ends_with('\\');
            if continues {
                continue;
            }
            let code = code_of_line(line, &mut in_block_comment);
            let why = if in_html_comment {
                if line.contains("-->") {
                    in_html_comment = false;
                }
                Some("an HTML comment")
            } else if code.trim_start().starts_with("<!--") {
                in_html_comment = !line.contains("-->");
                Some("an HTML comment")
            } else {
                not_glsl(&code)
            };
            let Some(why) = why else {
                continue;
            };
            self.drop_range(range);
            match runs.last_mut() {
                Some(run) if run.1 + 1 == index && run.2 == why => run.1 = index,
                _ => runs.push((index, index, why, line.trim().to_string())),
            }
        }
        for (first, last, why, text) in runs {
            let count = last - first + 1;
            let quoted: String = text.chars().take(40).collect();
            let cut = if quoted.len() < text.len() { "…" } else { "" };
            self.note(
                first,
                if count == 1 {
                    format!("dropped '{quoted}{cut}' ({why}, not GLSL)")
                } else {
                    format!("dropped {count} lines from '{quoted}{cut}' on ({why}, not GLSL)")
                },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPHERE: &str = "vec3 sample_sphere(vec2 random_numbers) {\n    float z = 2.0 * random_numbers.x - 1.0;\n    float r = sqrt(max(0.0, 1.0 - z * z));\n    float phi = 2.0 * M_PI * random_numbers.y;\n    return vec3(r * cos(phi), r * sin(phi), z);\n}\n";

    #[test]
    fn plain_glsl_comes_back_unchanged() {
        let text = format!(
            "// Notes: it's the slides' sampler, see `sample_sphere` ($x$).\n/* \"quoted\" — é */\n#define M_PI 3.14159\nstruct S {{ vec3 a; }};\n{SPHERE}float f(float x) {{\n    return x < 0.0 ? -x\n        : x;\n}}\nconst highp float K = 1.0;\ntriangle_t tri;\n"
        );
        let pasted = glsl_of_paste(&text);
        assert_eq!(pasted.text, text);
        assert!(pasted.notes.is_empty(), "{:?}", pasted.notes);
    }

    #[test]
    fn every_glsl_file_of_the_tests_comes_back_unchanged() {
        // The solutions and programs check's tests judge: GLSL as attendees write it,
        // ShaderToy tabs, page shaders, Vulkan shaders, snippets at file scope.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/solutions");
        let mut files = Vec::new();
        for directory in [root.clone(), root.join("programs")] {
            for entry in std::fs::read_dir(&directory).expect("tests/solutions") {
                let path = entry.expect("entry").path();
                if path.extension().is_some_and(|e| e == "glsl") {
                    files.push(path);
                }
            }
        }
        assert!(files.len() > 40, "{}", files.len());
        for path in files {
            let text = crate::glsl_intake::read_source_file(&path).expect("read");
            let pasted = glsl_of_paste(&text);
            assert!(
                pasted.text == text && pasted.notes.is_empty(),
                "{}: {:?}",
                path.display(),
                pasted.notes
            );
        }
    }

    #[test]
    fn markdown_keeps_only_its_glsl_blocks_on_their_lines() {
        let text = format!(
            "---\ntitle: My path tracer\n---\n# Exercise 3\n<p align=\"center\"><img src=\"x.png\"></p>\nThe sampler from the slides:\n```glsl\n{SPHERE}```\n```python\nprint(1)\n```\nDone.\n"
        );
        let pasted = glsl_of_paste(&text);
        let lines: Vec<&str> = pasted.text.split('\n').collect();
        assert_eq!(lines.len(), text.split('\n').count());
        assert_eq!(lines[7], "vec3 sample_sphere(vec2 random_numbers) {");
        for (index, line) in lines.iter().enumerate() {
            if !(7..=12).contains(&index) {
                assert!(line.trim().is_empty(), "line {}: {line}", index + 1);
            }
        }
        let notes: Vec<String> = pasted
            .notes
            .iter()
            .map(|n| format!("{}: {}", n.line, n.text))
            .collect();
        assert!(
            notes
                .iter()
                .any(|n| n.starts_with("1: dropped the front matter")),
            "{notes:?}"
        );
        assert!(
            notes.iter().any(|n| n.starts_with("7: read as Markdown")),
            "{notes:?}"
        );
        assert!(
            notes
                .iter()
                .any(|n| n.starts_with("15: dropped a ```python block")),
            "{notes:?}"
        );
    }

    #[test]
    fn a_closing_fence_alone_is_one_dropped_line() {
        let text = format!("{SPHERE}```\n");
        let pasted = glsl_of_paste(&text);
        assert_eq!(pasted.text, format!("{SPHERE}\n"));
    }

    #[test]
    fn prose_latex_html_and_ellipses_between_functions_are_dropped() {
        let text = format!(
            "Here is my sampler, as on the slides\n$$2{{\\pi}}\\frac{{1}}{{N}}$$\n<!-- a\ncomment -->\n<br>\nResult:\n{SPHERE}...\nThat is all.\n"
        );
        let pasted = glsl_of_paste(&text);
        let kept: Vec<&str> = pasted
            .text
            .split('\n')
            .filter(|l| !l.trim().is_empty())
            .collect();
        assert_eq!(kept.join("\n") + "\n", SPHERE);
        assert_eq!(pasted.text.split('\n').count(), text.split('\n').count());
    }

    #[test]
    fn snippets_at_file_scope_go_in_one_pass_and_open_braces_are_closed_or_named() {
        let text = format!(
            "Exercise 1\nfor (int i = 0; i != SAMPLE_COUNT; ++i) {{\n    if (hit) {{\n        // ...\n{SPHERE}color += c;\nfloat k = 1.0;\n"
        );
        let pasted = glsl_of_paste(&text);
        let notes: Vec<String> = pasted
            .notes
            .iter()
            .map(|n| format!("{}: {}", n.line, n.text))
            .collect();
        assert_eq!(notes.len(), 3, "{notes:?}");
        assert!(
            notes[0].starts_with("1: dropped 'Exercise 1' (prose"),
            "{notes:?}"
        );
        assert!(
            notes[1].starts_with("2: dropped 'for (int i = 0; i != SAMPLE_COUNT; ++i) { if (h")
                && notes[1].ends_with("its '{' is never closed before the definition at line 5)"),
            "{notes:?}"
        );
        assert!(
            notes[2].starts_with("11: dropped 'color += c;'"),
            "{notes:?}"
        );
        let kept: Vec<&str> = pasted
            .text
            .split('\n')
            .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with("//"))
            .collect();
        assert_eq!(kept.join("\n") + "\n", format!("{SPHERE}float k = 1.0;\n"));
        // An indented definition inside a brace never closed is not read; the note says so.
        let hidden = "struct s {\n    vec3 sample_sphere(vec2 u) { return vec3(u, 0.0); }\n";
        let notes = glsl_of_paste(hidden).notes;
        assert!(
            notes[0].text.contains(
                "the definition of sample_sphere at line 2 stands inside it and is not read"
            ),
            "{notes:?}"
        );
        // A function without its last brace gets it.
        let unfinished = "vec2 f(vec2 u) {\n    return u;\n\nvec2 g(vec2 u) {\n    return u;\n}\n";
        let pasted = glsl_of_paste(unfinished);
        assert_eq!(
            pasted.text,
            "vec2 f(vec2 u) {\n    return u;}\n\nvec2 g(vec2 u) {\n    return u;\n}\n"
        );
        assert!(pasted.notes[0]
            .text
            .starts_with("this '{' is never closed before the definition at line 4"));
    }

    #[test]
    fn glsl_in_a_template_string_is_read_and_named() {
        let text = format!(
            "import * as THREE from 'three';\nexport function material() {{\n  const shader = `\n{SPHERE}float k = ${{K}};\n`;\n  return shader;\n}}\n"
        );
        let pasted = glsl_of_paste(&text);
        assert!(pasted.from_script_strings);
        let kept: Vec<&str> = pasted
            .text
            .split('\n')
            .filter(|l| !l.trim().is_empty())
            .collect();
        assert_eq!(kept[0], "vec3 sample_sphere(vec2 random_numbers) {");
        assert_eq!(kept.last().map(|l| l.trim()), Some("float k =     ;"));
        assert!(
            pasted.notes[0]
                .text
                .starts_with("GLSL inside a JS/TS template string"),
            "{:?}",
            pasted.notes
        );
        assert_eq!(pasted.notes[0].line, 3);
    }
}
