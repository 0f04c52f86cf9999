//! `cargo xtask accuracy`: what accuracy costs in time, and what is lost
//! without it. Each study renders or traces with the robust default and
//! with the setting that gives it up, times both (medians of alternated
//! runs), measures the error against a stated reference, and writes
//! `docs/accuracy.md` with the plot `docs/accuracy-spp.svg`. Every number
//! in the report comes from the run that wrote it.

use crate::util::{self, sig3};
use crate::Outcome;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// What the studies return on failure.
pub type Res<T> = Result<T, Box<dyn std::error::Error>>;

/// Options of `cargo xtask accuracy`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A smoke run (about a minute): fewer samples per pixel, one run per
    /// setting, smaller images. Its report is written under
    /// target/accuracy/ unless --out is given, so docs/ keeps the full run.
    #[arg(long)]
    quick: bool,
    /// Timed runs per setting (alternated; the median is reported).
    #[arg(long, value_name = "R")]
    runs: Option<usize>,
    /// Where to write accuracy.md and the plots (default: docs/, or
    /// target/accuracy/ with --quick).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Skip the precision study (it builds the f32 and f64 binaries).
    #[arg(long)]
    no_precision: bool,
}

/// The sizes of one run.
#[derive(Debug, Clone)]
pub struct Opts {
    pub runs: usize,
    /// Image size of the render studies (the no-change and triangle-test
    /// renders use twice it).
    pub size: (u32, u32),
    pub spps: Vec<u32>,
    pub ref_spp: u32,
    /// Mesh scales and offsets of the triangle-test study.
    pub scales: Vec<f64>,
    pub offsets: Vec<f64>,
    /// Scene scales of the ray-offset study.
    pub offset_scales: Vec<f64>,
    /// Offsets from the origin of the precision study.
    pub far: Vec<f64>,
}

impl Opts {
    fn new(a: &Args) -> Self {
        let mut o = if a.quick {
            Self {
                runs: 1,
                size: (64, 48),
                spps: vec![1, 4, 16, 64],
                ref_spp: 256,
                scales: vec![1e-6, 1.0, 1e6],
                offsets: vec![0.0, 1e5],
                offset_scales: vec![1e-4, 1.0, 1e4],
                far: vec![0.0, 1e5],
            }
        } else {
            Self {
                runs: 5,
                size: (160, 120),
                spps: vec![1, 4, 16, 64, 256, 1024],
                ref_spp: 4096,
                scales: vec![1e-6, 1.0, 1e6],
                offsets: vec![0.0, 1e3, 1e5],
                offset_scales: vec![1e-4, 1e-2, 1.0, 1e2, 1e4],
                far: vec![0.0, 1e3, 1e5, 1e6],
            }
        };
        if let Some(r) = a.runs {
            o.runs = r.max(1);
        }
        o
    }
}

/// Seconds of a duration.
pub fn secs(d: Duration) -> f64 {
    d.as_secs_f64()
}

/// Runs `f(0), f(1), …, f(n − 1)` in rounds (so that every setting sees
/// the same machine load): one untimed warm-up round (thread pools, caches),
/// then `runs` timed ones; returns each setting's median time.
pub fn alternated(
    runs: usize,
    n: usize,
    mut f: impl FnMut(usize) -> Res<Duration>,
) -> Res<Vec<Duration>> {
    for k in 0..n {
        f(k)?;
    }
    let mut times = vec![Vec::with_capacity(runs); n];
    for _ in 0..runs.max(1) {
        for (k, t) in times.iter_mut().enumerate() {
            t.push(f(k)?);
        }
    }
    Ok(times.into_iter().map(util::median).collect())
}

/// Runs the studies and writes the report.
pub fn run(a: &Args) -> Outcome {
    let start = Instant::now();
    let o = Opts::new(a);
    let out = a.out.clone().unwrap_or_else(|| {
        if a.quick {
            util::target_dir().join("accuracy")
        } else {
            util::root().join("docs")
        }
    });
    let bins = if a.no_precision {
        None
    } else {
        Some(crate::accuracy_precision::build_binaries(
            &util::target_dir().join("accuracy/bin"),
        )?)
    };
    eprintln!("accuracy: samples per pixel");
    let (spp_md, spp_series) = crate::accuracy_studies::spp(&o)?;
    eprintln!("accuracy: triangle test");
    let tri_md = crate::accuracy_studies::triangle_test(&o)?;
    eprintln!("accuracy: ray offsets");
    let off_md = crate::accuracy_studies::offsets(&o)?;
    eprintln!("accuracy: settings that change no pixel");
    let same_md = crate::accuracy_studies::no_change(&o)?;
    let prec_md = match &bins {
        Some(b) => {
            eprintln!("accuracy: precision");
            crate::accuracy_precision::precision(&o, b)?
        }
        None => "Skipped in this run (`--no-precision`).\n".to_string(),
    };
    crate::accuracy_plot::charts_svg(
        &out.join("accuracy-spp.svg"),
        &[crate::accuracy_plot::Chart {
            title: "RMSE vs render time, 1 … N samples per pixel",
            x_desc: "render time (s)",
            y_desc: "RMSE vs reference",
            series: &spp_series,
        }],
    )?;
    let mut md = String::from("# What accuracy costs\n\n");
    md += "Generated by `cargo xtask accuracy`";
    if a.quick {
        md += " `--quick` (a smoke run: one run per setting, small images)";
    }
    md += &format!(
        " on {} in {} s, every number from this run. Times are medians of {} runs \
         alternated between the settings compared, after one untimed warm-up round; on a shared machine they vary from \
         run to run, so compare rows of one table, not tables. The robust \
         choices are gridrt's defaults; each table shows what giving one up saves in time \
         and what it loses in correctness. The switches are documented in \
         [cli.md](cli.md#switches-that-turn-robustness-off).\n\n",
        util::machine(),
        sig3(start.elapsed().as_secs_f64()),
        o.runs
    );
    md += "- [Samples per pixel](#samples-per-pixel)\n- [Precision: f32 and f64](#precision-f32-and-f64)\n- [Triangle test](#triangle-test)\n- [Ray offsets](#ray-offsets)\n- [Settings that change no pixel](#settings-that-change-no-pixel)\n\n";
    md += "## Samples per pixel\n\n";
    md += &spp_md;
    md += "\n![RMSE against render time, log-log, with the 1/√N line](accuracy-spp.svg)\n\n";
    md += "## Precision: f32 and f64\n\n";
    md += &prec_md;
    md += "\n## Triangle test\n\n";
    md += &tri_md;
    md += "\n## Ray offsets\n\n";
    md += &off_md;
    md += "\n## Settings that change no pixel\n\n";
    md += &same_md;
    let total = sig3(start.elapsed().as_secs_f64());
    util::write_atomic(&out.join("accuracy.md"), md.as_bytes())?;
    eprintln!(
        "accuracy: wrote {} and accuracy-spp.svg in {total} s",
        util::show(&out.join("accuracy.md"))
    );
    Ok(!md.contains("a bug to fix"))
}
