//! Batch closest-hit queries against a mesh: `gridrt rays MESH RAYS.csv`.
//!
//! Input: one ray per line, `ox,oy,oz,dx,dy,dz` or
//! `ox,oy,oz,dx,dy,dz,tmin,tmax` (defaults `tmin = 0`, `tmax = inf`;
//! `inf` is accepted). Blank lines and lines starting with `#` are skipped;
//! fields may have spaces around them. Output: one line per ray, in input
//! order: `t,triangle,u,v` for a hit (the triangle's index in the mesh
//! file's triangle order after triangulation; `u`, `v` the barycentric
//! weights of its second and third vertex) or `miss`.

use crate::error::{Error, Result};
use gridrt_bbox::{Real, Vec3};
use gridrt_grid::{Accelerator, Hit, Ray};
use std::fmt::Write as _;
use std::path::Path;

/// One ray query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayQuery {
    /// The ray.
    pub ray: Ray,
    /// Smallest accepted `t`.
    pub t_min: Real,
    /// Largest accepted `t`.
    pub t_max: Real,
}

/// Parses a rays CSV text (see the module docs for the format). `path`
/// names the file in messages.
///
/// ```
/// let rays = gridrt_io::parse_rays("# origin, direction\n0,0,1, 0,0,-1\n\n0,0,1,0,0,-1,0.5,inf\n",
///     std::path::Path::new("r.csv")).unwrap();
/// assert_eq!(rays.len(), 2);
/// assert_eq!(rays[1].t_min, 0.5);
/// let err = gridrt_io::parse_rays("1,2,3\n", std::path::Path::new("r.csv")).unwrap_err();
/// assert!(err.to_string().starts_with("r.csv:1: "));
/// ```
///
/// # Errors
/// [`Error::Rays`] naming the line of the first bad ray: wrong field
/// count, a field that is not a number, NaN, an infinite origin or
/// direction, a zero direction, `tmin > tmax`.
pub fn parse_rays(text: &str, path: &Path) -> Result<Vec<RayQuery>> {
    let mut out = Vec::new();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let q = parse_line(line).map_err(|msg| Error::Rays {
            path: path.to_path_buf(),
            line: i + 1,
            msg,
        })?;
        out.push(q);
    }
    Ok(out)
}

fn parse_line(line: &str) -> std::result::Result<RayQuery, String> {
    let fields: Vec<&str> = line.split(',').map(str::trim).collect();
    if fields.len() != 6 && fields.len() != 8 {
        return Err(format!(
            "expected 6 or 8 comma-separated numbers `ox,oy,oz,dx,dy,dz[,tmin,tmax]`, found {} field{}",
            fields.len(),
            if fields.len() == 1 { "" } else { "s" }
        ));
    }
    let mut v = [0.0 as Real; 8];
    for (k, f) in fields.iter().enumerate() {
        let x: Real = f
            .parse()
            .map_err(|_| format!("field {} `{f}` is not a number", k + 1))?;
        if x.is_nan() {
            return Err(format!("field {} is NaN", k + 1));
        }
        v[k] = x;
    }
    let origin = Vec3::new(v[0], v[1], v[2]);
    let dir = Vec3::new(v[3], v[4], v[5]);
    if !origin.is_finite() || !dir.is_finite() {
        return Err("the origin and direction must be finite".to_string());
    }
    if dir == Vec3::ZERO {
        return Err("the direction is (0, 0, 0): give a non-zero direction".to_string());
    }
    let (t_min, t_max) = if fields.len() == 8 {
        (v[6], v[7])
    } else {
        (0.0, Real::INFINITY)
    };
    if t_min > t_max {
        return Err(format!("tmin {t_min} is greater than tmax {t_max}"));
    }
    Ok(RayQuery {
        ray: Ray::new(origin, dir),
        t_min,
        t_max,
    })
}

/// Answers every query with the accelerator, in order.
pub fn trace_rays<A: Accelerator>(accel: &A, rays: &[RayQuery]) -> Vec<Option<Hit>> {
    let mut out = vec![None; rays.len()];
    answer(accel, rays, &mut out);
    out
}

/// Answers `rays` into `out`, one answer each, on this thread.
fn answer<A: Accelerator>(accel: &A, rays: &[RayQuery], out: &mut [Option<Hit>]) {
    let mut scratch = accel.scratch();
    for (q, o) in rays.iter().zip(out) {
        *o = accel.closest_hit(&q.ray, q.t_min, q.t_max, &mut scratch);
    }
}

