//! Frames split across processes: `render --tile/--crop`, `merge`, `diff`,
//! and the recipe scripts of `docs/farm/`, end to end.

use crate::{fixture, gridrt};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_gridrt");

fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "exit {:?}\nstdout: {}\nstderr: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

fn fails_with(o: &Output, needle: &str) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert!(e.starts_with("error: ") && e.contains(needle), "{e}");
}

fn scene() -> String {
    fixture("scenes/mirror_glass.ron").display().to_string()
}

/// The files in `dir`, sorted.
fn listing(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

/// Renders the whole frame (with `extra` options) to `name` in `dir`.
fn full(dir: &Path, name: &str, extra: &[&str]) -> Vec<u8> {
    let s = scene();
    let mut args = vec!["render", s.as_str(), "-o", name, "--quiet"];
    args.extend_from_slice(extra);
    ok(&gridrt(&args, dir));
    std::fs::read(dir.join(name)).unwrap()
}

#[test]
fn tiles_merge_to_the_full_render_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (png, exr) = (
        full(d, "full.png", &[]),
        full(d, "full.exr", &["--spp", "3"]),
    );
    let s = scene();
    for n in [1u32, 3, 4] {
        let mut parts = Vec::new();
        for i in 0..n {
            let part = format!("part{i}of{n}.exr");
            let spec = format!("{i}/{n}");
            let threads = (1 + i % 2).to_string();
            let o = gridrt(
                &[
                    "render",
                    &s,
                    "--tile",
                    &spec,
                    "-o",
                    &part,
                    "--quiet",
                    "--threads",
                    &threads,
                ],
                d,
            );
            ok(&o);
            parts.push(part);
        }
        let mut merge = vec!["merge"];
        merge.extend(parts.iter().map(String::as_str));
        ok(&gridrt(&[&merge[..], &["-o", "m.png"]].concat(), d));
        assert_eq!(
            std::fs::read(d.join("m.png")).unwrap(),
            png,
            "{n} tiles, PNG"
        );
        // The EXR frame at 3 samples per pixel, from tiles at 3 samples.
        for (i, part) in parts.iter().enumerate() {
            let spec = format!("{i}/{n}");
            let args = [
                "render", &s, "--tile", &spec, "-o", part, "--quiet", "--spp", "3",
            ];
            ok(&gridrt(&args, d));
        }
        ok(&gridrt(&[&merge[..], &["-o", "m.exr"]].concat(), d));
        assert_eq!(
            std::fs::read(d.join("m.exr")).unwrap(),
            exr,
            "{n} tiles, EXR"
        );
    }
}

#[test]
fn crop_windows_merge_and_fractions_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let png = full(d, "full.png", &[]);
    let s = scene();
    // Left half in pixels, right half as fractions (the image is 160 wide).
    ok(&gridrt(
        &[
            "render",
            &s,
            "--crop",
            "0,0,80,120",
            "-o",
            "l.exr",
            "--quiet",
        ],
        d,
    ));
    ok(&gridrt(
        &[
            "render",
            &s,
            "--crop",
            "0.5,0,1,1.0",
            "-o",
            "r.exr",
            "--quiet",
        ],
        d,
    ));
    ok(&gridrt(&["merge", "r.exr", "l.exr", "-o", "m.png"], d));
    assert_eq!(std::fs::read(d.join("m.png")).unwrap(), png);
}

#[test]
fn merge_refuses_gaps_overlaps_and_foreign_parts() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let s = scene();
    let other = fixture("scenes/shadows.ron").display().to_string();
    for (sc, spec, out) in [
        (&s, "0/2", "a.exr"),
        (&s, "1/2", "b.exr"),
        (&other, "1/2", "c.exr"),
    ] {
        ok(&gridrt(
            &["render", sc, "--tile", spec, "-o", out, "--quiet"],
            d,
        ));
    }
    // Another sample count is another render, too.
    let o = gridrt(
        &[
            "render", &s, "--tile", "1/2", "-o", "d.exr", "--quiet", "--spp", "2",
        ],
        d,
    );
    ok(&o);
    std::fs::write(d.join("x.exr"), b"not an exr").unwrap();
    let before = listing(d);
    fails_with(&gridrt(&["merge", "a.exr", "-o", "m.png"], d), "uncovered");
    fails_with(
        &gridrt(&["merge", "a.exr", "b.exr", "a.exr", "-o", "m.png"], d),
        "overlaps",
    );
    fails_with(
        &gridrt(&["merge", "a.exr", "c.exr", "-o", "m.png"], d),
        "another render",
    );
    fails_with(
        &gridrt(&["merge", "a.exr", "d.exr", "-o", "m.png"], d),
        "another render",
    );
    fails_with(
        &gridrt(&["merge", "a.exr", "x.exr", "-o", "m.png"], d),
        "x.exr",
    );
    // A part must be EXR; bad specs are errors before any work.
    fails_with(
        &gridrt(&["render", &s, "--tile", "0/2", "-o", "p.png"], d),
        ".exr",
    );
    fails_with(
        &gridrt(&["render", &s, "--tile", "0/100", "-o", "p.exr"], d),
        "at most 8 tiles",
    );
    fails_with(
        &gridrt(&["render", &s, "--crop", "0,0,500,10", "-o", "p.exr"], d),
        "outside",
    );
    let usage = gridrt(&["render", &s, "--tile", "2/2", "-o", "p.exr"], d);
    assert_eq!(usage.status.code(), Some(2));
    // Nothing was created or changed by the failures.
    assert_eq!(listing(d), before);
}

