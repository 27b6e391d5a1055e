//! "Paste anything": turns a file as people publish it (a whole ShaderToy tab, a WebGL page
//! shader, notes with just the functions) into GLSL that vkpath's kernels can include.
//!
//! What cannot take part is dropped, each with a note: `#version`, `#extension`, `#include`
//! and `#line` directives, `precision` statements, the entry points (`mainImage`, `main`, …),
//! uniform blocks. Global `uniform`/`in`/`out` variables become plain globals (samplers get
//! bindings that the kernels never use). A `struct triangle_t` identical to the workshop's
//! is dropped in favour of vkpath's; any other global name that vkpath's kernels declare
//! too is renamed `user_<name>` throughout the file, so that the user's code keeps calling
//! its own. ShaderToy's inputs (`iResolution`, `iFrame`, `iChannel0`, …) and
//! `gl_FragCoord`/`gl_FragColor` are supplied when the kept code reads them. The user's
//! macros are `#undef`ined before and after the file, so that they neither clash with
//! vkpath's nor leak into the kernel code that follows.
//!
//! The prepared text keeps every line where it was, so the compiler's line numbers are the
//! user's.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::sync::OnceLock;

use crate::contract::USER_OPAQUE_BINDING_FIRST;
use crate::glsl_intake::functions::{find_functions, FoundFunction, Signature};
use crate::glsl_intake::syntax::{
    matching, structural_tokens, tokenize, top_level_items, Item, ItemKind, Token,
};
use crate::shaders::GLSL_SOURCES;

/// Loop iterations the user's functions may run in one kernel invocation (all their loops
/// together) before their loops are ended and the call fails as an endless loop: below
/// llvmpipe's 65535, which would end a loop silently.
pub const USER_LOOP_LIMIT: u32 = 20_000;

/// Entry points of ShaderToy and page shaders: never judged, dropped.
const ENTRY_POINTS: [&str; 5] = ["mainImage", "main", "mainSound", "mainVR", "mainCubemap"];

/// Storage qualifiers of global variables that a compute kernel cannot take as they are.
const INTERFACE_QUALIFIERS: [&str; 6] = ["uniform", "in", "out", "varying", "attribute", "buffer"];

/// Qualifiers that may stand before an interface declaration's type.
const OTHER_QUALIFIERS: [&str; 9] = [
    "flat",
    "smooth",
    "noperspective",
    "centroid",
    "invariant",
    "highp",
    "mediump",
    "lowp",
    "precise",
];

/// ShaderToy's inputs with the declarations that supply them at frame 0 (the judged
/// functions should not depend on them); `iResolution`'s comes from
/// `IntakeOptions::resolution` (`resolution_declaration`). `iChannel0`–`3` are declared
/// separately (they need bindings).
const SHADERTOY_INPUTS: [(&str, &str); 10] = [
    ("iResolution", ""),
    ("iTime", "float iTime = 0.0;"),
    ("iTimeDelta", "float iTimeDelta = 1.0 / 60.0;"),
    ("iFrameRate", "float iFrameRate = 60.0;"),
    ("iFrame", "int iFrame = 0;"),
    ("iMouse", "vec4 iMouse = vec4(0.0);"),
    ("iDate", "vec4 iDate = vec4(2024.0, 0.0, 1.0, 0.0);"),
    ("iSampleRate", "float iSampleRate = 44100.0;"),
    (
        "iChannelResolution",
        "vec3 iChannelResolution[4] = vec3[4](vec3(1.0), vec3(1.0), vec3(1.0), vec3(1.0));",
    ),
    (
        "iChannelTime",
        "float iChannelTime[4] = float[4](0.0, 0.0, 0.0, 0.0);",
    ),
];

/// Fragment-shader built-ins that a compute kernel lacks, renamed to plain globals.
const FRAGMENT_BUILTINS: [(&str, &str, &str); 2] = [
    (
        "gl_FragCoord",
        "vkpath_FragCoord",
        "vec4 vkpath_FragCoord = vec4(0.5, 0.5, 0.5, 1.0);",
    ),
    (
        "gl_FragColor",
        "vkpath_FragColor",
        "vec4 vkpath_FragColor = vec4(0.0);",
    ),
];

/// A name the user's code reads that the intake cannot supply (a sampler or image uniform
/// whose data only the user's program has, ShaderToy's `iChannel0`–`3`, ray queries): the
/// code that reads it can be compiled only without it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Unavailable {
    /// The identifier.
    pub name: String,
    /// Where it is declared or first used (from 1).
    pub line: usize,
    /// What it is, in words ("uniform sampler2D u_scene").
    pub what: String,
}

/// A global `uniform` that plays the role of a workshop or ShaderToy constant and is given
/// its value (a plain global would be 0).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct UniformValue {
    /// The uniform's name.
    pub name: String,
    /// Its line (from 1).
    pub line: usize,
    /// The GLSL expression it is initialized with (e.g. `MAX_PATH_LENGTH`).
    pub value: String,
}

/// The user's file made ready to be included by vkpath's kernels.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PreparedSource {
    /// The file with what cannot take part blanked and clashing names renamed; every line
    /// where it was in the user's file.
    pub text: String,
    /// What was dropped, renamed or supplied, one line each ("line 3: ...").
    pub notes: Vec<String>,
    /// What goes before the text: `#undef`s of the user's macros and the supplied inputs.
    pub prelude: String,
    /// What goes after it: the user's macros undone, vkpath's redefined.
    pub epilogue: String,
    /// The user's `MAX_PATH_LENGTH` (a `#define` or an integer constant), if any.
    pub max_path_length: Option<u32>,
    /// Protected functions (`IntakeOptions::protected_functions`) that the file defines
    /// only with other parameters, renamed `user_<name>`: (name, line, the signature as
    /// written).
    pub renamed_functions: Vec<(String, usize, String)>,
    /// Whether the file's `triangle_t` differs from the workshop's (it is renamed
    /// `user_triangle_t`; functions taking it cannot be judged).
    pub other_triangle_struct: Option<usize>,
    /// What the kept code reads that cannot be supplied (only without
    /// `IntakeOptions::bind_opaque`): the declarations are dropped, and the caller leaves out
    /// the functions that read these names.
    pub unavailable: Vec<Unavailable>,
    /// Uniforms given the value of the constant they stand for (`IntakeOptions::uniform_values`).
    pub uniform_values: Vec<UniformValue>,
    /// The global `out` variables (type, name), made plain globals, in order: a page
    /// shader's colour output (`out vec4 fragColor;`).
    #[serde(default)]
    pub outputs: Vec<(String, String)>,
}

/// The global names that vkpath's own GLSL declares (functions, variables, constants,
/// structs) and its object-like macros with their values.
struct KernelNames {
    identifiers: BTreeSet<String>,
    macros: BTreeMap<String, String>,
    triangle_members: Vec<String>,
}

fn kernel_names() -> &'static KernelNames {
    static NAMES: OnceLock<KernelNames> = OnceLock::new();
    NAMES.get_or_init(|| {
        let mut identifiers = BTreeSet::new();
        let mut macros = BTreeMap::new();
        let mut triangle_members = Vec::new();
        for (file, text) in GLSL_SOURCES {
            if *file == crate::glsl_intake::USER_FUNCTIONS_FILE {
                continue;
            }
            let tokens = tokenize(text);
            for (name, value) in object_macros(&tokens) {
                macros.insert(name, value);
            }
            let structure = structural_tokens(&tokens);
            for item in top_level_items(&structure) {
                identifiers.extend(declared_names(&structure, &item));
                if let Some(members) = struct_members(&structure, &item, "triangle_t") {
                    triangle_members = members;
                }
            }
        }
        KernelNames {
            identifiers,
            macros,
            triangle_members,
        }
    })
}

/// `#define NAME value` directives without parameters: (name, value as written).
fn object_macros(tokens: &[Token]) -> Vec<(String, String)> {
    directives(tokens)
        .into_iter()
        .filter(|d| d.len() >= 3 && d[1].text == "define")
        .filter(|d| {
            d.get(3)
                .is_none_or(|t| t.text != "(" || t.start != d[2].end)
        })
        .map(|d| {
            let value: Vec<&str> = d[3..].iter().map(|t| t.text.as_str()).collect();
            (d[2].text.clone(), value.join(" "))
        })
        .collect()
}

