//! `docs/house.md`'s claims, held by tests that read the sources: which rooms may name a
//! light kind, which files a new light kind, a new lobe and a new material factor touch (the
//! doc's lists and counts against the files that spell each list), the variant room's inputs,
//! and that no import circle runs between two of `src/`'s top-level folders; and one claim of
//! the build's: the Python extension resolves vkpath's dependencies with the same features as
//! `cargo test`, so CI compiles vkpath once for both. The doc cannot go stale: a change that
//! moves one of these numbers fails here until the doc says the new one.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The checkout these tests read: the crate's root folder, or `$VKPATH_HOUSE_ROOT` (to
/// hold another checkout, e.g. the commit before a change, to the same claims).
fn root() -> PathBuf {
    std::env::var_os("VKPATH_HOUSE_ROOT")
        .map_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")), PathBuf::from)
}

/// Every file under `folder` (relative to the root) whose name ends with one of
/// `extensions`, as root-relative paths with `/`, sorted.
fn files_under(folder: &str, extensions: &[&str]) -> Vec<String> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|entry| entry.unwrap().path())
            .collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                walk(&path, out);
            } else {
                out.push(path);
            }
        }
    }
    let mut paths = Vec::new();
    walk(&root().join(folder), &mut paths);
    paths
        .into_iter()
        .map(|path| {
            path.strip_prefix(root())
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/")
        })
        .filter(|path| extensions.iter().any(|e| path.ends_with(e)))
        .collect()
}

