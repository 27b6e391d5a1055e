//! A user's GLSL file as `check` models it (`UserFunctions`): the workshop functions it
//! defines, those it cannot have judged and why, the ones that do not compile (dropped one
//! round at a time), stubs, and the code each judging kernel includes (`UserCode`, compiled
//! by `crate::check::compile`).

use std::collections::BTreeSet;
use std::ops::Range;

use crate::check::compile::{compile_kernel, CompileError, UserCode};
use crate::check::detect::{
    find_functions, Definition, FoundFunction, Signature, WorkshopFunction,
};
use crate::check::report::FunctionReport;
use crate::check::unavailable::leave_out_unavailable;
use crate::glsl_intake::syntax::{
    structural_tokens, tokenize, top_level_items, Item, ItemKind, Token,
};
use crate::glsl_intake::{prepare_with, IntakeOptions, PreparedSource};

/// The intake options of `check`: the user's code goes into vkpath's kernels, its entry
/// points are dropped, and the workshop functions keep their signatures (a definition with
/// other parameters is renamed `user_<name>` and listed as not judged).
pub fn check_intake_options() -> IntakeOptions {
    IntakeOptions {
        protected_functions: WorkshopFunction::ALL
            .iter()
            .filter_map(|f| Some((f.name().to_string(), f.signature()?)))
            .collect(),
        ..IntakeOptions::default()
    }
}

/// The most function definitions a file may have for its compile rounds to compile every
/// helper (and report each one that does not compile); beyond, they compile only what the
/// workshop functions reach, as the kernels do.
const WHOLE_FILE_FUNCTIONS: usize = 1000;

/// A workshop name in the user's file that cannot be judged, and why.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct NotJudged {
    /// The function's name.
    pub function: String,
    /// Its line in the user's file.
    pub line: usize,
    /// Why it is not judged.
    pub reason: String,
    /// The user's file where it stands (filled in for the report).
    #[serde(default)]
    pub file: String,
}

/// One of the user's files in the text that `UserFunctions` reads (several for the tabs of
/// a ShaderToy program).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SourceFile {
    /// The file as the user named it.
    pub name: String,
    /// The line of the text where it begins (from 1).
    pub first_line: usize,
}

/// A function of the user's file that does not compile: dropped, with the compiler's words.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct BrokenFunction {
    /// The function's name.
    pub name: String,
    /// Its line in the user's file.
    pub line: usize,
    /// The compiler's messages about it (naming the user's file and lines).
    pub messages: String,
}

/// A user's GLSL file with its versions of workshop functions.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct UserFunctions {
    /// The file as the user named it, for messages.
    pub display_name: String,
    /// Its text as written.
    pub text: String,
    /// The text made ready for the kernels.
    pub prepared: PreparedSource,
    /// The workshop functions it defines with the workshop's signatures, in order of
    /// appearance (those that do not compile included).
    pub definitions: Vec<Definition>,
    /// Workshop names it uses for something else.
    pub not_judged: Vec<NotJudged>,
    /// Workshop functions defined with the workshop's types but other parameter qualifiers
    /// (`inout` missing, `in`/`out` swapped): the user's definition is renamed
    /// `user_<name>` and judged through an adapter with the workshop's signature, so that
    /// the wrong qualifier has the effect it has in the user's program.
    pub qualifier_mismatches: Vec<QualifierMismatch>,
    /// Functions dropped because they do not compile.
    pub broken: Vec<BrokenFunction>,
    /// The compiler's warnings about the file (once it compiles).
    pub compile_warnings: String,
    /// The compiler's messages when an error lies outside every function, so that nothing
    /// can be judged.
    pub compile_errors: Option<String>,
    /// Workshop functions whose body only returns a constant (`return false;`,
    /// `return vec3(0.0);`): the exercise's stub, not yet written.
    pub stubs: Vec<(WorkshopFunction, String)>,
    /// The user's files in the text, in order (one unless several tabs were given).
    pub sources: Vec<SourceFile>,
}

/// A workshop function defined with other parameter qualifiers than the workshop's.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct QualifierMismatch {
    /// The function.
    pub function: WorkshopFunction,
    /// Its line in the user's file.
    pub line: usize,
    /// Its signature as written.
    pub signature: Signature,
}

impl QualifierMismatch {
    /// The mismatch of `signature` with `function`'s, if they differ only in the `out`/
    /// `inout` qualifiers of their parameters.
    pub fn of(function: WorkshopFunction, line: usize, signature: &Signature) -> Option<Self> {
        let workshop = function.signature()?;
        let bare = |s: &Signature| -> Vec<String> {
            s.parameters
                .iter()
                .map(|p| {
                    p.trim_start_matches("inout ")
                        .trim_start_matches("out ")
                        .to_string()
                })
                .collect()
        };
        let only_qualifiers = workshop != *signature
            && workshop.return_type == signature.return_type
            && bare(&workshop) == bare(signature);
        only_qualifiers.then(|| QualifierMismatch {
            function,
            line,
            signature: signature.clone(),
        })
    }