#[test]
fn diff_reports_identical_and_different_images() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    full(d, "a.png", &[]);
    full(d, "b.png", &[]);
    full(d, "c.png", &["--spp", "4"]);
    let same = gridrt(&["diff", "a.png", "b.png"], d);
    ok(&same);
    let text = String::from_utf8_lossy(&same.stdout).into_owned();
    assert!(text.contains("pixels differing  0 of 19200"), "{text}");
    let differ = gridrt(&["diff", "a.png", "c.png", "-o", "d.png"], d);
    fails_with(&differ, "differs from a.png");
    let text = String::from_utf8_lossy(&differ.stdout).into_owned();
    assert!(
        text.contains("RMSE") && text.contains("max difference"),
        "{text}"
    );
    assert!(d.join("d.png").is_file());
    fails_with(&gridrt(&["diff", "a.png", "nope.png"], d), "nope.png");
}

/// The recipes' scripts (`docs/farm/`), run as a farm would: one process
/// per tile, all at once, then the merge.
#[cfg(unix)]
#[test]
fn farm_scripts_render_tiles_in_parallel_processes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let png = full(d, "full.png", &[]);
    let scripts = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/farm");
    let out = d.join("frame");
    let n = 4;
    let children: Vec<_> = (0..n)
        .map(|i| {
            Command::new("bash")
                .arg(scripts.join("render-tile.sh"))
                .args([&scene(), &i.to_string(), &n.to_string()])
                .arg(&out)
                .args(["--threads", "1"])
                .env("GRIDRT", BIN)
                .spawn()
                .expect("bash runs")
        })
        .collect();
    for mut c in children {
        assert!(c.wait().unwrap().success());
    }
    let merged = d.join("frame.png");
    let o = Command::new("bash")
        .arg(scripts.join("merge-tiles.sh"))
        .arg(&out)
        .arg(n.to_string())
        .arg(&merged)
        .env("GRIDRT", BIN)
        .output()
        .unwrap();
    ok(&o);
    assert_eq!(std::fs::read(&merged).unwrap(), png);
}

/// `--write-partial` writes the image while it renders; with
/// `--save-on-interrupt` a Ctrl-C writes what is done and lists the
/// missing tiles, which `--crop` can then render.
#[cfg(target_os = "linux")]
#[test]
fn partial_images_and_a_saved_interrupted_render() {
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Minutes of work on one thread, in tiles of a few milliseconds.
    let mut child = Command::new(BIN)
        .args([
            "render", "--width", "512", "--height", "512", "--spp", "1024",
        ])
        .args(["--threads", "1", "-o", "out.png"])
        .args(["--write-partial", "0.2", "--save-on-interrupt"])
        .current_dir(d)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    crate::cli::wait_for_sigint_handler(&mut child);
    let out = d.join("out.png");
    let start = Instant::now();
    while !out.is_file() {
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "no partial image within 20 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let partial = image::open(&out).unwrap().to_rgb8();
    assert_eq!(partial.dimensions(), (512, 512));
    let pid = child.id().to_string();
    assert!(Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .unwrap()
        .success());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(
        err.starts_with("interrupted; wrote the image so far to out.png"),
        "{err}"
    );
    let saved = image::open(&out).unwrap().to_rgb8();
    assert_eq!(saved.dimensions(), (512, 512));
    let list = std::fs::read_to_string(d.join("out.png.missing")).unwrap();
    let rects: Vec<Vec<u32>> = list
        .lines()
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert!(
        !rects.is_empty() && rects.len() < 32 * 32,
        "{} missing",
        rects.len()
    );
    for r in &rects {
        assert!(r.len() == 4 && r[0] < r[2] && r[1] < r[3] && r[2] <= 512 && r[3] <= 512);
        // A missing tile is black in the saved image.
        assert_eq!(saved.get_pixel(r[0], r[1]).0, [0, 0, 0]);
    }
    // Only the image and the list: no temporary file left.
    assert_eq!(listing(d).len(), 2);
}
