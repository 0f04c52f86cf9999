//! The Embree peer of `cargo xtask scenes`: `../shared/peers/embree/
//! embree_rays.c`, compiled once into `target/scenes/` with the system's
//! Embree 3 (`apt-get install libembree-dev`), fed a triangle OBJ and a
//! rays CSV written here, its one-line summary parsed. The copy compiled
//! reads the thread's CPU clock where the original reads the monotonic
//! wall clock (its one change), so that both sides are timed alike on a
//! shared machine: Embree's device has `threads=1`, so its build and its
//! trace run on the calling thread.

use crate::corpus::Query;
use gridrt_grid::Vec3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// What one `embree_rays` run printed.
#[derive(Clone, Copy, Debug, Default)]
pub struct PeerRun {
    /// `rtcCommitScene`, best of the runs, seconds.
    pub build_s: f64,
    /// The `rtcIntersect1` loop, best of the runs, seconds.
    pub trace_s: f64,
    /// Rays that hit.
    pub hits: u64,
}

/// The compiled peer.
#[derive(Debug)]
pub struct Peer {
    exe: PathBuf,
    /// `# embree 3.13.5, ...` as the program prints it.
    pub version: String,
}

impl Peer {
    /// Compiles `embree_rays.c` from `shared/peers/embree` into `dir`.
    ///
    /// # Errors
    /// Why the peer is not available (no source, no compiler, no Embree),
    /// as a sentence for the report.
    pub fn build(shared: &Path, dir: &Path) -> Result<Peer, String> {
        let src = shared.join("peers/embree/embree_rays.c");
        if !src.is_file() {
            return Err(format!("{} is absent", src.display()));
        }
        std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
        let text = std::fs::read_to_string(&src).map_err(|e| e.to_string())?;
        if !text.contains("CLOCK_MONOTONIC") {
            return Err(format!("{} no longer reads CLOCK_MONOTONIC", src.display()));
        }
        let copy = dir.join("embree_rays_cpu.c");
        std::fs::write(
            &copy,
            text.replace("CLOCK_MONOTONIC", "CLOCK_THREAD_CPUTIME_ID"),
        )
        .map_err(|e| e.to_string())?;
        let src = copy;
        let exe = dir.join("embree_rays");
        let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_string());
        let out = Command::new(&cc)
            .args(["-O2", "-o"])
            .arg(&exe)
            .arg(&src)
            .args(["-lembree3", "-lm"])
            .output()
            .map_err(|e| format!("cannot run the C compiler `{cc}`: {e}"))?;
        if !out.status.success() {
            let msg = String::from_utf8_lossy(&out.stderr);
            let first = msg.lines().find(|l| l.contains("error")).unwrap_or("");
            return Err(format!(
                "embree_rays.c does not compile (is libembree-dev installed?): {first}"
            ));
        }
        Ok(Peer {
            exe,
            version: String::new(),
        })
    }

    /// Runs the peer on `obj` and `rays` (`runs` repetitions, one thread).
    ///
    /// # Errors
    /// When it fails or prints something unexpected.
    pub fn run(&mut self, obj: &Path, rays: &Path, runs: u32) -> Result<PeerRun, String> {
        let out = Command::new(&self.exe)
            .args(["-r", &runs.to_string()])
            .arg(obj)
            .arg(rays)
            .output()
            .map_err(|e| format!("cannot run {}: {e}", self.exe.display()))?;
        let err = String::from_utf8_lossy(&out.stderr);
        if !out.status.success() {
            return Err(format!("embree_rays failed: {}", err.trim()));
        }
        if let Some(v) = err.lines().find(|l| l.starts_with("# embree")) {
            self.version = v.trim_start_matches("# ").to_string();
        }
        let line = err
            .lines()
            .find(|l| l.starts_with("triangles "))
            .ok_or_else(|| format!("embree_rays printed no summary: {}", err.trim()))?;
        parse_summary(line).ok_or_else(|| format!("cannot read embree_rays' summary `{line}`"))
    }
}

/// Reads `triangles N rays N parse_s X build_s X trace_s X Mrays X hits N tsum X`.
fn parse_summary(line: &str) -> Option<PeerRun> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let get = |k: &str| {
        words
            .iter()
            .position(|w| *w == k)
            .and_then(|i| words.get(i + 1))
            .copied()
    };
    Some(PeerRun {
        build_s: get("build_s")?.parse().ok()?,
        trace_s: get("trace_s")?.parse().ok()?,
        hits: get("hits")?.parse().ok()?,
    })
}

/// Writes triangles as an OBJ of `v` and `f` lines (one vertex triple per
/// triangle, in order, so triangle indices are the scene's).
///
/// # Errors
/// When the file cannot be written.
pub fn write_obj(path: &Path, tris: &[[Vec3; 3]]) -> std::io::Result<()> {
    let mut s = String::with_capacity(tris.len() * 120);
    for t in tris {
        for p in t {
            // Shortest text that reads back to the same f32 (or f64).
            let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
        }
    }
    for k in 0..tris.len() {
        let _ = writeln!(s, "f {} {} {}", 3 * k + 1, 3 * k + 2, 3 * k + 3);
    }
    crate::util::write_atomic(path, s.as_bytes())
}

/// Writes rays as the peers' CSV (`ox,oy,oz,dx,dy,dz,tmin,inf`).
///
/// # Errors
/// When the file cannot be written.
pub fn write_rays(path: &Path, rays: &[Query]) -> std::io::Result<()> {
    let mut s = String::with_capacity(rays.len() * 100);
    for q in rays {
        let (o, d) = (q.ray.origin, q.ray.dir);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},inf",
            o.x, o.y, o.z, d.x, d.y, d.z, q.t_min
        );
    }
    crate::util::write_atomic(path, s.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_line_is_read() {
        let r = parse_summary(
            "triangles 75807 rays 76800 parse_s 0.1 build_s 0.0310 trace_s 0.0092 Mrays 8.300 hits 70000 tsum 1e6",
        )
        .unwrap();
        assert_eq!(r.hits, 70000);
        assert!((r.build_s - 0.031).abs() < 1e-12 && (r.trace_s - 0.0092).abs() < 1e-12);
        assert!(parse_summary("triangles 1 rays 2").is_none());
    }
}
