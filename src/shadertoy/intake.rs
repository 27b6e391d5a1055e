//! A pasted tab made ready to run as a pass: what a compute kernel cannot take is blanked
//! (`#version`, `#extension`, `precision`, declarations of the inputs the pass kernel
//! supplies), and a page shader's `main()` with `gl_FragCoord`/`gl_FragColor` (or an `out
//! vec4`) becomes a function the kernel calls once per pixel. Every line stays where it was,
//! so the compiler's line numbers are the user's.

use crate::check::glsl_syntax::{tokenize, Token};

/// ShaderToy's inputs, which the pass kernel declares (a tab that declares them itself, as
/// exported or page-shader files do, has its declarations dropped).
const SUPPLIED_INPUTS: [&str; 14] = [
    "iResolution",
    "iTime",
    "iTimeDelta",
    "iFrameRate",
    "iFrame",
    "iMouse",
    "iDate",
    "iSampleRate",
    "iChannelResolution",
    "iChannelTime",
    "iChannel0",
    "iChannel1",
    "iChannel2",
    "iChannel3",
];

/// A tab ready to be included by the pass kernel.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PreparedTab {
    /// The text with what cannot take part blanked, lines where they were.
    pub text: String,
    /// What goes before it (declarations the kept code needs).
    pub prelude: String,
    /// What was dropped or changed, one line each ("line 3: …").
    pub notes: Vec<String>,
    /// Whether the tab defines `mainImage`.
    pub has_main_image: bool,
    /// For a page shader (`main()` and no `mainImage`): the expression of its colour, its
    /// `out vec4` variable or `vkpath_FragColor` (its `gl_FragColor`).
    pub page_shader_output: Option<String>,
}

/// Replaces a byte range by spaces, keeping line breaks.
fn blank(text: &mut String, range: std::ops::Range<usize>) {
    let spaces: String = text[range.clone()]
        .chars()
        .map(|c| if c == '\n' { '\n' } else { ' ' })
        .collect();
    text.replace_range(range, &spaces);
}

/// The statement (up to and including `;`) that starts at token `first`.
fn statement_end(tokens: &[Token], first: usize) -> Option<usize> {
    tokens[first..]
        .iter()
        .position(|t| t.text == ";" && !t.in_directive)
        .map(|p| first + p)
}

