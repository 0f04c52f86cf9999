//! `--stats` of `gridrt rays` and `gridrt render`, `--threads` of `rays`,
//! and what `--accel auto` reports it chose.

use crate::{fixture, gridrt};
use std::fmt::Write as _;
use std::path::Path;
use std::process::Output;

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The fields every `--stats` file holds, with values that fit `rays`
/// rays of which `hits` hit.
fn check_perf(j: &serde_json::Value, rays: u64, hits: u64) {
    for k in [
        "accel",
        "accel_requested",
        "build_s",
        "trace_s",
        "rays",
        "hits",
        "mrays_per_s",
        "cells_per_ray",
        "tests_per_ray",
        "bytes",
    ] {
        assert!(!j[k].is_null(), "missing `{k}` in {j}");
    }
    assert_eq!(j["rays"].as_u64(), Some(rays), "{j}");
    assert_eq!(j["hits"].as_u64(), Some(hits), "{j}");
    let trace = j["trace_s"].as_f64().unwrap();
    assert!(trace > 0.0 && j["build_s"].as_f64().unwrap() >= 0.0, "{j}");
    let m = j["mrays_per_s"].as_f64().unwrap();
    assert!(
        (m - rays as f64 / trace * 1e-6).abs() <= 1e-9 * m.max(1.0),
        "{j}"
    );
    assert!(j["tests_per_ray"].as_f64().unwrap() > 0.0, "{j}");
}

/// A teapot in a stadium: a finely tessellated unit sphere (about `n`
/// triangles) at the origin inside a 2000-unit box of 12 triangles, and
/// rays from a corner of the box at the sphere and around it.
fn stadium(dir: &Path, n: usize) {
    let mut obj = String::new();
    let s = 1000.0;
    for (x, y, z) in [
        (-s, -s, -s),
        (s, -s, -s),
        (s, s, -s),
        (-s, s, -s),
        (-s, -s, s),
        (s, -s, s),
        (s, s, s),
        (-s, s, s),
    ] {
        writeln!(obj, "v {x} {y} {z}").unwrap();
    }
    for f in [
        [1, 2, 3],
        [1, 3, 4],
        [5, 7, 6],
        [5, 8, 7],
        [1, 5, 6],
        [1, 6, 2],
        [4, 3, 7],
        [4, 7, 8],
        [1, 4, 8],
        [1, 8, 5],
        [2, 6, 7],
        [2, 7, 3],
    ] {
        writeln!(obj, "f {} {} {}", f[0], f[1], f[2]).unwrap();
    }
    // A UV sphere of radius 1 at the origin: `lon` segments, `n / lon / 2`
    // rings (2·lon·(rings − 1) triangles).
    let lon = 64;
    let rings = n / lon / 2 + 1;
    writeln!(obj, "v 0 0 1").unwrap();
    writeln!(obj, "v 0 0 -1").unwrap();
    for i in 1..rings {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..lon {
            let ph = std::f64::consts::TAU * j as f64 / lon as f64;
            writeln!(
                obj,
                "v {} {} {}",
                th.sin() * ph.cos(),
                th.sin() * ph.sin(),
                th.cos()
            )
            .unwrap();
        }
    }
    // OBJ indices: the box's 8 vertices first, then the poles (9, 10).
    let ring = |i: usize, j: usize| 11 + (i - 1) * lon + j % lon;
    for j in 0..lon {
        writeln!(obj, "f 9 {} {}", ring(1, j), ring(1, j + 1)).unwrap();
        writeln!(
            obj,
            "f 10 {} {}",
            ring(rings - 1, j + 1),
            ring(rings - 1, j)
        )
        .unwrap();
        for i in 1..rings - 1 {
            let (a, b) = (ring(i, j), ring(i, j + 1));
            let (c, d) = (ring(i + 1, j), ring(i + 1, j + 1));
            writeln!(obj, "f {a} {c} {d}").unwrap();
            writeln!(obj, "f {a} {d} {b}").unwrap();
        }
    }
    std::fs::write(dir.join("stadium.obj"), obj).unwrap();
    let mut rays = String::new();
    for k in 0..3000 {
        let u = (k % 60) as f64 / 30.0 - 1.0;
        let v = (k / 60) as f64 / 25.0 - 1.0;
        writeln!(rays, "900,800,700,{},{},{}", u - 900.0, v - 800.0, -700.0).unwrap();
    }
    std::fs::write(dir.join("rays.csv"), rays).unwrap();
}