/// The text of a root-relative file.
fn read(path: &str) -> String {
    std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The code of a Rust or GLSL source: comments (line, block, doc) blanked, newlines kept;
/// string and character literals kept as they are (a message that lists the kinds of light
/// lists them).
fn code_of(text: &str) -> String {
    strip_comments(text, false)
}

/// `code_of`, with the insides of string and character literals blanked too (quotes, and
/// newlines, kept): what is left of braces is the code's own.
fn code_without_literals(text: &str) -> String {
    strip_comments(text, true)
}

/// Appends a literal to `out`: as it is, or with `blank` every character but the quotes and
/// newlines as a space.
fn push_literal(out: &mut String, literal: &[char], blank: bool) {
    let last = literal.len().saturating_sub(1);
    for (i, &c) in literal.iter().enumerate() {
        let keep = !blank || c == '\n' || ((i == 0 || i == last) && (c == '"' || c == '\''));
        out.push(if keep { c } else { ' ' });
    }
}

/// `code_of` and `code_without_literals`: comments blanked, literals kept or blanked.
fn strip_comments(text: &str, blank_literals: bool) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let at = |i: usize| chars.get(i).copied().unwrap_or('\0');
    while i < chars.len() {
        let c = chars[i];
        if c == '/' && at(i + 1) == '/' {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && at(i + 1) == '*' {
            // Rust's block comments nest.
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if chars[i] == '\n' {
                        out.push('\n');
                    }
                    i += 1;
                }
            }
        } else if c == 'r'
            && (at(i + 1) == '"' || at(i + 1) == '#')
            && !(i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_'))
        {
            // A raw string r"..." or r#"..."#: it ends at the quote and as many hashes.
            let mut j = i + 1;
            while at(j) == '#' {
                j += 1;
            }
            if at(j) != '"' {
                out.push(c);
                i += 1;
                continue;
            }
            let hashes = j - i - 1;
            let mut end = j + 1;
            while end < chars.len()
                && !(chars[end] == '"' && (1..=hashes).all(|k| at(end + k) == '#'))
            {
                end += 1;
            }
            let end = (end + 1 + hashes).min(chars.len());
            push_literal(&mut out, &chars[i..end], blank_literals);
            i = end;
        } else if c == '"' {
            let mut end = i + 1;
            while end < chars.len() && chars[end] != '"' {
                end += if chars[end] == '\\' { 2 } else { 1 };
            }
            let end = (end + 1).min(chars.len());
            push_literal(&mut out, &chars[i..end], blank_literals);
            i = end;
        } else if c == '\'' && (at(i + 1) == '\\' || at(i + 2) == '\'') {
            // A character literal ('"', '\n', '\''); a lifetime has no closing quote.
            let mut end = if at(i + 1) == '\\' { i + 3 } else { i + 2 };
            while end < chars.len() && chars[end] != '\'' {
                end += 1;
            }
            let end = (end + 1).min(chars.len());
            push_literal(&mut out, &chars[i..end], blank_literals);
            i = end;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The identifiers and string literals of `code` (`code_of`'s), with their line numbers.
fn tokens(code: &str) -> Vec<(usize, String)> {
    let mut tokens = Vec::new();
    for (number, line) in code.lines().enumerate() {
        let chars: Vec<char> = line.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            let c = chars[i];
            if c.is_alphabetic() || c == '_' {
                let start = i;
                while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                    i += 1;
                }
                tokens.push((number + 1, chars[start..i].iter().collect()));
            } else if c == '"' {
                let start = i;
                i += 1;
                while i < chars.len() && chars[i] != '"' {
                    i += if chars[i] == '\\' { 2 } else { 1 };
                }
                i = (i + 1).min(chars.len());
                tokens.push((number + 1, chars[start..i].iter().collect()));
            } else {
                i += 1;
            }
        }
    }
    tokens
}

/// The kinds of light, each by the words that name it in code (lower case): the emissive
/// triangles with the light tree over them, the environment and the punctual lights. A new
/// kind is a new row here.
const LIGHT_KINDS: &[(&str, &[&str])] = &[
    (
        "emissive triangles",
        &["emissive", "light_tree", "lighttree"],
    ),
    ("environment", &["environment"]),
    ("punctual lights", &["punctual"]),
];

/// Identifiers of `src/render/` that contain a kind's word but name no kind of light: none
/// since `GpuMaterial` packs by the material parameter table (before, its emission factor
/// and texture slot, `MATERIAL_TEXEL_EMISSIVE_METALLIC` and `MATERIAL_TEXTURE_EMISSIVE`).
const NOT_A_LIGHT_KIND: &[(&str, &str)] = &[];

/// The places in `files` where an identifier or string literal of the code names a kind of
/// light (contains one of `LIGHT_KINDS`' words, case aside), `allowed` aside: "file:line
/// token".
fn light_kinds_named(files: &[String], allowed: &[(&str, &str)]) -> Vec<String> {
    let mut found = Vec::new();
    for path in files {
        for (line, token) in tokens(&code_of(&read(path))) {
            let lower = token.to_lowercase();
            let names_a_kind = LIGHT_KINDS
                .iter()
                .any(|(_, words)| words.iter().any(|w| lower.contains(w)));
            if names_a_kind && !allowed.contains(&(path.as_str(), token.as_str())) {
                found.push(format!("{path}:{line} {token}"));
            }
        }
    }
    found
}

#[test]
fn render_names_no_light_kind() {
    // The renderer holds the lights as one value (`crate::lights::LightBuffers`, made from
    // `crate::lights::SceneLights`) that uploads, hashes and keeps its kinds itself: a new
    // kind of light touches no file of `src/render/`.
    let files = files_under("src/render", &[".rs"]);
    assert!(files.len() > 20, "src/render/ not found: {files:?}");
    let found = light_kinds_named(&files, NOT_A_LIGHT_KIND);
    assert!(
        found.is_empty(),
        "src/render/ names a kind of light (it belongs in src/lights/):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_light_kind_check_sees_a_kind_in_code_but_not_in_comments() {
    // The check above would pass on any source without these tokens: here it finds them.
    let files = vec!["src/lights/scene_lights.rs".to_owned()];
    let found = light_kinds_named(&files, &[]);
    for kind in ["environment", "punctual", "emissive"] {
        assert!(found.iter().any(|f| f.contains(kind)), "{kind}: {found:?}");
    }
    let code = code_of("let a = 1; // environment\n/* punctual /* nested */ */ let \"emissive\";");
    let names: Vec<String> = tokens(&code).into_iter().map(|(_, t)| t).collect();
    assert_eq!(names, ["let", "a", "let", "\"emissive\""]);
    assert_eq!(code.lines().count(), 2);
    let raw = code_of("r#\"a \"// b\" c\"# x // y\n'\"' z 'a");
    assert_eq!(raw, "r#\"a \"// b\" c\"# x \n'\"' z 'a");
}

/// A block of `docs/house.md` between `<!-- house: NAME -->` and `<!-- /house -->`.
fn house_block(name: &str) -> String {
    let doc = read("docs/house.md");
    let open = format!("<!-- house: {name} -->");
    let start = doc
        .find(&open)
        .unwrap_or_else(|| panic!("docs/house.md has no {open}"))
        + open.len();
    let end = start
        + doc[start..]
            .find("<!-- /house -->")
            .unwrap_or_else(|| panic!("docs/house.md: {open} is not closed"));
    doc[start..end].to_owned()
}

/// The files a block of `docs/house.md` lists, one list item each (`1. \`path\` ...`), and
/// whether each is new (`(new`).
fn listed_files(block: &str) -> Vec<(String, bool)> {
    block
        .lines()
        .map(str::trim_start)
        .filter(|line| line.starts_with(|c: char| c.is_ascii_digit()) || line.starts_with("- "))
        .filter_map(|line| {
            let start = line.find('`')? + 1;
            let end = start + line[start..].find('`')?;
            Some((line[start..end].to_owned(), line.contains("(new")))
        })
        .collect()
}

/// The number a block of `docs/house.md` states before `word` ("touch 10 files": `files`).
fn stated(block: &str, word: &str) -> usize {
    let words: Vec<&str> = block.split_whitespace().collect();
    let at = words
        .iter()
        .position(|w| w.trim_matches(|c: char| !c.is_alphanumeric()) == word)
        .unwrap_or_else(|| panic!("no '{word}' in {block}"));
    words[at - 1]
        .trim_start_matches('(')
        .parse()
        .unwrap_or_else(|e| panic!("'{} {word}': {e}", words[at - 1]))
}

/// The code files (Rust under `src/` and `python/src/`, GLSL under `glsl/`; test files and
/// test modules aside) whose code names every one of `groups` (each a list of words, one
/// of which names it; case aside).
fn files_naming_all(groups: &[&[&str]]) -> BTreeSet<String> {
    let mut files = files_under("src", &[".rs"]);
    files.extend(files_under("python/src", &[".rs"]));
    files.extend(files_under("glsl", &[".glsl", ".comp", ".h"]));
    files
        .into_iter()
        // Test files, and this one (whose tables name every kind and lobe), aside.
        .filter(|path| !path.ends_with("_tests.rs") && !path.ends_with("/tests.rs"))
        .filter(|path| path != "src/house.rs")
        .filter(|path| {
            let text = read(path);
            let text = match text.find("#[cfg(test)]") {
                Some(tests) => &text[..tests],
                None => &text,
            };
            let code = code_of(text).to_lowercase();
            groups
                .iter()
                .all(|words| words.iter().any(|w| code.contains(w)))
        })
        .collect()
}

/// Checks a cost `docs/house.md` states: its block `name` lists the files a new member of a
/// list (a light kind, a lobe) touches and says how many ("touch N files (K of them new)");
/// the files that spell the list today (name every member) must be exactly the ones it
/// lists as edited plus the ones its block `NAME beside` lists, and the new ones must exist
/// (as the list's existing members have them).
fn check_cost(name: &str, spelled: BTreeSet<String>) {
    let block = house_block(name);
    let listed = listed_files(&block);
    let beside_block = house_block(&format!("{name} beside"));
    let beside: BTreeSet<String> = listed_files(&beside_block)
        .into_iter()
        .map(|(path, _)| path)
        .collect();
    assert_eq!(
        listed.len(),
        stated(&block, "files"),
        "docs/house.md's {name}: the count and the list disagree"
    );
    let new = listed.iter().filter(|(_, new)| *new).count();
    assert_eq!(
        new,
        stated(&block, "new"),
        "docs/house.md's {name}: new files"
    );
    assert_eq!(
        beside.len(),
        stated(&beside_block, "files"),
        "{name} beside"
    );
    let every: Vec<&String> = listed.iter().map(|(path, _)| path).chain(&beside).collect();
    for path in every {
        assert!(
            root().join(path).is_file(),
            "docs/house.md's {name}: no {path}"
        );
    }
    let edited: BTreeSet<String> = listed
        .iter()
        .filter(|(_, new)| !new)
        .map(|(path, _)| path.clone())
        .chain(beside)
        .collect();
    assert_eq!(
        spelled, edited,
        "docs/house.md's {name}: the files that name every member (left) are not the ones \
         the doc lists (right); update the doc's list and count"
    );
}

#[test]
fn a_new_light_kind_touches_the_files_house_md_counts() {
    let groups: Vec<&[&str]> = LIGHT_KINDS.iter().map(|(_, words)| *words).collect();
    check_cost("light kind", files_naming_all(&groups));
}

#[test]
fn a_new_lobe_touches_the_files_house_md_counts() {
    // The lobes with glTF factors of their own: every place that spells both spells the
    // list a lobe with factors (iridescence) joins.
    check_cost("lobe", files_naming_all(&[&["sheen"], &["clearcoat"]]));
}

/// Two factors that a new factor joins the list of, each by the words that name it in code
/// (lower case: snake case, glTF's camel case, a nested field): factors with a texture slot
/// that a lobe reads, as a lobe's factors have (iridescence's thickness and ior).
const FACTORS: &[(&str, &[&str])] = &[
    (
        "clearcoat roughness",
        &[
            "clearcoat_roughness",
            "clearcoatroughness",
            "clearcoat.roughness",
        ],
    ),
    (
        "sheen roughness",
        &["sheen_roughness", "sheenroughness", "sheen.roughness"],
    ),
];

#[test]
fn a_new_factor_touches_the_files_house_md_counts() {
    // Every place whose code names both factors spells the list a new factor joins.
    let groups: Vec<&[&str]> = FACTORS.iter().map(|(_, words)| *words).collect();
    check_cost("factor", files_naming_all(&groups));
}

#[test]
fn the_variant_rooms_inputs_are_the_ones_house_md_names() {
    let code = code_of(&read("src/kernels/variant.rs"));
    let signature_start = code
        .find("pub fn path_tracer_variant(")
        .expect("path_tracer_variant");
    let signature = &code[signature_start..];
    let signature = &signature[..signature.find('{').unwrap()];
    let inputs: Vec<String> = signature
        [signature.find('(').unwrap() + 1..signature.rfind(')').unwrap()]
        .split(',')
        .filter_map(|parameter| parameter.split(':').nth(1))
        .map(|ty| ty.trim().trim_start_matches('&').to_owned())
        .collect();
    let output = signature[signature.rfind("->").unwrap() + 2..]
        .trim()
        .to_owned();
    let doc = read("docs/house.md");
    let claim = format!(
        "`path_tracer_variant({}) -> {}",
        inputs.join(", "),
        output.trim_start_matches("Result<").trim_end_matches('>')
    );
    assert!(
        doc.contains(&claim),
        "docs/house.md should name the variant room's inputs as {claim}`"
    );
    // Its inputs' fields, as the doc counts them.
    let fields = |name: &str| {
        let start = code.find(&format!("pub struct {name} {{")).unwrap();
        let body = &code[start..start + code[start..].find('}').unwrap()];
        body.matches("pub ").count() - 1
    };
    let block = house_block("variant inputs");
    assert_eq!(fields("SceneSummary"), stated(&block, "scene"), "{block}");
    assert_eq!(
        fields("VariantSettings"),
        stated(&block, "settings"),
        "{block}"
    );
}

/// The `crate::` paths a Rust source's code uses, braces expanded
/// (`crate::a::{b, c::d}` gives `a::b` and `a::c::d`).
fn crate_paths(code: &str) -> Vec<String> {
    fn expand(prefix: &str, rest: &str, out: &mut Vec<String>) -> usize {
        // Reads one path (with groups) from `rest`; returns how much it read.
        let mut path = prefix.to_owned();
        let chars: Vec<char> = rest.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            let c = chars[i];
            if c.is_alphanumeric() || c == '_' || c == ':' {
                path.push(c);
                i += 1;
            } else if c == '{' {
                i += 1;
                loop {
                    while i < chars.len() && (chars[i].is_whitespace() || chars[i] == ',') {
                        i += 1;
                    }
                    if i >= chars.len() || chars[i] == '}' {
                        i += 1;
                        break;
                    }
                    let tail: String = chars[i..].iter().collect();
                    i += expand(&path, &tail, out);
                }
                return i;
            } else {
                break;
            }
        }
        // `a::b as c`: the alias is not a path.
        out.push(path.trim_end_matches(':').to_owned());
        let tail: String = chars[i..].iter().collect();
        let alias = tail.trim_start();
        if let Some(after) = alias.strip_prefix("as ") {
            let skipped = tail.len() - alias.len() + 3;
            let name = after.trim_start();
            let name_len = name
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(name.len());
            i += skipped + (after.len() - name.len()) + name_len;
        }
        i
    }
    let mut paths = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("crate::") {
        let before_ok = !rest[..at]
            .chars()
            .last()
            .is_some_and(|c| c.is_alphanumeric() || c == '_');
        rest = &rest[at + "crate::".len()..];
        if before_ok {
            expand("", rest, &mut paths);
        }
    }
    paths
}

#[test]
fn crate_paths_expand_groups() {
    let code = "use crate::a::{b, c::{d, e as f}, g};\nlet x = crate::h::i(crate::j::K);";
    assert_eq!(
        crate_paths(code),
        ["a::b", "a::c::d", "a::c::e", "a::g", "h::i", "j::K"]
    );
}

/// The most lines `src/render/renderer.rs` may hold (`docs/house.md`, "Small rooms").
const RENDERER_MAX_LINES: usize = 600;

/// The most lines a function of `src/render/` or `src/cli/` may take, from its `fn` line to
/// its closing brace (`docs/house.md`, "Small rooms").
const FUNCTION_MAX_LINES: usize = 120;

/// The functions with a body in a Rust source: each one's name, the line of its `fn`
/// (counted from 1) and its lines from there to its closing brace. Braces are counted in the code without
/// comments and literals (`code_without_literals`), so a `"{"` or a `// }` is not one; a
/// function declared without a body (a trait's, `fn(u32)` types) is none; a function nested
/// in another is counted on its own too.
fn functions_of(text: &str) -> Vec<(String, usize, usize)> {
    let code: Vec<char> = code_without_literals(text).chars().collect();
    let word_at = |i: usize| {
        let mut end = i;
        while end < code.len() && (code[end].is_alphanumeric() || code[end] == '_') {
            end += 1;
        }
        end
    };
    let line_of = |i: usize| code[..i].iter().filter(|&&c| c == '\n').count() + 1;
    let mut functions = Vec::new();
    let mut i = 0;
    while i < code.len() {
        let starts_word = i == 0 || !(code[i - 1].is_alphanumeric() || code[i - 1] == '_');
        let end = word_at(i);
        if !starts_word || end == i {
            i += 1;
            continue;
        }
        if code[i..end].iter().collect::<String>() != "fn" {
            i = end;
            continue;
        }
        // `fn`, blanks, a name: a function (`fn(` is a pointer type).
        let mut name_start = end;
        while name_start < code.len() && code[name_start].is_whitespace() {
            name_start += 1;
        }
        let name_end = word_at(name_start);
        if name_end == name_start || name_start == end {
            i = end;
            continue;
        }
        // Its body is the first `{` before any `;` (a declaration without one).
        let mut open = name_end;
        while open < code.len() && code[open] != '{' && code[open] != ';' {
            open += 1;
        }
        if open < code.len() && code[open] == '{' {
            let mut depth = 0;
            let mut close = open;
            while close < code.len() {
                match code[close] {
                    '{' => depth += 1,
                    '}' => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    _ => {}
                }
                close += 1;
            }
            let first = line_of(i);
            let name = code[name_start..name_end].iter().collect();
            functions.push((name, first, line_of(close.min(code.len() - 1)) - first + 1));
        }
        i = name_end;
    }
    functions
}

#[test]
fn the_renderer_and_every_function_of_render_and_cli_stay_small() {
    // The busiest files of a round grow unless something holds them: `renderer.rs` keeps
    // the render and its accessors (each job in a room under `renderer/`), and no function
    // of `src/render/` or `src/cli/` takes more than a screen or two.
    let renderer = read("src/render/renderer.rs").lines().count();
    assert!(
        renderer <= RENDERER_MAX_LINES,
        "src/render/renderer.rs has {renderer} lines, more than {RENDERER_MAX_LINES}: give a job of it a room under src/render/renderer/"
    );
    let mut files = files_under("src/render", &[".rs"]);
    files.extend(files_under("src/cli", &[".rs"]));
    assert!(
        files.len() > 40,
        "src/render/ and src/cli/ not found: {files:?}"
    );
    let mut long = Vec::new();
    let mut seen = 0;
    for path in &files {
        for (name, line, lines) in functions_of(&read(path)) {
            seen += 1;
            if lines > FUNCTION_MAX_LINES {
                long.push(format!("{path}:{line} {name}: {lines} lines"));
            }
        }
    }
    assert!(seen > 400, "only {seen} functions found");
    assert!(
        long.is_empty(),
        "functions of more than {FUNCTION_MAX_LINES} lines (split them into steps):\n{}",
        long.join("\n")
    );
    // The doc says the same limits.
    let doc = read("docs/house.md");
    for limit in [
        format!("`src/render/renderer.rs` holds at most {RENDERER_MAX_LINES} lines"),
        format!(
            "no function of `src/render/` or `src/cli/` takes more than {FUNCTION_MAX_LINES} lines"
        ),
    ] {
        assert!(doc.contains(&limit), "docs/house.md does not say: {limit}");
    }
}

#[test]
fn the_function_scan_counts_code_braces_only() {
    let source = r##"
/// fn documented() { in a doc comment }
fn first(a: u32) -> u32 {
    let s = "}}} fn not_a_function() {";
    let r = r#"{"#;
    let c = '{';
    // }
    /* } fn also_not() { */
    a + 1
}

trait Shape {
    fn area(&self) -> f32;
    fn sides(&self) -> u32 {
        let call: fn(u32) -> u32 = |x| x;
        call(4)
    }
}

pub(crate) fn outer<'a>(x: &'a str) -> impl Fn() -> usize + 'a
where
    'a: 'a,
{
    fn inner() {}
    move || x.len()
}
"##;
    let functions = functions_of(source);
    let expected = [
        ("first", 3, 8),
        ("sides", 14, 4),
        ("outer", 20, 7),
        ("inner", 24, 1),
    ];
    let found: Vec<(&str, usize, usize)> = functions
        .iter()
        .map(|(name, line, lines)| (name.as_str(), *line, *lines))
        .collect();
    assert_eq!(found, expected);
    // A function of more than the limit is found as such.
    let long = format!(
        "fn long() {{\n{}}}\n",
        "    step();\n".repeat(FUNCTION_MAX_LINES)
    );
    assert_eq!(
        functions_of(&long),
        [("long".to_owned(), 1, FUNCTION_MAX_LINES + 2)]
    );
}

#[test]
fn no_import_circle_runs_between_two_folders() {
    // Modules by their path (`scene::error`) and their file; a `crate::` path names the
    // longest module it starts with (an item of `scene/mod.rs` is `scene`'s).
    let modules: BTreeMap<String, String> = files_under("src", &[".rs"])
        .into_iter()
        .map(|path| {
            let module = path
                .trim_start_matches("src/")
                .trim_end_matches(".rs")
                .trim_end_matches("/mod")
                .replace('/', "::");
            (module, path)
        })
        .collect();
    let resolve = |path: &str| -> Option<String> {
        let segments: Vec<&str> = path.split("::").collect();
        (1..=segments.len())
            .rev()
            .map(|n| segments[..n].join("::"))
            .find(|module| modules.contains_key(module))
    };
    // The imports of each module's own code (its tests aside).
    let mut edges: BTreeMap<&str, BTreeSet<String>> = BTreeMap::new();
    for (module, path) in &modules {
        let text = read(path);
        let text = match text.find("#[cfg(test)]\nmod") {
            Some(tests) => &text[..tests],
            None => &text,
        };
        let targets = crate_paths(&code_of(text))
            .iter()
            .filter_map(|p| resolve(p))
            .filter(|target| target != module)
            .collect();
        edges.insert(module.as_str(), targets);
    }
    // Strongly connected modules (Tarjan): a circle is a component of more than one; one
    // whose modules lie in more than one top-level folder is a circle between folders.
    struct Search<'a> {
        edges: &'a BTreeMap<&'a str, BTreeSet<String>>,
        index: BTreeMap<String, usize>,
        low: BTreeMap<String, usize>,
        stack: Vec<String>,
        components: Vec<Vec<String>>,
    }
    impl Search<'_> {
        fn visit(&mut self, module: &str) {
            let index = self.index.len();
            self.index.insert(module.to_owned(), index);
            self.low.insert(module.to_owned(), index);
            self.stack.push(module.to_owned());
            let targets = self.edges.get(module).cloned().unwrap_or_default();
            for target in &targets {
                if !self.index.contains_key(target) {
                    self.visit(target);
                    let low = self.low[module].min(self.low[target]);
                    self.low.insert(module.to_owned(), low);
                } else if self.stack.contains(target) {
                    let low = self.low[module].min(self.index[target]);
                    self.low.insert(module.to_owned(), low);
                }
            }
            if self.low[module] == self.index[module] {
                let mut component = Vec::new();
                while let Some(top) = self.stack.pop() {
                    let done = top == module;
                    component.push(top);
                    if done {
                        break;
                    }
                }
                self.components.push(component);
            }
        }
    }
    let mut search = Search {
        edges: &edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        components: Vec::new(),
    };
    for module in modules.keys() {
        if !search.index.contains_key(module) {
            search.visit(module);
        }
    }
    let folder = |module: &str| module.split("::").next().unwrap_or(module).to_owned();
    let between_folders: Vec<Vec<String>> = search
        .components
        .into_iter()
        .filter(|component| {
            let folders: BTreeSet<String> = component.iter().map(|m| folder(m)).collect();
            folders.len() > 1
        })
        .collect();
    assert!(
        between_folders.is_empty(),
        "modules of different folders import each other: {between_folders:?}"
    );
    // The search saw the imports (a few hundred between modules).
    let imports: usize = edges.values().map(BTreeSet::len).sum();
    assert!(imports > 300, "{imports} imports");
}

