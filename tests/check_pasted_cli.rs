//! `vkpath check` on files as attendees publish their functions (issue 58): a Markdown post
//! with front matter, HTML and prose around a fenced GLSL block, notes with snippets and
//! prose between the functions, a snippet whose `{` is never closed, LaTeX in prose, GLSL
//! inside a TypeScript template string. The inputs (tests/solutions/pasted/) were written
//! for these tests in the shapes of published files. Judged functions are cheap ones
//! (PCG2D bit for bit, a χ² test, an intersection), so each run takes a few seconds.

use crate::common;

use serde_json::Value;

fn pasted(name: &str) -> String {
    format!(
        "{}/tests/solutions/pasted/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// Checks `name` with `--json`, expects exit status `exit` and returns the report.
fn check_json(name: &str, exit: i32) -> Value {
    let dir = tempfile::tempdir().expect("temporary directory");
    let outcome = common::runs::check(dir.path(), &[pasted(name)], &["--json"], &[]);
    assert_eq!(
        outcome.code,
        Some(exit),
        "{name}: {}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    outcome.json()
}

/// The (function, passed) of each verdict.
fn verdicts(report: &Value) -> Vec<(String, bool)> {
    report["functions"]
        .as_array()
        .expect("functions")
        .iter()
        .map(|f| {
            (
                f["function"].as_str().expect("name").to_string(),
                f["passed"].as_bool().expect("verdict"),
            )
        })
        .collect()
}

/// The report's notes as one text.
fn notes(report: &Value) -> String {
    report["notes"]
        .as_array()
        .expect("notes")
        .iter()
        .map(|n| n.as_str().unwrap_or_default())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn a_markdown_post_is_judged_from_its_glsl_block() {
    // Before: the opening fence ran into sample_sphere's definition, which failed to
    // compile ("'`' : unexpected token"), exit 1 for a correct function.
    let report = check_json("blog_post.md", 1);
    assert_eq!(
        verdicts(&report),
        [
            ("sample_sphere".to_string(), true),
            ("sample_hemisphere".to_string(), false)
        ],
        "{report:#}"
    );
    let hemisphere = common::runs::verdict(&report, "sample_hemisphere").expect("verdict");
    assert_eq!(hemisphere["method"], "compile", "{hemisphere:#}");
    // Its own line in the post, not the fence's.
    assert_eq!(hemisphere["line"], 27, "{hemisphere:#}");
    let notes = notes(&report);
    assert!(
        notes.contains("blog_post.md:1: dropped the front matter")
            && notes.contains("blog_post.md:18: read as Markdown")
            && notes.contains("dropped a ```bash block"),
        "{notes}"
    );
    assert!(report["compile_errors"].is_null(), "{report:#}");
}

#[test]
fn notes_with_twenty_snippets_between_the_functions_lose_only_the_snippets() {
    // Before: one compile round dropped one snippet, at most 12 rounds, and then "too many
    // functions do not compile": nothing was judged.
    let report = check_json("notes_between_functions.glsl", 0);
    assert_eq!(
        verdicts(&report),
        [
            ("get_random_numbers".to_string(), true),
            ("ray_triangle_intersection".to_string(), true)
        ],
        "{report:#}"
    );
    let notes = notes(&report);
    assert!(
        notes.contains("notes_between_functions.glsl:5: dropped 2 lines from 'Exercise 1' on (prose, not GLSL)")
            && notes.contains("notes_between_functions.glsl:7: dropped 'seed = uvec2(pixel_coord)")
            && notes.contains("notes_between_functions.glsl:31: dropped 'for (int i = 0; i != TRIANGLE_COUNT; ++i)")
            && notes.contains("(a statement or text outside any function"),
        "{notes}"
    );
}

#[test]
fn an_open_brace_latex_or_a_script_string_hides_no_definition() {
    // Before, each was "defines none of the workshop functions" (exit 2): the snippet's `{`
    // was never closed, the LaTeX's braces made the definition part of the prose, the
    // object literal's `{` around the template string held everything.
    let cases: [(&str, &[&str]); 3] = [
        (
            "unclosed_snippet.glsl",
            &[
                "unclosed_snippet.glsl:3: dropped 'for (int i = 0; i != SAMPLE_COUNT; ++i) {",
                "its '{' is never closed before the definition at ",
                "unclosed_snippet.glsl:7)",
            ],
        ),
        (
            "latex_notes.glsl",
            &[
                "latex_notes.glsl:2: dropped 'Monte Carlo: $$L",
                "(characters GLSL does not have, not GLSL)",
            ],
        ),
        (
            "shaders.ts",
            &[
                "shaders.ts:7: GLSL inside a JS/TS template string: the text of its 1 GLSL string is read",
                "each of the 1 ${...} in it blanked",
            ],
        ),
    ];
    for (name, expected) in cases {
        let report = check_json(name, 0);
        assert_eq!(
            verdicts(&report),
            [("get_random_numbers".to_string(), true)],
            "{name}: {report:#}"
        );
        let notes = notes(&report);
        for part in expected {
            assert!(notes.contains(part), "{name}: {part}\n{notes}");
        }
    }
}
