//! The bad-input corpus `fixtures/bad/`: every file fails with a message
//! that names the file and the place and says what to fix. Never a panic.

use crate::fixture;
use crate::load_scene;
use gridrt_io::{parse_rays, Error};

/// (file in fixtures/bad, substrings the message must contain).
const CASES: &[(&str, &[&str])] = &[
    // RON scenes.
    ("ron_malformed.ron", &["ron_malformed.ron:4:", "comma"]),
    (
        "ron_unknown_field.ron",
        &[
            "ron_unknown_field.ron:4:",
            "unknown field `colour` in `Matte`",
            "`color`",
        ],
    ),
    (
        "ron_missing_mesh.ron",
        &[
            "ron_missing_mesh.ron:4:",
            "objects[0]",
            "no_such_mesh.obj: cannot read the file",
            "check the path",
        ],
    ),
    ("ron_not_utf8.ron", &["ron_not_utf8.ron:1:", "not UTF-8"]),
    (
        "ron_zero_width.ron",
        &[
            "ron_zero_width.ron:2:",
            "image size 0 is out of range",
            "1 to 16384",
        ],
    ),
    (
        "ron_huge_width.ron",
        &["ron_huge_width.ron:2:", "image size 100000 is out of range"],
    ),
    (
        "ron_too_many_pixels.ron",
        &["ron_too_many_pixels.ron:3:", "too large", "2^26"],
    ),
    (
        "ron_zero_spp.ron",
        &[
            "ron_zero_spp.ron:2:",
            "spp (samples per pixel) 0 is out of range",
        ],
    ),
    (
        "ron_negative_radius.ron",
        &[
            "ron_negative_radius.ron:3:",
            "expected a number > 0, found -1",
        ],
    ),
    (
        "ron_unknown_material.ron",
        &[
            "ron_unknown_material.ron:4:",
            "objects[0]",
            "unknown material \"blue\"",
            "defined: red",
        ],
    ),
    (
        "ron_duplicate_material.ron",
        &["ron_duplicate_material.ron:4:", "\"red\" is defined twice"],
    ),
    (
        "ron_empty_scene.ron",
        &["ron_empty_scene.ron:2:", "no objects"],
    ),
    (
        "ron_lens_without_focus.ron",
        &[
            "ron_lens_without_focus.ron:2:",
            "lens_radius",
            "focus_distance",
        ],
    ),
    (
        "ron_zero_focus_distance.ron",
        &["ron_zero_focus_distance.ron:2:", "expected a number > 0"],
    ),
    (
        "ron_conductor_two_fresnels.ron",
        &[
            "ron_conductor_two_fresnels.ron:2:",
            "\"metal\"",
            "color",
            "not both",
        ],
    ),
    (
        "ron_camera_eye_at_look_at.ron",
        &["ron_camera_eye_at_look_at.ron:2:", "camera", "same point"],
    ),
    (
        "ron_nan_coordinate.ron",
        &["ron_nan_coordinate.ron:2:", "finite coordinates"],
    ),
    (
        "ron_bad_override.ron",
        &[
            "ron_bad_override.ron:5:",
            "no material \"purple\"",
            "white, red, green, blue, light",
        ],
    ),
    (
        "ron_singular_transform.ron",
        &["ron_singular_transform.ron:5:", "singular"],
    ),
    (
        "ron_mesh_with_bad_obj.ron",
        &[
            "ron_mesh_with_bad_obj.ron:4:",
            "obj_index_out_of_range.obj:8:",
            "vertex 5",
        ],
    ),
    // OBJ and MTL.
    (
        "obj_index_out_of_range.obj",
        &[
            "obj_index_out_of_range.obj:8:",
            "face refers to vertex 5",
            "only 4 vertices",
        ],
    ),
    (
        "obj_nan_vertex.obj",
        &["obj_nan_vertex.obj:2:", "not finite"],
    ),
    (
        "obj_inf_vertex.obj",
        &["obj_inf_vertex.obj:3:", "not finite"],
    ),
    (
        "obj_zero_index.obj",
        &["obj_zero_index.obj:4:", "start at 1"],
    ),
    ("obj_no_faces.obj", &["obj_no_faces.obj:", "no triangles"]),
    (
        "obj_bad_mtl.obj",
        &["obj_bad_mtl.mtl:2:", "`Kd` needs a colour"],
    ),
    // glTF.
    (
        "gltf_no_meshes.gltf",
        &["gltf_no_meshes.gltf:", "no meshes"],
    ),
    (
        "gltf_missing_buffer.gltf",
        &[
            "gltf_missing_buffer.gltf: buffer 0 (\"missing.bin\")",
            "cannot read",
        ],
    ),
    (
        "gltf_nan_position.gltf",
        &[
            "gltf_nan_position.gltf: node 0 \"only\", mesh 0 \"tri\", primitive 0",
            "vertex 1",
            "non-finite",
        ],
    ),
    (
        "gltf_cyclic_nodes.gltf",
        &["gltf_cyclic_nodes.gltf: node 0", "cyclic"],
    ),
    (
        "gltf_accessor_out_of_bounds.gltf",
        &[
            "gltf_accessor_out_of_bounds.gltf: node 0",
            "POSITION",
            "do not fit",
        ],
    ),
    (
        "gltf_bad_accessor_index.gltf",
        &[
            "gltf_bad_accessor_index.gltf: mesh 0, primitive 0",
            "accessor 5",
            "1 accessors",
        ],
    ),
    (
        "gltf_invalid_json.gltf",
        &["gltf_invalid_json.gltf:3:25:", "invalid glTF JSON"],
    ),
    ("gltf_truncated.glb", &["gltf_truncated.glb:", "truncated"]),
];