/// Answers every query, in order: on the current rayon pool when
/// `parallel` (in chunks of [`CHUNK`] rays, so the answers and their order
/// do not depend on the thread count), else on this thread.
pub fn trace_rays_on<A: Accelerator + Sync>(
    accel: &A,
    rays: &[RayQuery],
    parallel: bool,
) -> Vec<Option<Hit>> {
    let mut out = vec![None; rays.len()];
    trace_rays_into(accel, rays, &mut out, parallel);
    out
}

/// [`trace_rays_on`] into `out` (as long as `rays`): the query loop alone,
/// with no allocation, so that timing it times the queries and not the
/// memory the answers go to.
///
/// # Panics
/// If `out` and `rays` differ in length.
pub fn trace_rays_into<A: Accelerator + Sync>(
    accel: &A,
    rays: &[RayQuery],
    out: &mut [Option<Hit>],
    parallel: bool,
) {
    assert_eq!(rays.len(), out.len(), "one answer per query");
    #[cfg(feature = "rayon")]
    if parallel && rays.len() > CHUNK {
        use rayon::prelude::*;
        out.par_chunks_mut(CHUNK)
            .zip(rays.par_chunks(CHUNK))
            .for_each(|(o, c)| answer(accel, c, o));
        return;
    }
    let _ = parallel;
    answer(accel, rays, out);
}

/// Rays per parallel task of [`trace_rays_on`].
pub const CHUNK: usize = 1024;

/// Formats answers as the output CSV: `t,triangle,u,v` or `miss` per line.
/// Numbers use the shortest text that reads back to the same value.
#[must_use]
pub fn format_hits(hits: &[Option<Hit>]) -> String {
    let mut s = String::with_capacity(hits.len() * 32);
    for h in hits {
        match h {
            // Writing to a String cannot fail.
            Some(h) => {
                let _ = writeln!(s, "{},{},{},{}", h.t, h.prim, h.u, h.v);
            }
            None => s.push_str("miss\n"),
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse_rays(text, Path::new("r.csv"))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn parses_both_forms_and_skips_comments() {
        let r = parse_rays(
            " 1, 2, 3, 0, 0, -1 \r\n# c\n\n0,0,0,1,0,0,0.5,10\n",
            Path::new("r.csv"),
        )
        .unwrap();
        assert_eq!(r.len(), 2);
        assert_eq!(r[0].ray.origin, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!((r[0].t_min, r[0].t_max), (0.0, Real::INFINITY));
        assert_eq!((r[1].t_min, r[1].t_max), (0.5, 10.0));
    }

    #[test]
    fn bad_lines_name_the_line() {
        assert!(err("0,0,0,1,0,0\n1,2\n").starts_with("r.csv:2: expected 6 or 8"));
        assert!(err("0,0,0,1,0,x\n").contains("field 6 `x` is not a number"));
        assert!(err("0,0,0,0,0,0\n").contains("non-zero direction"));
        assert!(err("0,0,0,1,0,0,5,1\n").contains("greater than"));
        assert!(err("nan,0,0,1,0,0\n").contains("NaN"));
        assert!(err("inf,0,0,1,0,0\n").contains("finite"));
    }

    #[test]
    fn parallel_answers_equal_sequential_ones() {
        use gridrt_grid::Exhaustive;
        use gridrt_tracer::Triangle;
        let tris: Vec<Triangle> = (0..40)
            .map(|i| {
                let z = -(i as Real);
                Triangle::new(
                    Vec3::new(-1.0, -1.0, z),
                    Vec3::new(1.0, -1.0, z),
                    Vec3::new(0.0, 1.0, z - 0.5),
                )
            })
            .collect();
        let e = Exhaustive::new(tris);
        let rays: Vec<RayQuery> = (0..3000)
            .map(|k| {
                let x = (k % 50) as Real / 25.0 - 1.0;
                let y = (k / 50) as Real / 30.0 - 1.0;
                RayQuery {
                    ray: Ray::new(Vec3::new(x, y, 1.0), Vec3::new(0.01, 0.0, -1.0)),
                    t_min: 0.0,
                    t_max: Real::INFINITY,
                }
            })
            .collect();
        let one = trace_rays_on(&e, &rays, false);
        #[cfg(feature = "rayon")]
        {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(3)
                .build()
                .unwrap();
            let many = pool.install(|| trace_rays_on(&e, &rays, true));
            assert_eq!(one, many);
        }
        assert_eq!(one.len(), rays.len());
        assert!(one.iter().any(Option::is_some) && one.iter().any(Option::is_none));
    }

    #[test]
    fn output_format() {
        let h = Hit {
            t: 1.5,
            u: 0.25,
            v: 0.5,
            part: 0,
            prim: 7,
            slot: 3,
        };
        assert_eq!(format_hits(&[Some(h), None]), "1.5,7,0.25,0.5\nmiss\n");
    }
}
