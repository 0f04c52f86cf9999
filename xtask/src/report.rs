//! What `regress` found per scene, as console lines and an HTML page.

use crate::bitdiff::BitDiff;
use crate::imgdiff::{Diff, Tolerance, DIFF_GAIN};
use std::fmt::Write as _;
use std::time::Duration;

/// What `--bless` did with a scene's reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BlessStatus {
    /// There was no reference; it was written.
    New,
    /// The reference differed; it was rewritten.
    Changed {
        /// How the old reference differs from the new image.
        diff: Diff,
        /// Whether the old reference would still have passed.
        within_tolerance: bool,
    },
    /// The reference had another size; it was rewritten.
    Resized {
        /// The old reference's size.
        from: (u32, u32),
    },
    /// Same pixels; the file was left alone.
    Unchanged,
    /// The scene failed a check (accelerators disagree, NaN pixels, …);
    /// nothing was written.
    Refused,
}

/// One scene's outcome.
#[derive(Clone, Debug, Default)]
pub struct SceneReport {
    /// File stem in `fixtures/scenes/`.
    pub name: String,
    /// Image size (0 × 0 when the scene did not load).
    pub size: (u32, u32),
    /// The scene's tolerance.
    pub tolerance: Tolerance,
    /// The reference's size, when there is one.
    pub reference: Option<(u32, u32)>,
    /// The comparison with the reference (when there is one of the same size).
    pub diff: Option<Diff>,
    /// Accelerators whose framebuffer differs from the exhaustive one.
    pub accel_mismatch: Vec<(String, BitDiff)>,
    /// Wall time of each accelerator's build + render.
    pub times: Vec<(String, Duration)>,
    /// Loader warnings.
    pub warnings: Vec<String>,
    /// Why the scene failed (empty: passed).
    pub failures: Vec<String>,
    /// What `--bless` did.
    pub bless: Option<BlessStatus>,
}

/// The diff's numbers in one phrase.
pub fn diff_phrase(d: &Diff) -> String {
    if d.pixels_differing == 0 {
        return "identical".to_string();
    }
    format!(
        "{} pixels differ, max {} steps, RMSE {:.4}, {:.3}% over threshold",
        d.pixels_differing,
        d.max_pixel,
        d.rmse,
        100.0 * d.fraction_over
    )
}

/// The tolerance in one phrase.
pub fn tolerance_phrase(t: &Tolerance) -> String {
    if *t == Tolerance::default() {
        "exact".to_string()
    } else {
        format!(
            "RMSE ≤ {}, max ≤ {}, ≤ {}% of pixels over {}",
            t.max_rmse,
            t.max_pixel,
            100.0 * t.max_fraction_over,
            t.pixel_threshold
        )
    }
}