/// The preprocessor directives of a token list, each as its tokens (`#` first).
fn directives(tokens: &[Token]) -> Vec<Vec<Token>> {
    let mut result: Vec<Vec<Token>> = Vec::new();
    for token in tokens.iter().filter(|t| t.in_directive) {
        if token.starts_directive || result.is_empty() {
            result.push(vec![token.clone()]);
        } else {
            result.last_mut().expect("not empty").push(token.clone());
        }
    }
    result
}

/// The names that a top-level item declares: a function's name, a struct's name, the
/// declarators of a variable declaration.
fn declared_names(tokens: &[Token], item: &Item) -> Vec<String> {
    if let Some(name) = item.name {
        return vec![tokens[name].text.clone()];
    }
    let items = &tokens[item.first..=item.last];
    let mut names = Vec::new();
    if items.first().is_some_and(|t| t.text == "precision") {
        return names;
    }
    if let Some(position) = items.iter().position(|t| t.text == "struct") {
        if let Some(name) = items.get(position + 1).filter(|t| t.is_identifier()) {
            names.push(name.text.clone());
        }
    }
    // Declarators: identifiers directly before `;`, `=`, `[` or `,` at bracket depth 0
    // (after the closing brace of a struct or block, if any).
    let body_end = items
        .iter()
        .rposition(|t| t.text == "}")
        .map_or(0, |i| i + 1);
    let mut depth = 0i32;
    for index in body_end..items.len() {
        match items[index].text.as_str() {
            "(" | "[" => depth += 1,
            ")" | "]" => depth -= 1,
            _ => {}
        }
        let ends = matches!(items[index].text.as_str(), ";" | "=" | "[" | ",");
        if ends && (depth == 0 || depth == 1 && items[index].text == "[") && index > body_end {
            let candidate = &items[index - 1];
            if candidate.is_identifier() && !is_type_keyword(&candidate.text) {
                names.push(candidate.text.clone());
            }
        }
    }
    names.dedup();
    names
}

/// Whether a word is a GLSL type or qualifier rather than a declared name.
fn is_type_keyword(word: &str) -> bool {
    INTERFACE_QUALIFIERS.contains(&word)
        || OTHER_QUALIFIERS.contains(&word)
        || matches!(word, "const" | "float" | "int" | "uint" | "bool" | "void")
}

