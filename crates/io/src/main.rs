//! The `gridrt` command-line renderer. Thin: clap parses the arguments,
//! `gridrt_io::cli::run` does the work, and any error becomes one line
//! `error: …` on standard error with exit code 1 (usage errors: 2, from clap).

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    match try_main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn try_main() -> gridrt_io::Result<()> {
    let cli = gridrt_io::cli::Cli::parse();
    gridrt_io::cli::run(cli, &mut std::io::stdout().lock())
}