#[test]
fn rays_stats_hold_the_figures_and_threads_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    stadium(dir.path(), 4096);
    let mut answers = Vec::new();
    // The stadium's 12 triangles are outsized beside the ball's: `auto`
    // sets them aside and keeps a flat grid over the ball.
    for (accel, threads, built) in [
        ("auto", "1", "grid"),
        ("auto", "3", "grid"),
        ("grid", "2", "grid"),
        ("hierarchy", "1", "hierarchy"),
        ("exhaustive", "2", "exhaustive"),
    ] {
        let o = gridrt(
            &[
                "rays",
                "stadium.obj",
                "rays.csv",
                "--accel",
                accel,
                "--threads",
                threads,
                "--stats",
                "s.json",
            ],
            dir.path(),
        );
        let out = ok(&o);
        let hits = out.lines().filter(|l| *l != "miss").count() as u64;
        assert!(hits > 1000 && out.lines().count() == 3000, "{accel}");
        let j = json(&dir.path().join("s.json"));
        check_perf(&j, 3000, hits);
        assert_eq!(j["accel"], built, "{j}");
        assert_eq!(j["accel_requested"], accel);
        assert_eq!(j["threads"].as_u64(), Some(threads.parse().unwrap()));
        assert_eq!(j["triangles"].as_u64(), Some(12 + 2 * 64 * 32));
        if accel == "exhaustive" {
            assert_eq!(j["tests_per_ray"].as_f64(), Some(12.0 + 2.0 * 64.0 * 32.0));
            assert_eq!(j["bytes"].as_u64(), Some(0));
        } else {
            assert!(j["bytes"].as_u64().unwrap() > 0);
            assert!(j["cells_per_ray"].as_f64().unwrap() >= 1.0);
            // The flat grid's one central cell holds the whole sphere:
            // the nested grids, or the flat grid's group boxes in that
            // cell, test a small part of its triangles.
            let tests = j["tests_per_ray"].as_f64().unwrap();
            assert!(tests < 400.0, "{j}");
            if built == "grid" {
                assert!(j["grid"]["grouped_cells"].as_u64().unwrap() > 0, "{j}");
            }
            // The walls are the primitives kept outside the cells (under
            // `hierarchy` too, which decides cell by cell below them).
            assert_eq!(j["grid"]["prims_outside_cells"].as_u64(), Some(12), "{j}");
            assert!(j["grid"]["nested_grids"].as_u64().is_some());
        }
        answers.push(out);
    }
    // Same answers whatever the accelerator and the thread count.
    assert!(answers.windows(2).all(|w| w[0] == w[1]));
    // `info` says so on its grid line.
    let info = ok(&gridrt(&["info", "stadium.obj"], dir.path()));
    assert!(info.contains(", 12 primitives outside the cells"), "{info}");
}

#[test]
fn auto_stays_flat_on_a_uniform_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = fixture("meshes/generated/tri.obj");
    let rays = fixture("meshes/generated/tri_rays.csv");
    let o = gridrt(
        &[
            "rays",
            mesh.to_str().unwrap(),
            rays.to_str().unwrap(),
            "--stats",
            "s.json",
        ],
        dir.path(),
    );
    ok(&o);
    let j = json(&dir.path().join("s.json"));
    assert_eq!(j["accel"], "grid");
    assert_eq!(j["accel_requested"], "auto");
    assert_eq!(j["grid"]["nested_grids"].as_u64(), Some(0));
}

