//! Hostile inputs, continued: budgets, glTF files the gltf crate would
//! panic on, and outputs that must survive every failure byte for byte.

use crate::untrusted::{gridrt, refused, snapshot, stderr, triangle_bytes};
use std::path::Path;

const SPHERE: &str =
    "(objects: [Sphere(center: (0, 0, 0), radius: 1)], settings: Settings(width: 8, height: 6))";

/// A glTF file around `extra` JSON members, with one triangle in a data:
/// URI buffer.
fn gltf(extra: &str) -> String {
    let b64 = base64_of(&triangle_bytes());
    format!(
        r#"{{"asset": {{"version": "2.0"}},
  "buffers": [{{"uri": "data:application/octet-stream;base64,{b64}", "byteLength": 36}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  {extra}}}"#
    )
}

fn base64_of(bytes: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

fn dir() -> (tempfile::TempDir, std::path::PathBuf) {
    let d = tempfile::tempdir().unwrap();
    let p = std::fs::canonicalize(d.path()).unwrap();
    (d, p)
}

#[test]
fn a_camera_without_its_projection_is_an_error_not_a_panic() {
    let (_d, dir) = dir();
    let f = dir.join("cam.gltf");
    std::fs::write(
        &f,
        gltf(
            r#""cameras": [{"type": "orthographic", "perspective": {"yfov": 1, "znear": 0.1}}],
  "nodes": [{"mesh": 0}, {"camera": 0}], "scenes": [{"nodes": [0, 1]}], "scene": 0"#,
        ),
    )
    .unwrap();
    for cmd in ["info", "render"] {
        refused(
            &[cmd, f.to_str().unwrap(), "-o", "x.png"][..if cmd == "info" { 2 } else { 4 }],
            &dir,
            &dir,
            &["cam.gltf: camera 0: its `type` does not name a projection it has"],
        );
    }
    // Through a scene, too.
    let s = dir.join("s.ron");
    std::fs::write(&s, "(objects: [Mesh(file: \"cam.gltf\")])").unwrap();
    refused(&["info", s.to_str().unwrap()], &dir, &dir, &["camera 0"]);
}

#[test]
fn node_graphs_are_counted_before_they_are_walked() {
    let (_d, dir) = dir();
    // Node i has children [i+1, i+1]: 2^61 paths to the last node.
    let nodes: Vec<String> = (0..60)
        .map(|i| format!("{{\"children\": [{}, {}]}}", i + 1, i + 1))
        .chain(std::iter::once("{\"mesh\": 0}".to_string()))
        .collect();
    let f = dir.join("dag.gltf");
    std::fs::write(
        &f,
        gltf(&format!(
            "\"nodes\": [{}], \"scenes\": [{{\"nodes\": [0]}}]",
            nodes.join(",")
        )),
    )
    .unwrap();
    refused(
        &["info", f.to_str().unwrap()],
        &dir,
        &dir,
        &["dag.gltf: the node graph expands to", "--max-nodes"],
    );
    // 2000 instances of one mesh: within the node limit, over a primitive
    // limit of 1000 (its one triangle stored once, plus one primitive per
    // placement).
    let nodes: Vec<&str> = vec!["{\"mesh\": 0}"; 2000];
    let roots: Vec<String> = (0..2000).map(|i| i.to_string()).collect();
    let f = dir.join("many.gltf");
    std::fs::write(
        &f,
        gltf(&format!(
            "\"nodes\": [{}], \"scenes\": [{{\"nodes\": [{}]}}]",
            nodes.join(","),
            roots.join(",")
        )),
    )
    .unwrap();
    refused(
        &["info", f.to_str().unwrap(), "--max-primitives", "1000"],
        &dir,
        &dir,
        &[
            "many.gltf: the scene expands to at least 2001 primitives",
            "--max-primitives",
        ],
    );
    let o = gridrt(&["info", f.to_str().unwrap()], &dir);
    assert!(o.status.success(), "{}", stderr(&o));
    // A cycle.
    let f = dir.join("cycle.gltf");
    std::fs::write(
        &f,
        gltf(r#""nodes": [{"children": [1]}, {"children": [0], "mesh": 0}], "scenes": [{"nodes": [0]}]"#),
    )
    .unwrap();
    refused(&["info", f.to_str().unwrap()], &dir, &dir, &["cyclic"]);
}

#[test]
fn generated_and_repeated_objects_are_counted_before_they_exist() {
    let (_d, dir) = dir();
    let s = dir.join("big.ron");
    let objs = "RandomSpheres(count: 10000000),\n".repeat(20);
    std::fs::write(&s, format!("(objects: [\n{objs}])")).unwrap();
    refused(
        &["info", s.to_str().unwrap()],
        &dir,
        &dir,
        &[
            "big.ron:3:1: objects[1]",
            "at least 20000000 primitives",
            "--max-primitives",
        ],
    );
    // 2000 objects naming one model: read once and shared, its triangle
    // counted once and each placement as one primitive (1 + 1500 > 1500).
    std::fs::write(dir.join("t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let objs = "Mesh(file: \"t.obj\"),".repeat(2000);
    std::fs::write(&s, format!("(objects: [{objs}])")).unwrap();
    refused(
        &["info", s.to_str().unwrap(), "--max-primitives", "1500"],
        &dir,
        &dir,
        &["objects[1499]", "--max-primitives"],
    );
    let o = gridrt(&["info", s.to_str().unwrap()], &dir);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn outputs_never_replace_inputs_devices_or_each_other() {
    let (_d, dir) = dir();
    let s = dir.join("s.ron");
    std::fs::write(&s, SPHERE).unwrap();
    std::fs::write(dir.join("old.png"), "old image").unwrap();
    let sp = s.to_str().unwrap();
    refused(
        &[sp, "-o", "old.png", "--stats", "old.png"],
        &dir,
        &dir,
        &["--stats and -o name the same file"],
    );
    refused(
        &[sp, "-o", "old.png", "--stats", "s.ron"],
        &dir,
        &dir,
        &["--stats names an input of this run"],
    );
    refused(
        &[sp, "-o", "old.png", "--stats", "/dev/null"],
        &dir,
        &dir,
        &["/dev/null: is a special file"],
    );
    refused(
        &[sp, "-o", "old.png", "--stats", "."],
        &dir,
        &dir,
        &["is a directory"],
    );
    // A mesh read by the scene is an input too.
    std::fs::write(dir.join("t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(dir.join("m.ron"), "(objects: [Mesh(file: \"t.obj\")])").unwrap();
    refused(
        &["m.ron", "-o", "old.png", "--stats", "t.obj"],
        &dir,
        &dir,
        &["names an input"],
    );
    // rays -o naming the mesh or the rays file.
    std::fs::write(dir.join("r.csv"), "0.2,0.2,1,0,0,-1\n").unwrap();
    refused(
        &["rays", "t.obj", "r.csv", "-o", "t.obj"],
        &dir,
        &dir,
        &["-o names an input"],
    );
    refused(
        &["rays", "t.obj", "r.csv", "-o", "./r.csv"],
        &dir,
        &dir,
        &["-o names an input"],
    );
    refused(
        &["rays", "t.obj", "r.csv", "-o", "/dev/null"],
        &dir,
        &dir,
        &["is a special file"],
    );
}

/// Runs gridrt under a file-size limit of `blocks` (of 512 or 1024 bytes,
/// as the shell counts them): SIGXFSZ must not kill it.
#[cfg(unix)]
fn under_file_limit(blocks: u32, args: &[&str], cwd: &Path) -> std::process::Output {
    let bin = env!("CARGO_BIN_EXE_gridrt");
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    std::process::Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -f {blocks}; exec '{bin}' {}",
            quoted.join(" ")
        ))
        .current_dir(cwd)
        .output()
        .unwrap()
}

#[cfg(unix)]
#[test]
fn a_file_size_limit_is_an_error_and_keeps_the_old_files() {
    let (_d, dir) = dir();
    let s = dir.join("s.ron");
    std::fs::write(&s, SPHERE).unwrap();
    std::fs::write(dir.join("old.png"), "old image").unwrap();
    std::fs::write(dir.join("old.json"), "old stats").unwrap();
    let before = snapshot(&dir);
    // The image is too large for one block.
    let o = under_file_limit(1, &["s.ron", "-o", "old.png", "--width", "300"], &dir);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("old.png: cannot write: File too large"), "{e}");
    assert_eq!(snapshot(&dir), before);
    // The small image fits but the statistics do not: neither is replaced.
    let o = under_file_limit(1, &["s.ron", "-o", "old.png", "--stats", "old.json"], &dir);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("old.json: cannot write: File too large"), "{e}");
    assert_eq!(snapshot(&dir), before);
}

#[test]
fn a_shared_sparse_accessor_without_a_view_is_read_once_and_counted() {
    let (_d, dir) = dir();
    // 3 million zero positions from a sparse accessor without a buffer
    // view, used by 50 primitives of one mesh: decoded once; the 50
    // million triangles they make are over the default budget before any
    // is made.
    let prims: Vec<&str> = vec![r#"{"attributes": {"POSITION": 1}}"#; 50];
    let f = dir.join("sparse.gltf");
    let text = gltf(r#""nodes": [{"mesh": 1}], "scenes": [{"nodes": [0]}]"#)
    .replace(
        r#""meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]"#,
        &format!(
            r#""meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}, {{"primitives": [{}]}}]"#,
            prims.join(",")
        ),
    )
    .replace(
        r#""accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}]"#,
        r#""accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
          {"componentType": 5126, "count": 3000000, "type": "VEC3",
           "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5125},
                      "values": {"bufferView": 0}}}]"#,
    );
    std::fs::write(&f, text).unwrap();
    refused(
        &["info", f.to_str().unwrap()],
        &dir,
        &dir,
        &[
            "sparse.gltf: the scene expands to at least 50000000 primitives",
            "--max-primitives",
        ],
    );
}
