//! Hostile inputs end to end through the `gridrt` binary: files outside the
//! allowed folders, special files, budgets, and outputs that must survive
//! every failure. Each case checks the exit code, the message, and that no
//! file was created or changed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub(crate) fn gridrt(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gridrt"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the gridrt binary runs")
}

pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Every file under `dir` with its bytes (symbolic links as their target).
pub(crate) fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let meta = std::fs::symlink_metadata(&p).unwrap();
            if meta.is_dir() {
                stack.push(p);
            } else if meta.file_type().is_symlink() {
                let t = std::fs::read_link(&p).unwrap();
                out.insert(p, t.to_string_lossy().as_bytes().to_vec());
            } else if meta.is_file() {
                out.insert(p.clone(), std::fs::read(&p).unwrap());
            } else {
                out.insert(p, b"<special>".to_vec());
            }
        }
    }
    out
}

/// Runs gridrt in `cwd` and checks a one-line error with exit code 1 that
/// contains every needle, and that nothing under `watch` changed.
pub(crate) fn refused(args: &[&str], cwd: &Path, watch: &Path, needles: &[&str]) -> String {
    let before = snapshot(watch);
    let o = gridrt(args, cwd);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
    assert!(e.starts_with("error: "), "{e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    for n in needles {
        assert!(e.contains(n), "{args:?}: `{n}` not in: {e}");
    }
    assert_eq!(snapshot(watch), before, "{args:?} changed files");
    e
}

/// A glTF file with one triangle whose buffer is `uri`.
pub(crate) fn gltf_with_buffer(uri: &str) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}},
  "buffers": [{{"uri": "{uri}", "byteLength": 36}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "nodes": [{{"mesh": 0}}],
  "scenes": [{{"nodes": [0]}}],
  "scene": 0}}"#
    )
}

/// 36 bytes: the triangle (0,0,0), (1,0,0), (0,1,0) as f32.
pub(crate) fn triangle_bytes() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect()
}

