//! The command line's file-access and budget arguments (`--allow-path`,
//! `--max-file-size`, `--max-primitives`, `--max-nodes`), turned into the
//! [`Sandbox`] every command reads through.

use crate::error::Result;
use crate::sandbox::Sandbox;
use clap::Args;
use std::path::{Path, PathBuf};

/// What the input may read, and the budgets (see the README's Security
/// section).
#[derive(Debug, Clone, Default, Args)]
pub struct AccessArgs {
    /// Also let the scene and its models read files under DIR (repeatable).
    /// By default a scene reads only from its own folder and the working
    /// directory, and a model file only from its own folder.
    #[arg(long = "allow-path", value_name = "DIR")]
    pub allow_path: Vec<PathBuf>,
    /// Largest file read, in bytes (suffixes K, M, G: powers of 1024);
    /// default 1G.
    #[arg(long = "max-file-size", value_name = "BYTES", value_parser = parse_size)]
    pub max_file_size: Option<u64>,
    /// Most primitives (spheres, boxes, planes, triangles) the scene may
    /// expand to; default 10000000.
    #[arg(long = "max-primitives", value_name = "N")]
    pub max_primitives: Option<u64>,
    /// Most nodes a glTF node graph may expand to (a node counts once per
    /// path from a root); default 1000000.
    #[arg(long = "max-nodes", value_name = "N")]
    pub max_nodes: Option<u64>,
}

fn parse_size(s: &str) -> std::result::Result<u64, String> {
    let t = s.trim();
    let (num, shift) = match t.char_indices().last() {
        Some((i, 'k' | 'K')) => (&t[..i], 10),
        Some((i, 'm' | 'M')) => (&t[..i], 20),
        Some((i, 'g' | 'G')) => (&t[..i], 30),
        _ => (t, 0),
    };
    let n: u64 = num
        .parse()
        .map_err(|_| format!("`{s}` is not a size: give bytes, or a number with K, M or G"))?;
    n.checked_mul(1u64 << shift)
        .ok_or_else(|| format!("`{s}` is too large"))
}

impl AccessArgs {
    /// The sandbox for the input `file` (or the working directory alone).
    ///
    /// # Errors
    /// [`crate::Error::Arg`] for an `--allow-path` that is not a folder.
    pub fn sandbox(&self, file: Option<&Path>) -> Result<Sandbox> {
        let mut s = file.map_or_else(Sandbox::working_directory, Sandbox::for_input);
        for d in &self.allow_path {
            s.allow(d)?;
        }
        if let Some(n) = self.max_file_size {
            s.limits.max_file_bytes = n;
        }
        if let Some(n) = self.max_primitives {
            s.limits.max_primitives = n;
        }
        if let Some(n) = self.max_nodes {
            s.limits.max_nodes = n;
        }
        Ok(s)
    }
}