/// The members of `struct <name> { ... };` as normalized lines ("vec3 positions [ 3 ]"), if
/// the item is that struct.
fn struct_members(tokens: &[Token], item: &Item, name: &str) -> Option<Vec<String>> {
    let items = &tokens[item.first..=item.last];
    let position = items.iter().position(|t| t.text == "struct")?;
    if items.get(position + 1)?.text != name || items.get(position + 2)?.text != "{" {
        return None;
    }
    let open = item.first + position + 2;
    let close = matching(tokens, open, "{", "}")?;
    let members = tokens[open + 1..close]
        .split(|t| t.text == ";")
        .filter(|member| !member.is_empty())
        .map(|member| {
            member
                .iter()
                .map(|t| t.text.as_str())
                .filter(|t| !matches!(*t, "highp" | "mediump" | "lowp"))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    Some(members)
}

/// An edit of the user's text: the byte range and what replaces it.
struct Edit {
    range: std::ops::Range<usize>,
    replacement: String,
}

/// Replaces a range by spaces, keeping its line breaks (so that lines stay where they are).
fn blank(text: &str, range: std::ops::Range<usize>) -> Edit {
    let replacement = text[range.clone()]
        .chars()
        .map(|c| if c == '\n' { '\n' } else { ' ' })
        .collect();
    Edit { range, replacement }
}

/// Applies non-overlapping edits (overlapping ones after the first are skipped).
fn apply(text: &str, mut edits: Vec<Edit>) -> String {
    edits.sort_by_key(|e| (e.range.start, e.range.end));
    let mut result = String::with_capacity(text.len());
    let mut position = 0;
    for edit in edits {
        if edit.range.start < position {
            continue;
        }
        result.push_str(&text[position..edit.range.start]);
        result.push_str(&edit.replacement);
        position = edit.range.end;
    }
    result.push_str(&text[position..]);
    result
}

/// What `prepare_with` keeps, supplies and protects.
#[derive(Clone, Debug, PartialEq)]
pub struct IntakeOptions {
    /// Keep the entry points (`mainImage`, `main`, …) instead of dropping them: a program
    /// that runs the user's passes needs them, `check` calls the functions itself.
    pub keep_entry_points: bool,
    /// Supply ShaderToy's inputs (`iResolution`, `iFrame`, `iChannel0`–`3`, …) and
    /// `gl_FragCoord`/`gl_FragColor` in the prelude when the kept code reads them (as
    /// `check` does: frame 0 of a 512 x 512 image). Without it the caller declares them.
    pub supply_inputs: bool,
    /// Guard every loop of the user's functions with `vkpath_loop_guard()` (see
    /// `USER_LOOP_LIMIT`); the guard's globals are declared in the prelude.
    pub guard_loops: bool,
    /// Rename the user's global names that vkpath's embedded kernels also declare
    /// `user_<name>` (needed when the user's code is included into vkpath's kernels).
    pub avoid_kernel_names: bool,
    /// Functions with a fixed signature (the workshop's): a file that defines one only with
    /// other parameters has it renamed `user_<name>` (listed in `renamed_functions`).
    pub protected_functions: Vec<(String, Signature)>,
    /// Keep the user's sampler and image uniforms, with bindings from
    /// `USER_OPAQUE_BINDING_FIRST + 4` on (the caller binds them). Without it (`check`) they
    /// are dropped and listed in `PreparedSource::unavailable`, with `iChannel0`–`3` and ray
    /// queries, for the caller to leave out the code that reads them.
    pub bind_opaque: bool,
    /// Give uniforms that stand for a constant its value (`PreparedSource::uniform_values`):
    /// an `int`/`uint` that bounds a loop or is named like a path length gets
    /// `MAX_PATH_LENGTH` (which the including code defines), a `vec2`/`vec3` resolution
    /// `iResolution`'s value, a frame counter 0 and a time 0.0, as `check` supplies
    /// ShaderToy's inputs.
    pub uniform_values: bool,
    /// The image size (width, height) in pixels that `iResolution` and the uniforms that
    /// stand for a resolution get: 512 x 512 for `check`'s functions, the render's size for a
    /// program that runs (`vkpath shadertoy`, check's `program` verdict).
    pub resolution: (u32, u32),
    /// Names that the including code declares itself (`vkpath shadertoy`'s pass kernel
    /// declares ShaderToy's inputs and `iChannel0`–`3`): the file's own declarations of them
    /// are dropped with a note (a page shader's `uniform vec3 iResolution;`), and they are
    /// neither supplied nor listed as unavailable.
    pub caller_declares: Vec<String>,
    /// Identifiers renamed throughout the file, (old, new): a page shader's `main` becomes a
    /// function that `vkpath shadertoy`'s kernel calls once per pixel.
    pub renames: Vec<(String, String)>,
    /// The including code declares the loop guard (`vkpath_loop_guard()` and its globals,
    /// see `LOOP_GUARD_NAMES`) once for several prepared files (a Common tab and a pass), so
    /// the prelude leaves it out.
    pub caller_declares_loop_guard: bool,
}

impl Default for IntakeOptions {
    /// What `check` does (`prepare`), without protected functions.
    fn default() -> IntakeOptions {
        IntakeOptions {
            keep_entry_points: false,
            supply_inputs: true,
            guard_loops: true,
            avoid_kernel_names: true,
            protected_functions: Vec::new(),
            bind_opaque: false,
            uniform_values: true,
            resolution: (512, 512),
            caller_declares: Vec::new(),
            renames: Vec::new(),
            caller_declares_loop_guard: false,
        }
    }
}

/// The globals the loop guard uses: its counter, its flag and the guard function that every
/// loop condition of the user's code calls (`IntakeOptions::guard_loops`).
pub const LOOP_GUARD_NAMES: [&str; 3] = [
    "g_user_loop_iterations",
    "g_user_loop_limit_hit",
    "vkpath_loop_guard",
];

/// The declarations of the loop guard with `limit` as the GLSL expression of the most
/// iterations one invocation's loops may run together (a `uint`; 0 is no limit): past it
/// every guarded loop ends and `g_user_loop_limit_hit` is set, for the kernel to report.
pub fn loop_guard_declarations(limit: &str) -> String {
    format!(
        "uint g_user_loop_iterations = 0u;\nbool g_user_loop_limit_hit = false;\n\
         bool vkpath_loop_guard() {{ if ({limit} != 0u && ++g_user_loop_iterations > {limit}) {{ \
         g_user_loop_limit_hit = true; return false; }} return true; }}\n"
    )
}

/// The declaration that supplies `iResolution` for an image of `(width, height)` pixels.
fn resolution_declaration((width, height): (u32, u32)) -> String {
    format!("vec3 iResolution = vec3({width}.0, {height}.0, 1.0);")
}

/// Prepares a user's file with `IntakeOptions::default()` (what `check` does, except that
/// `check` also protects the workshop functions; see the module documentation).
pub fn prepare(source: &str) -> PreparedSource {
    prepare_with(source, &IntakeOptions::default())
}

/// Prepares a user's file (see the module documentation and `IntakeOptions`): one job per
/// step of `Intake`.
pub fn prepare_with(source: &str, options: &IntakeOptions) -> PreparedSource {
    let mut intake = Intake::new(source, options);
    intake.read_directives();
    intake.drop_repeated_items();
    intake.read_top_level_items();
    let renames = intake.choose_renames();
    intake.rename(&renames);
    intake.guard_loops();
    intake.prepared.text = apply(source, std::mem::take(&mut intake.edits));
    intake.find_unavailable_names();
    intake.write_prelude();
    intake.write_epilogue();
    intake.prepared
}

/// Whether `token` lies in text that the intake blanked.
fn is_blanked(blanked: &[std::ops::Range<usize>], token: &Token) -> bool {
    // `blanked` is sorted and merged (`merged`): the one range that can hold the token is the
    // last that starts at or before it, so a 2 MB paste's thousands of dropped repeats cost a
    // binary search per token, not a scan.
    let after = blanked.partition_point(|r| r.start <= token.start);
    after > 0 && blanked[after - 1].contains(&token.start)
}

/// `ranges` sorted by start, with overlapping or nested ones merged (what `is_blanked` reads).
fn merged(mut ranges: Vec<std::ops::Range<usize>>) -> Vec<std::ops::Range<usize>> {
    ranges.sort_by_key(|r| r.start);
    let mut result: Vec<std::ops::Range<usize>> = Vec::with_capacity(ranges.len());
    for range in ranges {
        match result.last_mut() {
            Some(last) if range.start < last.end => last.end = last.end.max(range.end),
            _ => result.push(range),
        }
    }
    result
}

/// What identifies a top-level item among its repeats: a function definition by its name
/// and parameter list (GLSL rejects a second body for the same signature), anything else
/// by its whole text (a struct or global pasted twice, word for word).
fn repeat_key(tokens: &[Token], item: &Item) -> String {
    let end = match (&item.kind, item.name) {
        (&ItemKind::FunctionDefinition, Some(name)) => {
            matching(tokens, name + 1, "(", ")").unwrap_or(item.last)
        }
        _ => item.last,
    };
    let texts: Vec<&str> = tokens[item.first..=end]
        .iter()
        .map(|t| t.text.as_str())
        .collect();
    texts.join(" ")
}

/// A user's file on its way through `prepare_with`: what its steps read (the tokens, the
/// top-level items, the functions found) and what they add to (the edits, the blanked
/// ranges, the prepared source with its notes).
struct Intake<'a> {
    source: &'a str,
    options: &'a IntakeOptions,
    ours: &'static KernelNames,
    tokens: Vec<Token>,
    /// The tokens outside comments and directives.
    structure: Vec<Token>,
    items: Vec<Item>,
    found: Vec<FoundFunction>,
    /// Names that the conditions of the user's loops read.
    loop_bounds: BTreeSet<String>,
    prepared: PreparedSource,
    edits: Vec<Edit>,
    blanked: Vec<std::ops::Range<usize>>,
    /// The user's macros.
    user_macros: Vec<String>,
    /// The user's macros whose value is an integer literal (bounds of counted loops).
    macro_integers: BTreeMap<String, i64>,
    /// The global names the file declares, with the line of the first declaration.
    declared: BTreeMap<String, usize>,
    /// The identifiers the kept code reads.
    referenced: BTreeSet<String>,
}

impl<'a> Intake<'a> {
    /// Tokenizes `source` and finds its top-level items and functions.
    fn new(source: &'a str, options: &'a IntakeOptions) -> Intake<'a> {
        let tokens = tokenize(source);
        let structure = structural_tokens(&tokens);
        let items = top_level_items(&structure);
        let loop_bounds = loop_condition_names(&structure, &items, &ENTRY_POINTS);
        Intake {
            source,
            options,
            ours: kernel_names(),
            tokens,
            structure,
            items,
            found: find_functions(source),
            loop_bounds,
            prepared: PreparedSource::default(),
            edits: Vec::new(),
            blanked: Vec::new(),
            user_macros: Vec::new(),
            macro_integers: BTreeMap::new(),
            declared: BTreeMap::new(),
            referenced: BTreeSet::new(),
        }
    }

    /// Directives: keeps `#define` (and its kin), drops what a kernel cannot take.
    fn read_directives(&mut self) {
        for directive in directives(&self.tokens) {
            let Some(word) = directive.get(1) else {
                continue;
            };
            // To the end of the line: a directive dropped takes its trailing comment (or what
            // the tokenizer read as one, the `//` of `"file://bufferA.glsl"`) with it.
            let end = directive.last().expect("not empty").end;
            let end = self.source[end..]
                .find('\n')
                .map_or(self.source.len(), |at| end + at);
            let range = directive[0].start..end;
            match word.text.as_str() {
                "version" | "extension" | "include" | "line" => {
                    self.prepared.notes.push(format!(
                        "line {}: dropped #{} ({})",
                        word.line,
                        word.text,
                        match word.text.as_str() {
                            "version" => "vkpath compiles GLSL 4.60 for Vulkan",
                            "extension" => "vkpath enables what its kernels need",
                            "include" => "the tabs given on the command line are all that is read; a Common tab given first is put before every tab",
                            _ => "line numbers stay your file's",
                        }
                    ));
                    self.blanked.push(range.clone());
                    self.edits.push(blank(self.source, range));
                }
                word if word.starts_with("iChannel") => {
                    self.prepared.notes.push(format!(
                        "line {}: dropped #{word} (VS Code Shader Toy's channel wiring: read to wire the channel, not compiled)",
                        directive[1].line
                    ));
                    self.blanked.push(range.clone());
                    self.edits.push(blank(self.source, range));
                }
                "undef" | "if" | "ifdef" | "ifndef" | "else" | "elif" | "endif" | "error"
                | "pragma" | "" => {}
                "define" => {
                    if let Some(name) = directive.get(2) {
                        self.user_macros.push(name.text.clone());
                        let value: Vec<&str> =
                            directive[3..].iter().map(|t| t.text.as_str()).collect();
                        if let Some(number) = integer_value(&value.join("")) {
                            self.macro_integers.insert(name.text.clone(), number);
                        }
                        if name.text == "MAX_PATH_LENGTH" {
                            self.prepared.max_path_length =
                                value.join("").trim_end_matches('u').parse().ok();
                        }
                    }
                }
                other => {
                    self.prepared.notes.push(format!(
                        "line {}: dropped #{other} (not a GLSL directive)",
                        word.line
                    ));
                    self.blanked.push(range.clone());
                    self.edits.push(blank(self.source, range));
                }
            }
        }
    }

    /// Repeats: a function defined again with the same parameters, or a struct or global
    /// pasted again word for word, is dropped with one note per item ("defined 90 times;
    /// judged the first"), so that a paste of the helpers repeated is compiled (and judged)
    /// once, whatever its size.
    fn drop_repeated_items(&mut self) {
        // (index of the first item, its line, the lines of the repeats) by key.
        let mut firsts: BTreeMap<String, usize> = BTreeMap::new();
        let mut repeats: Vec<(usize, Vec<usize>)> = Vec::new();
        let mut kept = Vec::with_capacity(self.items.len());
        for item in std::mem::take(&mut self.items) {
            let is_repeatable = item.kind == ItemKind::FunctionDefinition
                || self.structure[item.last].text == ";"
                    && item.last > item.first
                    && self.structure[item.first].text != "precision";
            if !is_repeatable {
                kept.push(item);
                continue;
            }
            let key = repeat_key(&self.structure, &item);
            match firsts.get(&key) {
                Some(&at) => {
                    let range = self.structure[item.first].start..self.structure[item.last].end;
                    repeats[at].1.push(self.structure[item.first].line);
                    self.blanked.push(range.clone());
                    self.edits.push(blank(self.source, range));
                }
                None => {
                    firsts.insert(key, repeats.len());
                    repeats.push((kept.len(), Vec::new()));
                    kept.push(item);
                }
            }
        }
        for (at, lines) in &repeats {
            if lines.is_empty() {
                continue;
            }
            let item = &kept[*at];
            let first = &self.structure[item.first];
            let what = match item.name {
                Some(name) => format!("{}()", self.structure[name].text),
                None => self.structure[item.first..=item.last]
                    .iter()
                    .take_while(|t| !["{", "=", ";"].contains(&t.text.as_str()))
                    .map(|t| t.text.as_str())
                    .collect::<Vec<_>>()
                    .join(" "),
            };
            let last = lines.last().expect("not empty");
            let (verb, kept_word) = match item.kind {
                ItemKind::FunctionDefinition => ("defined", "judged"),
                _ => ("written", "kept"),
            };
            self.prepared.notes.push(format!(
                "line {}: {what} is {verb} {} times (the last at line {last}); {kept_word} the first, the other {} dropped",
                first.line,
                lines.len() + 1,
                lines.len()
            ));
        }
        self.items = kept;
        let blanked = self.blanked.clone();
        self.found
            .retain(|f| !blanked.iter().any(|r| r.contains(&f.span.start)));
    }

    /// Top-level items: entry points, precision statements, interface variables, the
    /// triangle struct; collects what the file declares.
    fn read_top_level_items(&mut self) {
        let mut opaque_bindings = 0u32;

        for item in &self.items {
            let first = &self.structure[item.first];
            let range = first.start..self.structure[item.last].end;
            if let Some(name) = item.name {
                let name_text = &self.structure[name].text;
                if ENTRY_POINTS.contains(&name_text.as_str()) && !self.options.keep_entry_points {
                    if item.kind == ItemKind::FunctionDefinition {
                        self.prepared.notes.push(format!(
                            "line {}: dropped {name_text}() (the entry point; vkpath's kernels call your functions)",
                            self.structure[name].line
                        ));
                    }
                    self.blanked.push(range.clone());
                    self.edits.push(blank(self.source, range));
                    continue;
                }
                self.declared
                    .entry(name_text.clone())
                    .or_insert(self.structure[name].line);
                continue;
            }
            if first.text == "precision" {
                self.blanked.push(range.clone());
                self.edits.push(blank(self.source, range));
                continue;
            }
            // vkpath's kernels declare their own triangle_t; a program that runs on its own
            // (`avoid_kernel_names` off) keeps the user's.
            let triangle = struct_members(&self.structure, item, "triangle_t")
                .filter(|_| self.options.avoid_kernel_names);
            if let Some(members) = triangle {
                if members == self.ours.triangle_members {
                    self.prepared.notes.push(format!(
                        "line {}: your struct triangle_t is the workshop's; vkpath's declaration is used",
                        first.line
                    ));
                    self.blanked.push(range.clone());
                    self.edits.push(blank(self.source, range));
                    continue;
                }
                self.prepared.other_triangle_struct = Some(first.line);
            }
            let names_declared = declared_names(&self.structure, item);
            if let Some(name) = names_declared
                .iter()
                .find(|n| self.options.caller_declares.contains(n))
            {
                self.prepared.notes.push(format!(
                    "line {}: dropped your declaration of {name} (vkpath supplies it, as ShaderToy does)",
                    first.line
                ));
                self.blanked.push(range.clone());
                self.edits.push(blank(self.source, range));
                continue;
            }
            let tokens_of_item = &self.structure[item.first..=item.last];
            let mut position = 0;
            let mut interface = None;
            while position < tokens_of_item.len() {
                let text = tokens_of_item[position].text.as_str();
                if text == "layout" {
                    match matching(tokens_of_item, position + 1, "(", ")") {
                        Some(close) => position = close + 1,
                        None => break,
                    }
                } else if INTERFACE_QUALIFIERS.contains(&text) {
                    interface = Some(text.to_string());
                    position += 1;
                } else if OTHER_QUALIFIERS.contains(&text) || text == "const" {
                    position += 1;
                } else {
                    break;
                }
            }
            if let Some(qualifier) = interface {
                let type_token = tokens_of_item.get(position);
                let is_block = tokens_of_item.iter().any(|t| t.text == "{");
                let is_opaque = type_token.is_some_and(|t| is_opaque_type(&t.text));
                // `layout(local_size_x = 8) in;` declares no variable.
                let no_variable = type_token.is_none_or(|t| t.text == ";");
                if is_block || no_variable || is_opaque && qualifier != "uniform" {
                    self.prepared.notes.push(format!(
                        "line {}: dropped the {qualifier} declaration{}",
                        first.line,
                        if is_block { " block" } else { "" }
                    ));
                    self.blanked.push(range.clone());
                    self.edits.push(blank(self.source, range));
                    continue;
                }
                let qualifiers = first.start..tokens_of_item[position].start;
                let declarators = declared_names(&self.structure, item);
                let interface_at = tokens_of_item
                    .iter()
                    .position(|t| INTERFACE_QUALIFIERS.contains(&t.text.as_str()))
                    .unwrap_or(0);
                let written = tokens_of_item[interface_at..]
                    .iter()
                    .take_while(|t| t.text != ";" && t.text != "=")
                    .map(|t| t.text.as_str())
                    .collect::<Vec<_>>()
                    .join(" ");
                if is_opaque && !self.options.bind_opaque {
                    let what = tokens_of_item[position - 1..]
                        .iter()
                        .take_while(|t| t.text != ";")
                        .map(|t| t.text.as_str())
                        .collect::<Vec<_>>()
                        .join(" ");
                    self.prepared.notes.push(format!(
                        "line {}: dropped '{written}' (check has no data for it): functions that read it are not judged",
                        first.line
                    ));
                    for name in &declarators {
                        self.prepared.unavailable.push(Unavailable {
                            name: name.clone(),
                            line: first.line,
                            what: what.replace(" ,", ","),
                        });
                    }
                    self.blanked.push(range.clone());
                    self.edits.push(blank(self.source, range));
                    continue;
                }
                let type_text = type_token.map_or("", |t| t.text.as_str());
                let role = (self.options.uniform_values
                    && qualifier == "uniform"
                    && declarators.len() == 1)
                    .then(|| {
                        uniform_role(type_text, &declarators[0], &self.loop_bounds, self.options)
                    })
                    .flatten();
                if let Some(value) = role {
                    let name = &declarators[0];
                    let end = tokens_of_item.last().map_or(range.end, |t| t.start);
                    self.edits.push(Edit {
                        range: qualifiers.clone(),
                        replacement: "const ".into(),
                    });
                    self.edits.push(Edit {
                        range: end..end,
                        replacement: format!(" = {value}"),
                    });
                    self.prepared.notes.push(format!(
                        "line {}: 'uniform {type_text} {name}' is {} here ({})",
                        first.line,
                        value_in_words(&value, self.prepared.max_path_length, name),
                        role_in_words(&value)
                    ));
                    self.prepared.uniform_values.push(UniformValue {
                        name: name.clone(),
                        line: first.line,
                        value,
                    });
                } else if is_opaque {
                    let binding = USER_OPAQUE_BINDING_FIRST + 4 + opaque_bindings;
                    opaque_bindings += 1;
                    self.edits.push(Edit {
                        range: qualifiers,
                        replacement: format!("layout(set = 0, binding = {binding}) uniform "),
                    });
                } else {
                    if qualifier == "out" && declarators.len() == 1 {
                        self.prepared
                            .outputs
                            .push((type_text.to_string(), declarators[0].clone()));
                    }
                    self.prepared.notes.push(format!(
                        "line {}: '{}' is a plain global here (no {qualifier} in a compute kernel{})",
                        first.line,
                        tokens_of_item[position..]
                            .iter()
                            .take_while(|t| t.text != ";" && t.text != "=")
                            .map(|t| t.text.as_str())
                            .collect::<Vec<_>>()
                            .join(" "),
                        if qualifier == "uniform" {
                            "; it is 0"
                        } else {
                            ""
                        }
                    ));
                    self.edits.push(blank(self.source, qualifiers));
                }
            }
            for name in declared_names(&self.structure, item) {
                self.declared.entry(name).or_insert(first.line);
            }
            if self.prepared.max_path_length.is_none() {
                // const int MAX_PATH_LENGTH = 5;
                let texts: Vec<&str> = tokens_of_item.iter().map(|t| t.text.as_str()).collect();
                if let Some(at) = texts.iter().position(|t| *t == "MAX_PATH_LENGTH") {
                    if texts.get(at + 1) == Some(&"=") {
                        self.prepared.max_path_length = texts
                            .get(at + 2)
                            .and_then(|v| v.trim_end_matches('u').parse().ok());
                    }
                }
            }
        }
    }

    /// Names that clash with vkpath's: workshop functions with other parameters, a
    /// different `triangle_t`, and any other global name the kernels declare too; returns
    /// each with its new name.
    fn choose_renames(&mut self) -> BTreeMap<String, String> {
        let mut renames: BTreeMap<String, String> = self.options.renames.iter().cloned().collect();
        for (function, signature) in &self.options.protected_functions {
            let definitions: Vec<_> = self
                .found
                .iter()
                .filter(|f| f.has_body && f.name == *function)
                .collect();
            let any_protected = definitions.iter().any(|f| f.signature == *signature);
            if !definitions.is_empty() && !any_protected {
                for definition in &definitions {
                    self.prepared.renamed_functions.push((
                        function.clone(),
                        definition.line,
                        definition.signature.to_string(),
                    ));
                }
                renames.insert(function.clone(), format!("user_{function}"));
            }
        }
        if let Some(line) = self.prepared.other_triangle_struct {
            self.prepared.notes.push(format!(
                "line {line}: your struct triangle_t differs from the workshop's; it is renamed user_triangle_t, and functions that take it cannot be judged"
            ));
            renames.insert("triangle_t".into(), "user_triangle_t".into());
        }
        for (name, line) in &self.declared {
            let is_protected = self
                .options
                .protected_functions
                .iter()
                .any(|(f, _)| f == name);
            if self.options.avoid_kernel_names
                && !is_protected
                && name != "triangle_t"
                && (self.ours.identifiers.contains(name) || self.ours.macros.contains_key(name))
                && !self.user_macros.contains(name)
            {
                self.prepared.notes.push(format!(
                    "line {line}: your {name} is renamed user_{name} (vkpath's kernels declare a {name} of their own)"
                ));
                renames.insert(name.clone(), format!("user_{name}"));
            }
        }

        renames
    }

    /// Renames (`renames`) and fragment built-ins, everywhere except in blanked text;
    /// notes the identifiers the kept code reads.
    fn rename(&mut self, renames: &BTreeMap<String, String>) {
        self.blanked = merged(std::mem::take(&mut self.blanked));
        for token in self
            .tokens
            .iter()
            .filter(|t| t.is_identifier() && !is_blanked(&self.blanked, t))
        {
            if let Some(new_name) = renames.get(&token.text) {
                self.edits.push(Edit {
                    range: token.start..token.end,
                    replacement: new_name.clone(),
                });
            } else if let Some((_, replacement, _)) = FRAGMENT_BUILTINS
                .iter()
                .find(|(name, _, _)| *name == token.text)
            {
                self.edits.push(Edit {
                    range: token.start..token.end,
                    replacement: replacement.to_string(),
                });
            }
            self.referenced.insert(token.text.clone());
        }
    }

    /// Guards the loops of the user's functions (`IntakeOptions::guard_loops`).
    fn guard_loops(&mut self) {
        // Every loop of the user's functions gets a guard in its condition: an endless loop ends
        // after USER_LOOP_LIMIT iterations, and the kernel knows it (llvmpipe would end it
        // silently after 65535 and return whatever the function had). A counted loop (a counter
        // from a constant to a constant, see `is_counted_loop`) cannot run without end and is left
        // as it is: a guard in its condition keeps the compiler from unrolling it, which made the
        // workshop's Exercise 7 tab (its loop over 30 triangles in a local array) about 50 times
        // slower on lavapipe (`vkpath shadertoy`, 128 x 128: 0.3 against 14.5 frames/s).
        for item in self
            .items
            .iter()
            .filter(|i| i.kind == ItemKind::FunctionDefinition && self.options.guard_loops)
        {
            if self
                .blanked
                .iter()
                .any(|r| r.contains(&self.structure[item.first].start))
            {
                continue;
            }
            for index in item.first..item.last {
                let keyword = self.structure[index].text.as_str();
                if !(keyword == "for" || keyword == "while")
                    || self.structure.get(index + 1).is_none_or(|t| t.text != "(")
                {
                    continue;
                }
                let Some(close) = matching(&self.structure, index + 1, "(", ")") else {
                    continue;
                };
                let (start, end) = if keyword == "while" {
                    (self.structure[index + 1].end, self.structure[close].start)
                } else {
                    // The condition of for (init; condition; increment)
                    let mut depth = 0i32;
                    let semicolons: Vec<usize> = (index + 1..close)
                        .filter(|&i| {
                            match self.structure[i].text.as_str() {
                                "(" => depth += 1,
                                ")" => depth -= 1,
                                _ => {}
                            }
                            depth == 1 && self.structure[i].text == ";"
                        })
                        .collect();
                    let [first, second] = semicolons[..] else {
                        continue;
                    };
                    if second == first + 1 {
                        self.edits.push(Edit {
                            range: self.structure[first].end..self.structure[first].end,
                            replacement: " vkpath_loop_guard()".into(),
                        });
                        continue;
                    }
                    let is_constant = |name: &str| {
                        self.user_macros.iter().any(|m| m == name)
                            || self.ours.macros.contains_key(name)
                            || self.prepared.uniform_values.iter().any(|u| u.name == name)
                    };
                    let value_of = |word: &str| {
                        integer_value(word).or_else(|| self.macro_integers.get(word).copied())
                    };
                    let constants = Constants {
                        is_constant: &is_constant,
                        value_of: &value_of,
                    };
                    if is_counted_loop(&self.structure, index + 1, first, second, close, &constants)
                    {
                        continue;
                    }
                    (self.structure[first].end, self.structure[second].start)
                };
                self.edits.push(Edit {
                    range: start..start,
                    replacement: "vkpath_loop_guard() && (".into(),
                });
                self.edits.push(Edit {
                    range: end..end,
                    replacement: ")".into(),
                });
            }
        }
    }

    /// Names the kept code reads that check cannot supply: ray queries, and ShaderToy's
    /// channels where no caller binds them.
    fn find_unavailable_names(&mut self) {
        self.blanked = merged(std::mem::take(&mut self.blanked));
        if !self.options.bind_opaque {
            let mut seen = BTreeSet::new();
            for token in self
                .tokens
                .iter()
                .filter(|t| t.is_identifier() && !is_blanked(&self.blanked, t))
            {
                let what = if token.text.starts_with("rayQuery") {
                    "ray queries (GL_EXT_ray_query), which vkpath cannot run".to_string()
                } else if token.text.len() == 9
                    && token.text.starts_with("iChannel")
                    && !self.declared.contains_key(&token.text)
                    && !self.options.caller_declares.contains(&token.text)
                {
                    format!("ShaderToy's {}, whose data check does not have", token.text)
                } else {
                    continue;
                };
                if seen.insert(token.text.clone()) {
                    self.prepared.unavailable.push(Unavailable {
                        name: token.text.clone(),
                        line: token.line,
                        what,
                    });
                }
            }
        }
    }

    /// The prelude: undefines the user's macros, supplies what the kept code reads, and
    /// declares the guard of the user's loops.
    fn write_prelude(&mut self) {
        let mut prelude = String::new();
        if self.options.guard_loops && !self.options.caller_declares_loop_guard {
            prelude = loop_guard_declarations(&format!("{USER_LOOP_LIMIT}u"));
        }
        let unique_macros: BTreeSet<&String> = self.user_macros.iter().collect();
        for name in &unique_macros {
            let _ = writeln!(prelude, "#undef {name}");
        }
        let mut supplied = Vec::new();
        for (name, declaration) in SHADERTOY_INPUTS {
            if self.options.supply_inputs
                && self.referenced.contains(name)
                && !self.declared.contains_key(name)
                && !unique_macros.contains(&name.to_string())
                && !self.options.caller_declares.iter().any(|n| n == name)
            {
                if name == "iResolution" {
                    let _ = writeln!(
                        prelude,
                        "{}",
                        resolution_declaration(self.options.resolution)
                    );
                } else {
                    let _ = writeln!(prelude, "{declaration}");
                }
                supplied.push(name);
            }
        }
        for channel in 0..4u32 {
            let name = format!("iChannel{channel}");
            if self.options.supply_inputs
                && self.options.bind_opaque
                && self.referenced.contains(&name)
                && !self.declared.contains_key(&name)
            {
                let _ = writeln!(
                    prelude,
                    "layout(set = 0, binding = {}) uniform sampler2D {name};",
                    USER_OPAQUE_BINDING_FIRST + channel
                );
                supplied.push(match channel {
                    0 => "iChannel0",
                    1 => "iChannel1",
                    2 => "iChannel2",
                    _ => "iChannel3",
                });
            }
        }
        for (name, _, declaration) in FRAGMENT_BUILTINS {
            if self.options.supply_inputs && self.referenced.contains(name) {
                let _ = writeln!(prelude, "{declaration}");
                supplied.push(name);
            }
        }
        if self.referenced.contains("texture2D")
            && !unique_macros.contains(&"texture2D".to_string())
        {
            prelude.push_str("#define texture2D texture\n");
            self.user_macros.push("texture2D".into());
        }
        if !supplied.is_empty() {
            let (width, height) = self.options.resolution;
            self.prepared.notes.push(format!(
                "supplied for your code: {} (ShaderToy's inputs at frame 0 of a {width} x {height} image)",
                supplied.join(", ")
            ));
        }
        self.prepared.prelude = prelude;
    }

    /// The epilogue: the user's macros end with the file; vkpath's come back.
    fn write_epilogue(&mut self) {
        let mut epilogue = String::from("\n");
        let unique_macros: BTreeSet<&String> = self.user_macros.iter().collect();
        for name in unique_macros {
            let _ = writeln!(epilogue, "#undef {name}");
            if let Some(value) = self.ours.macros.get(name.as_str()) {
                let _ = writeln!(epilogue, "#define {name} {value}");
            }
        }
        self.prepared.epilogue = epilogue;
    }
}

