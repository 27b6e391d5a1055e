//! Leaving out the code that needs what check cannot supply (`PreparedSource::unavailable`:
//! the user's sampler and image uniforms, ShaderToy's `iChannel0`–`3`, ray queries), so that
//! the rest of the file is judged.
//!
//! A function needs a name when its body reads it, or when it calls one of the user's
//! helper functions that needs it (a workshop function it calls is the reference version in
//! the kernel that judges another, so needs do not pass through workshop functions). Every
//! function that needs an unavailable name is blanked out of the prepared text: a workshop
//! function is then not judged, naming what it reads, and a helper is listed in a note.

use std::collections::{BTreeMap, BTreeSet};

use crate::check::detect::WorkshopFunction;
use crate::glsl_intake::syntax::{structural_tokens, tokenize, top_level_items};
use crate::glsl_intake::{PreparedSource, Unavailable};

/// A function left out because it needs an unavailable name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LeftOut {
    /// The function's name in the prepared text.
    pub name: String,
    /// Its line (from 1).
    pub line: usize,
    /// Why, in words: what it reads, and through which helper.
    pub reason: String,
}

/// Blanks every function of `prepared.text` that needs an unavailable name (prototypes
/// too) and returns them, in the order of the file. `workshop_of` maps a function's name to
/// the workshop function it stands for, if any.
pub fn leave_out_unavailable(
    prepared: &mut PreparedSource,
    workshop_of: impl Fn(&str) -> Option<WorkshopFunction>,
) -> Vec<LeftOut> {
    if prepared.unavailable.is_empty() {
        return Vec::new();
    }
    let tokens = structural_tokens(&tokenize(&prepared.text));
    let items = top_level_items(&tokens);
    // Each function's name, line, byte range and the identifiers it references.
    let mut functions: Vec<(String, usize, std::ops::Range<usize>, BTreeSet<String>)> = Vec::new();
    for item in &items {
        let Some(name) = item.name else { continue };
        let referenced: BTreeSet<String> = tokens[item.first..=item.last]
            .iter()
            .enumerate()
            .filter(|(index, t)| t.is_identifier() && item.first + index != name)
            .map(|(_, t)| t.text.clone())
            .collect();
        functions.push((
            tokens[name].text.clone(),
            tokens[name].line,
            tokens[item.first].start..tokens[item.last].end,
            referenced,
        ));
    }
    let defined: BTreeSet<&str> = functions
        .iter()
        .filter(|(name, ..)| workshop_of(name).is_none())
        .map(|(name, ..)| name.as_str())
        .collect();
    // needs[f] = (the unavailable name, the helper through which), to a fixed point.
    let mut needs: BTreeMap<String, (Unavailable, Option<String>)> = BTreeMap::new();
    loop {
        let mut changed = false;
        for (name, _, _, referenced) in &functions {
            if needs.contains_key(name) {
                continue;
            }
            let direct = prepared
                .unavailable
                .iter()
                .find(|u| referenced.contains(&u.name))
                .map(|u| (u.clone(), None));
            let through = || {
                referenced
                    .iter()
                    .filter(|r| defined.contains(r.as_str()) && *r != name)
                    .find_map(|helper| {
                        needs
                            .get(helper)
                            .map(|(u, _)| (u.clone(), Some(helper.clone())))
                    })
            };
            if let Some(need) = direct.or_else(through) {
                needs.insert(name.clone(), need);
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let mut left_out = Vec::new();
    let mut ranges = Vec::new();
    for (name, line, range, _) in &functions {
        let Some((unavailable, helper)) = needs.get(name) else {
            continue;
        };
        ranges.push(range.clone());
        if left_out.iter().any(|l: &LeftOut| l.name == *name) {
            continue;
        }
        let through = helper
            .as_ref()
            .map(|h| format!(" (through your {h})"))
            .unwrap_or_default();
        let reason = if unavailable.what.contains("ray queries")
            || unavailable.what.starts_with("ShaderToy's")
        {
            format!("it uses {}{through}", unavailable.what)
        } else if unavailable.what.contains("accelerationStructure") {
            format!(
                "it uses ray queries (GL_EXT_ray_query) on '{}' (line {}){through}, which check cannot run",
                unavailable.what, unavailable.line
            )
        } else {
            format!(
                "it reads '{}' (line {}){through}, data that only your program has; check cannot judge it without that data",
                unavailable.what, unavailable.line
            )
        };
        left_out.push(LeftOut {
            name: name.clone(),
            line: *line,
            reason,
        });
    }
    for range in ranges {
        let blank: String = prepared.text[range.clone()]
            .chars()
            .map(|c| if c == '\n' { '\n' } else { ' ' })
            .collect();
        prepared.text.replace_range(range, &blank);
    }
    left_out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::user_functions::check_intake_options;
    use crate::glsl_intake::prepare_with;

    #[test]
    fn what_reads_a_texture_is_left_out_and_the_rest_stays() {
        let source = "uniform sampler2D u_scene;\n\
            vec4 fetch(int i) { return texelFetch(u_scene, ivec2(i, 0), 0); }\n\
            vec3 scene_normal(int i) { return fetch(i).xyz; }\n\
            vec3 sample_sphere(vec2 u) { return vec3(u, 1.0); }\n\
            bool ray_mesh_intersection(out float t, out triangle_t tri, vec3 o, vec3 d) { t = scene_normal(0).x; return false; }\n";
        let mut prepared = prepare_with(source, &check_intake_options());
        assert_eq!(prepared.unavailable.len(), 1, "{:?}", prepared.unavailable);
        let left_out = leave_out_unavailable(&mut prepared, WorkshopFunction::from_name);
        let names: Vec<&str> = left_out.iter().map(|l| l.name.as_str()).collect();
        assert_eq!(names, ["fetch", "scene_normal", "ray_mesh_intersection"]);
        assert!(left_out[2].reason.contains("u_scene"), "{:?}", left_out[2]);
        assert!(left_out[2].reason.contains("through your scene_normal"));
        assert!(prepared.text.contains("vec3 sample_sphere"));
        assert!(!prepared.text.contains("texelFetch"));
        assert_eq!(prepared.text.lines().count(), source.lines().count());
    }
}
