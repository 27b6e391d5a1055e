//! Whether a ShaderToy program renders the workshop's scene, read from its text before it
//! runs: the `program` verdict compares it with vkpath's render of the Cornell box, which
//! means something only for a program whose `mainImage` traces with `get_ray_radiance`,
//! whose `get_ray_radiance` finds its hits with `ray_mesh_intersection` (where the
//! workshop's tab holds the Cornell box), and whose tracing reads no texture (a scene of its
//! own, such as a height field in `iChannel0`). What the text cannot show (the running mean,
//! an image that never changes) is found from the frames (`crate::check::program`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use crate::glsl_intake::functions::find_functions;
use crate::glsl_intake::syntax::tokenize;

/// A function definition of one of the tabs: what it calls and which channels it reads.
#[derive(Clone, Debug, Default)]
struct Body {
    /// The names it calls (identifiers followed by `(`).
    calls: BTreeSet<String>,
    /// The first `iChannelN` it reads: (name, file, line).
    channel: Option<(String, String, usize)>,
}

/// Every function defined in `tabs`, by name (a name defined in several tabs, as two passes
/// may, merges what its definitions do).
fn bodies(tabs: &[(PathBuf, String)]) -> BTreeMap<String, Body> {
    let mut bodies: BTreeMap<String, Body> = BTreeMap::new();
    for (path, text) in tabs {
        let tokens = tokenize(text);
        for function in find_functions(text).into_iter().filter(|f| f.has_body) {
            let inside: Vec<_> = tokens
                .iter()
                .filter(|t| !t.in_directive && function.span.contains(&t.start))
                .collect();
            let body = bodies.entry(function.name.clone()).or_default();
            for pair in inside.windows(2) {
                if pair[0].is_identifier() && pair[1].text == "(" && pair[0].text != function.name {
                    body.calls.insert(pair[0].text.clone());
                }
            }
            if body.channel.is_none() {
                body.channel = inside
                    .iter()
                    .find(|t| is_channel(&t.text))
                    .map(|t| (t.text.clone(), path.display().to_string(), t.line));
            }
        }
    }
    bodies
}

/// Whether a name is one of ShaderToy's `iChannel0`–`3`.
fn is_channel(name: &str) -> bool {
    name.strip_prefix("iChannel")
        .is_some_and(|n| n.len() == 1 && n.as_bytes()[0].is_ascii_digit())
}

/// The functions defined in `bodies` that `from` calls, directly or not (`from` included
/// when it is defined).
fn reachable(bodies: &BTreeMap<String, Body>, from: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut stack = vec![from.to_string()];
    while let Some(name) = stack.pop() {
        let Some(body) = bodies.get(&name) else {
            continue;
        };
        if seen.insert(name) {
            stack.extend(body.calls.iter().cloned());
        }
    }
    seen
}

/// Why the program of `tabs` (a `mainImage` among them, `get_ray_radiance` named in them)
/// does not render the workshop's scene, read from its text; `None` when it may (then the
/// frames tell the rest).
pub fn not_the_workshops_scene(tabs: &[(PathBuf, String)]) -> Option<String> {
    let bodies = bodies(tabs);
    let from_main = reachable(&bodies, "mainImage");
    if !from_main.contains("get_ray_radiance") {
        return Some(
            "your mainImage never calls get_ray_radiance, so its image is not the workshop's \
             path-traced Cornell box (a colour of its own)"
                .into(),
        );
    }
    let tracing = reachable(&bodies, "get_ray_radiance");
    if let Some((name, file, line)) = tracing
        .iter()
        .filter_map(|f| bodies.get(f).and_then(|b| b.channel.clone()))
        .min_by(|a, b| (&a.1, a.2).cmp(&(&b.1, b.2)))
    {
        return Some(format!(
            "your get_ray_radiance reads {name} as a texture ({file}:{line}), so it traces a \
             scene of its own, not the workshop's Cornell box"
        ));
    }
    if !tracing.contains("ray_mesh_intersection") {
        return Some(
            "your get_ray_radiance never calls ray_mesh_intersection (where the workshop's tab \
             holds the Cornell box), so it traces a scene of its own"
                .into(),
        );
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tabs(text: &str) -> Vec<(PathBuf, String)> {
        vec![(PathBuf::from("tab.glsl"), text.to_string())]
    }

    const TRACER: &str = "bool ray_mesh_intersection(out float t) { t = 1.0; return true; }\n\
        vec3 get_ray_radiance(vec3 o, vec3 d, inout uvec2 seed) { float t; ray_mesh_intersection(t); return vec3(t); }\n";

    #[test]
    fn the_workshops_shape_is_taken() {
        let text = format!(
            "{TRACER}void mainImage(out vec4 c, in vec2 p) {{ uvec2 s; c.rgb = get_ray_radiance(vec3(0), vec3(1), s);\n\
             c.rgb = mix(texture(iChannel0, p / iResolution.xy).rgb, c.rgb, 1.0 / float(iFrame + 1)); }}\n"
        );
        assert_eq!(not_the_workshops_scene(&tabs(&text)), None);
    }

    #[test]
    fn a_constant_colour_is_not_the_workshops_scene() {
        let text = format!("{TRACER}void mainImage(out vec4 c, in vec2 p) {{ c = vec4(0.5); }}\n");
        let reason = not_the_workshops_scene(&tabs(&text)).expect("a reason");
        assert!(reason.contains("never calls get_ray_radiance"), "{reason}");
    }

    #[test]
    fn a_height_field_in_a_channel_is_a_scene_of_its_own() {
        let text = "float height(vec2 p) { return texture(iChannel0, p).r; }\n\
             vec3 get_ray_radiance(vec3 o, vec3 d) { return vec3(height(o.xz)); }\n\
             void mainImage(out vec4 c, in vec2 p) { c.rgb = get_ray_radiance(vec3(0), vec3(1)); }\n";
        let reason = not_the_workshops_scene(&tabs(text)).expect("a reason");
        assert!(
            reason.contains("reads iChannel0 as a texture (tab.glsl:1)"),
            "{reason}"
        );
        let own = "vec3 get_ray_radiance(vec3 o, vec3 d) { return d; }\n\
             void mainImage(out vec4 c, in vec2 p) { c.rgb = get_ray_radiance(vec3(0), vec3(1)); }\n";
        let reason = not_the_workshops_scene(&tabs(own)).expect("a reason");
        assert!(
            reason.contains("never calls ray_mesh_intersection"),
            "{reason}"
        );
    }
}