/// Most iterations of a loop that `is_counted_loop` leaves unguarded: the workshop's loops
/// over triangles (30), path vertices and samples, far below llvmpipe's limit even nested.
const COUNTED_LOOP_MAX: i64 = 256;

/// An integer literal's value (`30`, `8u`, `0x10`), if the text is one.
fn integer_value(text: &str) -> Option<i64> {
    let digits = text.trim_end_matches(['u', 'U']);
    match digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
    {
        Some(hex) => i64::from_str_radix(hex, 16).ok(),
        None => digits.parse().ok(),
    }
}

/// What `is_counted_loop` knows of the names in a loop header.
struct Constants<'a> {
    /// Whether a name is a constant (a macro, a constant the intake gave a uniform).
    is_constant: &'a dyn Fn(&str) -> bool,
    /// The integer value of a literal or of a macro whose value is one.
    value_of: &'a dyn Fn(&str) -> Option<i64>,
}

/// Whether the `for` loop whose parentheses are `tokens[open]`..`tokens[close]` (with its two
/// semicolons at `first` and `second`) is a counted loop, which ends after a number of
/// iterations fixed by constants: `for ([int|uint] i = A; i < B; i++)` with `<`/`<=` and an
/// increment (`i++`, `++i`, `i += k`) or `>` and a decrement, or `i != B` with a step of one
/// towards B (the workshop's `for (int i = 0; i != TRIANGLE_COUNT; ++i)`); A, B and k integer
/// literals or macros with such values, at most `COUNTED_LOOP_MAX` iterations; and `i` not
/// written in the loop's body.
fn is_counted_loop(
    tokens: &[Token],
    open: usize,
    first: usize,
    second: usize,
    close: usize,
    constants: &Constants,
) -> bool {
    let is_constant = constants.is_constant;
    let texts = |range: std::ops::Range<usize>| operator_texts(&tokens[range]);
    let constant = |word: &str| word.starts_with(|c: char| c.is_ascii_digit()) || is_constant(word);
    let init = texts(open + 1..first);
    let init: Vec<&str> = init.iter().map(String::as_str).collect();
    let init: &[&str] = match init.first() {
        Some(&"int" | &"uint") => &init[1..],
        _ => &init,
    };
    let [counter, "=", start] = init else {
        return false;
    };
    let condition = texts(first + 1..second);
    let condition: Vec<&str> = condition.iter().map(String::as_str).collect();
    let [name, comparison, bound] = condition[..] else {
        return false;
    };
    // Not `>=`: an unsigned counter is always >= 0, and `for (uint i = n; i >= 0u; i--)` has
    // no end.
    let step = texts(second + 1..close);
    let step: Vec<&str> = step.iter().map(String::as_str).collect();
    let (step_upwards, unit_step) = match step[..] {
        [n, "++"] | ["++", n] if n == *counter => (true, true),
        [n, "--"] | ["--", n] if n == *counter => (false, true),
        [n, "+=", k] if n == *counter && constant(k) => (true, false),
        [n, "-=", k] if n == *counter && constant(k) => (false, false),
        _ => return false,
    };
    let upwards = match comparison {
        "<" | "<=" => true,
        ">" => false,
        // Counting one by one from A to B reaches B when B lies that way.
        "!=" if unit_step => {
            let (Some(a), Some(b)) = ((constants.value_of)(start), (constants.value_of)(bound))
            else {
                return false;
            };
            if step_upwards {
                a <= b
            } else {
                a >= b
            }
        }
        _ => return false,
    };
    if name != *counter || upwards != step_upwards || !constant(start) || !constant(bound) {
        return false;
    }
    // Few iterations, known from the values: an unguarded loop is not counted towards the
    // guard's limit, so a long one could still reach llvmpipe's.
    let value = |word: &str| (constants.value_of)(word);
    let step_size = match step[..] {
        [_, "+=" | "-=", k] => value(k),
        _ => Some(1),
    };
    let (Some(a), Some(b), Some(k)) = (value(start), value(bound), step_size) else {
        return false;
    };
    if k <= 0 || (b - a).abs() / k > COUNTED_LOOP_MAX {
        return false;
    }
    // The body: a block, or one statement.
    let body_end = match tokens.get(close + 1).map(|t| t.text.as_str()) {
        Some("{") => matching(tokens, close + 1, "{", "}"),
        _ => tokens[close + 1..]
            .iter()
            .position(|t| t.text == ";")
            .map(|p| close + 1 + p),
    };
    let Some(body_end) = body_end else {
        return false;
    };
    const WRITES: [&str; 13] = [
        "=", "+=", "-=", "*=", "/=", "%=", "++", "--", "<<=", ">>=", "&=", "|=", "^=",
    ];
    let body = texts(close + 1..body_end + 1);
    !(0..body.len()).any(|i| {
        body[i] == *counter
            && (body
                .get(i + 1)
                .is_some_and(|t| WRITES.contains(&t.as_str()))
                || i > 0 && (body[i - 1] == "++" || body[i - 1] == "--"))
    })
}