    /// Why the verdict may be what it is: which parameters differ and what that does.
    pub fn explanation(&self) -> String {
        let workshop = self
            .function
            .signature()
            .unwrap_or_else(|| self.signature.clone());
        let differences: Vec<String> = workshop
            .parameters
            .iter()
            .zip(&self.signature.parameters)
            .enumerate()
            .filter(|(_, (ours, yours))| ours != yours)
            .map(|(index, (ours, yours))| {
                let effect = if ours.starts_with("inout ") && !yours.starts_with("inout ") {
                    if yours.starts_with("out ") {
                        "the value passed in is never read"
                    } else {
                        "what your function writes to it never reaches the caller (a seed that never advances, for get_random_numbers)"
                    }
                } else if ours.starts_with("out ") && !yours.starts_with("out ") {
                    "what your function writes to it never reaches the caller"
                } else {
                    "the caller's value is overwritten or not passed in"
                };
                format!(
                    "parameter {} is '{yours}' where the workshop's is '{ours}': {effect}",
                    index + 1
                )
            })
            .collect();
        format!(
            "your {} is {} where the workshop's is {}; {}",
            self.function.name(),
            self.signature,
            workshop,
            differences.join("; ")
        )
    }

    /// The adapter with the workshop's signature that calls the user's renamed function,
    /// compiled only where the function is taken from the user.
    fn adapter(&self) -> Option<String> {
        let workshop = self.function.signature()?;
        let parameters: Vec<String> = workshop
            .parameters
            .iter()
            .enumerate()
            .map(|(i, p)| format!("{p} vkpath_a{i}"))
            .collect();
        let arguments: Vec<String> = (0..workshop.parameters.len())
            .map(|i| format!("vkpath_a{i}"))
            .collect();
        let name = self.function.name();
        Some(format!(
            "#ifdef {}
{} {name}({}) {{ return user_{name}({}); }}
#endif
",
            self.function.user_defines_macro(),
            workshop.return_type,
            parameters.join(", "),
            arguments.join(", ")
        ))
    }
}
impl UserFunctions {
    /// Reads `text`: prepares it and finds the workshop functions it defines.
    pub fn new(display_name: &str, text: String) -> UserFunctions {
        let mut prepared = prepare_with(&text, &check_intake_options());
        let mut definitions = Vec::new();
        let mut not_judged = Vec::new();
        let mut qualifier_mismatches = Vec::new();
        for (name, line, signature) in &prepared.renamed_functions {
            let Some(function) = WorkshopFunction::from_name(name) else {
                continue;
            };
            let written = find_functions(&text)
                .into_iter()
                .find(|f| f.has_body && f.line == *line && f.name == *name)
                .map(|f| f.signature);
            if let Some(mismatch) = written
                .as_ref()
                .and_then(|s| QualifierMismatch::of(function, *line, s))
            {
                definitions.push(Definition {
                    function,
                    line: *line,
                    signature: mismatch.signature.clone(),
                });
                qualifier_mismatches.push(mismatch);
                continue;
            }
            not_judged.push(NotJudged {
                function: function.name().to_string(),
                line: *line,
                reason: format!(
                    "its parameters are {signature} but the workshop's {} is {}; it is kept as your own user_{} and not judged",
                    function.name(),
                    function
                        .signature()
                        .map_or_else(|| "unknown".to_string(), |s| s.to_string()),
                    function.name()
                ),
                file: String::new(),
            });
        }
        for found in find_functions(&prepared.text)
            .into_iter()
            .filter(|f| f.has_body)
        {
            let Some(function) = WorkshopFunction::from_name(&found.name) else {
                continue;
            };
            let definition = Definition {
                function,
                line: found.line,
                signature: found.signature,
            };
            if definition.has_workshop_signature() {
                definitions.push(definition);
            } else {
                // A second definition of the name with other parameters, beside one with
                // the workshop's: GLSL takes it as an overload.
                not_judged.push(NotJudged {
                    function: function.name().to_string(),
                    line: found.line,
                    reason: format!(
                        "this overload takes {} rather than the workshop's parameters; it is kept and not judged",
                        definition.signature
                    ),
                    file: String::new(),
                });
            }
        }
        if prepared.other_triangle_struct.is_some() {
            for entry in &mut not_judged {
                if entry.reason.contains("user_triangle_t") {
                    entry
                        .reason
                        .push_str(" (your triangle_t differs from the workshop's)");
                }
            }
        }
        // What needs data check does not have is left out; the rest is judged.
        let renamed: Vec<WorkshopFunction> =
            qualifier_mismatches.iter().map(|m| m.function).collect();
        let workshop_of = |name: &str| {
            WorkshopFunction::from_name(name).or_else(|| {
                WorkshopFunction::from_name(name.strip_prefix("user_")?)
                    .filter(|f| renamed.contains(f))
            })
        };
        for left_out in leave_out_unavailable(&mut prepared, workshop_of) {
            match workshop_of(&left_out.name) {
                Some(function) => {
                    definitions.retain(|d| !(d.function == function && d.line == left_out.line));
                    not_judged.push(NotJudged {
                        function: function.name().to_string(),
                        line: left_out.line,
                        reason: left_out.reason,
                        file: String::new(),
                    });
                }
                None => prepared.notes.push(format!(
                    "line {}: left out your {}: {}",
                    left_out.line, left_out.name, left_out.reason
                )),
            }
        }
        qualifier_mismatches.retain(|m| definitions.iter().any(|d| d.function == m.function));
        let stubs = find_stubs(&prepared.text, &workshop_of);
        not_judged.sort_by_key(|n| n.line);
        UserFunctions {
            display_name: display_name.to_string(),
            text,
            prepared,
            definitions,
            not_judged,
            qualifier_mismatches,
            broken: Vec::new(),
            compile_warnings: String::new(),
            compile_errors: None,
            stubs,
            sources: vec![SourceFile {
                name: display_name.to_string(),
                first_line: 1,
            }],
        }
    }

