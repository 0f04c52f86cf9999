//! Shared by the loader targets: a scratch folder per process and a
//! sandbox confined to it with small budgets, so an input cannot make one
//! run slow for reasons the budgets already cover.

use gridrt_io::Sandbox;
use std::path::PathBuf;
use std::sync::OnceLock;

/// The process's scratch folder (kept for the whole run).
pub fn scratch() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = tempfile::Builder::new()
            .prefix("gridrt-fuzz-")
            .tempdir()
            .expect("a scratch folder")
            .keep();
        std::fs::canonicalize(d).expect("the scratch folder resolves")
    })
}

/// A sandbox confined to the scratch folder, with small budgets.
pub fn sandbox() -> Sandbox {
    let mut s = Sandbox::confined(&[scratch().as_path()]).expect("the scratch folder exists");
    s.limits.max_file_bytes = 1 << 20;
    s.limits.max_primitives = 20_000;
    s.limits.max_nodes = 5_000;
    s
}

/// Splits a fuzz input into up to `n` parts at the separator line
/// `\n--8<--\n`.
pub fn parts(data: &[u8], n: usize) -> Vec<&[u8]> {
    const SEP: &[u8] = b"\n--8<--\n";
    let mut out = Vec::new();
    let mut rest = data;
    while out.len() + 1 < n {
        match rest.windows(SEP.len()).position(|w| w == SEP) {
            Some(at) => {
                out.push(&rest[..at]);
                rest = &rest[at + SEP.len()..];
            }
            None => break,
        }
    }
    out.push(rest);
    out
}
