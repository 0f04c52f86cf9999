//! The switches that turn robustness off, end to end: `--triangle-test`,
//! `--slab`, `--ray-offset`, `--mailbox` and `--exact-insertion` on
//! `gridrt render` and `gridrt rays`.

use crate::{fixture, gridrt};
use gridrt_bbox::{Real, Vec3};

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Two triangles sharing an edge from the origin to (0.3, 1, 0), and rays
/// aimed exactly at points of that edge.
fn shared_edge(dir: &std::path::Path) {
    std::fs::write(
        dir.join("edge.obj"),
        "v 0 0 0\nv 1 0.1 0\nv 0.3 1 0\nv -0.7 0.9 0\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let origin = Vec3::new(0.37, -0.21, 1.3);
    let mut csv = String::new();
    for i in 1..2000 {
        let target = Vec3::new(0.3, 1.0, 0.0) * (i as Real / 2000.0);
        let d = target - origin;
        csv += &format!(
            "{},{},{},{},{},{}\n",
            origin.x, origin.y, origin.z, d.x, d.y, d.z
        );
    }
    std::fs::write(dir.join("edge.csv"), csv).unwrap();
}

fn misses(dir: &std::path::Path, extra: &[&str]) -> usize {
    let mut args = vec!["rays", "edge.obj", "edge.csv"];
    args.extend_from_slice(extra);
    let o = gridrt(&args, dir);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert_eq!(out.lines().count(), 1999);
    out.lines().filter(|l| l.trim() == "miss").count()
}

#[test]
fn rays_through_a_shared_edge_leak_only_with_moller_trumbore() {
    let dir = tempfile::tempdir().unwrap();
    shared_edge(dir.path());
    assert_eq!(misses(dir.path(), &[]), 0);
    assert_eq!(misses(dir.path(), &["--accel", "exhaustive"]), 0);
    assert_eq!(
        misses(
            dir.path(),
            &["--mailbox", "--exact-insertion", "--slab", "textbook"]
        ),
        0
    );
    assert!(misses(dir.path(), &["--triangle-test", "moller-trumbore"]) > 0);
}

#[test]
fn render_switches_that_change_no_pixel_and_one_that_does() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("scenes/shadows.ron");
    let scene = scene.to_str().unwrap();
    let run = |out: &str, extra: &[&str]| {
        let mut args = vec![
            "render", scene, "-o", out, "--width", "48", "--height", "36",
        ];
        args.extend_from_slice(extra);
        let o = gridrt(&args, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        (
            std::fs::read(dir.path().join(out)).unwrap(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
        )
    };
    let (robust, summary) = run("a.png", &[]);
    assert!(!summary.contains("robustness"), "{summary}");
    let (same, summary) = run(
        "b.png",
        &["--mailbox", "--exact-insertion", "--slab", "textbook"],
    );
    assert_eq!(robust, same, "grid switches changed pixels");
    assert!(
        summary.contains("robustness  off: slab textbook, mailbox, exact insertion"),
        "{summary}"
    );
    let (_, summary) = run(
        "c.png",
        &[
            "--triangle-test",
            "moller-trumbore",
            "--ray-offset",
            "fixed:1e-3",
        ],
    );
    assert!(
        summary.contains("triangle test moller-trumbore, ray offset fixed:0.001"),
        "{summary}"
    );
}

#[test]
fn bad_switch_values_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, value, needle) in [
        ("--ray-offset", "fixed:x", "not a number"),
        ("--ray-offset", "fixed:-1", "positive finite"),
        ("--ray-offset", "epsilon", "error-bound"),
        ("--triangle-test", "fast", "watertight"),
        ("--slab", "naive", "textbook"),
    ] {
        let o = gridrt(&["render", flag, value], dir.path());
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(needle),
            "{flag} {value}: {}",
            stderr(&o)
        );
    }
    // `rays` casts no secondary rays: no --ray-offset there.
    let o = gridrt(
        &["rays", "a.obj", "r.csv", "--ray-offset", "fixed:1e-4"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
}