    /// The distinct workshop functions the file defines (with the workshop's signature), in
    /// the workshop's order.
    pub fn functions(&self) -> Vec<WorkshopFunction> {
        let defined: BTreeSet<WorkshopFunction> =
            self.definitions.iter().map(|d| d.function).collect();
        defined.into_iter().collect()
    }

    /// The functions that compile and can be judged.
    pub fn judged_functions(&self) -> Vec<WorkshopFunction> {
        self.functions()
            .into_iter()
            .filter(|f| !self.broken.iter().any(|b| b.name == f.name()))
            .collect()
    }

    /// Whether the file defines `function`.
    pub fn defines(&self, function: WorkshopFunction) -> bool {
        self.definitions.iter().any(|d| d.function == function)
    }

    /// The line of the file's first definition of `function` (0 if none).
    pub fn line_of(&self, function: WorkshopFunction) -> usize {
        self.definitions
            .iter()
            .find(|d| d.function == function)
            .map_or(0, |d| d.line)
    }

    /// The code a kernel includes to take `active` from the user (the user's other workshop
    /// functions and the functions that do not compile are left out; of its helpers, those
    /// that the active functions, the global declarations or the macros name, directly or
    /// through other helpers).
    pub fn code(&self, active: &[WorkshopFunction]) -> UserCode {
        self.code_with(active, true)
    }

    /// `code`, with every helper kept when `prune` is false (to find all that do not
    /// compile). Pruning is what keeps a long paste fast: glslang and the driver translate
    /// every function they are given, called or not, and each judged function compiles its
    /// own kernels (a 2 MB paste of 14 000 helpers spent most of its time there).
    fn code_with(&self, active: &[WorkshopFunction], prune: bool) -> UserCode {
        let tokens = tokenize(&self.prepared.text);
        let structure = structural_tokens(&tokens);
        let items = top_level_items(&structure);
        let mut left_out: Vec<Range<usize>> = Vec::new();
        // (name, item) of each definition kept so far.
        let mut kept: Vec<(&str, &Item)> = Vec::new();
        for item in &items {
            let Some(name_index) = item
                .name
                .filter(|_| item.kind == ItemKind::FunctionDefinition)
            else {
                continue;
            };
            let found = structure[name_index].text.as_str();
            let workshop = self.workshop_function_of(found);
            let inactive = workshop.is_some_and(|f| !active.contains(&f));
            let name = workshop.map_or(found.to_string(), |f| f.name().to_string());
            let broken = self.broken.iter().any(|b| b.name == name);
            if inactive || broken {
                left_out.push(structure[item.first].start..structure[item.last].end);
            } else {
                kept.push((found, item));
            }
        }
        if prune {
            let reached = reached_functions(&tokens, &structure, &items, &kept, active);
            for (name, item) in &kept {
                if !reached.contains(*name) {
                    left_out.push(structure[item.first].start..structure[item.last].end);
                }
            }
        }
        // A function with other qualifiers is the user's `user_<name>`: where it is taken
        // from the user an adapter with the workshop's signature calls it, elsewhere the
        // user's calls of it go to the reference version.
        let mut before = String::new();
        let mut after = String::new();
        for mismatch in &self.qualifier_mismatches {
            let name = mismatch.function.name();
            let taken =
                active.contains(&mismatch.function) && !self.broken.iter().any(|b| b.name == name);
            if taken {
                after.push_str(&mismatch.adapter().unwrap_or_default());
            } else {
                before.push_str(&format!("#define user_{name} {name}\n"));
                after.push_str(&format!("#undef user_{name}\n"));
            }
        }
        // Blanked byte for byte, so that every range stays where it was (a character of
        // several bytes becomes as many spaces) and the lines stay the user's.
        let mut bytes = self.prepared.text.clone().into_bytes();
        for range in left_out {
            for byte in &mut bytes[range] {
                if *byte != b'\n' {
                    *byte = b' ';
                }
            }
        }
        let text = String::from_utf8_lossy(&bytes);
        UserCode {
            include: format!(
                "{}{before}#line 1\n{}{}{after}",
                self.prepared.prelude, text, self.prepared.epilogue
            ),
            active: active.to_vec(),
            display_name: self.display_name.clone(),
        }
    }

