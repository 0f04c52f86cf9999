//! Hostile inputs, continued: messages that name the true cause and the
//! place, and echo nothing that could drive a terminal.

use crate::untrusted::refused;
use crate::{load_scene, parse_scene};
use gridrt_bbox::Real;
use gridrt_tracer::Geometry;
use std::path::Path;

fn err(text: &str) -> String {
    parse_scene(text, Path::new("t.ron"))
        .unwrap_err()
        .to_string()
}

/// True when `Real` is f32 (values beyond ±3.4e38 do not fit).
fn f32_build() -> bool {
    std::mem::size_of::<Real>() == 4
}

#[test]
fn values_are_blamed_where_they_are() {
    let e = err("(objects: [\n  Sphere(center: (0,0,0), radius: 1),\n  Box(min: (1, 1, 1), max: (0, 2, 2)),\n])");
    assert!(e.starts_with("t.ron:3:7: objects[1]: box min"), "{e}");
    if f32_build() {
        let e = err("(objects: [\n  Sphere(center: (0,0,0), radius: 1e39),\n])");
        assert!(e.starts_with("t.ron:2:"), "{e}");
        assert!(e.contains("objects[0]: radius 1e39"), "{e}");
        assert!(!e.contains("camera"), "{e}");
        let e = err("(objects: [Box(min: (0,0,0), max: (1e300, 1, 1))])");
        assert!(
            e.contains("objects[0]: max (1e300, 1, 1) is beyond the range"),
            "{e}"
        );
        let e = err("(objects: [Sphere(center: (3e38,0,0), radius: 1), Sphere(center: (-3e38,0,0), radius: 1)])");
        assert!(e.contains("objects: the objects span more than"), "{e}");
        let e = err("(camera: Camera(eye: (3e38, 0, 0), look_at: (-3e38, 0, 0)),\n objects: [Sphere(center: (0,0,0), radius: 1)])");
        assert!(
            e.contains("camera: eye and look_at are too far apart"),
            "{e}"
        );
        assert!(!e.contains("same point"), "{e}");
    }
}

#[test]
fn a_huge_rotation_axis_rotates() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("t.obj"),
        "v 0 1 0\nv 0 2 0\nv 0 1 1\nf 1 2 3\n",
    )
    .unwrap();
    let scene = dir.path().join("s.ron");
    std::fs::write(
        &scene,
        "(objects: [Mesh(file: \"t.obj\", transform: [Rotate(axis: (1e300, 0, 0), degrees: 90)])])",
    )
    .unwrap();
    let s = load_scene(&scene).unwrap();
    let Geometry::Mesh(m) = &s.scene.objects[0].geometry else {
        panic!("not a mesh")
    };
    // (0, 1, 0) turns to (0, 0, 1): rotated, not scaled.
    let p = m.positions[0];
    assert!((p.y.abs() < 1e-5) && ((p.z - 1.0).abs() < 1e-5), "{p}");
}

#[test]
fn byte_order_marks_are_skipped() {
    let s = parse_scene(
        "\u{feff}(objects: [Sphere(center: (0,0,0), radius: 1)])",
        Path::new("t.ron"),
    )
    .unwrap();
    assert_eq!(s.scene.objects.len(), 1);
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("b.obj");
    std::fs::write(&obj, "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let m = gridrt_io::load_model(&obj).unwrap();
    assert_eq!(m.triangle_count(), 1);
    let r = gridrt_io::parse_rays("\u{feff}0,0,1,0,0,-1\n", Path::new("r.csv")).unwrap();
    assert_eq!(r.len(), 1);
}

#[test]
fn obj_and_mtl_edge_cases() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("m.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775808\n",
    )
    .unwrap();
    let e = gridrt_io::load_model(&obj).unwrap_err().to_string();
    assert!(
        e.contains("m.obj:4: face refers to vertex -9223372036854775808"),
        "{e}"
    );
    // A bare texture statement does not cost the OBJ its materials.
    std::fs::write(
        dir.path().join("m.mtl"),
        "newmtl red\nKd 1 0 0\nmap_Kd\nbump\n",
    )
    .unwrap();
    std::fs::write(
        &obj,
        "mtllib m.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let m = gridrt_io::load_model(&obj).unwrap();
    assert_eq!(m.materials.len(), 1, "{:?}", m.warnings);
    assert_eq!(m.materials[0].name, "red");
    // `usemtl` without a name is an error on its line; `mtllib` without a
    // file a warning.
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl\nf 1 2 3\n").unwrap();
    let e = gridrt_io::load_model(&obj).unwrap_err().to_string();
    assert!(e.contains("m.obj:4: `usemtl` needs"), "{e}");
    std::fs::write(&obj, "mtllib\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let m = gridrt_io::load_model(&obj).unwrap();
    assert!(
        m.warnings.iter().any(|w| w.contains("names no file")),
        "{:?}",
        m.warnings
    );
}

#[test]
fn control_characters_are_escaped_in_messages() {
    let dir = tempfile::tempdir().unwrap();
    let root = std::fs::canonicalize(dir.path()).unwrap();
    let s = root.join("s.ron");
    std::fs::write(
        &s,
        "(objects: [Sphere(center: (0,0,0), radius: 1, material: \"x\\u{1b}[2J\\nerror: forged\")])",
    )
    .unwrap();
    let e = refused(
        &["info", "s.ron"],
        &root,
        &root,
        &["unknown material", "\\u{1b}[2J\\nerror: forged"],
    );
    assert!(!e.contains('\u{1b}'), "{e:?}");
}

#[test]
fn a_large_scene_is_read_without_a_quadratic_search() {
    // 40k objects on one line (2 MB), with the error at the end: the place
    // is found by one pass over the text.
    let mut text = String::from("(objects: [");
    for _ in 0..40_000 {
        text.push_str("Sphere(center: (0, 0, 0), radius: 1, material: \"m\"), ");
    }
    text.push_str("Box(min: (1, 1, 1), max: (0, 0, 0))], materials: {\"m\": Matte()})");
    let e = err(&text);
    assert!(e.starts_with("t.ron:1:"), "{}", &e[..80.min(e.len())]);
    assert!(
        e.contains("objects[40000]: box min"),
        "{}",
        &e[..200.min(e.len())]
    );
}