#[test]
fn every_bad_file_fails_with_a_located_message() {
    let mut failures = Vec::new();
    for (file, needles) in CASES {
        let path = fixture(&format!("bad/{file}"));
        match load_scene(&path) {
            Ok(_) => failures.push(format!("{file}: loaded without an error")),
            Err(e) => {
                let msg = e.to_string();
                for n in *needles {
                    if !msg.contains(n) {
                        failures.push(format!("{file}: message lacks {n:?}: {msg}"));
                    }
                }
                if msg.contains('\n') {
                    failures.push(format!("{file}: message is not one line: {msg}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_file_in_the_corpus_is_covered() {
    let dir = fixture("bad");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        let helper = name.ends_with(".mtl") || name.ends_with(".csv");
        assert!(
            helper || CASES.iter().any(|(f, _)| *f == name),
            "fixtures/bad/{name} has no expected message in CASES"
        );
    }
}

#[test]
fn error_kinds_are_typed() {
    let e = load_scene(&fixture("bad/ron_missing_mesh.ron")).unwrap_err();
    match e {
        Error::Mesh { source, .. } => assert!(matches!(*source, Error::Read { .. }), "{source:?}"),
        other => panic!("expected Error::Mesh, got {other:?}"),
    }
    assert!(matches!(
        load_scene(&fixture("bad/ron_zero_spp.ron")),
        Err(Error::Ron { line: 2, .. })
    ));
    assert!(matches!(
        load_scene(&fixture("bad/obj_nan_vertex.obj")),
        Err(Error::Obj { line: Some(2), .. })
    ));
    assert!(matches!(
        load_scene(&fixture("bad/gltf_no_meshes.gltf")),
        Err(Error::Gltf { .. })
    ));
}

#[test]
fn a_bad_rays_line_is_named() {
    let path = fixture("bad/rays_bad_line.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let msg = parse_rays(&text, &path).unwrap_err().to_string();
    assert!(
        msg.contains("rays_bad_line.csv:3: expected 6 or 8"),
        "{msg}"
    );
}

#[test]
fn missing_unreadable_and_unknown_files() {
    let dir = tempfile::tempdir().unwrap();
    // A missing scene.
    let msg = load_scene(&dir.path().join("nope.ron"))
        .unwrap_err()
        .to_string();
    assert!(msg.contains("nope.ron: cannot read the file"), "{msg}");
    // A directory where a file should be.
    let sub = dir.path().join("adir.ron");
    std::fs::create_dir(&sub).unwrap();
    let msg = load_scene(&sub).unwrap_err().to_string();
    assert!(
        msg.contains("adir.ron: is a folder, not a regular file"),
        "{msg}"
    );
    // An unknown extension.
    let txt = dir.path().join("scene.txt");
    std::fs::write(&txt, "hello").unwrap();
    let msg = load_scene(&txt).unwrap_err().to_string();
    assert!(
        msg.contains("scene.txt: not a scene gridrt supports (\".txt\": it is a text file)"),
        "{msg}"
    );
    // An unreadable file (permissions; root can read anything, so only
    // checked when the read really fails).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let locked = dir.path().join("locked.ron");
        std::fs::write(&locked, "Scene(objects: [])").unwrap();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o000)).unwrap();
        if std::fs::read(&locked).is_err() {
            let msg = load_scene(&locked).unwrap_err().to_string();
            assert!(msg.contains("locked.ron: cannot read the file"), "{msg}");
        }
    }
}

#[test]
fn random_garbage_never_panics() {
    // Mutations of a valid scene and of a valid OBJ: every outcome is Ok or
    // Err, never a panic. Deterministic (fixed seed), small.
    let scene = std::fs::read_to_string(fixture("scenes/shadows.ron")).unwrap();
    let obj = std::fs::read_to_string(fixture("meshes/cube/cube.obj")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let junk = [
        "", "-", "1e40", "NaN", "(", ")", ",", "\"", "0", "f", "v", "/", "-9",
    ];
    for round in 0..200 {
        let (base, ext) = if round % 2 == 0 {
            (&scene, "ron")
        } else {
            (&obj, "obj")
        };
        let mut text: Vec<char> = base.chars().collect();
        for _ in 0..3 {
            let at = (next() % text.len() as u64) as usize;
            let j = junk[(next() % junk.len() as u64) as usize];
            text.splice(at..(at + 1).min(text.len()), j.chars());
        }
        let s: String = text.into_iter().collect();
        let p = dir.path().join(format!("m{round}.{ext}"));
        std::fs::write(&p, s).unwrap();
        let _ = load_scene(&p);
    }
}

/// Files that sit beside models (material libraries, glTF buffers,
/// textures) and mesh formats gridrt does not read are refused with a
/// message that says what the file is and what to give instead.
#[test]
fn companion_files_are_not_scenes() {
    let dir = tempfile::tempdir().unwrap();
    for (name, note) in [
        ("model.mtl", "OBJ material library, give the .obj"),
        ("model0.bin", "glTF buffer, give the .gltf"),
        ("albedo.PNG", "it is an image"),
        ("bunny.stl", "convert it to OBJ, PLY or glTF"),
        ("LICENSE", "the file has no extension"),
    ] {
        let p = dir.path().join(name);
        std::fs::write(&p, b"\x89PNG\0\0 not a scene").unwrap();
        let err = load_scene(&p).unwrap_err();
        assert!(
            matches!(err, gridrt_io::Error::UnsupportedInput { .. }),
            "{err:?}"
        );
        let msg = err.to_string();
        assert!(msg.contains("not a scene gridrt supports"), "{msg}");
        assert!(msg.contains(note), "{msg}");
        assert!(
            msg.ends_with("use a .ron scene, or an .obj, .ply, .gltf or .glb model"),
            "{msg}"
        );
    }
    // Where only meshes are accepted (a scene's Mesh, `gridrt rays`), a
    // scene file is not one.
    let msg = gridrt_io::load_model(&dir.path().join("scene.ron"))
        .unwrap_err()
        .to_string();
    assert!(msg.contains("not a mesh gridrt supports"), "{msg}");
    assert!(
        msg.ends_with("use an .obj, .ply, .gltf or .glb model"),
        "{msg}"
    );
}

/// An image or an empty file renamed to a model extension is named as such,
/// not reported as a JSON syntax error or an OBJ without faces.
#[test]
fn wrong_content_behind_a_model_extension() {
    let dir = tempfile::tempdir().unwrap();
    let png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR";
    let cases: [(&str, &[u8], &str); 5] = [
        ("image.glb", png, "a .glb file starts with the bytes `glTF`"),
        ("image.gltf", png, "a .gltf file is JSON text"),
        ("empty.glb", b"", "the file is empty"),
        ("blank.gltf", b" \n", "the file is empty"),
        ("image.obj", png, "the file is binary, not OBJ text"),
    ];
    for (name, bytes, note) in cases {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        let msg = load_scene(&p).unwrap_err().to_string();
        assert!(msg.starts_with(&p.display().to_string()), "{msg}");
        assert!(msg.contains(note), "{msg}");
    }
}