    /// `report` (the verdict on `function`) with what the file tells about it: a parameter
    /// qualifier that differs from the workshop's (the likely cause of a failure, a warning
    /// beside a pass), a body that is still the exercise's stub.
    pub fn annotate(
        &self,
        function: WorkshopFunction,
        mut report: FunctionReport,
    ) -> FunctionReport {
        let (file, line) = self.locate(report.line);
        report.file = file;
        report.line = line;
        if report.method == "compile" {
            if let Some(hint) = &report.hint {
                if let Some(missing) = self.undefined_names(hint) {
                    report.summary = format!(
                        "does not compile: {missing} not defined in any of your files; if your program has a Common tab, pass it first"
                    );
                }
                report.hint = Some(self.localize(hint));
            }
        }
        if let Some(mismatch) = self
            .qualifier_mismatches
            .iter()
            .find(|m| m.function == function)
        {
            if report.passed {
                report.warnings.push(mismatch.explanation());
            } else {
                report.hint = Some(mismatch.explanation());
            }
        }
        if let Some((_, body)) = self.stubs.iter().find(|(f, _)| *f == function) {
            if !report.passed {
                report.hint = Some(format!(
                    "this function is still the exercise's stub (its body is only '{body}'): write it as the slides describe"
                ));
            }
        }
        report
    }

    /// The file and line of the user's that line `line` of the text is.
    pub fn locate(&self, line: usize) -> (String, usize) {
        match self.sources.iter().rev().find(|s| s.first_line <= line) {
            Some(source) => (source.name.clone(), line + 1 - source.first_line),
            None => (self.display_name.clone(), line),
        }
    }

    /// `text` (a note, compiler messages) with each place in the text, `line N` or
    /// `<display name>:N`, written as the user's `file:line`.
    pub fn localize(&self, text: &str) -> String {
        let prefix = format!("{}:", self.display_name);
        let mut result = String::with_capacity(text.len());
        let mut rest = text;
        loop {
            let at_name = rest.find(&prefix).map(|i| (i, prefix.len()));
            let at_line = rest
                .match_indices("line ")
                .find(|(i, _)| rest[i + 5..].starts_with(|c: char| c.is_ascii_digit()))
                .map(|(i, _)| (i, 5));
            let Some((start, skip)) = [at_name, at_line].into_iter().flatten().min() else {
                result.push_str(rest);
                return result;
            };
            let digits_end = rest[start + skip..]
                .find(|c: char| !c.is_ascii_digit())
                .map_or(rest.len(), |i| start + skip + i);
            result.push_str(&rest[..start]);
            match rest[start + skip..digits_end].parse::<usize>() {
                Ok(line) => {
                    let (file, line) = self.locate(line);
                    result.push_str(&format!("{file}:{line}"));
                }
                Err(_) => result.push_str(&rest[start..digits_end]),
            }
            rest = &rest[digits_end..];
        }
    }

    /// The identifiers that compiler `messages` call undeclared and that none of the user's
    /// files declares, as "'a' is" or "'a', 'b' are"; `None` when there are none.
    fn undefined_names(&self, messages: &str) -> Option<String> {
        crate::glsl_intake::undefined_names(messages, &[&self.text])
    }

    /// The workshop function that a function of the prepared text stands for: its own
    /// name, or `user_<name>` for a definition with other qualifiers.
    pub fn workshop_function_of(&self, name: &str) -> Option<WorkshopFunction> {
        WorkshopFunction::from_name(name).or_else(|| {
            let workshop = WorkshopFunction::from_name(name.strip_prefix("user_")?)?;
            self.qualifier_mismatches
                .iter()
                .any(|m| m.function == workshop)
                .then_some(workshop)
        })
    }

