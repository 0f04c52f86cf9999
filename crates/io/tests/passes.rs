//! `gridrt render --aov`: render passes as EXR channels and PNG pictures.

use crate::{fixture, gridrt};

fn channel(img: &exr::prelude::FlatImage, name: &str) -> Vec<f32> {
    let c = img.layer_data[0]
        .channel_data
        .list
        .iter()
        .find(|c| c.name.eq(name))
        .unwrap_or_else(|| panic!("no channel {name}"));
    match &c.sample_data {
        exr::prelude::FlatSamples::F32(v) => v.clone(),
        other => panic!("{name}: {other:?}"),
    }
}

#[test]
fn exr_passes_agree_with_each_other_and_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = fixture("scenes/shadows.ron").display().to_string();
    let o = gridrt(
        &["render", &scene, "-o", "a.exr", "--aov", "all", "--quiet"],
        d,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = exr::prelude::read_all_flat_layers_from_file(d.join("a.exr")).unwrap();
    let ids = channel(&img, "prim-id.V");
    let mats = channel(&img, "material-id.V");
    let depth = channel(&img, "depth.Z");
    let tests = channel(&img, "tests.V");
    let (nx, ny, nz) = (
        channel(&img, "normal.X"),
        channel(&img, "normal.Y"),
        channel(&img, "normal.Z"),
    );
    let r = channel(&img, "R");
    assert_eq!(ids.len(), r.len());
    assert!(ids.iter().any(|&i| i >= 0.0), "something is hit");
    for k in 0..ids.len() {
        if ids[k] < 0.0 {
            // A miss: no material, infinite depth, no normal.
            assert_eq!(mats[k], -1.0);
            assert_eq!(depth[k], f32::INFINITY);
            assert_eq!((nx[k], ny[k], nz[k]), (0.0, 0.0, 0.0));
        } else {
            assert!(mats[k] >= 0.0);
            assert!(depth[k].is_finite() && depth[k] > 0.0);
            let len = (nx[k] * nx[k] + ny[k] * ny[k] + nz[k] * nz[k]).sqrt();
            assert!((len - 1.0).abs() < 1e-3, "unit normal, got {len}");
        }
        assert!(tests[k] >= 0.0);
    }
    // The image is the same with or without passes.
    let o = gridrt(&["render", &scene, "-o", "b.exr", "--quiet"], d);
    assert!(o.status.success());
    let plain = exr::prelude::read_all_flat_layers_from_file(d.join("b.exr")).unwrap();
    assert_eq!(channel(&plain, "R"), r);
}

#[test]
fn png_passes_are_pictures_beside_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = gridrt(
        &[
            "--width",
            "64",
            "--height",
            "48",
            "--aov",
            "normal,cells-visited",
            "-o",
            "x.png",
        ],
        d,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(text.contains("pass        x.normal.png"), "{text}");
    for f in ["x.png", "x.normal.png", "x.cells-visited.png"] {
        let img = image::open(d.join(f)).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (64, 48), "{f}");
        assert!(img.pixels().any(|p| p.0 != [0, 0, 0]), "{f} is not black");
    }
}

#[test]
fn bad_pass_lists_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = gridrt(&["--aov", "albedo,colour", "-o", "x.png"], d);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("unknown pass `colour`"));
    let o = gridrt(&["--aov", "albedo", "--tile", "0/2", "-o", "x.exr"], d);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read_dir(d).unwrap().count(), 0);
}
