//! The VS Code Shader Toy extension's channel directives, read from a tab's text:
//! `#iChannelN "TARGET"` (what the channel reads) and `#iChannelN::KEY "VALUE"` (its
//! settings, e.g. `::Type "CubeMap"`), as `crate::shadertoy::program` wires them.

/// The VS Code Shader Toy extension's channel directives of a tab, `#iChannelN "TARGET"`:
/// (line from 1, N, TARGET) each. The channels' settings (`#iChannelN::Type "CubeMap"`) are
/// `channel_settings`.
pub fn channel_directives(text: &str) -> Vec<(usize, usize, String)> {
    channel_lines(text)
        .filter(|(_, _, rest)| !rest.starts_with("::"))
        .map(|(line, channel, rest)| (line, channel, unquoted(rest)))
        .collect()
}

/// The extension's channel settings of a tab, `#iChannelN::KEY "VALUE"` (`Type`,
/// `MinFilter`, `MagFilter`, `WrapMode`): (line from 1, N, KEY, VALUE) each.
pub fn channel_settings(text: &str) -> Vec<(usize, usize, String, String)> {
    channel_lines(text)
        .filter_map(|(line, channel, rest)| {
            let setting = rest.strip_prefix("::")?;
            let (key, value) = setting.split_once(|c: char| c.is_whitespace() || c == '"')?;
            Some((line, channel, key.to_string(), unquoted(value)))
        })
        .collect()
}

/// The lines `#iChannelN…` of channels 0..3: (line from 1, N, the rest of the line).
fn channel_lines(text: &str) -> impl Iterator<Item = (usize, usize, &str)> {
    text.lines().enumerate().filter_map(|(index, line)| {
        let rest = line.trim_start().strip_prefix('#')?.trim_start();
        let rest = rest.strip_prefix("iChannel")?;
        let channel = rest.get(..1)?.parse::<usize>().ok().filter(|c| *c < 4)?;
        Some((index + 1, channel, rest[1..].trim()))
    })
}

/// A directive's value without its quotes and a trailing `// comment`.
fn unquoted(text: &str) -> String {
    let text = text.trim();
    let text = match text.strip_prefix('"') {
        Some(quoted) => quoted.split('"').next().unwrap_or(quoted),
        None => text.split("//").next().unwrap_or(text).trim(),
    };
    text.to_string()
}

/// File extensions of the extension's audio inputs.
pub const AUDIO_EXTENSIONS: [&str; 4] = ["mp3", "wav", "ogg", "flac"];

/// Whether `text` says its channel `channel` is a cube map (`#iChannelN::Type "CubeMap"`).
pub fn is_cube_map(text: &str, channel: usize) -> bool {
    channel_settings(text).iter().any(|(_, c, key, value)| {
        *c == channel && key == "Type" && value.eq_ignore_ascii_case("CubeMap")
    })
}

/// Whether a channel directive's target is the pass itself (`self`, as the extension's own
/// demos also write it, `file://self`).
pub fn is_self(target: &str) -> bool {
    target.strip_prefix("file://").unwrap_or(target) == "self"
}

/// The line (from 1) of the extension's `#iVertex` directive in `text`, if any.
pub fn vertex_shader_line(text: &str) -> Option<usize> {
    text.lines()
        .position(|line| {
            line.trim_start()
                .strip_prefix('#')
                .is_some_and(|rest| rest.trim_start().starts_with("iVertex"))
        })
        .map(|index| index + 1)
}

/// `text` with the extension's custom uniforms (`#iUniform float gain = 1.0 in { 0.0, 5.0 }`,
/// `#iUniform color3 tint = color3(1.0)`), which its preview edits with sliders, made
/// globals of their initial values (`float gain = 1.0;`, `color3` as `vec3`), each on its
/// line; with one note per uniform ("line N: …").
pub fn rewrite_custom_uniforms(text: &str) -> (String, Vec<String>) {
    let mut notes = Vec::new();
    let lines: Vec<String> = text
        .split('\n')
        .enumerate()
        .map(|(index, line)| {
            let Some(declaration) = custom_uniform(line) else {
                return line.to_string();
            };
            notes.push(format!(
                "line {}: #iUniform {}: its initial value (a headless run has no sliders)",
                index + 1,
                declaration.trim_end_matches(';')
            ));
            declaration
        })
        .collect();
    (lines.join("\n"), notes)
}

/// The global declaration of one `#iUniform TYPE NAME = VALUE [in {…}] [step …]` line.
fn custom_uniform(line: &str) -> Option<String> {
    let rest = line.trim_start().strip_prefix('#')?.trim_start();
    let rest = rest.strip_prefix("iUniform")?;
    let rest = rest.split("//").next().unwrap_or(rest);
    let (declared, value) = rest.split_once('=')?;
    let mut words = declared.split_whitespace();
    let (kind, name) = (words.next()?, words.next()?);
    if words.next().is_some() {
        return None;
    }
    let value = [" in ", " in{", " step "]
        .iter()
        .filter_map(|stop| value.find(stop))
        .min()
        .map_or(value, |end| &value[..end])
        .trim();
    if value.is_empty() {
        return None;
    }
    let glsl = |text: &str| text.replace("color3", "vec3").replace("color4", "vec4");
    Some(format!("{} {name} = {};", glsl(kind), glsl(value)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_directives_are_read_with_their_line() {
        let text = "// tab\n#iChannel0 \"self\"\n  # iChannel3 \"file://textures/noise.png\"\n#iChannel7 \"x\"\n";
        assert_eq!(
            channel_directives(text),
            [
                (2, 0, "self".to_string()),
                (3, 3, "file://textures/noise.png".to_string())
            ]
        );
    }

    #[test]
    fn channel_settings_are_apart_from_the_channels() {
        let text = "#iChannel0 \"file://cube/yokohama_{}.jpg\" // Note the wildcard '{}'\n#iChannel0::Type \"CubeMap\"\n#iChannel0::MinFilter \"LinearMipMapLinear\"\n";
        assert_eq!(
            channel_directives(text),
            [(1, 0, "file://cube/yokohama_{}.jpg".to_string())]
        );
        assert_eq!(
            channel_settings(text),
            [
                (2, 0, "Type".to_string(), "CubeMap".to_string()),
                (
                    3,
                    0,
                    "MinFilter".to_string(),
                    "LinearMipMapLinear".to_string()
                )
            ]
        );
        assert!(is_cube_map(text, 0) && !is_cube_map(text, 1));
    }

    /// `Program::from_files` on an Image tab of `text` (and Buffers A-D of `buffers` tabs
    /// that only write a colour), in a temporary folder.

    #[test]
    fn custom_uniforms_are_their_initial_values() {
        let text = "#iUniform float my_scalar = 1.0 in { 0.0, 5.0 } // a slider\n#iUniform color3 my_color = color3(1.0)\n  #iUniform float step_size = 1.0 in { 0.0, 5.0 } step 0.2\nfloat f;\n#iUniform broken\n";
        let (out, notes) = rewrite_custom_uniforms(text);
        assert_eq!(
            out,
            "float my_scalar = 1.0;\nvec3 my_color = vec3(1.0);\nfloat step_size = 1.0;\nfloat f;\n#iUniform broken\n"
        );
        assert_eq!(
            notes[1],
            "line 2: #iUniform vec3 my_color = vec3(1.0): its initial value (a headless run has no sliders)"
        );
        assert_eq!(notes.len(), 3);
    }
}