/// The texts of `tokens` with adjacent operator characters joined (the tokenizer gives one
/// token per punctuation character: `+`, `+` become `++`, `!`, `=` become `!=`).
fn operator_texts(tokens: &[Token]) -> Vec<String> {
    const OPERATOR: &str = "+-*/%<>=!&|^";
    let is_operator = |t: &Token| t.text.len() == 1 && OPERATOR.contains(t.text.as_str());
    let mut texts: Vec<String> = Vec::new();
    for (index, token) in tokens.iter().enumerate() {
        let joins = index > 0
            && is_operator(token)
            && is_operator(&tokens[index - 1])
            && tokens[index - 1].end == token.start;
        match texts.last_mut() {
            Some(last) if joins => last.push_str(&token.text),
            _ => texts.push(token.text.clone()),
        }
    }
    texts
}

/// The identifiers that stand in the loop conditions (`for (…; condition; …)`, `while
/// (condition)`) of the functions other than `excluded` (the entry points, which are not
/// kept).
fn loop_condition_names(tokens: &[Token], items: &[Item], excluded: &[&str]) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    for item in items
        .iter()
        .filter(|i| i.kind == ItemKind::FunctionDefinition)
    {
        if item
            .name
            .is_some_and(|n| excluded.contains(&tokens[n].text.as_str()))
        {
            continue;
        }
        for index in item.first..item.last {
            let keyword = tokens[index].text.as_str();
            if !(keyword == "for" || keyword == "while")
                || tokens.get(index + 1).is_none_or(|t| t.text != "(")
            {
                continue;
            }
            let Some(close) = matching(tokens, index + 1, "(", ")") else {
                continue;
            };
            let inside = &tokens[index + 2..close];
            let condition: &[Token] = if keyword == "for" {
                let parts: Vec<&[Token]> = inside.split(|t| t.text == ";").collect();
                parts.get(1).copied().unwrap_or(&[])
            } else {
                inside
            };
            names.extend(
                condition
                    .iter()
                    .filter(|t| t.is_identifier())
                    .map(|t| t.text.clone()),
            );
        }
    }
    names
}

