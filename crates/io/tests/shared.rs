//! Optional checks against the real models in `../shared/scenes` (beside
//! the workspace). Skipped, with a note, when that folder is absent: the
//! project's own tests never need it.

use crate::load_scene;
use gridrt_io::load_model;
use std::path::PathBuf;

fn shared_scenes() -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes");
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("skipped: {} is absent", p.display());
        None
    }
}

/// Every small model in shared/scenes loads into a scene (the large ones,
/// dragon and bunny, are left to `gridrt info` in release builds).
#[test]
fn shared_models_load() {
    let Some(root) = shared_scenes() else { return };
    let mut n = 0;
    for dir in std::fs::read_dir(&root).unwrap() {
        let dir = dir.unwrap().path();
        let name = dir.file_name().unwrap().to_string_lossy().into_owned();
        if !dir.is_dir() || name == "dragon" || name == "bunny" || name == "teapot_in_stadium" {
            continue;
        }
        for f in std::fs::read_dir(&dir).unwrap() {
            let f = f.unwrap().path();
            let ext = f.extension().map(|e| e.to_string_lossy().to_lowercase());
            if matches!(ext.as_deref(), Some("obj" | "ply" | "gltf" | "glb")) {
                let s = load_scene(&f).unwrap_or_else(|e| panic!("{e}"));
                assert!(!s.scene.objects.is_empty(), "{}", f.display());
                n += 1;
            }
        }
    }
    assert!(n >= 15, "only {n} models found");
}

/// The teapot in a stadium is stored twice: pre-transformed OBJ and a glTF
/// node hierarchy. Both must give the same world-space triangles.
#[test]
fn stadium_obj_and_gltf_agree() {
    let Some(root) = shared_scenes() else { return };
    let dir = root.join("teapot_in_stadium");
    let obj = load_model(&dir.join("teapot_in_stadium.obj")).unwrap();
    let glb = load_model(&dir.join("teapot_in_stadium.glb")).unwrap();
    assert_eq!(obj.triangle_count(), 75_807);
    assert_eq!(glb.triangle_count(), 75_807);
    let bo = obj.bounds();
    let bg = glb.bounds();
    assert!(
        (bo.min - bg.min).abs().max_element() < 1e-2,
        "{bo:?} {bg:?}"
    );
    assert!(
        (bo.max - bg.max).abs().max_element() < 1e-2,
        "{bo:?} {bg:?}"
    );
    // Triangle by triangle (the OBJ is printed with 6 decimals).
    let mut worst: gridrt_bbox::Real = 0.0;
    for (a, b) in obj.triangles().zip(glb.triangles()) {
        for k in 0..3 {
            let d = (a[k] - b[k]).abs().max_element();
            worst = worst.max(d);
        }
    }
    assert!(worst < 1e-3, "largest vertex difference {worst}");
}

/// Every other file in shared/scenes (MTL, glTF buffers, textures, the
/// SOURCE.txt notes) is refused as "not a scene", never read as one.
#[test]
fn shared_companion_files_are_refused() {
    let Some(root) = shared_scenes() else { return };
    let mut files = vec![root.join("INDEX.txt")];
    for dir in std::fs::read_dir(&root).unwrap() {
        let dir = dir.unwrap().path();
        if dir.is_dir() {
            files.extend(std::fs::read_dir(&dir).unwrap().map(|f| f.unwrap().path()));
        }
    }
    let mut n = 0;
    for f in files {
        let ext = f.extension().map(|e| e.to_string_lossy().to_lowercase());
        if matches!(ext.as_deref(), Some("obj" | "gltf" | "glb" | "ron")) {
            continue;
        }
        let err = load_scene(&f).unwrap_err();
        assert!(
            matches!(err, gridrt_io::Error::UnsupportedInput { .. }),
            "{}: {err}",
            f.display()
        );
        n += 1;
    }
    assert!(n >= 30, "only {n} companion files found");
}

/// The scenes behind the README's model images (`docs/model-*.ron`) read
/// their meshes from shared/scenes; they load and keep their two objects.
#[test]
fn readme_model_scenes_load() {
    let Some(_) = shared_scenes() else { return };
    let docs = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs");
    for name in ["model-obj.ron", "model-gltf.ron"] {
        let s = load_scene(&docs.join(name)).unwrap_or_else(|e| panic!("{e}"));
        assert!(!s.framed_camera, "{name}");
        assert!(s.scene.objects.len() >= 2, "{name}");
        assert_eq!(
            (s.scene.settings.width, s.scene.settings.height),
            (640, 480)
        );
    }
}

/// The Stanford bunny from PLY loads like its OBJ: its own PLY when the
/// folder has one (the same vertex count and bounds), else the OBJ written
/// as binary PLY (the same triangles, corner for corner).
#[test]
fn bunny_from_ply_loads_like_its_obj() {
    use crate::ply::{corners, to_ply, Encoding};
    let Some(root) = shared_scenes() else { return };
    let dir = root.join("bunny");
    let obj = load_model(&dir.join("stanford-bunny.obj")).unwrap();
    let own = std::fs::read_dir(&dir)
        .unwrap()
        .map(|f| f.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("ply")));
    if let Some(own) = own {
        let ply = load_model(&own).unwrap();
        let (a, b) = (ply.bounds(), obj.bounds());
        assert!((a.min - b.min).abs().max_element() < 1e-3, "{a:?} {b:?}");
        assert!((a.max - b.max).abs().max_element() < 1e-3, "{a:?} {b:?}");
    }
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("bunny.ply");
    std::fs::write(&path, to_ply(&obj, Encoding::Little)).unwrap();
    let ply = load_model(&path).unwrap();
    assert_eq!(ply.triangle_count(), obj.triangle_count());
    assert_eq!(corners(&ply), corners(&obj));
}
