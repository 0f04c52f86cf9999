//! Closed triangle meshes that are hard for a ray–triangle test, and the
//! rays that probe them for leaks.
//!
//! Every mesh here is closed (each edge is shared by exactly two
//! triangles) and has a point strictly inside, so every ray from that
//! point must hit it: a ray that reports no hit has *leaked* through a
//! crack the test opened between neighbouring triangles. The meshes
//! collect what breaks tests with epsilons or error-bound rejections:
//! fans of slivers at the poles of a sphere, slivers of a 10⁻⁵-radian
//! wedge, faces made of fans mixing areas 10⁻⁸ and 1, and the saddle
//! points of a torus. [`ClosedMesh::triangles`] places a mesh at any scale
//! and offset; [`ClosedMesh::probe_rays`] aims rays from the inside point
//! through every vertex, every edge midpoint and points near both ends of
//! every edge, exactly where a crack would be.
//!
//! The tracer's tests, and `cargo xtask accuracy`, count leaks with these.
//!
//! ```
//! use gridrt_tracer::hard_meshes::{self, DirLength};
//! use gridrt_grid::{Accelerator, Exhaustive, Real};
//! let mesh = hard_meshes::bicone(6, 1e-5);
//! let tris = mesh.triangles(1e-6, 0.0);
//! let accel = Exhaustive::new(tris);
//! let mut scratch = accel.scratch();
//! let rays = mesh.probe_rays(1e-6, 0.0, DirLength::Short);
//! assert!(!rays.is_empty());
//! let leaks = rays
//!     .iter()
//!     .filter(|r| accel.closest_hit(r, 0.0, Real::INFINITY, &mut scratch).is_none())
//!     .count();
//! assert_eq!(leaks, 0);
//! ```

mod random;

pub use random::random_star;
#[cfg(test)]
pub(crate) use random::SplitMix;

use crate::shapes::Triangle;
use gridrt_bbox::{Ray, Real, Vec3};
use std::f64::consts::{PI, TAU};

/// A closed triangle mesh in `f64` model coordinates with a point inside.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosedMesh {
    /// A short name for reports.
    pub name: String,
    /// Vertex positions (model space, about unit size).
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as indices into `vertices`; every edge is shared by two.
    pub faces: Vec<[u32; 3]>,
    /// A point strictly inside the surface.
    pub inside: [f64; 3],
}

/// How long the probe rays' direction vectors are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirLength {
    /// Unit length.
    Unit,
    /// About 10⁻⁶ (the unit direction times 2⁻²⁰): a test whose bounds mix
    /// world units with units of `t` fails here.
    Short,
    /// `target − origin`, as a shadow ray towards a point is built.
    ToTarget,
}

impl ClosedMesh {
    /// The mesh scaled by `scale` and moved by `offset` along every axis
    /// (`p·scale + offset`, computed in `f64` and rounded once to
    /// [`Real`], so shared vertices stay shared bit for bit).
    #[must_use]
    pub fn triangles(&self, scale: f64, offset: f64) -> Vec<Triangle> {
        let p: Vec<Vec3> = self
            .vertices
            .iter()
            .map(|&v| place(v, scale, offset))
            .collect();
        self.faces
            .iter()
            .map(|f| Triangle::new(p[f[0] as usize], p[f[1] as usize], p[f[2] as usize]))
            .collect()
    }

    /// The points a crack would let a ray through, in model space: every
    /// vertex, every edge's midpoint, and the points at 1/1024 and
    /// 1023/1024 along every edge.
    #[must_use]
    pub fn probe_targets(&self) -> Vec<[f64; 3]> {
        let mut targets = self.vertices.clone();
        let mut edges: Vec<(u32, u32)> = self
            .faces
            .iter()
            .flat_map(|f| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])])
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        for (a, b) in edges {
            let (pa, pb) = (self.vertices[a as usize], self.vertices[b as usize]);
            for s in [0.5, 1.0 / 1024.0, 1023.0 / 1024.0] {
                targets.push(std::array::from_fn(|k| pa[k] + (pb[k] - pa[k]) * s));
            }
        }
        targets
    }

    /// Rays from the inside point through every probe target, with the mesh
    /// placed as by [`Self::triangles`]. Both ends are rounded to [`Real`]
    /// first and the direction is their difference (then scaled to the
    /// asked length), so a ray passes as close to the target as the
    /// precision allows. Targets that round onto the origin give no ray.
    #[must_use]
    pub fn probe_rays(&self, scale: f64, offset: f64, len: DirLength) -> Vec<Ray> {
        let origin = place(self.inside, scale, offset);
        self.probe_targets()
            .into_iter()
            .filter_map(|t| {
                let d = place(t, scale, offset) - origin;
                let d = match len {
                    DirLength::ToTarget => d,
                    DirLength::Unit => d.try_normalize()?,
                    DirLength::Short => d.try_normalize()? * (1.0 / 1_048_576.0),
                };
                (d != Vec3::ZERO && d.is_finite()).then(|| Ray::new(origin, d))
            })
            .collect()
    }
}