/// The value of a uniform that stands for a constant, by its type and name: an integer that
/// bounds a loop or is named like a path length is `MAX_PATH_LENGTH`; a `vec2`/`vec3`
/// resolution is `options.resolution` where the image's size is known; where the intake
/// supplies ShaderToy's inputs (check) a frame counter is `iFrame`'s 0 and a time `iTime`'s
/// 0.0. Constant expressions, as a global's initializer must be.
fn uniform_role(
    type_name: &str,
    name: &str,
    loop_bounds: &BTreeSet<String>,
    options: &IntakeOptions,
) -> Option<String> {
    let (width, height) = options.resolution;
    // The image's size is known where the intake supplies ShaderToy's inputs or the
    // including code declares iResolution (a program that runs); the frame and the time
    // only where they are constants (check's frame 0).
    let inputs = options.supply_inputs;
    let resolution_known = inputs || options.caller_declares.iter().any(|n| n == "iResolution");
    let lower = name.to_lowercase();
    let named = |words: &[&str]| words.iter().any(|w| lower.contains(w));
    let value = match type_name {
        "int" | "uint" if named(&["frame"]) => format!("{type_name}(0)"),
        // A loop bound that is named like a count of things (triangles, samples, lights) is
        // not a path length.
        "int" | "uint"
            if loop_bounds.contains(name)
                && !named(&["count", "num", "sample", "spp", "triangle", "light", "size"])
                || named(&["pathlength", "path_length", "bounce", "depth", "maxpath"]) =>
        {
            return Some(format!("{type_name}(MAX_PATH_LENGTH)"));
        }
        "vec2" if named(&["resolution"]) && resolution_known => {
            return Some(format!("vec2({width}.0, {height}.0)"));
        }
        "vec3" if named(&["resolution"]) && resolution_known => {
            return Some(format!("vec3({width}.0, {height}.0, 1.0)"));
        }
        "float" if named(&["frame"]) || named(&["time"]) => "0.0".into(),
        _ => return None,
    };
    inputs.then_some(value)
}