/// Each package's resolved features, as `cargo tree` prints them for `package` with the
/// dependency `edges` given: package name and version → the feature lists it is built with (a
/// package built for the host and for the target may have two).
fn resolved_features(package: &str, edges: &str) -> BTreeMap<String, BTreeSet<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = std::process::Command::new(cargo)
        .current_dir(root())
        .args([
            "tree",
            "--offline",
            "--locked",
            "--prefix",
            "none",
            "-p",
            package,
            "-e",
            edges,
        ])
        .args(["-f", "{p} [{f}]"])
        .output()
        .expect("cargo runs");
    assert!(
        output.status.success(),
        "cargo tree -p {package}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let mut packages: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in String::from_utf8_lossy(&output.stdout).lines() {
        let (Some(open), Some(close)) = (line.find(" ["), line.rfind(']')) else {
            continue;
        };
        // `syn v3.0.10`; a path package's `(/path)` is dropped with the rest.
        let name: String = line[..open]
            .split(' ')
            .take(2)
            .collect::<Vec<_>>()
            .join(" ");
        packages
            .entry(name)
            .or_default()
            .insert(line[open + 2..close].to_owned());
    }
    packages
}

#[test]
fn the_python_extension_resolves_the_features_vkpath_is_tested_with() {
    // python/test.sh builds the extension after `cargo test`: if pyo3 turned on a feature of a
    // crate vkpath uses that vkpath's own build leaves off, that crate and everything above it
    // (vkpath included, about 4 minutes of a 2-core CI) would compile a second time. Cargo.toml
    // names those features (once_cell, syn) so the two resolutions agree.
    let tested = resolved_features("vkpath", "normal,build,dev");
    let extension = resolved_features("vkpath-python", "normal,build");
    assert!(
        tested.keys().any(|name| name.starts_with("syn "))
            && extension.contains_key("vkpath v0.1.0"),
        "cargo tree's output was not read: {tested:?}"
    );
    let differing: Vec<String> = tested
        .iter()
        .filter_map(|(name, features)| {
            let other = extension.get(name)?;
            (other != features).then(|| format!("{name}: vkpath {features:?}, extension {other:?}"))
        })
        .collect();
    assert!(
        differing.is_empty(),
        "the extension's build resolves other features than vkpath's (name them in Cargo.toml): {differing:#?}"
    );
}