    /// The code with every judged function taken from the user, as the file runs on its own,
    /// and every helper (called or not).
    pub fn whole(&self) -> UserCode {
        self.code_with(&self.judged_functions(), false)
    }

    /// Compiles the file with all its functions; functions whose code the compiler rejects
    /// are dropped (recorded in `broken`, with the compiler's messages) and the rest compiled
    /// again. Returns the compiler's warnings, or its messages when an error lies outside
    /// every function (then nothing can be judged).
    pub fn find_broken_functions(&mut self) -> Result<String, CompileError> {
        // Every round sets aside at least one function or declaration, or ends: rounds go on
        // while they make progress, so a file with many broken items (notes with snippets
        // between the functions) loses only those. The bound is one round per item.
        let items = top_level_items(&structural_tokens(&tokenize(&self.prepared.text)));
        let definitions = items
            .iter()
            .filter(|i| i.kind == ItemKind::FunctionDefinition)
            .count();
        // A long paste is compiled as the kernels compile it, without the helpers nothing
        // reaches: glslang's call-graph check grows with the square of the functions given
        // (a 2 MB paste of 13 000 helpers spent a third of its time there).
        let prune = definitions > WHOLE_FILE_FUNCTIONS;
        if prune {
            self.prepared.notes.push(format!(
                "your file defines {definitions} functions: those that no workshop function of yours calls, directly or through others, are left out of every compile"
            ));
        }
        for _ in 0..=items.len() {
            let code = self.code_with(&self.judged_functions(), prune);
            let error = match compile_kernel("probe_get_random_numbers.comp", Some(&code), &[]) {
                Ok(compiled) => return Ok(compiled.warnings),
                Err(error) => error,
            };
            let messages = error.to_string();
            let functions = find_functions(&self.prepared.text);
            // Where each line starts, found once per round: each error message then finds its
            // function by binary search instead of counting the file's lines again.
            let newlines: Vec<usize> = self
                .prepared
                .text
                .match_indices('\n')
                .map(|(at, _)| at)
                .collect();
            let mut newly_broken: Vec<BrokenFunction> = Vec::new();
            let mut outside = false;
            let mut dropped_declaration = false;
            let mut dropped_lines: Vec<std::ops::RangeInclusive<usize>> = Vec::new();
            for message in messages.lines().filter(|l| l.contains(": error:")) {
                let Some(line) = self.error_line(message) else {
                    outside = true;
                    continue;
                };
                let found = enclosing(&functions, &newlines, line).map(|found| {
                    let name = self
                        .workshop_function_of(&found.name)
                        .map_or(found.name.clone(), |f| f.name().to_string());
                    (name, found)
                });
                match found {
                    Some((name, found)) if !self.broken.iter().any(|b| b.name == name) => {
                        match newly_broken.iter_mut().find(|b| b.name == name) {
                            Some(broken) => {
                                broken.messages.push_str(message);
                                broken.messages.push('\n');
                            }
                            None => newly_broken.push(BrokenFunction {
                                name,
                                line: found.line,
                                messages: format!("{message}\n"),
                            }),
                        }
                    }
                    Some(_) => {}
                    // A declaration dropped in this round may have had several errors:
                    // the later ones are its own, not errors outside any function.
                    None if dropped_lines.iter().any(|lines| lines.contains(&line)) => {}
                    None => match self.drop_declaration_at(line, message) {
                        Some(lines) => {
                            dropped_lines.push(lines);
                            dropped_declaration = true;
                        }
                        None => outside = true,
                    },
                }
            }
            if outside || newly_broken.is_empty() && !dropped_declaration {
                return Err(error);
            }
            self.broken.extend(newly_broken);
        }
        Err(CompileError::TooManyBrokenFunctions {
            file: self.display_name.clone(),
        })
    }

    /// Drops (blanks) the global declaration of the prepared text that covers `line`, with a
    /// note quoting the compiler's `message`; false when no declaration covers it. The
    /// functions that need what it declares then fail to compile one by one, and are
    /// reported, instead of the whole file. Returns the lines dropped, `None` when no
    /// declaration covers `line`.
    fn drop_declaration_at(
        &mut self,
        line: usize,
        message: &str,
    ) -> Option<std::ops::RangeInclusive<usize>> {
        let tokens = structural_tokens(&tokenize(&self.prepared.text));
        let item = top_level_items(&tokens)
            .into_iter()
            .filter(|item| item.kind == ItemKind::Declaration)
            .find(|item| (tokens[item.first].line..=tokens[item.last].line).contains(&line))?;
        let lines = tokens[item.first].line..=tokens[item.last].line;
        let range = tokens[item.first].start..tokens[item.last].end;
        // The declaration as the user wrote it, on one line.
        let written: Vec<&str> = self.prepared.text[range.clone()]
            .split_whitespace()
            .collect();
        let reason = message
            .split(": error:")
            .nth(1)
            .map_or(message, str::trim)
            .to_string();
        self.prepared.notes.push(format!(
            "line {}: dropped '{}' (it does not compile here: {reason}); a function that needs it fails to compile",
            tokens[item.first].line,
            shorten(&written.join(" "), 60)
        ));
        let blank: String = self.prepared.text[range.clone()]
            .chars()
            .map(|c| if c == '\n' { '\n' } else { ' ' })
            .collect();
        self.prepared.text.replace_range(range, &blank);
        Some(lines)
    }

