//! Randomly generated closed meshes: star-shaped surfaces over a random
//! spherical triangulation, with slivers and fans made by splitting edges
//! and faces at extreme points.
//!
//! The construction keeps every mesh closed and every ray from the centre
//! crossing it exactly once, whatever the random choices: the mesh starts
//! as an octahedron's triangulation of the unit sphere; splitting an edge
//! at a point of its great arc (both faces beside it split too), or a face
//! at a point inside it, refines that triangulation without changing the
//! directions it covers; finally each vertex is pushed to its own random
//! distance from the centre. A triangle then spans exactly the cone of
//! directions of its spherical triangle, the cones tile the sphere, so the
//! centre is inside and a ray from it can only leave through a crack.

use super::ClosedMesh;

/// SplitMix64: a small, fixed, seedable generator, so that a seed names a
/// mesh on every platform.
pub(crate) struct SplitMix(pub(crate) u64);

impl SplitMix {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    #[allow(clippy::cast_precision_loss)] // 53 bits fit an f64 exactly
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A split parameter in (0, 1): half the time uniform, half the time
    /// within 10⁻⁷…10⁻² of either end (slivers).
    fn split(&mut self) -> f64 {
        if self.next() & 1 == 0 {
            0.05 + 0.9 * self.unit()
        } else {
            let near = 10f64.powf(-7.0 + 5.0 * self.unit());
            if self.next() & 1 == 0 {
                near
            } else {
                1.0 - near
            }
        }
    }

    #[allow(clippy::cast_possible_truncation)] // n is small
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

fn normalize(p: [f64; 3]) -> [f64; 3] {
    let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    p.map(|x| x / l)
}

/// The point a fraction `s` along the great arc from `a` to `b` (unit
/// vectors less than π apart). The angle comes from the chord, which stays
/// accurate for arcs down to the smallest a split makes.
fn slerp(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    let chord = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    let w = 2.0 * (0.5 * chord).min(1.0).asin();
    let (wa, wb) = if w > 1e-150 {
        (((1.0 - s) * w).sin(), (s * w).sin())
    } else {
        (1.0 - s, s)
    };
    normalize(std::array::from_fn(|k| a[k] * wa + b[k] * wb))
}

/// A random closed, star-shaped mesh around the origin with `splits`
/// random edge and face splits (each adds two faces) on an octahedron,
/// vertex distances in [`r_min`, 1], and a random rotation, so no face
/// lies in a coordinate plane by construction. The point inside is the
/// origin. The same seed gives the same mesh.
///
/// # Panics
/// If `r_min` is not in (0, 1].
#[must_use]
pub fn random_star(seed: u64, splits: u32, r_min: f64) -> ClosedMesh {
    assert!(r_min > 0.0 && r_min <= 1.0, "r_min must be in (0, 1]");
    let mut rng = SplitMix(seed);
    let (mut dirs, mut faces) = super::octahedron();
    for _ in 0..splits {
        let f = rng.below(faces.len());
        if rng.next().is_multiple_of(3) {
            // A point inside the face: a fan of three around it.
            let [a, b, c] = faces[f];
            let (s, t) = (rng.split(), rng.split());
            let (wa, wb) = (s * (1.0 - t), s * t);
            let wc = 1.0 - s;
            let [pa, pb, pc] = [a, b, c].map(|i| dirs[i as usize]);
            dirs.push(normalize(std::array::from_fn(|k| {
                pa[k] * wa + pb[k] * wb + pc[k] * wc
            })));
            let p = (dirs.len() - 1) as u32;
            faces[f] = [a, b, p];
            faces.push([b, c, p]);
            faces.push([c, a, p]);
        } else {
            // A point on one of the face's edges, splitting both faces
            // beside it.
            let e = rng.below(3);
            let (a, b) = (faces[f][e], faces[f][(e + 1) % 3]);
            let g = faces
                .iter()
                .position(|h| (0..3).any(|k| h[k] == b && h[(k + 1) % 3] == a))
                .expect("a closed mesh has the edge's twin");
            dirs.push(slerp(dirs[a as usize], dirs[b as usize], rng.split()));
            let p = (dirs.len() - 1) as u32;
            for (face, (x, y)) in [(f, (a, b)), (g, (b, a))] {
                let h = faces[face];
                let k = (0..3)
                    .find(|&k| h[k] == x && h[(k + 1) % 3] == y)
                    .expect("the face has the edge");
                let opposite = h[(k + 2) % 3];
                faces[face] = [x, p, opposite];
                faces.push([p, y, opposite]);
            }
        }
    }
    // A random rotation (a unit quaternion from three uniforms).
    let (u1, u2, u3) = (rng.unit(), rng.unit(), rng.unit());
    let tau = std::f64::consts::TAU;
    let q = [
        (1.0 - u1).sqrt() * (tau * u2).sin(),
        (1.0 - u1).sqrt() * (tau * u2).cos(),
        u1.sqrt() * (tau * u3).sin(),
        u1.sqrt() * (tau * u3).cos(),
    ];
    let vertices = dirs
        .iter()
        .map(|&d| {
            let r = r_min + (1.0 - r_min) * rng.unit();
            rotate(q, d).map(|x| x * r)
        })
        .collect();
    ClosedMesh {
        name: format!("random-star-{seed}-{splits}"),
        vertices,
        faces,
        inside: [0.0; 3],
    }
}

/// `v` rotated by the unit quaternion `q = (x, y, z, w)`.
fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let [x, y, z, w] = q;
    let u = [x, y, z];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let t = cross(u, v).map(|c| 2.0 * c);
    let ut = cross(u, t);
    std::array::from_fn(|k| v[k] + w * t[k] + ut[k])
}
