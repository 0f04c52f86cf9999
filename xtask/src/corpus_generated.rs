//! Generated scenes of the corpus, built from the committed Utah teapot
//! (`fixtures/meshes/teapot/teapot.obj`) with fixed seeds: the kinds of
//! non-uniform scene users render that the model files do not cover.
//!
//! - **teapots**: 40 teapots, 0.1 to 31 units across (a log-uniform
//!   spread), at random places in a 1,000-unit cube, seen from outside it
//!   (most rays cross occupied regions of the scene and hit nothing) and
//!   from close to the largest.
//! - **city**: a 4,000-unit ground, 30 × 30 blocks of 10 to 200 units
//!   high, and a one-unit teapot in a street, seen from close (the teapot
//!   in a stadium again, in a scene of many large objects) and from above
//!   the city.

// `Real` is f32 or f64 (the `f64` feature): casts to it are not no-ops in
// both builds.
#![allow(clippy::unnecessary_cast)]

use crate::corpus::{tris_bounds, Lcg, View};
use gridrt_grid::{Real, Vec3};
use std::path::Path;

/// What a generated scene is.
#[derive(Clone, Copy, Debug)]
pub enum Generated {
    Teapots,
    City,
}

/// A generated scene: its triangles, its views and what it is.
pub struct Built {
    pub tris: Vec<[Vec3; 3]>,
    pub views: Vec<(&'static str, View)>,
    pub about: String,
}

/// Builds scene `g` from the teapot under `root`.
pub fn build(g: Generated, root: &Path) -> Result<Built, String> {
    let file = root.join("fixtures/meshes/teapot/teapot.obj");
    let sandbox = gridrt_io::Sandbox::for_input(&file);
    let model = gridrt_io::load_model_in(&file, &sandbox).map_err(|e| e.to_string())?;
    let tris: Vec<[Vec3; 3]> = model.triangles().collect();
    if tris.is_empty() {
        return Err(format!("{}: no triangles", file.display()));
    }
    let b = tris_bounds(&tris);
    let teapot = Shape {
        tris,
        centre: (b.min + b.max) * 0.5,
        extent: (b.max - b.min).max_element(),
    };
    Ok(match g {
        Generated::Teapots => teapots(&teapot),
        Generated::City => city(&teapot),
    })
}

/// The triangles of a model placed many times, with its box's centre and
/// longest extent.
struct Shape {
    tris: Vec<[Vec3; 3]>,
    centre: Vec3,
    extent: Real,
}

impl Shape {
    /// The triangles scaled so that their longest extent is `size` and
    /// centred on `at`.
    fn placed(&self, size: f64, at: Vec3) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        let s = (size / self.extent as f64) as Real;
        let c = self.centre;
        self.tris.iter().map(move |t| t.map(|p| (p - c) * s + at))
    }
}

/// The twelve triangles of box `[lo, hi]`.
fn cuboid(lo: Vec3, hi: Vec3) -> [[Vec3; 3]; 12] {
    let v = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    let quads = [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ];
    let mut out = [[Vec3::ZERO; 3]; 12];
    for (k, [a, b, c, d]) in quads.into_iter().enumerate() {
        out[2 * k] = [v(a), v(b), v(c)];
        out[2 * k + 1] = [v(a), v(c), v(d)];
    }
    out
}