/// `v·scale + offset` per axis, rounded once.
#[allow(clippy::cast_possible_truncation)] // the rounding to `f32` is the point
fn place(v: [f64; 3], scale: f64, offset: f64) -> Vec3 {
    Vec3::new(
        (v[0] * scale + offset) as Real,
        (v[1] * scale + offset) as Real,
        (v[2] * scale + offset) as Real,
    )
}

/// A UV sphere of radius 1 with `lon` segments and `lat` rings; each pole
/// is one vertex with a fan of `lon` thin triangles around it.
///
/// # Panics
/// If `lon < 3` or `lat < 2`.
#[must_use]
pub fn uv_sphere(lon: u32, lat: u32) -> ClosedMesh {
    assert!(
        lon >= 3 && lat >= 2,
        "a sphere needs 3 segments and 2 rings"
    );
    let mut vertices = vec![[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
    for i in 1..lat {
        let th = PI * f64::from(i) / f64::from(lat);
        for j in 0..lon {
            let ph = TAU * f64::from(j) / f64::from(lon);
            vertices.push([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]);
        }
    }
    let ring = |i: u32, j: u32| 2 + (i - 1) * lon + j % lon;
    let mut faces = Vec::new();
    for j in 0..lon {
        faces.push([0, ring(1, j), ring(1, j + 1)]);
        faces.push([1, ring(lat - 1, j + 1), ring(lat - 1, j)]);
        for i in 1..lat - 1 {
            let (a, b) = (ring(i, j), ring(i, j + 1));
            let (c, d) = (ring(i + 1, j), ring(i + 1, j + 1));
            faces.push([a, c, d]);
            faces.push([a, d, b]);
        }
    }
    ClosedMesh {
        name: format!("uv-sphere-{lon}x{lat}"),
        vertices,
        faces,
        inside: [0.1, -0.05, 0.02],
    }
}

/// A double cone (apexes at z = ±1, a ring of radius 1 at z = 0) whose
/// ring has `k` groups of three vertices a `wedge` radians apart: every
/// group adds two sliver triangles per cone, long and `wedge` wide.
///
/// # Panics
/// If `k < 2`.
#[must_use]
pub fn bicone(k: u32, wedge: f64) -> ClosedMesh {
    assert!(k >= 2, "a bicone needs two groups");
    let mut vertices = vec![[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
    for g in 0..k {
        let a0 = TAU * f64::from(g) / f64::from(k);
        for s in 0..3 {
            let a = a0 + wedge * f64::from(s);
            vertices.push([a.cos(), a.sin(), 0.0]);
        }
    }
    let n = 3 * k;
    let mut faces = Vec::new();
    for j in 0..n {
        let (a, b) = (2 + j, 2 + (j + 1) % n);
        faces.push([0, a, b]);
        faces.push([1, b, a]);
    }
    ClosedMesh {
        name: format!("bicone-{k}x3-wedge-{wedge:e}"),
        vertices,
        faces,
        inside: [0.01, 0.02, -0.03],
    }
}

/// The cube [−1, 1]³ whose every face is a fan around its centre. Each
/// face edge carries, besides the corners, a cluster of vertices around
/// its midpoint `gap` apart, so each face mixes fan triangles of area
/// about `gap/2` (10⁻⁸ with `gap` = 2·10⁻⁸) with triangles of area about 1.
#[must_use]
pub fn fan_cube(gap: f64) -> ClosedMesh {
    // Positions along an edge, from −1 up to (not including) 1; symmetric,
    // so that the two faces of an edge, which walk it in opposite
    // directions, put their vertices at the same points.
    let along = [-1.0, -0.5, -gap, 0.0, gap, 0.5];
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut vid = |p: [f64; 3], vertices: &mut Vec<[f64; 3]>| -> u32 {
        // `+ 0.0` turns −0.0 into 0.0, so that both are one vertex.
        let key = p.map(|x| (x + 0.0).to_bits());
        *index.entry(key).or_insert_with(|| {
            vertices.push(p);
            (vertices.len() - 1) as u32
        })
    };
    let mut faces = Vec::new();
    for axis in 0..3 {
        for side in [-1.0, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let point = |a: f64, b: f64| {
                let mut p = [0.0; 3];
                p[axis] = side;
                p[u] = a;
                p[v] = b;
                p
            };
            // The face's boundary, counter-clockwise in (u, v).
            let mut rim = Vec::new();
            for &s in &along {
                rim.push(point(s, -1.0));
            }
            for &s in &along {
                rim.push(point(1.0, s));
            }
            for &s in &along {
                rim.push(point(-s, 1.0));
            }
            for &s in &along {
                rim.push(point(-1.0, -s));
            }
            let c = vid(point(0.0, 0.0), &mut vertices);
            let ids: Vec<u32> = rim.iter().map(|&p| vid(p, &mut vertices)).collect();
            for j in 0..ids.len() {
                let (a, b) = (ids[j], ids[(j + 1) % ids.len()]);
                // Outward winding: (u, v, axis) is right-handed.
                faces.push(if side > 0.0 { [c, a, b] } else { [c, b, a] });
            }
        }
    }
    ClosedMesh {
        name: format!("fan-cube-gap-{gap:e}"),
        vertices,
        faces,
        inside: [0.05, -0.1, 0.15],
    }
}

/// A torus around the z axis: tube centre radius 1, tube radius `r`
/// (0 < r < 1), `n` segments around the axis and `m` around the tube.
///
/// # Panics
/// If `n < 3` or `m < 3`.
#[must_use]
pub fn torus(n: u32, m: u32, r: f64) -> ClosedMesh {
    assert!(n >= 3 && m >= 3, "a torus needs 3 segments each way");
    let mut vertices = Vec::new();
    for i in 0..n {
        let a = TAU * f64::from(i) / f64::from(n);
        for j in 0..m {
            let b = TAU * f64::from(j) / f64::from(m);
            let w = 1.0 + r * b.cos();
            vertices.push([w * a.cos(), w * a.sin(), r * b.sin()]);
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + j % m;
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    ClosedMesh {
        name: format!("torus-{n}x{m}"),
        vertices,
        faces,
        inside: [1.0 + 0.1 * r, 0.05 * r, -0.1 * r],
    }
}

/// `mesh` with a T-junction closed by a zero-area triangle on every edge:
/// for each edge `a`–`b`, the triangle `(a, b, c)` that runs it from `a`
/// to `b` becomes `(a, m, c)` and `(m, b, c)`, with `m` the midpoint, and
/// the triangle `(m, a, b)`, whose vertices are collinear, joins the other
/// side's edge `b`–`a` to `a`–`m`–`b`. The mesh stays closed and
/// consistently wound. Placed where the midpoints are exact (vertices on a
/// dyadic lattice, as in [`lattice_ball`]), those triangles have zero area
/// in `Real` too, and only they cover the cracks the shear's rounding
/// opens between `a`–`m`–`b` and `b`–`a`.
#[must_use]
pub fn with_t_junctions(mesh: &ClosedMesh) -> ClosedMesh {
    let mut vertices = mesh.vertices.clone();
    let mut faces = mesh.faces.clone();
    let mut edges: Vec<(u32, u32)> = mesh
        .faces
        .iter()
        .flat_map(|f| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])])
        .filter(|(a, b)| a < b)
        .collect();
    edges.sort_unstable();
    for (a, b) in edges {
        // The face running a → b: it is still there, since splitting
        // other edges keeps every edge but the split one.
        let Some((k, c)) = faces.iter().enumerate().find_map(|(k, f)| {
            (0..3).find_map(|i| (f[i] == a && f[(i + 1) % 3] == b).then(|| (k, f[(i + 2) % 3])))
        }) else {
            continue;
        };
        let (pa, pb) = (vertices[a as usize], vertices[b as usize]);
        let m = vertices.len() as u32;
        vertices.push(std::array::from_fn(|i| (pa[i] + pb[i]) / 2.0));
        faces[k] = [a, m, c];
        faces.push([m, b, c]);
        faces.push([m, a, b]);
    }
    ClosedMesh {
        name: format!("{}-t-junctions", mesh.name),
        vertices,
        faces,
        inside: mesh.inside,
    }
}

/// The unit octahedron: its six vertices on the axes and its eight faces,
/// counter-clockwise seen from outside.
fn octahedron() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let vertices = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let faces = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    (vertices, faces)
}

/// An octahedron subdivided `levels` times (each triangle into four), its
/// vertices pushed out to radius 4 and rounded to multiples of 1/8: a
/// closed ball whose coordinates, and their midpoints, are exact in `f32`
/// up to an offset of 2¹⁷.
#[must_use]
pub fn lattice_ball(levels: u32) -> ClosedMesh {
    let (mut vertices, mut faces) = octahedron();
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut split = |a: u32, b: u32, vertices: &mut Vec<[f64; 3]>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (pa, pb) = (vertices[a as usize], vertices[b as usize]);
                vertices.push(std::array::from_fn(|i| (pa[i] + pb[i]) / 2.0));
                (vertices.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let (ab, bc, ca) = (
                split(a, b, &mut vertices),
                split(b, c, &mut vertices),
                split(c, a, &mut vertices),
            );
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        faces = next;
    }
    for v in &mut vertices {
        let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        *v = v.map(|x| (x / r * 4.0 * 8.0).round() / 8.0);
    }
    ClosedMesh {
        name: format!("lattice-ball-{levels}"),
        vertices,
        faces,
        inside: [0.3, -0.2, 0.1],
    }
}

/// The four hard meshes of the leak tests and `cargo xtask accuracy`, at
/// sizes that keep a probe run short: a UV sphere with pole fans, a
/// bicone of 10⁻⁵-radian slivers, a fan cube mixing areas 10⁻⁸ and 1, and
/// a torus.
#[must_use]
pub fn standard_set() -> Vec<ClosedMesh> {
    vec![
        uv_sphere(24, 12),
        bicone(8, 1e-5),
        fan_cube(2e-8),
        torus(16, 8, 0.3),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Every edge is used twice, once in each direction (closed, oriented).
    fn assert_closed(m: &ClosedMesh) {
        let mut uses: HashMap<(u32, u32), i32> = HashMap::new();
        for f in &m.faces {
            for (a, b) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
                assert_ne!(a, b, "{}: repeated vertex in {f:?}", m.name);
                *uses.entry((a.min(b), a.max(b))).or_default() += if a < b { 1 } else { -1 };
            }
        }
        let mut count: HashMap<(u32, u32), u32> = HashMap::new();
        for f in &m.faces {
            for (a, b) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
                *count.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        assert!(count.values().all(|&c| c == 2), "{}: open edge", m.name);
        assert!(uses.values().all(|&u| u == 0), "{}: flipped face", m.name);
    }

    /// The signed volume (divergence theorem) is positive: outward faces.
    fn volume(m: &ClosedMesh) -> f64 {
        m.faces
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|i| m.vertices[i as usize]);
                let cross = [
                    b[1] * c[2] - b[2] * c[1],
                    b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0],
                ];
                (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
            })
            .sum()
    }

    #[test]
    fn meshes_are_closed_and_outward() {
        for m in standard_set() {
            assert_closed(&m);
            assert!(volume(&m) > 0.0, "{}: volume {}", m.name, volume(&m));
        }
        assert!((volume(&fan_cube(2e-8)) - 8.0).abs() < 1e-9);
    }

    #[test]
    fn t_junctions_keep_the_mesh_closed_with_zero_area_triangles() {
        let ball = lattice_ball(2);
        assert_closed(&ball);
        assert!(volume(&ball) > 0.0);
        let t = with_t_junctions(&ball);
        assert_closed(&t);
        assert!((volume(&t) - volume(&ball)).abs() < 1e-9);
        let edges = 3 * ball.faces.len() / 2;
        assert_eq!(t.faces.len(), ball.faces.len() + 2 * edges);
        // One zero-area triangle per edge, exactly, in `Real` too.
        let flat = t
            .triangles(1.0, 131_072.0)
            .iter()
            .filter(|t| t.is_degenerate())
            .count();
        assert_eq!(flat, edges);
    }

    #[test]
    fn random_stars_are_closed_and_outward() {
        for seed in 0..40 {
            let m = random_star(seed, seed as u32 * 5, 0.3);
            assert_eq!(m.faces.len(), 8 + 2 * seed as usize * 5);
            assert_closed(&m);
            assert!(volume(&m) > 0.0, "{}: volume {}", m.name, volume(&m));
        }
        assert_eq!(random_star(7, 50, 0.5), random_star(7, 50, 0.5));
        assert_ne!(random_star(7, 50, 0.5), random_star(8, 50, 0.5));
    }

    #[test]
    fn probes_cover_vertices_and_edges() {
        let m = bicone(3, 1e-5);
        let edges = 3 * m.faces.len() / 2;
        assert_eq!(m.probe_targets().len(), m.vertices.len() + 3 * edges);
        let rays = m.probe_rays(1.0, 0.0, DirLength::Short);
        assert_eq!(rays.len(), m.probe_targets().len());
        let len = rays[0].dir.length();
        assert!((len - 1.0 / 1_048_576.0).abs() < 1e-9);
    }
}
