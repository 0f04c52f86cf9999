//! `cargo xtask <task>`: project automation (see the README).
//!
//! A thin binary: it parses arguments, calls the gridrt crates, and formats
//! what they return. Scratch output goes under `target/`; generated docs go
//! to `docs/`, written atomically.
//!
//! - `cargo xtask regress [--bless] [--scene NAME]...` renders every scene of
//!   `fixtures/scenes/` with the grid and exhaustively, checks that the two
//!   framebuffers are bitwise identical, compares the grid's image with
//!   `fixtures/reference/<scene>.png` within the tolerance stated in
//!   `fixtures/reference/tolerances.ron`, and writes actual and diff images
//!   and an HTML report to `target/regress/`.
//! - `cargo xtask speedup-table [--sizes ...] [--runs R] [--threads T]
//!   [--full] [--out DIR]` regenerates Suffern's grid vs exhaustive table
//!   (`docs/speedup-table.md`) and its plot (`docs/speedup.svg`).
//! - `cargo xtask scenes [--only NAME,...] [--runs R] [--no-embree]` measures
//!   the scene corpus beside Embree (`docs/scenes.md`, `docs/scenes.svg`).
//! - `cargo xtask accuracy [--quick] [--runs R] [--out DIR] [--no-precision]`
//!   measures what accuracy costs (`docs/accuracy.md`, `docs/accuracy-spp.svg`).

/// The `gridrt` binary's allocator, so that the timings here (the scene
/// corpus, the speed-up table) see the memory the binary's users get: large
/// arrays on huge pages.
#[global_allocator]
static ALLOC: gridrt_io::HugePageAlloc = gridrt_io::HugePageAlloc;

mod accuracy;
mod accuracy_plot;
mod accuracy_precision;
mod accuracy_studies;
mod bitdiff;
mod corpus;
mod corpus_generated;
#[cfg(feature = "embree")]
mod embree;
mod imgdiff;
mod measure;
mod peer;
mod plot;
mod regress;
mod report;
mod scenes;
mod scenes_render;
mod scenes_report;
mod speedup;
mod table;
mod tolerances;
mod util;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Project automation for gridrt.
#[derive(Debug, Parser)]
#[command(name = "cargo xtask", bin_name = "cargo xtask")]
struct Cli {
    #[command(subcommand)]
    task: Task,
}

#[derive(Debug, Subcommand)]
enum Task {
    /// Render every fixture scene and compare it with fixtures/reference/
    /// (and the grid's image with the exhaustive one, bit for bit).
    Regress(regress::Args),
    /// Regenerate Suffern's grid vs exhaustive speed-up table
    /// (docs/speedup-table.md, docs/speedup.svg).
    SpeedupTable(speedup::Args),
    /// Measure the scene corpus beside Embree (docs/scenes.md,
    /// docs/scenes.svg).
    Scenes(scenes::Args),
    /// Measure what accuracy costs in time and what is lost without it
    /// (docs/accuracy.md, docs/accuracy-spp.svg).
    Accuracy(accuracy::Args),
}

/// What a task reports when it ran to the end: whether every check passed.
pub(crate) type Outcome = Result<bool, Box<dyn std::error::Error>>;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.task {
        Task::Regress(args) => regress::run(&args),
        Task::SpeedupTable(args) => speedup::run(&args),
        Task::Scenes(args) => scenes::run(&args),
        Task::Accuracy(args) => accuracy::run(&args),
    };
    match outcome {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("xtask: error: {e}");
            ExitCode::FAILURE
        }
    }
}
