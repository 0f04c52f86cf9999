//! `cargo xtask regress`: render every fixture scene, check that every
//! accelerator gives the same framebuffer bit for bit, and compare the image
//! with its reference.
//!
//! For each `fixtures/scenes/<name>.ron`:
//! 1. render it with the grid (default configuration), the grid with the
//!    other cell storage, and exhaustively; the framebuffers (linear `f32`)
//!    must be identical bit for bit, and finite;
//! 2. write the grid's image as `target/regress/<name>-actual.png` and compare
//!    its 8-bit pixels with `fixtures/reference/<name>.png` within the scene's
//!    tolerance (`fixtures/reference/tolerances.ron`; exact when not listed);
//!    the difference, magnified, goes to `<name>-diff.png`;
//! 3. `target/regress/index.html` shows reference, actual and diff side by
//!    side with the numbers.
//!
//! `--bless` writes the references instead (new and changed scenes only,
//! never for a scene whose accelerators disagree) and lists what changed.

use crate::bitdiff::bitwise_diff;
use crate::imgdiff::{compare, Diff, Tolerance, DIFF_GAIN};
use crate::report::{self, BlessStatus, SceneReport};
use crate::tolerances;
use crate::util;
use gridrt_grid::CellStorage;
use gridrt_tracer::{render, AccelKind, Framebuffer, RenderOptions, Scene};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Options of `cargo xtask regress`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Rewrite fixtures/reference/ with the images rendered now (new and
    /// changed scenes only) and list what changed.
    #[arg(long)]
    bless: bool,
    /// Run only this scene (a file stem in fixtures/scenes/); repeat or
    /// separate with commas for more.
    #[arg(long = "scene", value_name = "NAME", value_delimiter = ',')]
    scenes: Vec<String>,
    /// Worker threads (default: all cores). Images do not depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    threads: Option<u32>,
}

/// The fixture scenes, sorted by name: (name, path).
fn scene_files(dir: &Path) -> Result<Vec<(String, PathBuf)>, String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", util::show(dir)))?;
    let mut out = Vec::new();
    for entry in entries {
        let path = entry
            .map_err(|e| format!("{}: {e}", util::show(dir)))?
            .path();
        if path.extension().and_then(|e| e.to_str()) == Some("ron") {
            if let Some(stem) = path.file_stem().and_then(|s| s.to_str()) {
                out.push((stem.to_string(), path.clone()));
            }
        }
    }
    out.sort();
    Ok(out)
}

/// Picks the scenes asked for (all when `wanted` is empty).
fn select(
    all: Vec<(String, PathBuf)>,
    wanted: &[String],
) -> Result<Vec<(String, PathBuf)>, String> {
    if wanted.is_empty() {
        return Ok(all);
    }
    let names: Vec<&str> = all.iter().map(|(n, _)| n.as_str()).collect();
    if let Some(bad) = wanted.iter().find(|w| !names.contains(&w.as_str())) {
        return Err(format!(
            "no scene \"{bad}\" in fixtures/scenes/; the scenes are: {}",
            names.join(", ")
        ));
    }
    Ok(all
        .into_iter()
        .filter(|(n, _)| wanted.contains(n))
        .collect())
}

/// One render: framebuffer and wall time (build + render).
struct Rendered {
    fb: Framebuffer,
    time: Duration,
}

fn render_with(scene: &Scene, options: &RenderOptions) -> Result<Rendered, String> {
    let start = Instant::now();
    let (fb, _stats) = render(scene, options).map_err(|e| e.to_string())?;
    Ok(Rendered {
        fb,
        time: start.elapsed(),
    })
}

