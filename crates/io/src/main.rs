//! The `gridrt` command-line renderer. Thin: clap parses the arguments,
//! `gridrt_io::cli::run_with_cancel` does the work, and any error becomes
//! one line `error: …` on standard error with exit code 1 (usage errors: 2,
//! from clap).
//!
//! Ctrl-C during a render: the first one raises the cancel flag, the
//! renderer stops after the tiles in progress, nothing is written (a file
//! already at the output path is kept), `interrupted; nothing written` goes
//! to standard error and the exit code is 130. A second Ctrl-C (when the
//! first is not honoured fast enough, e.g. while a huge mesh loads) exits at
//! once with 130. `info` and `rays` keep the default Ctrl-C behaviour.

use clap::Parser;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit code of a command stopped by Ctrl-C (128 + SIGINT), as shells use.
const EXIT_INTERRUPTED: u8 = 130;

/// Large arrays on huge pages (see [`gridrt_io::huge_page_alloc`]).
#[global_allocator]
static ALLOC: gridrt_io::HugePageAlloc = gridrt_io::HugePageAlloc;

/// Raised by the Ctrl-C handler; polled by the renderer between tiles.
static CANCEL: AtomicBool = AtomicBool::new(false);

/// Bytes from which an allocation gets pages of its own (glibc's initial
/// threshold, kept fixed).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const LARGE_ALLOCATION: libc::c_int = 128 * 1024;

fn main() -> ExitCode {
    #[cfg(unix)]
    // SAFETY: setting SIGXFSZ to SIG_IGN installs no handler code; with it
    // ignored, a write past the file-size limit fails with EFBIG (reported,
    // temporary file removed) instead of killing the process mid-write.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only changes a tuning parameter of glibc's malloc,
    // before any other thread exists.
    //
    // Large arrays (a mesh's vertices, a grid's cells) are then always
    // mapped on their own and returned to the system when freed. By
    // default glibc raises this threshold after the first such free, so
    // the arrays freed while a scene loads stay in the main thread's heap
    // while the renderer's threads allocate theirs in arenas of their
    // own: 108 MiB instead of 91 MiB at the peak for the dragon on two
    // threads.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, LARGE_ALLOCATION);
    }
    match try_main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e @ (gridrt_io::Error::Cancelled | gridrt_io::Error::Interrupted { .. })) => {
            eprintln!("{e}");
            ExitCode::from(EXIT_INTERRUPTED)
        }
        Err(e) => {
            eprintln!("error: {}", gridrt_io::escape_control(&e.to_string()));
            ExitCode::FAILURE
        }
    }
}

fn try_main() -> gridrt_io::Result<()> {
    let cli = gridrt_io::cli::Cli::parse();
    if cli.renders() {
        // ctrlc runs this on its own thread, not in the signal handler, so
        // printing and exiting here are safe.
        let handler = || {
            // A second Ctrl-C exits at once, except while the outputs are
            // written (a moment): then the write finishes, is discarded,
            // and no temporary file is left.
            if CANCEL.swap(true, Ordering::SeqCst)
                && !gridrt_io::cli::WRITING.load(Ordering::SeqCst)
            {
                eprintln!("{}", gridrt_io::Error::Cancelled);
                std::process::exit(i32::from(EXIT_INTERRUPTED));
            }
        };
        if let Err(e) = ctrlc::set_handler(handler) {
            eprintln!("warning: cannot handle Ctrl-C ({e}); it will stop gridrt at once");
        }
    }
    gridrt_io::cli::run_with_cancel(cli, &mut std::io::stdout().lock(), &CANCEL)
}
