//! Every RON example in `docs/scene-format.md` is valid: whole scenes parse
//! as they are, fragments parse inside a minimal scene. Keeps the page and
//! the schema in step.

use crate::fixture;
use crate::parse_scene;

const SPHERE: &str = "Sphere(center: (0, 0, 0), radius: 1)";

/// The ```ron blocks of the page.
fn ron_blocks(md: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut cur: Option<String> = None;
    for line in md.lines() {
        match (&mut cur, line.trim_start()) {
            (None, l) if l.starts_with("```ron") => cur = Some(String::new()),
            (Some(_), l) if l.starts_with("```") => blocks.extend(cur.take()),
            (Some(b), _) => {
                b.push_str(line);
                b.push('\n');
            }
            _ => {}
        }
    }
    blocks
}

/// The first token of a block that is not a comment.
fn head(block: &str) -> &str {
    block
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with("//"))
        .unwrap_or("")
}

/// A scene that contains the fragment, by what the fragment starts with.
fn wrap(block: &str) -> Vec<String> {
    let h = head(block);
    let scene = |inner: &str| format!("Scene(\n{inner}\n)");
    if h.starts_with("Scene(") || h.starts_with('(') {
        vec![block.to_string()]
    } else if h.starts_with("projection:") {
        block
            .lines()
            .filter(|l| l.trim_start().starts_with("projection:"))
            .map(|l| {
                scene(&format!(
                    "camera: Camera(eye: (0, 0, 5), look_at: (0, 0, 0), {}), objects: [{SPHERE}],",
                    l.split("//").next().unwrap_or(l).trim()
                ))
            })
            .collect()
    } else if ["camera:", "settings:", "lights:", "materials:"]
        .iter()
        .any(|k| h.starts_with(k))
    {
        vec![scene(&format!("{block}\nobjects: [{SPHERE}],"))]
    } else if ["Translate(", "Scale(", "Rotate(", "Euler(", "Matrix("]
        .iter()
        .any(|k| h.starts_with(k))
    {
        vec![scene(&format!(
            "objects: [Mesh(file: \"../meshes/cube/cube.obj\", transform: [\n{block}\n])],"
        ))]
    } else {
        // An object, with the materials the examples name.
        vec![scene(&format!(
            "materials: {{ \"red\": Matte(), \"floor\": Matte(), \"steel\": Matte(), \"glass\": Dielectric() }},\n\
             objects: [\n{block}\n{SPHERE}],"
        ))]
    }
}

#[test]
fn every_example_in_the_scene_format_page_parses() {
    let md = std::fs::read_to_string(fixture("../docs/scene-format.md")).unwrap();
    let blocks = ron_blocks(&md);
    assert!(blocks.len() >= 12, "found {} ron blocks", blocks.len());
    // Relative mesh paths resolve as if the scene were in fixtures/scenes.
    let path = fixture("scenes/doc-example.ron");
    let mut failures = Vec::new();
    for (i, b) in blocks.iter().enumerate() {
        for text in wrap(b) {
            if let Err(e) = parse_scene(&text, &path) {
                failures.push(format!("block {i} ({}): {e}\n{text}", head(b)));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