/// The accelerator configurations every scene is rendered with; the first
/// is the one compared with the reference, the last is the exhaustive
/// ground truth.
fn configurations(threads: Option<usize>) -> Vec<(&'static str, RenderOptions)> {
    let base = RenderOptions {
        threads,
        ..RenderOptions::default()
    };
    let mut other = base;
    let other_name = match base.grid.storage {
        CellStorage::Dense => {
            other.grid.storage = CellStorage::Hashed;
            "grid (hashed cells)"
        }
        CellStorage::Hashed => {
            other.accel = AccelKind::DenseGrid;
            "grid (dense cells)"
        }
    };
    let exhaustive = RenderOptions {
        accel: AccelKind::Exhaustive,
        ..base
    };
    vec![
        ("grid", base),
        (other_name, other),
        ("exhaustive", exhaustive),
    ]
}

/// 8-bit RGB pixels of a PNG file.
fn read_rgb8(path: &Path) -> Result<(u32, u32, Vec<u8>), String> {
    let img = image::open(path)
        .map_err(|e| format!("{}: {e}", util::show(path)))?
        .to_rgb8();
    Ok((img.width(), img.height(), img.into_raw()))
}

/// Encodes RGB8 pixels as PNG and writes them atomically.
fn write_rgb8(path: &Path, width: u32, height: u32, pixels: Vec<u8>) -> Result<(), String> {
    let img =
        image::RgbImage::from_raw(width, height, pixels).ok_or("diff image of the wrong size")?;
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .map_err(|e| format!("{}: {e}", util::show(path)))?;
    util::write_atomic(path, &bytes).map_err(|e| format!("{}: {e}", util::show(path)))
}

/// Runs the regression (or the bless); `Ok(false)` when a scene failed.
pub fn run(args: &Args) -> crate::Outcome {
    let root = util::root();
    let scenes_dir = root.join("fixtures/scenes");
    let ref_dir = root.join("fixtures/reference");
    let out_dir = util::target_dir().join("regress");
    let tol_path = ref_dir.join("tolerances.ron");

    let all = scene_files(&scenes_dir)?;
    let names: Vec<String> = all.iter().map(|(n, _)| n.clone()).collect();
    let tols = tolerances::load(&tol_path)?;
    let stale = tolerances::unknown(&tols, &names);
    if !stale.is_empty() {
        return Err(format!(
            "{}: no scene named {} in fixtures/scenes/ (remove or rename the entry)",
            util::show(&tol_path),
            stale.join(", ")
        )
        .into());
    }
    let scenes = select(all, &args.scenes)?;

    // A fresh report directory: no images left over from an earlier run.
    if out_dir.exists() {
        std::fs::remove_dir_all(&out_dir).map_err(|e| format!("{}: {e}", util::show(&out_dir)))?;
    }
    std::fs::create_dir_all(&out_dir).map_err(|e| format!("{}: {e}", util::show(&out_dir)))?;

    let threads = args.threads.map(|t| t as usize);
    let configs = configurations(threads);
    eprintln!(
        "regress: {} scene{}, {} threads, accelerators: {}{}",
        scenes.len(),
        if scenes.len() == 1 { "" } else { "s" },
        threads.map_or_else(|| "all".to_string(), |t| t.to_string()),
        configs.iter().map(|c| c.0).collect::<Vec<_>>().join(", "),
        if args.bless { " (bless)" } else { "" }
    );
    let start = Instant::now();
    let mut reports = Vec::new();
    for (name, path) in &scenes {
        let tolerance = tolerances::of(&tols, name);
        let rep = run_scene(
            name, path, &ref_dir, &out_dir, tolerance, &configs, args.bless,
        );
        eprintln!("{}", report::line(&rep));
        reports.push(rep);
    }
    let elapsed = start.elapsed();

    let html = report::html(&reports, &util::machine(), elapsed, args.bless);
    let index = out_dir.join("index.html");
    util::write_atomic(&index, html.as_bytes())
        .map_err(|e| format!("{}: {e}", util::show(&index)))?;

    // References without a scene (only worth a note: nothing reads them).
    if args.scenes.is_empty() {
        if let Ok(entries) = std::fs::read_dir(&ref_dir) {
            let mut orphans: Vec<String> = entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("png"))
                .filter_map(|p| p.file_stem().and_then(|s| s.to_str()).map(str::to_string))
                .filter(|s| !names.contains(s))
                .collect();
            orphans.sort();
            if !orphans.is_empty() {
                eprintln!("note: references without a scene: {}", orphans.join(", "));
            }
        }
    }

    let failed: Vec<&SceneReport> = reports.iter().filter(|r| !r.failures.is_empty()).collect();
    if args.bless {
        eprintln!("\n{}", report::bless_summary(&reports));
    }
    eprintln!(
        "\nregress: {} of {} scenes passed in {:.1} s; report: {}",
        reports.len() - failed.len(),
        reports.len(),
        elapsed.as_secs_f64(),
        util::show(&index)
    );
    if failed.is_empty() {
        return Ok(true);
    }
    eprintln!("FAILED:");
    for r in &failed {
        eprintln!("  {}: {}", r.name, r.failures.join("; "));
    }
    if !args.bless
        && failed
            .iter()
            .any(|r| r.diff.is_some() || r.reference.is_none())
    {
        eprintln!(
            "(if a change is intended, look at the report, then run `cargo xtask regress --bless`)"
        );
    }
    Ok(false)
}

