//! A scene far from the origin: the insertion pad follows the scene's
//! extent and the rounding of positions is made exact, so the Utah teapot
//! moved by 10⁵ keeps about the references it has at the origin, moved by
//! 10⁶ (f32 ulp 0.0625) the grid still spares all but a fiftieth of the
//! exhaustive tests, and at every offset the answers are the exhaustive
//! ones bit for bit.

use crate::support::prims::Triangle;
use crate::support::scenes::Lcg;
use crate::support::Checker;
use gridrt_grid::{
    Accelerator, CellStorage, Exhaustive, Grid, GridConfig, QueryCounters, Ray, Real, Vec3,
};

/// The committed Utah teapot (6,320 triangles, about 6 × 3 × 4 units),
/// moved by `offset`. A minimal reader: `v x y z` and `f a b c` lines.
fn teapot(offset: Vec3) -> Vec<Triangle> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/meshes/teapot/teapot.obj"
    );
    let text = std::fs::read_to_string(path).expect("the teapot fixture is committed");
    let mut v = Vec::new();
    let mut tris = Vec::new();
    for line in text.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => {
                let c: Vec<f64> = w.map(|x| x.parse().expect("a coordinate")).collect();
                // Moved in f64, then rounded once, as a loader would.
                let p = Vec3::new(
                    (c[0] + offset.x as f64) as Real,
                    (c[1] + offset.y as f64) as Real,
                    (c[2] + offset.z as f64) as Real,
                );
                v.push(p);
            }
            Some("f") => {
                let i: Vec<usize> = w
                    .map(|x| {
                        x.split('/')
                            .next()
                            .and_then(|s| s.parse().ok())
                            .expect("an index")
                    })
                    .collect();
                for k in 1..i.len() - 1 {
                    tris.push(Triangle::new(v[i[0] - 1], v[i[k] - 1], v[i[k + 1] - 1]));
                }
            }
            _ => {}
        }
    }
    tris
}

/// Rays from all around the teapot at `offset`, aimed at its vertices.
fn rays(tris: &[Triangle], offset: Vec3, n: usize) -> Vec<Ray> {
    let mut rng = Lcg::new(11);
    (0..n)
        .map(|_| {
            let from = offset
                + Vec3::new(
                    rng.range(-8.0, 8.0),
                    rng.range(-8.0, 8.0),
                    rng.range(-8.0, 8.0),
                );
            let t = &tris[rng.next_u32() as usize % tris.len()];
            let to = t.vertices()[rng.next_u32() as usize % 3];
            Ray::new(from, to - from)
        })
        .collect()
}

/// Primitive tests of the closest-hit queries of `rays`.
fn tests<A>(a: &A, rays: &[Ray], scratch: &mut A::Scratch) -> u64
where
    A: Counted,
{
    let mut c = QueryCounters::default();
    for ray in rays {
        a.counted(ray, scratch, &mut c);
    }
    c.tests
}

/// The counted closest-hit query of both accelerators.
trait Counted: Accelerator {
    fn counted(&self, ray: &Ray, s: &mut Self::Scratch, c: &mut QueryCounters);
}

impl Counted for Grid<Triangle> {
    fn counted(&self, ray: &Ray, s: &mut Self::Scratch, c: &mut QueryCounters) {
        self.closest_hit_counted(ray, 0.0, Real::INFINITY, s, c);
    }
}

impl Counted for Exhaustive<Triangle> {
    fn counted(&self, ray: &Ray, s: &mut Self::Scratch, c: &mut QueryCounters) {
        let () = s;
        self.closest_hit_counted(ray, 0.0, Real::INFINITY, c);
    }
}

#[test]
fn moved_far_away_the_references_stay_nearly_the_same() {
    let config = GridConfig::default();
    let at = |x: Real| {
        let g = Grid::build(teapot(Vec3::new(x, 0.0, 0.0)), &config);
        g.check_invariants().expect("a valid grid");
        g.stats().references as f64
    };
    let (home, far) = (at(0.0), at(1e5));
    let limit = if cfg!(feature = "f64") { 1.10 } else { 1.25 };
    assert!(
        far <= home * limit && home <= far * limit,
        "{home} references at the origin, {far} at 1e5"
    );
}

#[test]
fn a_million_units_away_the_grid_still_spares_the_tests() {
    let offset = Vec3::new(1e6, -1e6, 1e6);
    let tris = teapot(offset);
    let far_rays = rays(&tris, offset, 200);
    let grid = Grid::build(tris.clone(), &GridConfig::default());
    grid.check_invariants().expect("a valid grid");
    let all = Exhaustive::new(tris);
    let g = tests(&grid, &far_rays, &mut grid.scratch());
    let e = tests(&all, &far_rays, &mut ());
    // The teapot itself is coarser there (its vertices rounded to 1/16):
    // 72 times fewer tests than exhaustive, against 120 at the origin.
    assert!(g * 50 < e, "grid {g} tests, exhaustive {e}");
}

#[test]
fn the_answers_are_exhaustive_at_every_offset() {
    let configs: Vec<GridConfig> = [CellStorage::Dense, CellStorage::Hashed]
        .into_iter()
        .flat_map(|storage| {
            [false, true].map(|mailbox| GridConfig {
                storage,
                mailbox,
                nest_min_refs: if mailbox { 4 } else { 0 },
                ..GridConfig::default()
            })
        })
        .collect();
    for x in [0.0, 1e3, 1e5, 1e6, -3e6] {
        let offset = Vec3::new(x, 0.5 * x, -x);
        let tris = teapot(offset);
        let rays = rays(&tris, offset, 60);
        let c = Checker::new(tris, &configs);
        let mut hits = 0;
        for ray in &rays {
            hits += usize::from(c.check(ray, 0.0, Real::INFINITY).is_some());
        }
        assert!(hits > rays.len() / 2, "{hits} hits at offset {x}");
    }
}