    /// The user's line that a compiler message names, if it names the user's file.
    fn error_line(&self, message: &str) -> Option<usize> {
        let rest = message.strip_prefix(&format!("{}:", self.display_name))?;
        rest.split(':').next()?.trim().parse().ok()
    }
}

/// The names of the kept functions (`kept`: (name, definition)) that a kernel taking
/// `active` from the user can call: the active workshop functions (under their name or as
/// `user_<name>`), and what any global declaration or macro names, then whatever the
/// functions reached name, until nothing new is reached (overloads go together, by name).
fn reached_functions(
    tokens: &[Token],
    structure: &[Token],
    items: &[Item],
    kept: &[(&str, &Item)],
    active: &[WorkshopFunction],
) -> BTreeSet<String> {
    let defined: BTreeSet<&str> = kept.iter().map(|(name, _)| *name).collect();
    let mut reached: BTreeSet<String> = BTreeSet::new();
    let mut pending: Vec<String> = Vec::new();
    let reach = |name: &str, reached: &mut BTreeSet<String>, pending: &mut Vec<String>| {
        if defined.contains(name) && !reached.contains(name) {
            reached.insert(name.to_string());
            pending.push(name.to_string());
        }
    };
    for function in active {
        reach(function.name(), &mut reached, &mut pending);
        reach(
            &format!("user_{}", function.name()),
            &mut reached,
            &mut pending,
        );
    }
    for token in tokens.iter().filter(|t| t.in_directive) {
        reach(&token.text, &mut reached, &mut pending);
    }
    for item in items
        .iter()
        .filter(|i| i.kind != ItemKind::FunctionDefinition)
    {
        for token in &structure[item.first..=item.last] {
            reach(&token.text, &mut reached, &mut pending);
        }
    }
    let mut definitions: std::collections::BTreeMap<&str, Vec<&Item>> =
        std::collections::BTreeMap::new();
    for (name, item) in kept {
        definitions.entry(name).or_default().push(item);
    }
    while let Some(name) = pending.pop() {
        for item in definitions.get(name.as_str()).into_iter().flatten() {
            let body = item.name.map_or(item.first, |n| n + 1)..=item.last;
            for token in &structure[body] {
                reach(&token.text, &mut reached, &mut pending);
            }
        }
    }
    reached
}

/// The workshop functions of `text` whose body is only `return <constant>;` (no identifier
/// other than a type's constructor, `true` or `false`): the exercise's stub, with the body.
fn find_stubs(
    text: &str,
    workshop_of: &impl Fn(&str) -> Option<WorkshopFunction>,
) -> Vec<(WorkshopFunction, String)> {
    let tokens = structural_tokens(&tokenize(text));
    let mut stubs = Vec::new();
    for item in top_level_items(&tokens) {
        let (Some(name), ItemKind::FunctionDefinition) = (item.name, &item.kind) else {
            continue;
        };
        let Some(function) = workshop_of(&tokens[name].text) else {
            continue;
        };
        let Some(open) = (name..item.last).find(|&i| tokens[i].text == "{") else {
            continue;
        };
        let body = &tokens[open + 1..item.last];
        let constant = body.first().is_some_and(|t| t.text == "return")
            && body.last().is_some_and(|t| t.text == ";")
            && body.iter().filter(|t| t.text == ";").count() == 1
            && body[1..body.len() - 1].iter().all(|t| {
                !t.is_identifier()
                    || matches!(t.text.as_str(), "true" | "false")
                    || is_constructor(&t.text)
            });
        if constant && body.len() >= 2 {
            let words: Vec<&str> = body.iter().map(|t| t.text.as_str()).collect();
            let written = words
                .join(" ")
                .replace(" ( ", "(")
                .replace(" )", ")")
                .replace(" ,", ",")
                .replace(" ;", ";");
            stubs.push((function, written));
        }
    }
    stubs
}

/// Whether a word is a scalar, vector or matrix type (a constructor in an expression).
fn is_constructor(word: &str) -> bool {
    matches!(word, "float" | "int" | "uint" | "bool" | "double")
        || ["vec", "ivec", "uvec", "bvec", "dvec", "mat", "dmat"]
            .iter()
            .any(|prefix| {
                word.strip_prefix(prefix)
                    .is_some_and(|rest| rest.starts_with(|c: char| c.is_ascii_digit()))
            })
}