/// Prepares a tab (see the module documentation). `is_common`: the Common tab, which has no
/// entry point.
pub fn prepare_tab(source: &str) -> PreparedTab {
    let tokens = tokenize(source);
    let mut prepared = PreparedTab {
        text: source.to_string(),
        ..PreparedTab::default()
    };
    // Edits as (range, replacement), applied back to front so that ranges stay valid.
    let mut blanks: Vec<std::ops::Range<usize>> = Vec::new();
    let mut renames: Vec<(std::ops::Range<usize>, String)> = Vec::new();
    let mut index = 0;
    while index < tokens.len() {
        let token = &tokens[index];
        if token.starts_directive {
            let word = tokens.get(index + 1).map(|t| t.text.as_str());
            let end = tokens[index + 1..]
                .iter()
                .position(|t| !t.in_directive || t.starts_directive)
                .map_or(tokens.len(), |p| index + 1 + p);
            if matches!(word, Some("version" | "extension")) {
                prepared.notes.push(format!(
                    "line {}: dropped #{} (vkpath compiles GLSL 4.60 for Vulkan)",
                    token.line,
                    word.unwrap_or_default()
                ));
                blanks.push(token.start..tokens[end - 1].end);
            }
            index = end;
            continue;
        }
        if token.in_directive {
            index += 1;
            continue;
        }
        let at_statement_start = index == 0
            || matches!(tokens[index - 1].text.as_str(), ";" | "}")
            || tokens[index - 1].in_directive;
        if at_statement_start && (token.text == "precision" || token.text == "uniform") {
            if let Some(end) = statement_end(&tokens, index) {
                let names_input = tokens[index..end]
                    .iter()
                    .any(|t| SUPPLIED_INPUTS.contains(&t.text.as_str()));
                if token.text == "precision" || names_input {
                    if names_input {
                        prepared.notes.push(format!(
                            "line {}: dropped your declaration of a ShaderToy input (vkpath supplies them)",
                            token.line
                        ));
                    }
                    blanks.push(token.start..tokens[end].end);
                    index = end + 1;
                    continue;
                }
                let is_block = tokens[index..end].iter().any(|t| t.text == "{");
                let is_opaque = tokens[index..end]
                    .iter()
                    .any(|t| t.text.starts_with("sampler") || t.text.starts_with("image"));
                if !is_block && !is_opaque {
                    prepared.notes.push(format!(
                        "line {}: your uniform {} is a plain global here (zero unless your code sets it)",
                        token.line,
                        tokens.get(end - 1).map_or("", |t| t.text.as_str())
                    ));
                    blanks.push(token.start..token.end);
                }
            }
        }
        if token.text == "mainImage" {
            prepared.has_main_image = true;
        }
        index += 1;
    }
    let defines_main = tokens
        .windows(3)
        .any(|w| w[0].text == "void" && w[1].text == "main" && w[2].text == "(");
    if !prepared.has_main_image && defines_main {
        let mut output = None;
        for (i, token) in tokens.iter().enumerate() {
            match token.text.as_str() {
                "main" if tokens.get(i + 1).is_some_and(|t| t.text == "(") => {
                    renames.push((token.start..token.end, "vkpath_user_main".into()));
                }
                "gl_FragCoord" => renames.push((token.start..token.end, "vkpath_FragCoord".into())),
                "gl_FragColor" => {
                    renames.push((token.start..token.end, "vkpath_FragColor".into()));
                    output.get_or_insert_with(|| "vkpath_FragColor".to_string());
                }
                "out"
                    if (i == 0 || matches!(tokens[i - 1].text.as_str(), ";" | "}" | ")"))
                        && tokens.get(i + 1).is_some_and(|t| t.text == "vec4")
                        && tokens.get(i + 3).is_some_and(|t| t.text == ";") =>
                {
                    // `out vec4 fragColor;` (also after a layout(...) qualifier).
                    blanks.push(token.start..token.end);
                    output = Some(tokens[i + 2].text.clone());
                    prepared.notes.push(format!(
                        "line {}: '{}' is your page shader's colour output",
                        token.line,
                        tokens[i + 2].text
                    ));
                }
                "layout" if tokens.get(i + 1).is_some_and(|t| t.text == "(") => {
                    // layout(location = 0) before an out variable
                    if let Some(close) = tokens[i..].iter().position(|t| t.text == ")") {
                        if tokens.get(i + close + 1).is_some_and(|t| t.text == "out") {
                            blanks.push(token.start..tokens[i + close].end);
                        }
                    }
                }
                _ => {}
            }
        }
        prepared.prelude =
            "vec4 vkpath_FragCoord = vec4(0.0);\nvec4 vkpath_FragColor = vec4(0.0);\n".into();
        prepared.page_shader_output = Some(output.unwrap_or_else(|| "vkpath_FragColor".into()));
        prepared.notes.push(
            "your main() runs once per pixel as the Image pass (gl_FragCoord at pixel centres)"
                .into(),
        );
    }
    let mut edits: Vec<(std::ops::Range<usize>, Option<String>)> = blanks
        .into_iter()
        .map(|r| (r, None))
        .chain(renames.into_iter().map(|(r, s)| (r, Some(s))))
        .collect();
    edits.sort_by_key(|(r, _)| std::cmp::Reverse(r.start));
    let mut last_start = usize::MAX;
    for (range, replacement) in edits {
        if range.end > last_start {
            continue;
        }
        last_start = range.start;
        match replacement {
            Some(text) => prepared.text.replace_range(range, &text),
            None => blank(&mut prepared.text, range),
        }
    }
    prepared
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_page_shader_becomes_a_function_with_its_output() {
        let source = "#version 300 es\nprecision highp float;\nuniform vec3 iResolution;\nout vec4 fragColor;\nvoid main() {\n    fragColor = vec4(gl_FragCoord.xy / iResolution.xy, 0.0, 1.0);\n}\n";
        let prepared = prepare_tab(source);
        assert_eq!(prepared.text.lines().count(), source.lines().count());
        assert!(prepared.text.contains("void vkpath_user_main()"));
        assert!(prepared.text.contains("vkpath_FragCoord.xy"));
        assert!(!prepared.text.contains("#version"));
        assert!(!prepared.text.contains("precision"));
        assert!(!prepared.text.contains("uniform"));
        assert!(!prepared.text.contains("out vec4"));
        assert_eq!(prepared.page_shader_output.as_deref(), Some("fragColor"));
    }

    #[test]
    fn a_shadertoy_tab_keeps_its_entry_point() {
        let source = "void mainImage(out vec4 c, in vec2 p) { c = vec4(p, 0.0, 1.0); }\n";
        let prepared = prepare_tab(source);
        assert!(prepared.has_main_image);
        assert_eq!(prepared.text, source);
        assert_eq!(prepared.page_shader_output, None);
    }
}