fn teapots(teapot: &Shape) -> Built {
    let mut rng = Lcg(0x7ea);
    let mut tris = Vec::new();
    // The largest teapot's centre and size, for the close view.
    let mut largest = (Vec3::ZERO, 0.0);
    for _ in 0..40 {
        let at = Vec3::new(
            (rng.next() * 1000.0 - 500.0) as Real,
            (rng.next() * 1000.0 - 500.0) as Real,
            (rng.next() * 1000.0 - 500.0) as Real,
        );
        let size = 10f64.powf(rng.next() * 2.5 - 1.0);
        if size > largest.1 {
            largest = (at, size);
        }
        tris.extend(teapot.placed(size, at));
    }
    let (at, size) = largest;
    Built {
        tris,
        views: vec![
            (
                "far",
                View {
                    eye: Vec3::new(0.0, 0.0, 900.0),
                    look_at: Vec3::ZERO,
                    vfov_deg: 70.0,
                },
            ),
            (
                "close",
                View {
                    eye: at + Vec3::new(0.4, 0.5, 1.5) * size as Real,
                    look_at: at,
                    vfov_deg: 40.0,
                },
            ),
        ],
        about:
            "40 teapots (fixtures/meshes/teapot) of 0.1 to 31 units at random in a 1000-unit cube"
                .to_string(),
    }
}

fn city(teapot: &Shape) -> Built {
    let mut rng = Lcg(0xc17);
    let mut tris = Vec::new();
    tris.extend(cuboid(
        Vec3::new(-2000.0, -1.0, -2000.0),
        Vec3::new(2000.0, 0.0, 2000.0),
    ));
    for i in 0..30 {
        for j in 0..30 {
            let (x, z) = (-1500.0 + 100.0 * i as Real, -1500.0 + 100.0 * j as Real);
            let h = (10.0 + 190.0 * rng.next()) as Real;
            tris.extend(cuboid(
                Vec3::new(x + 10.0, 0.0, z + 10.0),
                Vec3::new(x + 90.0, h, z + 90.0),
            ));
        }
    }
    // In the street between four blocks, standing on the ground.
    tris.extend(teapot.placed(1.0, Vec3::new(5.0, 0.3, 5.0)));
    Built {
        tris,
        views: vec![
            (
                "close",
                View {
                    eye: Vec3::new(7.0, 1.5, 9.0),
                    look_at: Vec3::new(5.0, 0.4, 5.0),
                    vfov_deg: 40.0,
                },
            ),
            (
                "high",
                View {
                    eye: Vec3::new(-1800.0, 600.0, -1800.0),
                    look_at: Vec3::ZERO,
                    vfov_deg: 50.0,
                },
            ),
        ],
        about: "a 4000-unit ground, 30×30 blocks 10 to 200 units high, a 1-unit teapot (fixtures/meshes/teapot) in a street"
            .to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
    }

    #[test]
    fn the_scenes_are_the_teapot_placed_as_documented() {
        let file = root().join("fixtures/meshes/teapot/teapot.obj");
        let sandbox = gridrt_io::Sandbox::for_input(&file);
        let n = gridrt_io::load_model_in(&file, &sandbox)
            .map(|m| m.triangles().count())
            .unwrap_or_else(|e| panic!("{e}"));
        let t = build(Generated::Teapots, &root()).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(t.tris.len(), 40 * n);
        let b = tris_bounds(&t.tris);
        assert!(
            b.min.min_element() > -520.0 && b.max.max_element() < 520.0,
            "{b:?}"
        );
        // The close view looks at a teapot from outside it.
        let (_, close) = t.views[1];
        assert!(close.eye.distance(close.look_at) > 1.0);
        let c = build(Generated::City, &root()).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(c.tris.len(), 12 + 900 * 12 + n);
        // The same scene every time.
        let again = build(Generated::City, &root()).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(c.tris, again.tris);
    }

    #[test]
    fn a_cuboid_is_closed() {
        // Every edge of a closed surface is shared by exactly two triangles.
        let tris = cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        let key = |p: Vec3| [p.x, p.y, p.z].map(|x| x as f64).map(f64::to_bits);
        let mut edges = std::collections::HashMap::new();
        for t in &tris {
            for k in 0..3 {
                let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
                *edges
                    .entry(if a < b { (a, b) } else { (b, a) })
                    .or_insert(0) += 1;
            }
        }
        assert_eq!(edges.len(), 18);
        assert!(edges.values().all(|&c| c == 2));
    }
}
