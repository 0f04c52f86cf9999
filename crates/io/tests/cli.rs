//! The `gridrt` binary end to end.

use crate::{fixture, gridrt};
use std::path::Path;
use std::process::{Command, Output};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The one-line `error: …` contract.
fn assert_one_line_error(o: &Output, needle: &str) {
    assert_eq!(o.status.code(), Some(1), "stderr: {}", stderr(o));
    let e = stderr(o);
    assert!(e.starts_with("error: "), "{e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    assert!(e.contains(needle), "{e}");
}

fn png_size(p: &Path) -> (u32, u32) {
    let img = image::open(p).unwrap();
    (img.width(), img.height())
}

#[test]
fn default_render_without_a_subcommand() {
    let dir = tempfile::tempdir().unwrap();
    let o = gridrt(&["--width", "64", "--height", "48"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.path().join("out.png");
    assert_eq!(png_size(&out), (64, 48));
    let s = stdout(&o);
    assert!(s.contains("wrote       out.png"), "{s}");
    assert!(
        s.contains("Mrays/s") && s.contains("shadows") && s.contains("grid"),
        "{s}"
    );
    // Nothing noisy on a non-terminal stderr, no temporary files left.
    assert_eq!(stderr(&o), "");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn render_subcommand_exr_and_stats() {
    let dir = tempfile::tempdir().unwrap();
    let o = gridrt(
        &[
            "render",
            "-o",
            "img.exr",
            "--width",
            "32",
            "--spp",
            "1",
            "--threads",
            "1",
            "--stats",
            "s.json",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(dir.path().join("img.exr")).unwrap().to_rgb32f();
    assert_eq!((img.width(), img.height()), (32, 24));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(json["width"], 32);
    assert_eq!(json["spp"], 1);
    assert_eq!(json["accel"], "grid");
    assert_eq!(json["accel_requested"], "auto");
    assert!(json["rays_by_kind"]["camera"].as_u64().unwrap() == 32 * 24);
    assert!(json["plan"]["shadows"].as_bool().unwrap());
    assert!(json["render_time"].as_f64().is_some());
    assert!(json["grid"]["dims"].is_array());
}

#[test]
fn a_png_rendered_as_bytes_is_the_exr_converted() {
    // A PNG alone is kept as 8-bit sRGB while it renders; with partial
    // images it is kept linear and converted at the end; an EXR is linear.
    let dir = tempfile::tempdir().unwrap();
    let args = ["render", "--width", "40", "--height", "30", "--spp", "2"];
    for (out, extra) in [
        ("a.png", &[][..]),
        ("b.png", &["--write-partial", "60"][..]),
        ("c.exr", &[][..]),
    ] {
        let all: Vec<&str> = args
            .iter()
            .chain(&["-o", out])
            .chain(extra)
            .copied()
            .collect();
        let o = gridrt(&all, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let a = std::fs::read(dir.path().join("a.png")).unwrap();
    assert_eq!(a, std::fs::read(dir.path().join("b.png")).unwrap());
    let exr = image::open(dir.path().join("c.exr")).unwrap().to_rgb32f();
    let codes: Vec<u8> = exr
        .as_raw()
        .iter()
        .map(|&x| gridrt_tracer::srgb8(x))
        .collect();
    let png = image::open(dir.path().join("a.png")).unwrap().to_rgb8();
    assert_eq!(png.as_raw(), &codes);
    assert!(codes.iter().any(|&c| c > 0 && c < 255));
}

#[test]
fn render_a_fixture_scene_and_a_model_with_each_accelerator() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("scenes/obj_cube_transform.ron");
    let fixtures = crate::fixtures();
    for accel in [
        "auto",
        "grid",
        "hierarchy",
        "hashed-grid",
        "dense-grid",
        "exhaustive",
    ] {
        let out = format!("{accel}.png");
        let o = gridrt(
            &[
                "render",
                scene.to_str().unwrap(),
                "-o",
                &out,
                "--width",
                "40",
                "--accel",
                accel,
                "--grid-m",
                "3",
                "--grid-nest",
                "2",
                "--grid-nest-m",
                "1.5",
                "--allow-path",
                fixtures.to_str().unwrap(),
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{accel}: {}", stderr(&o));
        assert_eq!(png_size(&dir.path().join(&out)), (40, 30));
    }
    // Both grids and exhaustive render the same image.
    let b = std::fs::read(dir.path().join("exhaustive.png")).unwrap();
    for grid in ["grid", "hashed-grid"] {
        let a = std::fs::read(dir.path().join(format!("{grid}.png"))).unwrap();
        assert!(a == b, "{grid} differs from exhaustive");
    }
    let model = fixture("meshes/generated/hierarchy.glb");
    let o = gridrt(
        &[
            "render",
            model.to_str().unwrap(),
            "-o",
            "m.png",
            "--width",
            "40",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: "),
        "a points-primitive warning expected"
    );
}

#[test]
fn a_bad_scene_fails_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let bad = fixture("bad/ron_unknown_material.ron");
    let o = gridrt(
        &["render", bad.to_str().unwrap(), "-o", "x.png"],
        dir.path(),
    );
    assert_one_line_error(&o, "unknown material \"blue\"");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn a_failed_render_keeps_the_existing_image() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("keep.png"), b"GOOD").unwrap();
    for bad in [
        "bad/ron_malformed.ron",
        "bad/obj_nan_vertex.obj",
        "bad/gltf_missing_buffer.gltf",
    ] {
        let p = fixture(bad);
        let o = gridrt(
            &["render", p.to_str().unwrap(), "-o", "keep.png"],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(1), "{bad}");
        assert_eq!(
            std::fs::read(dir.path().join("keep.png")).unwrap(),
            b"GOOD",
            "{bad}"
        );
    }
    // Bad overrides fail before rendering, too.
    let o = gridrt(&["render", "-o", "keep.png", "--spp", "0"], dir.path());
    assert_one_line_error(&o, "--spp");
    let o = gridrt(
        &["render", "-o", "keep.png", "--width", "100000"],
        dir.path(),
    );
    assert_one_line_error(&o, "--width");
    assert_eq!(std::fs::read(dir.path().join("keep.png")).unwrap(), b"GOOD");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn bad_output_paths_fail_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let o = gridrt(&["render", "-o", "out.jpg"], dir.path());
    assert_one_line_error(&o, "unknown image format \".jpg\"");
    let o = gridrt(&["render", "-o", "no/such/dir/out.png"], dir.path());
    assert_one_line_error(&o, "does not exist");
    let o = gridrt(
        &["render", "-o", "out.png", "--stats", "missing/s.json"],
        dir.path(),
    );
    assert_one_line_error(&o, "does not exist");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn usage_errors_exit_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let o = gridrt(&["render", "--accel", "octree"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let o = gridrt(&["render", "--grid-m", "-1"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let o = gridrt(&["render", "--grid-nest-m", "0"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("out of range"), "{}", stderr(&o));
    let o = gridrt(&["rays"], dir.path());
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn info_prints_scene_and_grid_statistics() {
    let dir = tempfile::tempdir().unwrap();
    let p = fixture("scenes/gltf_hierarchy.ron");
    // The scene's meshes are in ../meshes: outside its folder.
    let o = gridrt(&["info", p.to_str().unwrap()], dir.path());
    assert_one_line_error(&o, "--allow-path");
    let fixtures = crate::fixtures();
    let o = gridrt(
        &[
            "info",
            p.to_str().unwrap(),
            "--allow-path",
            fixtures.to_str().unwrap(),
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    for needle in [
        "objects",
        "triangles",
        "grid ",
        "occupied",
        "build",
        "camera",
    ] {
        assert!(s.contains(needle), "{needle}: {s}");
    }
    let o = gridrt(&["info"], dir.path());
    assert!(stdout(&o).contains("<built-in default scene>"));
    let bad = fixture("bad/gltf_no_meshes.gltf");
    let o = gridrt(&["info", bad.to_str().unwrap()], dir.path());
    assert_one_line_error(&o, "no meshes");
}

#[test]
fn rays_on_a_tiny_mesh_give_the_known_answers() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = fixture("meshes/generated/tri.obj");
    let rays = fixture("meshes/generated/tri_rays.csv");
    let expected =
        std::fs::read_to_string(fixture("meshes/generated/tri_rays.expected.csv")).unwrap();
    for accel in [
        "auto",
        "grid",
        "hierarchy",
        "hashed-grid",
        "dense-grid",
        "exhaustive",
    ] {
        let o = gridrt(
            &[
                "rays",
                mesh.to_str().unwrap(),
                rays.to_str().unwrap(),
                "--accel",
                accel,
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(stdout(&o), expected, "{accel}");
    }
    let o = gridrt(
        &[
            "rays",
            mesh.to_str().unwrap(),
            rays.to_str().unwrap(),
            "-o",
            "hits.csv",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("hits.csv")).unwrap(),
        expected
    );
    let bad = fixture("bad/rays_bad_line.csv");
    let o = gridrt(
        &["rays", mesh.to_str().unwrap(), bad.to_str().unwrap()],
        dir.path(),
    );
    assert_one_line_error(&o, "rays_bad_line.csv:3:");
    assert_eq!(stdout(&o), "");
}

/// `--triangles indexed` answers every ray as the copied triangles do, on
/// an OBJ and on a glTF whose wheel mesh is placed twice.
#[test]
fn rays_with_indexed_triangles_answer_as_copies() {
    let dir = tempfile::tempdir().unwrap();
    // Rays from a ring around the origin towards points near it.
    let mut csv = String::new();
    for i in 0..400 {
        let a = i as f64 * 0.37;
        let (o, t) = (
            [6.0 * a.cos(), 1.0 + (a * 0.7).sin(), 6.0 * a.sin()],
            [(a * 1.3).sin(), (a * 0.9).cos(), (a * 2.1).sin()],
        );
        let d: Vec<String> = (0..3).map(|k| format!("{}", t[k] - o[k])).collect();
        csv += &format!("{},{},{},{}\n", o[0], o[1], o[2], d.join(","));
    }
    std::fs::write(dir.path().join("r.csv"), csv).unwrap();
    for mesh in [
        "meshes/teapot/teapot.obj",
        "meshes/gltf_cesium_milk_truck/CesiumMilkTruck.glb",
    ] {
        let mesh = fixture(mesh);
        let run = |extra: &[&str]| {
            let mut args = vec!["rays", mesh.to_str().unwrap(), "r.csv"];
            args.extend_from_slice(extra);
            let o = gridrt(&args, dir.path());
            assert!(o.status.success(), "{}", stderr(&o));
            stdout(&o)
        };
        let copies = run(&[]);
        assert!(
            copies.lines().filter(|l| *l != "miss").count() > 40,
            "{mesh:?}"
        );
        for accel in ["auto", "grid", "hierarchy", "exhaustive"] {
            let indexed = run(&["--triangles", "indexed", "--accel", accel]);
            assert_eq!(indexed, copies, "{mesh:?} {accel}");
        }
    }
}

#[test]
fn render_with_indexed_triangles_gives_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    for (k, mesh) in [
        "meshes/teapot/teapot.obj",
        "meshes/gltf_cesium_milk_truck/CesiumMilkTruck.glb",
    ]
    .iter()
    .enumerate()
    {
        let mesh = fixture(mesh);
        let run = |name: &str, extra: &[&str]| {
            let out = format!("{k}-{name}.png");
            let mut args = vec!["render", mesh.to_str().unwrap(), "-o", &out];
            args.extend_from_slice(&["--width", "48", "--threads", "2"]);
            args.extend_from_slice(extra);
            let o = gridrt(&args, dir.path());
            assert!(o.status.success(), "{}", stderr(&o));
            (std::fs::read(dir.path().join(&out)).unwrap(), stdout(&o))
        };
        // `--triangles auto`, the default, keeps small meshes' copies.
        let (copies, summary) = run("copies", &["--no-instancing"]);
        assert!(
            summary.contains("primitives, triangles copies)"),
            "{summary}"
        );
        let (indexed, summary) = run("indexed", &["--no-instancing", "--triangles", "indexed"]);
        assert!(indexed == copies, "{mesh:?}");
        assert!(summary.contains("triangles indexed"), "{summary}");
        // Shared instances keep their own grids of copies.
        let (shared_copies, _) = run("shared-copies", &[]);
        let (shared, _) = run("shared", &["--triangles", "indexed"]);
        assert!(shared == shared_copies, "{mesh:?}");
    }
}

#[test]
fn indexed_triangles_need_the_watertight_test() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("r.csv"), "0,0,5,0,0,-1\n").unwrap();
    let mesh = fixture("meshes/teapot/teapot.obj");
    let mesh = mesh.to_str().unwrap();
    for command in [vec!["rays", mesh, "r.csv"], vec!["render", mesh]] {
        let mut args = command.clone();
        args.extend_from_slice(&[
            "--triangles",
            "indexed",
            "--triangle-test",
            "moller-trumbore",
        ]);
        let o = gridrt(&args, dir.path());
        assert_one_line_error(&o, "--triangles");
    }
    assert!(!dir.path().join("out.png").exists());
}

#[test]
fn rays_number_gltf_triangles_in_node_order() {
    // Ray straight down onto the glass triangle (index 27) of hierarchy.gltf.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("r.csv"), "0.25,0.25,5,0,0,-1\n").unwrap();
    let mesh = fixture("meshes/generated/hierarchy.glb");
    let o = gridrt(&["rays", mesh.to_str().unwrap(), "r.csv"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), "3,27,0.25,0.25\n");
}

/// Ctrl-C (SIGINT) during a render stops it: exit code 130, one line
/// `interrupted; nothing written`, the file already at the output path kept
/// and no temporary file left. Linux only: readiness is read from
/// `/proc/PID/status` (the SIGINT bit of `SigCgt` is set once gridrt has
/// installed its handler), so the signal never races the start-up.
#[cfg(target_os = "linux")]
#[test]
fn ctrl_c_cancels_a_render_and_writes_nothing() {
    use std::process::Stdio;
    use std::time::{Duration, Instant};

    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("out.png"), b"an older image").unwrap();
    // Minutes of work on one thread, but 16×16-pixel tiles of a few
    // milliseconds each, so cancellation is prompt.
    let mut child = Command::new(env!("CARGO_BIN_EXE_gridrt"))
        .args([
            "render", "--width", "1024", "--height", "1024", "--spp", "1024",
        ])
        .args(["--threads", "1", "--stats", "stats.json", "-o", "out.png"])
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid = child.id().to_string();
    wait_for_sigint_handler(&mut child);
    // Let the render itself start (loading the built-in scene is instant).
    std::thread::sleep(Duration::from_millis(200));
    let kill = Command::new("kill").args(["-INT", &pid]).status().unwrap();
    assert!(kill.success());
    let sent = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if sent.elapsed() > Duration::from_secs(4) {
            let _ = child.kill();
            panic!("gridrt still running 4 s after SIGINT");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let o = child.wait_with_output().unwrap();
    assert_eq!(status.code(), Some(130), "stderr: {}", stderr(&o));
    assert_eq!(stderr(&o), "interrupted; nothing written\n");
    assert_eq!(stdout(&o), "");
    assert_eq!(
        std::fs::read(dir.path().join("out.png")).unwrap(),
        b"an older image"
    );
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, ["out.png"], "no stats file, no temporary file");
}

/// Waits until `child` has installed its SIGINT handler (the SIGINT bit of
/// `SigCgt` in `/proc/PID/status`), so a signal never races the start-up.
#[cfg(target_os = "linux")]
pub fn wait_for_sigint_handler(child: &mut std::process::Child) {
    use std::time::{Duration, Instant};
    let pid = child.id();
    let start = Instant::now();
    let handler_installed = || {
        let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
        status
            .lines()
            .find_map(|l| l.strip_prefix("SigCgt:"))
            .and_then(|m| u64::from_str_radix(m.trim(), 16).ok())
            .is_some_and(|mask| mask & (1 << (2 - 1)) != 0) // SIGINT = 2
    };
    while !handler_installed() {
        if start.elapsed() > Duration::from_secs(3) {
            let _ = child.kill();
            panic!("gridrt installed no SIGINT handler within 3 s");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// In-process and on every platform: a render whose cancel flag is already
/// raised returns `Cancelled` and writes neither the image nor the stats.
#[test]
fn a_cancelled_render_writes_nothing() {
    use clap::Parser;
    use std::sync::atomic::AtomicBool;

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png");
    let stats = dir.path().join("stats.json");
    std::fs::write(&out, b"an older image").unwrap();
    let cli = gridrt_io::cli::Cli::try_parse_from([
        "gridrt".as_ref(),
        "--width".as_ref(),
        "32".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
        "--stats".as_ref(),
        stats.as_os_str(),
    ])
    .unwrap();
    assert!(cli.renders());
    let mut summary = Vec::new();
    let err =
        gridrt_io::cli::run_with_cancel(cli, &mut summary, &AtomicBool::new(true)).unwrap_err();
    assert!(matches!(err, gridrt_io::Error::Cancelled), "{err:?}");
    assert_eq!(err.to_string(), "interrupted; nothing written");
    assert!(summary.is_empty());
    assert_eq!(std::fs::read(&out).unwrap(), b"an older image");
    assert!(!stats.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

/// `--eye`, `--look-at`, `--fov` and `--max-depth` move the camera: the
/// triangle seen from its front and from behind it differ, and a bad value
/// is one error line naming the flag.
#[test]
fn camera_and_depth_flags_override_the_view() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = fixture("meshes/generated/tri.obj");
    let run = |name: &str, extra: &[&str]| {
        let mut args = vec![
            "render",
            mesh.to_str().unwrap(),
            "-o",
            name,
            "--width",
            "20",
            "--height",
            "16",
        ];
        args.extend_from_slice(extra);
        gridrt(&args, dir.path())
    };
    let o = run("a.png", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(
        "b.png",
        &[
            "--eye",
            "-3,-2,-6",
            "--look-at",
            "0,0,0",
            "--fov",
            "20",
            "--max-depth",
            "0",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let a = std::fs::read(dir.path().join("a.png")).unwrap();
    let b = std::fs::read(dir.path().join("b.png")).unwrap();
    assert_ne!(a, b);
    let o = run("c.png", &["--fov", "0"]);
    assert_one_line_error(&o, "--fov");
    assert!(!dir.path().join("c.png").exists());
    let o = run("c.png", &["--eye", "1,2"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// `--camera NAME` picks a glTF camera by name; an unnamed one is
/// `camera N`, and an unknown name lists the file's cameras.
#[test]
fn camera_flag_picks_a_gltf_camera_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let model = fixture("meshes/generated/hierarchy.gltf");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "render",
            model.to_str().unwrap(),
            "-o",
            "c.png",
            "--width",
            "16",
            "--height",
            "12",
            "--spp",
            "1",
        ];
        args.extend_from_slice(extra);
        gridrt(&args, dir.path())
    };
    let o = run(&["--camera", "camera 0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The model's own warnings (a points primitive) come
    // first; the error is the last line.
    let o = run(&["--camera", "top"]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    let last = e.trim_end().lines().last().unwrap_or_default();
    assert!(last.starts_with("error: --camera: "), "{e}");
    assert!(
        last.ends_with("has no camera \"top\"; its cameras are: camera 0"),
        "{e}"
    );
}