/// `text` cut to at most `limit` characters, with "…" where it was cut.
fn shorten(text: &str, limit: usize) -> String {
    if text.chars().count() <= limit {
        return text.to_string();
    }
    let cut: String = text.chars().take(limit).collect();
    format!("{cut}…")
}

/// The function (defined at global scope) whose text covers `line`.
/// `newlines`: the byte offsets of the text's line breaks, in order.
fn enclosing<'a>(
    functions: &'a [FoundFunction],
    newlines: &[usize],
    line: usize,
) -> Option<&'a FoundFunction> {
    functions.iter().filter(|f| f.has_body).find(|f| {
        let first_line = newlines.partition_point(|&at| at < f.span.start) + 1;
        (first_line..=f.last_line).contains(&line)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::compile::USER_FUNCTIONS_FILE;

    #[test]
    fn user_functions_replace_the_reference_and_errors_name_their_file() {
        let user = UserFunctions::new(
            "mine.glsl",
            "vec3 sample_sphere(vec2 u) {\n    return vec3(0.0, 0.0, 1.0);\n}\n".into(),
        );
        assert_eq!(user.functions(), [WorkshopFunction::SampleSphere]);
        let code = user.whole();
        assert!(code
            .macros()
            .contains(&("USER_DEFINES_SAMPLE_SPHERE".into(), "1".into())));
        let compiled = compile_kernel("probe_sample_hemisphere.comp", Some(&code), &[]);
        assert!(compiled.is_ok(), "{:?}", compiled.err());

        let mut broken = UserFunctions::new(
            "mine.glsl",
            "#version 300 es\nvec3 sample_sphere(vec2 u) {\n    return vec3(0.0, 0.0, 1.0)\n}\n"
                .into(),
        );
        let Err(error) = compile_kernel("probe_sample_sphere.comp", Some(&broken.whole()), &[])
        else {
            panic!("a missing semicolon must not compile");
        };
        let error = error.to_string();
        assert!(error.contains("mine.glsl:4:"), "{error}");
        assert!(!error.contains(USER_FUNCTIONS_FILE), "{error}");
        // The function is dropped, and with it nothing is left to judge.
        assert!(broken.find_broken_functions().is_ok());
        assert_eq!(broken.broken.len(), 1);
        assert!(broken.judged_functions().is_empty());
    }

    #[test]
    fn one_function_that_does_not_compile_leaves_the_others() {
        let mut user = UserFunctions::new(
            "tab.glsl",
            "vec3 sample_sphere(vec2 u) {\n    return vec3(0.0, 0.0, 1.0);\n}\n\
             vec3 sample_hemisphere(vec2 u, vec3 n) {\n    return undefined_name;\n}\n"
                .into(),
        );
        assert!(user.find_broken_functions().is_ok());
        assert_eq!(user.judged_functions(), [WorkshopFunction::SampleSphere]);
        assert_eq!(user.broken[0].name, "sample_hemisphere");
        assert!(
            user.broken[0].messages.contains("tab.glsl:5:"),
            "{:?}",
            user.broken
        );
    }

    #[test]
    fn each_kernel_takes_only_the_function_it_judges() {
        let user = UserFunctions::new(
            "tab.glsl",
            "vec3 sample_sphere(vec2 u) { return vec3(0.0, 0.0, 1.0); }\n\
             vec3 sample_hemisphere(vec2 u, vec3 n) { return sample_sphere(u); }\n"
                .into(),
        );
        let code = user.code(&[WorkshopFunction::SampleHemisphere]);
        assert!(!code.include.contains("return vec3(0.0, 0.0, 1.0)"));
        assert!(code.include.contains("return sample_sphere(u)"));
        assert!(compile_kernel("probe_sample_hemisphere.comp", Some(&code), &[]).is_ok());
    }

    #[test]
    fn kernels_leave_out_the_helpers_nothing_they_call_reaches() {
        let user = UserFunctions::new(
            "notes.glsl",
            "#define SCALE scale_of()\nfloat scale_of() { return 1.0; }\nfloat twice(float x) { return 2.0 * x; }\n\
             float unused(float x) { /* é */ return x; }\nfloat unused_helper(float x) { return unused(x); }\n\
             float offset() { return 0.5; }\nfloat K = offset();\n\
             vec3 sample_sphere(vec2 u) {\n    float z = twice(u.x) * SCALE - 1.0;\n    return vec3(0.0, 0.0, z);\n}\n"
                .into(),
        );
        let code = user.code(&[WorkshopFunction::SampleSphere]);
        for kept in [
            "float twice(",
            "float scale_of(",
            "float offset(",
            "vec3 sample_sphere(",
        ] {
            assert!(code.include.contains(kept), "{kept}: {}", code.include);
        }
        assert!(!code.include.contains("unused_helper("), "{}", code.include);
        // Blanked byte for byte: every line stays where it was.
        assert_eq!(
            code.include.matches('\n').count(),
            user.whole().include.matches('\n').count()
        );
        assert!(user.whole().include.contains("unused_helper("));
        assert!(compile_kernel("probe_sample_sphere.comp", Some(&code), &[]).is_ok());
    }

    #[test]
    fn a_missing_inout_is_judged_through_an_adapter() {
        let user = UserFunctions::new(
            "tab.glsl",
            "vec2 get_random_numbers(uvec2 seed) {\n    seed += 1u;\n    return vec2(seed);\n}\n"
                .into(),
        );
        assert_eq!(user.functions(), [WorkshopFunction::GetRandomNumbers]);
        assert!(user.not_judged.is_empty(), "{:?}", user.not_judged);
        let explanation = user.qualifier_mismatches[0].explanation();
        assert!(
            explanation.contains("'uvec2' where the workshop's is 'inout uvec2'"),
            "{explanation}"
        );
        let code = user.code(&[WorkshopFunction::GetRandomNumbers]);
        assert!(code
            .include
            .contains("return user_get_random_numbers(vkpath_a0);"));
        assert!(compile_kernel("probe_get_random_numbers.comp", Some(&code), &[]).is_ok());
        // Where another function is judged, the user's calls go to the reference.
        let other = user.code(&[]);
        assert!(other
            .include
            .contains("#define user_get_random_numbers get_random_numbers"));
        // Other types than the workshop's are not a qualifier mismatch.
        let signature = Signature {
            return_type: "vec2".into(),
            parameters: vec!["uvec3".into()],
        };
        assert!(QualifierMismatch::of(WorkshopFunction::GetRandomNumbers, 1, &signature).is_none());
    }

    #[test]
    fn snippet_lines_at_top_level_are_dropped_for_real() {
        // The slides' two snippet lines pasted at file scope (written for this test): the
        // second has three errors of its own once the first is dropped; all of them go with
        // it, and the function compiles.
        let mut user = UserFunctions::new(
            "snippets.glsl",
            "vec3 sample_sphere(vec2 u) {\n    return vec3(0.0, 0.0, 2.0 * u.x - 1.0);\n}\n\
             uvec2 seed = uvec2(pixel_coord) ^ uvec2(iFrame << 16);\n\
             vec2 r = get_random_numbers(seed);\n"
                .into(),
        );
        let compiled = user.find_broken_functions();
        assert!(compiled.is_ok(), "{compiled:?}");
        assert!(user.broken.is_empty());
        for line in [4, 5] {
            assert!(
                user.prepared
                    .notes
                    .iter()
                    .any(|n| n.starts_with(&format!("line {line}: dropped '"))),
                "{:?}",
                user.prepared.notes
            );
        }
    }

    #[test]
    fn stubs_places_and_undefined_names_are_found() {
        let mut user = UserFunctions::new(
            "tab.glsl",
            "bool ray_triangle_intersection(out float out_t, vec3 o, vec3 d, triangle_t tri) {\n    return false;\n}\n\
             vec3 sample_sphere(vec2 u) {\n    return vec3(0.0, 0.0, 1.0);\n}\n\
             vec3 sample_hemisphere(vec2 u, vec3 n) {\n    return n;\n}\n"
                .into(),
        );
        let stubs: Vec<WorkshopFunction> = user.stubs.iter().map(|(f, _)| *f).collect();
        assert_eq!(
            stubs,
            [
                WorkshopFunction::RayTriangleIntersection,
                WorkshopFunction::SampleSphere
            ]
        );
        assert_eq!(user.stubs[0].1, "return false;");
        user.display_name = "a.glsl + b.glsl".into();
        user.sources = vec![
            SourceFile {
                name: "a.glsl".into(),
                first_line: 1,
            },
            SourceFile {
                name: "b.glsl".into(),
                first_line: 4,
            },
        ];
        assert_eq!(user.locate(5), ("b.glsl".into(), 2));
        assert_eq!(
            user.localize("line 2: x; a.glsl + b.glsl:7: error: 'f' : undeclared identifier"),
            "a.glsl:2: x; b.glsl:4: error: 'f' : undeclared identifier"
        );
        // sample_sphere is declared in the text, helper is not.
        assert_eq!(
            user.undefined_names(
                "b.glsl:4: error: 'helper' : no matching overloaded function found\n\
                 b.glsl:5: error: 'sample_sphere' : undeclared identifier"
            ),
            Some("'helper' is".into())
        );
    }
}
