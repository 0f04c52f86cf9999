//! Scenes shared by the tests and the benches: Suffern's random spheres with
//! the exact random numbers and camera of the Embree peer
//! (`../shared/peers/embree/embree_bench.c`), and their tessellation.

#![allow(dead_code)]
// `3.14159` and the f32 round trips reproduce the peer's C code exactly
// (the casts are not no-ops with the `f64` feature).
#![allow(clippy::approx_constant, clippy::unnecessary_cast)]

use super::prims::{Sphere, Triangle};
use gridrt_grid::{Ray, Real, Vec3};

/// The peer's 64-bit LCG (Knuth's MMIX constants), seed 15.
#[derive(Clone, Debug)]
pub struct Lcg(pub u64);

impl Lcg {
    /// The generator with the peer's seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// A float in `[0, 1)` with 24 random bits.
    pub fn next_f32(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 * (1.0 / 16_777_216.0)
    }
    /// A `u64` with 32 random bits.
    pub fn next_u32(&mut self) -> u32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 32) as u32
    }
    /// A float in `[lo, hi)`.
    pub fn range(&mut self, lo: Real, hi: Real) -> Real {
        lo + (hi - lo) * self.next_f32() as Real
    }
}

/// The radius of Suffern's spheres for `n` of them: total volume 0.1.
pub fn suffern_radius(n: usize) -> f32 {
    let volume = 0.1f32 / n as f32;
    (0.75f32 * volume / 3.14159f32).powf(0.333333f32)
}

/// Suffern's scene: `n` spheres, centres uniform in `[−1, 1]³` (the peer's
/// LCG, seed 15, three discarded colour draws per sphere).
pub fn suffern_spheres(n: usize) -> Vec<Sphere> {
    let r = suffern_radius(n);
    let mut rng = Lcg::new(15);
    (0..n)
        .map(|_| {
            for _ in 0..3 {
                rng.next_f32();
            }
            let x = 1.0f32 - 2.0 * rng.next_f32();
            let y = 1.0f32 - 2.0 * rng.next_f32();
            let z = 1.0f32 - 2.0 * rng.next_f32();
            Sphere::new(Vec3::new(x as Real, y as Real, z as Real), r as Real)
        })
        .collect()
}

/// Image size of the benchmark.
pub const W: usize = 400;
/// Image size of the benchmark.
pub const H: usize = 400;

/// The benchmark's 160,000 primary rays, row by row (row 0 at the bottom):
/// eye (0, 0, 20), view-plane distance 3600, one ray per pixel centre,
/// directions normalised in f32 exactly as the peer does.
pub fn suffern_rays() -> Vec<Ray> {
    let mut rays = Vec::with_capacity(W * H);
    for r in 0..H {
        for c in 0..W {
            let dx = (c as f64 - 0.5 * W as f64 + 0.5) as f32;
            let dy = (r as f64 - 0.5 * H as f64 + 0.5) as f32;
            let dz = -3600.0f32;
            let inv = 1.0f32 / (dx * dx + dy * dy + dz * dz).sqrt();
            let d = Vec3::new((dx * inv) as Real, (dy * inv) as Real, (dz * inv) as Real);
            rays.push(Ray::new(Vec3::new(0.0, 0.0, 20.0), d));
        }
    }
    rays
}

/// The peer's checksum over hit pixels: `((prim + 1)·2654435761) XOR pixel`, summed.
pub fn checksum(hits: &[Option<u32>]) -> (usize, u64) {
    let mut n = 0;
    let mut sum = 0u64;
    for (pixel, h) in hits.iter().enumerate() {
        if let Some(p) = h {
            n += 1;
            sum = sum.wrapping_add((u64::from(*p) + 1).wrapping_mul(2654435761) ^ pixel as u64);
        }
    }
    (n, sum)
}

/// Each sphere as a `slices × stacks` UV sphere, in the peer's vertex and
/// triangle order (32 × 17 gives 1024 triangles per sphere).
pub fn uv_sphere_mesh(spheres: &[Sphere], slices: usize, stacks: usize) -> Vec<Triangle> {
    let mut tris = Vec::with_capacity(spheres.len() * (2 * slices + (stacks - 2) * slices * 2));
    for s in spheres {
        let (cx, cy, cz, rad) = (
            s.center.x as f32,
            s.center.y as f32,
            s.center.z as f32,
            s.radius as f32,
        );
        let mut verts: Vec<Vec3> = Vec::with_capacity((stacks - 1) * slices + 2);
        let v3 = |x: f32, y: f32, z: f32| Vec3::new(x as Real, y as Real, z as Real);
        verts.push(v3(cx, cy + rad, cz));
        for k in 1..stacks {
            for j in 0..slices {
                let th = std::f64::consts::PI * k as f64 / stacks as f64;
                let ph = 2.0 * std::f64::consts::PI * j as f64 / slices as f64;
                verts.push(v3(
                    cx + rad * (th.sin() * ph.sin()) as f32,
                    cy + rad * th.cos() as f32,
                    cz + rad * (th.sin() * ph.cos()) as f32,
                ));
            }
        }
        let south = verts.len();
        verts.push(v3(cx, cy - rad, cz));
        let ring = |k: usize, j: usize| 1 + (k - 1) * slices + j % slices;
        let mut tri =
            |a: usize, b: usize, c: usize| tris.push(Triangle::new(verts[a], verts[b], verts[c]));
        for j in 0..slices {
            tri(0, ring(1, j), ring(1, j + 1));
            tri(south, ring(stacks - 1, j + 1), ring(stacks - 1, j));
        }
        for k in 1..stacks - 1 {
            for j in 0..slices {
                tri(ring(k, j), ring(k + 1, j), ring(k + 1, j + 1));
                tri(ring(k, j), ring(k + 1, j + 1), ring(k, j + 1));
            }
        }
    }
    tris
}

/// A square of `n`×`n` quads, two triangles each, waved in y, `size`
/// wide, its corner at `at`.
pub fn wavy_sheet(n: u32, at: Vec3, size: Real) -> Vec<Triangle> {
    let p = |i: u32, j: u32| {
        let (x, z) = (i as Real / n as Real, j as Real / n as Real);
        at + Vec3::new(x, 0.05 * (9.0 * x).sin() * (7.0 * z).cos(), z) * size
    };
    let mut sheet = Vec::new();
    for j in 0..n {
        for i in 0..n {
            sheet.push(Triangle::new(p(i, j), p(i + 1, j), p(i + 1, j + 1)));
            sheet.push(Triangle::new(p(i, j), p(i + 1, j + 1), p(i, j + 1)));
        }
    }
    sheet
}