/// A uniform's value in words, for its note.
fn value_in_words(value: &str, max_path_length: Option<u32>, name: &str) -> String {
    if value.contains("MAX_PATH_LENGTH") {
        let length = max_path_length.unwrap_or(crate::contract::DEFAULT_MAX_PATH_LENGTH);
        format!("MAX_PATH_LENGTH = {length}")
    } else if name.to_lowercase().contains("resolution") {
        format!("{value} (the image's size, as iResolution)")
    } else {
        format!("{value}, as at frame 0 and time 0,")
    }
}

/// What the uniform was taken for, for its note.
fn role_in_words(value: &str) -> &'static str {
    if value.contains("MAX_PATH_LENGTH") {
        "an integer uniform that bounds a loop or is named like a path length plays the workshop's MAX_PATH_LENGTH; a plain global would be 0"
    } else {
        "its name says what it holds; a plain global would be 0"
    }
}

/// Every global name that `source` declares: functions, structs, variables and constants,
/// and its macros.
pub fn declared_globals(source: &str) -> BTreeSet<String> {
    let tokens = tokenize(source);
    let mut names: BTreeSet<String> = directives(&tokens)
        .into_iter()
        .filter(|d| d.len() >= 3 && d[1].text == "define")
        .map(|d| d[2].text.clone())
        .collect();
    let structure = structural_tokens(&tokens);
    for item in top_level_items(&structure) {
        names.extend(declared_names(&structure, &item));
    }
    names
}