/// Renders and checks one scene; every problem ends up in `failures`.
fn run_scene(
    name: &str,
    path: &Path,
    ref_dir: &Path,
    out_dir: &Path,
    tolerance: Tolerance,
    configs: &[(&'static str, RenderOptions)],
    bless: bool,
) -> SceneReport {
    let mut rep = SceneReport {
        name: name.to_string(),
        tolerance,
        ..SceneReport::default()
    };
    if let Err(e) = check_scene(&mut rep, path, ref_dir, out_dir, configs, bless) {
        rep.failures.push(e);
    }
    rep
}

fn check_scene(
    rep: &mut SceneReport,
    path: &Path,
    ref_dir: &Path,
    out_dir: &Path,
    configs: &[(&'static str, RenderOptions)],
    bless: bool,
) -> Result<(), String> {
    let name = rep.name.clone();
    let loaded = crate::util::load_scene(path).map_err(|e| e.to_string())?;
    rep.warnings = loaded.warnings.clone();
    let scene = &loaded.scene;
    rep.size = (scene.settings.width, scene.settings.height);

    // 1. Every accelerator, bit for bit.
    let mut renders = Vec::new();
    for (label, options) in configs {
        let r = render_with(scene, options).map_err(|e| format!("{label}: {e}"))?;
        rep.times.push((label.to_string(), r.time));
        renders.push(r);
    }
    let truth = &renders[renders.len() - 1].fb;
    let bad = renders[0].fb.non_finite_pixels();
    if bad > 0 {
        rep.failures
            .push(format!("{bad} pixels are NaN or infinite"));
    }
    for ((label, _), r) in configs.iter().zip(&renders).take(configs.len() - 1) {
        if let Some(d) = bitwise_diff(&r.fb, truth, None)? {
            rep.failures
                .push(format!("{label} and exhaustive differ: {d}"));
            rep.accel_mismatch.push((label.to_string(), d));
        }
    }
    if !rep.accel_mismatch.is_empty() {
        let p = out_dir.join(format!("{name}-exhaustive.png"));
        gridrt_io::write_framebuffer(&p, truth).map_err(|e| e.to_string())?;
    }

    // 2. The grid's image against the reference.
    let actual_path = out_dir.join(format!("{name}-actual.png"));
    gridrt_io::write_framebuffer(&actual_path, &renders[0].fb).map_err(|e| e.to_string())?;
    let (w, h, actual) = read_rgb8(&actual_path)?;
    let ref_path = ref_dir.join(format!("{name}.png"));
    let reference = if ref_path.exists() {
        Some(read_rgb8(&ref_path)?)
    } else {
        None
    };
    rep.reference = reference.as_ref().map(|r| (r.0, r.1));
    let mut diff: Option<Diff> = None;
    match &reference {
        None => {}
        // A resized scene: nothing to compare (bless rewrites the reference).
        Some((rw, rh, _)) if (*rw, *rh) != (w, h) => rep
            .failures
            .extend((!bless).then(|| format!("the reference is {rw}×{rh}, the image {w}×{h}"))),
        Some((_, _, ref_px)) => {
            std::fs::copy(&ref_path, out_dir.join(format!("{name}-reference.png")))
                .map_err(|e| format!("{}: {e}", util::show(&ref_path)))?;
            let (d, img) = compare(ref_px, &actual, rep.tolerance.pixel_threshold, DIFF_GAIN);
            write_rgb8(&out_dir.join(format!("{name}-diff.png")), w, h, img)?;
            if !bless {
                for v in d.violations(&rep.tolerance) {
                    rep.failures.push(v);
                }
            }
            diff = Some(d);
        }
    }
    rep.diff = diff;

    if !bless {
        if reference.is_none() {
            rep.failures.push(format!(
                "no reference {}: render it with `cargo xtask regress --bless --scene {name}` and look at it",
                util::show(&ref_path)
            ));
        }
        return Ok(());
    }

    // 3. Bless: never bless a scene the accelerators disagree on.
    let status = match (&reference, &diff) {
        (None, _) => BlessStatus::New,
        (Some(_), Some(d)) if d.pixels_differing == 0 => BlessStatus::Unchanged,
        (Some(_), Some(d)) => BlessStatus::Changed {
            diff: *d,
            within_tolerance: d.violations(&rep.tolerance).is_empty(),
        },
        (Some((rw, rh, _)), None) => BlessStatus::Resized { from: (*rw, *rh) },
    };
    if !rep.failures.is_empty() {
        rep.bless = Some(BlessStatus::Refused);
        return Ok(());
    }
    if status != BlessStatus::Unchanged {
        let bytes = std::fs::read(&actual_path)
            .map_err(|e| format!("{}: {e}", util::show(&actual_path)))?;
        util::write_atomic(&ref_path, &bytes)
            .map_err(|e| format!("{}: {e}", util::show(&ref_path)))?;
        std::fs::copy(&ref_path, out_dir.join(format!("{name}-reference.png")))
            .map_err(|e| format!("{}: {e}", util::show(&ref_path)))?;
    }
    rep.bless = Some(status);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selecting_unknown_scenes_names_the_known_ones() {
        let all = vec![
            ("a".to_string(), PathBuf::from("a.ron")),
            ("b".to_string(), PathBuf::from("b.ron")),
        ];
        assert_eq!(select(all.clone(), &[]).unwrap().len(), 2);
        assert_eq!(select(all.clone(), &["b".to_string()]).unwrap()[0].0, "b");
        let e = select(all, &["c".to_string()]).unwrap_err();
        assert!(e.contains("\"c\"") && e.contains("a, b"), "{e}");
    }

    #[test]
    fn exhaustive_comes_last_and_the_grid_first() {
        let c = configurations(Some(1));
        assert_eq!(c[0].1.accel, AccelKind::Grid);
        assert_eq!(c.last().map(|c| c.1.accel), Some(AccelKind::Exhaustive));
        assert!(c.iter().all(|c| c.1.threads == Some(1)));
    }

    /// Every fixture scene parses, and has a reference image of its size.
    #[test]
    fn every_fixture_scene_loads_and_has_a_reference() {
        let root = util::root();
        for (name, path) in scene_files(&root.join("fixtures/scenes")).unwrap() {
            let loaded = crate::util::load_scene(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
            let s = &loaded.scene.settings;
            let png = root.join(format!("fixtures/reference/{name}.png"));
            let (w, h, _) = read_rgb8(&png).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!((w, h), (s.width, s.height), "{name}");
        }
        let tols = tolerances::load(&root.join("fixtures/reference/tolerances.ron")).unwrap();
        let names: Vec<String> = scene_files(&root.join("fixtures/scenes"))
            .unwrap()
            .into_iter()
            .map(|s| s.0)
            .collect();
        assert!(tolerances::unknown(&tols, &names).is_empty());
    }
}