/// `root/` with `secret.bin` (a valid buffer, so reading it would succeed),
/// `job/` (the model's folder) and `work/` (the working directory).
fn layout() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let root = std::fs::canonicalize(dir.path()).unwrap();
    std::fs::write(root.join("secret.bin"), triangle_bytes()).unwrap();
    std::fs::write(
        root.join("secret.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(root.join("secret.mtl"), "newmtl a\nKd 1 0 0\n").unwrap();
    std::fs::create_dir(root.join("job")).unwrap();
    std::fs::create_dir(root.join("job/sub")).unwrap();
    std::fs::create_dir(root.join("work")).unwrap();
    std::fs::write(root.join("job/own.bin"), triangle_bytes()).unwrap();
    (dir, root.join("job"), root.join("work"))
}

#[test]
fn gltf_buffers_outside_the_model_folder_are_refused_alike() {
    let (_d, job, work) = layout();
    let root = job.parent().unwrap().to_path_buf();
    #[cfg(unix)]
    std::os::unix::fs::symlink(root.join("secret.bin"), job.join("link.bin")).unwrap();
    let cases = [
        "../secret.bin",
        "../no-such.bin",
        "%2E%2E/secret.bin",
        "%2e%2e%2fsecret.bin",
        "sub/../../secret.bin",
        "file:../secret.bin",
        "/etc/passwd",
        "file:///etc/passwd",
        "/proc/self/environ",
    ];
    let mut messages = Vec::new();
    for uri in cases.iter().chain(cfg!(unix).then_some(&"link.bin")) {
        let model = job.join("m.gltf");
        std::fs::write(&model, gltf_with_buffer(uri)).unwrap();
        let e = refused(
            &["info", model.to_str().unwrap()],
            &work,
            &root,
            &[
                "m.gltf",
                "is outside the folders a model file may read",
                "--allow-path",
            ],
        );
        assert!(!e.contains("bytes"), "{e}");
        messages.push(e);
    }
    // Whether the target exists or not, the message is the same apart from
    // the reference itself.
    assert_eq!(
        messages[0].replace("secret", "X"),
        messages[1].replace("no-such", "X")
    );
    // The model's own folder, and a data: URI, are fine.
    for uri in [
        "own.bin",
        "./sub/../own.bin",
        "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA",
    ] {
        let model = job.join("m.gltf");
        std::fs::write(&model, gltf_with_buffer(uri)).unwrap();
        let o = gridrt(&["info", model.to_str().unwrap()], &work);
        assert!(o.status.success(), "{uri}: {}", stderr(&o));
    }
    // --allow-path lets the model read the parent folder.
    std::fs::write(job.join("m.gltf"), gltf_with_buffer("../secret.bin")).unwrap();
    let m = job.join("m.gltf");
    let o = gridrt(
        &[
            "info",
            m.to_str().unwrap(),
            "--allow-path",
            root.to_str().unwrap(),
        ],
        &work,
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn scene_meshes_and_mtllibs_outside_are_refused() {
    let (_d, job, work) = layout();
    let root = job.parent().unwrap().to_path_buf();
    let abs = root.join("secret.obj");
    #[cfg(unix)]
    std::os::unix::fs::symlink(&abs, job.join("link.obj")).unwrap();
    let mut refs = vec!["../secret.obj".to_string(), abs.display().to_string()];
    if cfg!(unix) {
        refs.push("link.obj".to_string());
    }
    for r in &refs {
        let scene = job.join("s.ron");
        std::fs::write(
            &scene,
            format!("(\n objects: [\n  Mesh(file: \"{r}\"),\n ],\n)\n"),
        )
        .unwrap();
        refused(
            &["info", scene.to_str().unwrap()],
            &work,
            &root,
            &[
                "s.ron:3:14: objects[0]",
                "is outside the folders the scene may read",
                "--allow-path",
            ],
        );
    }
    // The working directory is a default root for the scene.
    std::fs::write(work.join("w.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let scene = job.join("s.ron");
    std::fs::write(
        &scene,
        format!(
            "(objects: [Mesh(file: \"{}\")])",
            work.join("w.obj").display()
        ),
    )
    .unwrap();
    let o = gridrt(&["info", scene.to_str().unwrap()], &work);
    assert!(o.status.success(), "{}", stderr(&o));
    // An OBJ's mtllib outside its folder.
    std::fs::write(
        job.join("m.obj"),
        "mtllib ../secret.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let m = job.join("m.obj");
    refused(
        &["info", m.to_str().unwrap()],
        &work,
        &root,
        &[
            "m.obj",
            "\"../secret.mtl\" is outside the folders a model file may read",
        ],
    );
}

#[cfg(unix)]
#[test]
fn special_files_are_refused_without_blocking() {
    let (_d, job, work) = layout();
    let root = job.parent().unwrap().to_path_buf();
    let fifo = job.join("pipe.ron");
    let st = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(st.success());
    refused(
        &["info", fifo.to_str().unwrap()],
        &work,
        &root,
        &["pipe.ron: is a FIFO, not a regular file"],
    );
    let fifo_obj = job.join("pipe.obj");
    Command::new("mkfifo").arg(&fifo_obj).status().unwrap();
    let scene = job.join("s.ron");
    std::fs::write(&scene, "(objects: [Mesh(file: \"pipe.obj\")])").unwrap();
    refused(
        &["info", scene.to_str().unwrap()],
        &work,
        &root,
        &["pipe.obj: is a FIFO"],
    );
    std::fs::write(
        job.join("m.obj"),
        "mtllib pipe.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    Command::new("mkfifo")
        .arg(job.join("pipe.mtl"))
        .status()
        .unwrap();
    let m = job.join("m.obj");
    refused(
        &["info", m.to_str().unwrap()],
        &work,
        &root,
        &["pipe.mtl: is a FIFO"],
    );
    std::fs::write(&scene, "(objects: [Mesh(file: \"/dev/zero\")])").unwrap();
    refused(
        &["info", scene.to_str().unwrap(), "--allow-path", "/dev"],
        &work,
        &root,
        &["zero: is a device, not a regular file"],
    );
    refused(&["info", "/dev/zero"], &work, &root, &["not a scene"]);
}

#[test]
fn file_size_limit_names_its_flag() {
    let (_d, job, work) = layout();
    let root = job.parent().unwrap().to_path_buf();
    let scene = job.join("s.ron");
    std::fs::write(&scene, "(objects: [Sphere(center: (0, 0, 0), radius: 1)])").unwrap();
    refused(
        &["info", scene.to_str().unwrap(), "--max-file-size", "10"],
        &work,
        &root,
        &[
            "s.ron: the file is",
            "over the limit of 10 bytes",
            "--max-file-size",
        ],
    );
    let o = gridrt(
        &["info", scene.to_str().unwrap(), "--max-file-size", "1K"],
        &work,
    );
    assert!(o.status.success(), "{}", stderr(&o));
}