/// Whether a GLSL type is opaque (a sampler, image or the like), which only a uniform with
/// a binding can hold.
fn is_opaque_type(word: &str) -> bool {
    [
        "sampler",
        "isampler",
        "usampler",
        "image",
        "iimage",
        "uimage",
        "texture",
        "itexture",
        "utexture",
        "subpassInput",
        "atomic_uint",
        "accelerationStructure",
        "rayQuery",
    ]
    .iter()
    .any(|prefix| word.starts_with(prefix))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TAB: &str = "#version 300 es\nprecision highp float;\n#define M_PI 3.141592653589793238462643\n\
        #define MAX_PATH_LENGTH 4\nuniform vec2 u_resolution;\nuniform sampler2D u_texture;\nout vec4 fragColor;\n\
        struct triangle_t {\n    vec3 positions[3];\n    vec3 normal;\n    highp vec3 color;\n    vec3 emission;\n};\n\
        float get_triangle(float x) { return x; }\n\
        vec3 sample_sphere(vec2 random_numbers) { return vec3(get_triangle(random_numbers.x)); }\n\
        vec3 get_ray_radiance(vec3 origin, int depth) { return vec3(M_PI * u_resolution.x); }\n\
        void mainImage(out vec4 out_color, in vec2 pixel_coord) {\n    out_color = texture(iChannel0, pixel_coord / iResolution.xy) + gl_FragCoord;\n}\n";

    #[test]
    fn a_shadertoy_tab_keeps_its_lines_and_drops_what_cannot_take_part() {
        let options = IntakeOptions {
            protected_functions: vec![(
                "get_ray_radiance".into(),
                Signature {
                    return_type: "vec3".into(),
                    parameters: vec!["vec3".into(), "vec3".into(), "inout uvec2".into()],
                },
            )],
            ..IntakeOptions::default()
        };
        let prepared = prepare_with(TAB, &options);
        assert_eq!(prepared.text.lines().count(), TAB.lines().count());
        let lines: Vec<&str> = prepared.text.lines().collect();
        assert!(lines[0].trim().is_empty(), "#version dropped");
        assert!(lines[1].trim().is_empty(), "precision dropped");
        assert_eq!(
            lines[2], "#define M_PI 3.141592653589793238462643",
            "macros stay"
        );
        assert_eq!(
            lines[4].trim(),
            "const vec2 u_resolution = vec2(512.0, 512.0);",
            "a resolution uniform gets check's iResolution"
        );
        assert!(lines[5].trim().is_empty(), "the sampler is dropped");
        assert_eq!(prepared.unavailable[0].name, "u_texture");
        assert_eq!(lines[6].trim(), "vec4 fragColor;");
        assert!(
            lines[7..13].iter().all(|l| l.trim().is_empty()),
            "the workshop's struct is dropped"
        );
        assert!(
            lines[13].contains("float user_get_triangle(float x)"),
            "{}",
            lines[13]
        );
        assert!(lines[14].contains("vec3(user_get_triangle(random_numbers.x))"));
        assert!(lines[15].contains("vec3 user_get_ray_radiance(vec3 origin, int depth)"));
        assert!(
            lines[16..].iter().all(|l| l.trim().is_empty()),
            "mainImage dropped"
        );
        assert_eq!(prepared.max_path_length, Some(4));
        assert_eq!(prepared.renamed_functions.len(), 1);
        assert!(prepared.prelude.contains("#undef M_PI"));
        assert!(
            !prepared.prelude.contains("iChannel0"),
            "only mainImage read it"
        );
        assert!(prepared
            .epilogue
            .contains("#undef M_PI\n#define M_PI 3.141592653589793"));
        assert!(prepared.epilogue.contains("#undef MAX_PATH_LENGTH\n"));
    }

    #[test]
    fn inputs_are_supplied_when_kept_code_reads_them() {
        let prepared = prepare(
            "float vignette(vec2 uv) { return texture(iChannel1, uv).r * iResolution.x + gl_FragCoord.x + float(iFrame); }\n",
        );
        for expected in ["iResolution", "iFrame", "vkpath_FragCoord"] {
            assert!(
                prepared.prelude.contains(expected),
                "{expected}: {}",
                prepared.prelude
            );
        }
        assert!(prepared.text.contains("vkpath_FragCoord.x"));
        // Check has no channel data: iChannel1 is not supplied but listed, for the caller
        // to leave out what reads it; with bind_opaque it gets its binding.
        assert!(!prepared.prelude.contains("iChannel"));
        let names: Vec<&str> = prepared
            .unavailable
            .iter()
            .map(|u| u.name.as_str())
            .collect();
        assert_eq!(names, ["iChannel1"]);
        let bound = prepare_with(
            "float f(vec2 uv) { return texture(iChannel1, uv).r; }\n",
            &IntakeOptions {
                bind_opaque: true,
                ..IntakeOptions::default()
            },
        );
        assert!(bound.prelude.contains("uniform sampler2D iChannel1;"));
        assert!(bound.unavailable.is_empty());
    }

    #[test]
    fn counted_loops_keep_their_condition_and_others_get_the_guard() {
        let prepared = prepare(
            "#define COUNT 30\nfloat f(float x) {\n\
             for (int i = 0; i < COUNT; i++) x += 1.0;\n\
             for (uint j = 2u; j > 0u; j -= 1u) { x += 2.0; }\n\
             for (int k = 0; k < 8; k++) { k = 0; }\n\
             for (uint n = 2u; n >= 0u; n--) x += 1.0;\n\
             for (int p = 0; p != COUNT; ++p) x += 1.0;\n\
             for (int q = 40; q != COUNT; ++q) x += 1.0;\n\
             for (int m = 0; m < int(x); m++) x -= 1.0;\n\
             for (int r = 0; r < 100000; r++) x += 1.0;\n\
             while (x > 0.0) x -= 1.0;\n    return x;\n}\n",
        );
        let lines: Vec<&str> = prepared.text.lines().collect();
        assert_eq!(lines[2], "for (int i = 0; i < COUNT; i++) x += 1.0;");
        assert_eq!(lines[3], "for (uint j = 2u; j > 0u; j -= 1u) { x += 2.0; }");
        assert_eq!(lines[6], "for (int p = 0; p != COUNT; ++p) x += 1.0;");
        for line in [lines[4], lines[5], lines[7], lines[8], lines[9], lines[10]] {
            assert!(line.contains("vkpath_loop_guard() && ("), "{line}");
        }
    }

    #[test]
    fn a_different_triangle_struct_is_renamed() {
        let prepared = prepare(
            "struct triangle_t { vec3 a, b, c; };\nbool ray_triangle_intersection(out float out_t, vec3 o, vec3 d, triangle_t t) { return false; }\n",
        );
        assert_eq!(prepared.other_triangle_struct, Some(1));
        assert!(prepared.text.contains("struct user_triangle_t"));
        assert!(prepared.text.contains("vec3 d, user_triangle_t t"));
    }

    #[test]
    fn repeated_definitions_are_named_once_and_kept_once() {
        // The shape of a long paste: the same helpers, struct and global written again and
        // again (written for this test, 40 copies).
        let helpers = "struct hit_t { float t; vec3 n; };\nconst float SCALE = 2.0;\n\
            vec3 my_direction(vec2 u) {\n    float z = 1.0 - SCALE * u.x;\n    return vec3(0.0, 0.0, z);\n}\n\
            float helper(float x) { return x * SCALE; }\n";
        let source = helpers.repeat(40);
        let prepared = prepare(&source);
        // One definition of each is left in the text compiled, so a file is compiled (and each
        // function judged) once however often it repeats itself; lines stay where they were.
        assert_eq!(prepared.text.lines().count(), source.lines().count());
        let functions = find_functions(&prepared.text);
        let names: Vec<&str> = functions.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, ["my_direction", "helper"]);
        assert_eq!(prepared.text.matches("struct hit_t").count(), 1);
        assert_eq!(prepared.text.matches("const float SCALE").count(), 1);
        let repeats: Vec<&String> = prepared
            .notes
            .iter()
            .filter(|n| n.contains("40 times"))
            .collect();
        assert_eq!(repeats.len(), 4, "{:?}", prepared.notes);
        assert!(repeats.iter().any(|n| n
            .starts_with("line 3: my_direction() is defined 40 times")
            && n.contains("judged the first, the other 39 dropped")));
        assert!(repeats
            .iter()
            .any(|n| n.starts_with("line 1: struct hit_t is written 40 times")));
        // A function defined again with other parameters is an overload, not a repeat.
        let overloads = prepare("float f(float x) { return x; }\nvec2 f(vec2 x) { return x; }\n");
        assert_eq!(find_functions(&overloads.text).len(), 2);
        assert!(!overloads.notes.iter().any(|n| n.contains("times")));
    }

    #[test]
    fn channel_and_unknown_directives_are_dropped_with_a_note() {
        let source = "#iChannel0 \"self\"\n#iChannel1 \"file://bufferA.glsl\"\n#iKeyboard\n#ifdef X\n#endif\nfloat f() { return 1.0; }\n";
        let prepared = prepare(source);
        assert_eq!(prepared.text.lines().count(), source.lines().count());
        assert!(!prepared.text.contains("#iC"), "{}", prepared.text);
        assert!(!prepared.text.contains("bufferA"), "{}", prepared.text);
        assert!(prepared.text.contains("#ifdef X"));
        assert!(prepared
            .notes
            .iter()
            .any(|n| n.starts_with("line 1: dropped #iChannel0")));
        assert!(prepared
            .notes
            .iter()
            .any(|n| n.starts_with("line 2: dropped #iChannel1")));
        assert!(prepared
            .notes
            .iter()
            .any(|n| n == "line 3: dropped #iKeyboard (not a GLSL directive)"));
    }

    #[test]
    fn kernel_names_come_from_the_embedded_glsl() {
        let names = kernel_names();
        for name in [
            "get_triangle",
            "offset_ray_origin",
            "MAX_PATH_LENGTH",
            "packed_triangle_t",
            "g_path",
        ] {
            assert!(names.identifiers.contains(name), "{name}");
        }
        // The workshop-facing alias of g_path.hit_triangle_index (glsl/path_state.glsl).
        assert_eq!(
            names.macros.get("g_hit_triangle_index").map(String::as_str),
            Some("g_path . hit_triangle_index")
        );
        assert_eq!(
            names.macros.get("M_PI").map(String::as_str),
            Some("3.141592653589793")
        );
        assert_eq!(names.triangle_members.len(), 4);
    }
}