fn times_phrase(r: &SceneReport) -> String {
    r.times
        .iter()
        .map(|(l, t)| format!("{l} {:.3} s", t.as_secs_f64()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// One console line for a scene.
pub fn line(r: &SceneReport) -> String {
    let status = match (&r.bless, r.failures.is_empty()) {
        (Some(BlessStatus::New), _) => "new",
        (Some(BlessStatus::Changed { .. } | BlessStatus::Resized { .. }), _) => "changed",
        (Some(BlessStatus::Unchanged), _) => "same",
        (_, true) => "ok",
        (_, false) => "FAIL",
    };
    let what = match (&r.diff, r.failures.first()) {
        (_, Some(f)) => f.clone(),
        (Some(d), None) => diff_phrase(d),
        (None, None) => "no reference".to_string(),
    };
    format!(
        "{status:<7} {:<20} {:>4}×{:<4} {what}  [{}]",
        r.name,
        r.size.0,
        r.size.1,
        times_phrase(r)
    )
}

/// What `--bless` did, one line per scene, grouped.
pub fn bless_summary(reports: &[SceneReport]) -> String {
    let mut s = String::from("bless:");
    for r in reports {
        let what = match &r.bless {
            Some(BlessStatus::New) => format!("new        {} ({}×{})", r.name, r.size.0, r.size.1),
            Some(BlessStatus::Changed {
                diff,
                within_tolerance,
            }) => format!(
                "changed    {}: {} ({} its tolerance)",
                r.name,
                diff_phrase(diff),
                if *within_tolerance {
                    "within"
                } else {
                    "beyond"
                }
            ),
            Some(BlessStatus::Resized { from }) => format!(
                "changed    {}: size {}×{} → {}×{}",
                r.name, from.0, from.1, r.size.0, r.size.1
            ),
            Some(BlessStatus::Unchanged) => format!("unchanged  {}", r.name),
            Some(BlessStatus::Refused) | None => {
                format!("NOT BLESSED {}: {}", r.name, r.failures.join("; "))
            }
        };
        let _ = write!(s, "\n  {what}");
    }
    s
}

/// Escapes text for HTML.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The HTML report: a summary table, then per scene the reference, actual
/// and diff images side by side with the numbers. Image paths are relative
/// (`<scene>-reference.png`, …), so the page works wherever the directory is
/// copied (a CI artifact, for example).
pub fn html(reports: &[SceneReport], machine: &str, elapsed: Duration, bless: bool) -> String {
    let failed = reports.iter().filter(|r| !r.failures.is_empty()).count();
    let mut h = String::new();
    let _ = write!(
        h,
        r#"<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>gridrt regress: {verdict}</title>
<style>
body {{ font-family: sans-serif; margin: 1.5em; }}
table {{ border-collapse: collapse; }}
td, th {{ border: 1px solid #ccc; padding: 3px 8px; text-align: left; vertical-align: top; }}
.fail {{ color: #b00; font-weight: bold; }} .ok {{ color: #070; }}
figure {{ display: inline-block; margin: 0 12px 12px 0; }}
figure img {{ image-rendering: pixelated; border: 1px solid #888; background: #eee; }}
figcaption {{ font-size: 90%; }}
section {{ border-top: 1px solid #aaa; margin-top: 1.2em; }}
</style></head><body>
<h1>gridrt image regression{mode}: <span class="{cls}">{verdict}</span></h1>
<p>{n} scenes, {failed} failed, {secs:.1} s on {machine}. Diff images show each channel's
difference multiplied by {gain}. Every scene is also rendered with every accelerator, whose
framebuffers must equal the exhaustive one bit for bit.</p>
<table><tr><th>scene</th><th>size</th><th>result</th><th>against the reference</th><th>tolerance</th><th>time (build + render)</th></tr>
"#,
        mode = if bless { " (bless)" } else { "" },
        cls = if failed == 0 { "ok" } else { "fail" },
        verdict = if failed == 0 {
            "passed".to_string()
        } else {
            format!("{failed} FAILED")
        },
        n = reports.len(),
        secs = elapsed.as_secs_f64(),
        machine = esc(machine),
        gain = DIFF_GAIN,
    );
    for r in reports {
        let (cls, res) = if r.failures.is_empty() {
            ("ok", "pass")
        } else {
            ("fail", "FAIL")
        };
        let _ = writeln!(
            h,
            r##"<tr><td><a href="#{id}">{name}</a></td><td>{w}×{hh}</td><td class="{cls}">{res}</td><td>{diff}</td><td>{tol}</td><td>{times}</td></tr>"##,
            id = esc(&r.name),
            name = esc(&r.name),
            w = r.size.0,
            hh = r.size.1,
            diff = r.diff.as_ref().map_or_else(|| "—".to_string(), diff_phrase),
            tol = esc(&tolerance_phrase(&r.tolerance)),
            times = esc(&times_phrase(r)),
        );
    }
    h.push_str("</table>\n");
    for r in reports {
        let _ = writeln!(
            h,
            r#"<section id="{}"><h2>{}</h2>"#,
            esc(&r.name),
            esc(&r.name)
        );
        if !r.failures.is_empty() {
            h.push_str("<ul class=\"fail\">");
            for f in &r.failures {
                let _ = write!(h, "<li>{}</li>", esc(f));
            }
            h.push_str("</ul>\n");
        }
        if let Some(d) = &r.diff {
            let _ = writeln!(
                h,
                "<p>RMSE {:.4} (≤ {}), largest channel difference {} (≤ {}), {} pixels differ, {:.4}% by more than {} (≤ {}%).</p>",
                d.rmse,
                r.tolerance.max_rmse,
                d.max_pixel,
                r.tolerance.max_pixel,
                d.pixels_differing,
                100.0 * d.fraction_over,
                r.tolerance.pixel_threshold,
                100.0 * r.tolerance.max_fraction_over
            );
        }
        if let Some(b) = &r.bless {
            let _ = writeln!(h, "<p>bless: {}</p>", esc(&format!("{b:?}")));
        }
        for w in &r.warnings {
            let _ = writeln!(h, "<p>warning: {}</p>", esc(w));
        }
        let zoom = if r.size.0 <= 200 { 2 } else { 1 };
        let fig = |h: &mut String, file: String, caption: &str| {
            let _ = write!(
                h,
                r#"<figure><img src="{f}" width="{w}" height="{hh}" alt="{c}"><figcaption>{c}</figcaption></figure>"#,
                f = esc(&file),
                w = r.size.0 * zoom,
                hh = r.size.1 * zoom,
                c = esc(caption)
            );
        };
        if r.reference.is_some() {
            fig(&mut h, format!("{}-reference.png", r.name), "reference");
        }
        if r.size.0 > 0 {
            fig(&mut h, format!("{}-actual.png", r.name), "actual (grid)");
        }
        if r.diff.is_some() {
            fig(
                &mut h,
                format!("{}-diff.png", r.name),
                &format!("difference × {}", DIFF_GAIN),
            );
        }
        if !r.accel_mismatch.is_empty() {
            fig(&mut h, format!("{}-exhaustive.png", r.name), "exhaustive");
        }
        h.push_str("</section>\n");
    }
    h.push_str("</body></html>\n");
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn passing() -> SceneReport {
        SceneReport {
            name: "shadows".into(),
            size: (160, 120),
            reference: Some((160, 120)),
            diff: Some(Diff::default()),
            times: vec![("grid".into(), Duration::from_millis(20))],
            ..SceneReport::default()
        }
    }

    #[test]
    fn console_lines_say_pass_or_fail_and_why() {
        let ok = passing();
        assert!(line(&ok).starts_with("ok "), "{}", line(&ok));
        assert!(line(&ok).contains("identical"));
        let mut bad = passing();
        bad.failures.push("RMSE 1.0000 > 0.0000".into());
        assert!(line(&bad).starts_with("FAIL") && line(&bad).contains("RMSE 1.0000"));
    }

    #[test]
    fn html_escapes_and_links_the_images() {
        let mut bad = passing();
        bad.name = "a<b".into();
        bad.failures.push("x & y".into());
        let page = html(&[passing(), bad], "cpu", Duration::from_secs(1), false);
        assert!(page.contains("1 FAILED"));
        assert!(page.contains("a&lt;b-diff.png") && page.contains("x &amp; y"));
        assert!(page.contains(r#"src="shadows-reference.png""#));
        assert!(!page.contains("a<b"));
    }

    #[test]
    fn bless_summary_lists_every_kind() {
        let mut a = passing();
        a.bless = Some(BlessStatus::New);
        let mut b = passing();
        b.name = "phong".into();
        b.bless = Some(BlessStatus::Changed {
            diff: Diff {
                rmse: 0.5,
                max_pixel: 3,
                fraction_over: 0.01,
                pixels_differing: 12,
            },
            within_tolerance: false,
        });
        let mut c = passing();
        c.name = "same".into();
        c.bless = Some(BlessStatus::Unchanged);
        let s = bless_summary(&[a, b, c]);
        assert!(s.contains("new        shadows"));
        assert!(
            s.contains("changed    phong: 12 pixels differ, max 3 steps") && s.contains("beyond")
        );
        assert!(s.contains("unchanged  same"));
    }

    #[test]
    fn tolerance_phrases() {
        assert_eq!(tolerance_phrase(&Tolerance::default()), "exact");
        let t = Tolerance {
            max_rmse: 0.1,
            max_pixel: 2,
            pixel_threshold: 1,
            max_fraction_over: 0.001,
        };
        assert_eq!(
            tolerance_phrase(&t),
            "RMSE ≤ 0.1, max ≤ 2, ≤ 0.1% of pixels over 1"
        );
    }
}