#[test]
fn rays_stats_refuse_to_overwrite_an_input() {
    let dir = tempfile::tempdir().unwrap();
    stadium(dir.path(), 256);
    let o = gridrt(
        &["rays", "stadium.obj", "rays.csv", "--stats", "rays.csv"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--stats names an input"), "{e}");
    assert!(std::fs::read_to_string(dir.path().join("rays.csv"))
        .unwrap()
        .starts_with("900,800,700"));
}

#[test]
fn render_stats_hold_the_figures_and_the_summary_a_speed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("scenes/obj_teapot.ron");
    for accel in ["auto", "exhaustive"] {
        let o = gridrt(
            &[
                "render",
                scene.to_str().unwrap(),
                "--allow-path",
                fixture("").to_str().unwrap(),
                "--width",
                "24",
                "--height",
                "18",
                "--threads",
                "2",
                "--accel",
                accel,
                "--stats",
                "s.json",
                "-o",
                "t.png",
            ],
            dir.path(),
        );
        let out = ok(&o);
        let speed = out
            .lines()
            .find(|l| l.starts_with("speed"))
            .unwrap_or_else(|| panic!("{out}"));
        assert!(speed.ends_with("Mrays/s"), "{speed}");
        assert!(!speed.contains(" 0.00 "), "{speed}");
        let j = json(&dir.path().join("s.json"));
        let rays = j["rays_by_kind"]["camera"].as_u64().unwrap();
        assert_eq!(rays, 24 * 18);
        let total = j["rays_total"].as_u64().unwrap();
        check_perf(&j, total, j["pixels_hit"].as_u64().unwrap());
        assert_eq!(j["accel_requested"], accel);
        if accel == "exhaustive" {
            assert_eq!(j["accel"], "exhaustive");
            assert_eq!(j["cells_per_ray"].as_f64(), Some(0.0));
        } else {
            assert!(j["cells_per_ray"].as_f64().unwrap() > 0.0);
        }
    }
}

#[test]
fn grid_memory_caps_absurd_settings_and_keeps_the_answers() {
    let dir = tempfile::tempdir().unwrap();
    stadium(dir.path(), 1024);
    let run = |extra: &[&str]| {
        let mut args = vec!["rays", "stadium.obj", "rays.csv", "--stats", "s.json"];
        args.extend_from_slice(extra);
        let out = ok(&gridrt(&args, dir.path()));
        (out, json(&dir.path().join("s.json")))
    };
    let (reference, _) = run(&["--accel", "exhaustive"]);
    // One nested grid per cell of a single reference, a thousand cells per
    // primitive: far over a MiB if nothing stopped it.
    let (out, j) = run(&["--grid-nest", "1", "--grid-m", "1000", "--grid-memory", "1"]);
    assert_eq!(j["grid"]["budget"].as_u64(), Some(1 << 20), "{j}");
    assert!(j["bytes"].as_u64().unwrap() <= 1 << 20, "{j}");
    assert_eq!(out, reference);
    let o = gridrt(
        &["rays", "stadium.obj", "rays.csv", "--grid-memory", "0"],
        dir.path(),
    );
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--grid-memory"));
}

#[test]
fn no_cell_groups_turns_the_group_boxes_off_and_keeps_the_answers() {
    let dir = tempfile::tempdir().unwrap();
    stadium(dir.path(), 1024);
    let run = |extra: &[&str]| {
        let mut args = vec![
            "rays",
            "stadium.obj",
            "rays.csv",
            "--accel",
            "grid",
            "--stats",
            "s.json",
        ];
        args.extend_from_slice(extra);
        let out = ok(&gridrt(&args, dir.path()));
        (out, json(&dir.path().join("s.json")))
    };
    let (grouped, g) = run(&[]);
    let (plain, p) = run(&["--no-cell-groups"]);
    assert_eq!(grouped, plain);
    assert!(g["grid"]["grouped_cells"].as_u64().unwrap() > 0, "{g}");
    assert_eq!(p["grid"]["grouped_cells"].as_u64(), Some(0), "{p}");
    let tests = |j: &serde_json::Value| j["tests_per_ray"].as_f64().unwrap();
    assert!(tests(&p) > tests(&g), "{} {}", tests(&p), tests(&g));
}
