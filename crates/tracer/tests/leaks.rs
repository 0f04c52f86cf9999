//! No ray leaks out of a closed mesh, at any scale, offset and direction
//! length the precision resolves, and the grid agrees with the exhaustive
//! baseline on every probe ray.

use gridrt_grid::{Accelerator, Exhaustive, Grid, GridConfig, Hit, PrimHit, Ray, Real, Vec3};
use gridrt_tracer::hard_meshes::{self, DirLength};
use gridrt_tracer::{MtTriangle, Shear, Triangle};

const SCALES: [f64; 3] = [1e-6, 1.0, 1e6];
const OFFSETS: [f64; 3] = [0.0, 1e3, 1e5];

/// Whether a mesh of about unit size scaled by `scale` and moved by
/// `offset` keeps its shape: its extent spans at least 2¹² ulps of the
/// offset. Below that vertices merge, and the inside point may end up on
/// or outside the surface.
// `Real` is f64 in the f64 build, where the conversion does nothing.
#[allow(clippy::useless_conversion)]
fn resolved(scale: f64, offset: f64) -> bool {
    scale >= offset * f64::from(Real::EPSILON) * 4096.0
}

fn closest<A: Accelerator>(a: &A, r: &Ray, s: &mut A::Scratch) -> Option<Hit> {
    a.closest_hit(r, 0.0, Real::INFINITY, s)
}

#[test]
fn closed_meshes_never_leak_and_grid_equals_exhaustive() {
    let mut report = Vec::new();
    let mut total = 0usize;
    for mesh in hard_meshes::standard_set() {
        for scale in SCALES {
            for offset in OFFSETS {
                if !resolved(scale, offset) {
                    continue;
                }
                let tris = mesh.triangles(scale, offset);
                let ex = Exhaustive::new(tris.clone());
                let grid = Grid::build(tris, &GridConfig::default());
                let (mut se, mut sg) = (ex.scratch(), grid.scratch());
                for len in [DirLength::Unit, DirLength::Short, DirLength::ToTarget] {
                    let rays = mesh.probe_rays(scale, offset, len);
                    assert!(rays.len() > 100, "{}: {} rays", mesh.name, rays.len());
                    let (mut leaks, mut mismatches) = (0, 0);
                    for r in &rays {
                        let e = closest(&ex, r, &mut se);
                        leaks += usize::from(e.is_none());
                        mismatches += usize::from(closest(&grid, r, &mut sg) != e);
                    }
                    total += rays.len();
                    if leaks + mismatches > 0 {
                        report.push(format!(
                            "{} scale {scale:e} offset {offset:e} {len:?}: {leaks} leaks, \
                             {mismatches} grid/exhaustive mismatches of {}",
                            mesh.name,
                            rays.len()
                        ));
                    }
                }
            }
        }
    }
    assert!(total > 50_000, "{total} rays");
    assert!(report.is_empty(), "{}", report.join("\n"));
}

/// The issue's first minimal case: a unit triangle seen from the origin
/// along a direction of length about 10⁻⁶.
#[test]
fn issue_25_short_direction_hits() {
    let tri = Triangle::new(Vec3::X, Vec3::Y, Vec3::Z);
    for len in [1e-6, 1e-5, 1.0, 1e6] {
        let r = Ray::new(Vec3::ZERO, Vec3::splat(len));
        let h = tri.intersect(&Shear::new(&r), 0.0, Real::INFINITY);
        assert!(h.is_some(), "direction length {len}");
        let h = h.unwrap();
        assert!((h.t * len * 3.0 - 1.0).abs() < 1e-5, "{h:?} at {len}");
    }
}

/// The issue's second minimal case: the unit case scaled by exactly 2⁻²⁰
/// must give the same answer.
#[test]
fn issue_25_power_of_two_scaled_case_is_unchanged() {
    let unit = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
    let r = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
    let h = unit
        .intersect(&Shear::new(&r), 0.0, Real::INFINITY)
        .unwrap();
    assert_eq!((h.t, h.u, h.v), (1.0, 0.25, 0.25));
    let s = (2.0 as Real).powi(-20); // 9.5367431640625e-7
    let small = Triangle::new(Vec3::ZERO, Vec3::X * s, Vec3::Y * s);
    let r = Ray::new(Vec3::new(0.25, 0.25, 1.0) * s, -Vec3::Z * s);
    assert_eq!(
        small.intersect(&Shear::new(&r), 0.0, Real::INFINITY),
        Some(h)
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 512, ..Default::default() })]

    /// Scaling a triangle, a ray's origin and its direction by powers of two
    /// (each its own) changes nothing but `t`, by the ratio of the two.
    #[test]
    fn answers_are_invariant_under_power_of_two_scaling(
        p in proptest::array::uniform9(-4.0f32..4.0),
        o in proptest::array::uniform3(-4.0f32..4.0),
        d in proptest::array::uniform3(-1.0f32..1.0),
        k in -20i32..20,
        j in -20i32..20,
    ) {
        let v = |i: usize| Vec3::new(Real::from(p[3 * i]), Real::from(p[3 * i + 1]), Real::from(p[3 * i + 2]));
        let o = Vec3::new(Real::from(o[0]), Real::from(o[1]), Real::from(o[2]));
        let d = Vec3::new(Real::from(d[0]), Real::from(d[1]), Real::from(d[2]));
        let (sk, sj) = ((2.0 as Real).powi(k), (2.0 as Real).powi(j));
        let a = Triangle::new(v(0), v(1), v(2)).intersect(&Shear::new(&Ray::new(o, d)), 0.0, Real::INFINITY);
        let b = Triangle::new(v(0) * sk, v(1) * sk, v(2) * sk)
            .intersect(&Shear::new(&Ray::new(o * sk, d * sj)), 0.0, Real::INFINITY);
        let scaled = a.map(|h| PrimHit { t: h.t * (sk / sj), ..h });
        proptest::prop_assert_eq!(b, scaled);
    }
}

/// The switch that turns watertightness off: Möller–Trumbore lets probe
/// rays through the closed meshes (at scale 1 through shared edges and
/// vertices, at scale 10⁻⁶ through its fixed epsilon too), where the
/// watertight test lets none through.
#[test]
fn moller_trumbore_leaks_where_watertight_does_not() {
    let mut report = Vec::new();
    let (mut wt_leaks, mut mt_leaks_unit_scale, mut mt_leaks_small) = (0, 0, 0);
    for mesh in hard_meshes::standard_set() {
        for scale in [1.0, 1e-6] {
            let tris = mesh.triangles(scale, 0.0);
            let mt: Vec<MtTriangle> = tris.iter().copied().map(MtTriangle).collect();
            let (wt, mt) = (Exhaustive::new(tris), Exhaustive::new(mt));
            let (mut sw, mut sm) = (wt.scratch(), mt.scratch());
            let rays = mesh.probe_rays(scale, 0.0, DirLength::Unit);
            let w = rays
                .iter()
                .filter(|r| closest(&wt, r, &mut sw).is_none())
                .count();
            let m = rays
                .iter()
                .filter(|r| closest(&mt, r, &mut sm).is_none())
                .count();
            report.push(format!(
                "{} scale {scale:e}: watertight {w}, MT {m} of {}",
                mesh.name,
                rays.len()
            ));
            wt_leaks += w;
            if scale == 1.0 {
                mt_leaks_unit_scale += m;
            } else {
                mt_leaks_small += m;
            }
        }
    }
    let report = report.join("\n");
    assert_eq!(wt_leaks, 0, "{report}");
    assert!(mt_leaks_small > 100, "{report}");
    #[cfg(not(feature = "f64"))]
    assert!(mt_leaks_unit_scale > 0, "{report}");
    #[cfg(feature = "f64")]
    let _ = mt_leaks_unit_scale;
}

/// Two triangles sharing the diagonal of a square, rays aimed exactly at
/// points of the diagonal: Möller–Trumbore misses both triangles for some
/// of them (the two `u + v ≤ 1` tests round differently), the watertight
/// test never does.
#[test]
fn moller_trumbore_falls_through_a_shared_edge() {
    let a = Triangle::new(
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.1, 0.0),
        Vec3::new(0.3, 1.0, 0.0),
    );
    let b = Triangle::new(
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.3, 1.0, 0.0),
        Vec3::new(-0.7, 0.9, 0.0),
    );
    let (mut wt_miss, mut mt_miss) = (0, 0);
    let n = 20_000;
    for i in 1..n {
        let s = i as Real / n as Real;
        let target = Vec3::new(0.3, 1.0, 0.0) * s;
        let origin = Vec3::new(0.37, -0.21, 1.3);
        let r = Ray::new(origin, target - origin);
        let hit = |p: &dyn Fn(&Ray) -> bool| p(&r);
        wt_miss += usize::from(!hit(&|r| {
            let shear = Shear::new(r);
            a.intersect(&shear, 0.0, Real::INFINITY).is_some()
                || b.intersect(&shear, 0.0, Real::INFINITY).is_some()
        }));
        mt_miss += usize::from(!hit(&|r| {
            MtTriangle(a).intersect(r, 0.0, Real::INFINITY).is_some()
                || MtTriangle(b).intersect(r, 0.0, Real::INFINITY).is_some()
        }));
    }
    assert_eq!(wt_miss, 0);
    assert!(mt_miss > 0, "Möller–Trumbore missed none of {n} rays");
}

/// The grid's optional work and its textbook slab test change no answer:
/// on the closed meshes at every placement, each grid variant returns
/// exactly the exhaustive baseline's hits (the entry box is padded beyond
/// the primitives, so the textbook test's `0·∞` cases fall outside them).
#[test]
#[allow(clippy::let_unit_value)] // the exhaustive accelerator's scratch is `()`
fn grid_switches_change_no_answer() {
    use gridrt_grid::{CellStorage, SlabTest};
    let variants = [
        GridConfig {
            mailbox: true,
            ..GridConfig::default()
        },
        GridConfig {
            exact_insertion: true,
            ..GridConfig::default()
        },
        GridConfig {
            slab: SlabTest::Textbook,
            ..GridConfig::default()
        },
        GridConfig {
            storage: CellStorage::Hashed,
            m: 2.0,
            ..GridConfig::default()
        },
        GridConfig {
            nest_min_refs: 4,
            m: 0.3,
            ..GridConfig::default()
        },
    ];
    let mut report = Vec::new();
    for mesh in hard_meshes::standard_set() {
        for (scale, offset) in [(1.0, 0.0), (1e-6, 0.0), (1e6, 1e5)] {
            let tris = mesh.triangles(scale, offset);
            let ex = Exhaustive::new(tris.clone());
            let mut se = ex.scratch();
            let rays = mesh.probe_rays(scale, offset, DirLength::ToTarget);
            let want: Vec<_> = rays.iter().map(|r| closest(&ex, r, &mut se)).collect();
            for (k, config) in variants.iter().enumerate() {
                let grid = Grid::build(tris.clone(), config);
                let mut sg = grid.scratch();
                let bad = rays
                    .iter()
                    .zip(&want)
                    .filter(|(r, w)| closest(&grid, r, &mut sg) != **w)
                    .count();
                if bad > 0 {
                    report.push(format!(
                        "{} scale {scale:e}: variant {k}: {bad} mismatches",
                        mesh.name
                    ));
                }
            }
        }
    }
    assert!(report.is_empty(), "{}", report.join("\n"));
}

/// A closed mesh and its probe rays scaled by 2⁻²⁰ or 2²⁰ get the same
/// answers from the grid: the same triangle, the same barycentrics, and `t`
/// scaled by exactly the inverse for unit directions (unchanged for
/// `target − origin` ones, which scale with the mesh).
#[test]
fn grid_answers_are_unchanged_under_power_of_two_scaling() {
    let mut report = Vec::new();
    for mesh in hard_meshes::standard_set() {
        let answers = |scale: f64, len: DirLength| {
            let grid = Grid::build(mesh.triangles(scale, 0.0), &GridConfig::default());
            let mut s = grid.scratch();
            mesh.probe_rays(scale, 0.0, len)
                .iter()
                .map(|r| closest(&grid, r, &mut s))
                .collect::<Vec<_>>()
        };
        for len in [DirLength::Unit, DirLength::ToTarget] {
            let unit = answers(1.0, len);
            for k in [-20, 20] {
                let s = (2.0f64).powi(k);
                let t_scale = if len == DirLength::Unit {
                    s as Real
                } else {
                    1.0
                };
                let want: Vec<_> = unit
                    .iter()
                    .map(|h| {
                        h.map(|h| Hit {
                            t: h.t * t_scale,
                            ..h
                        })
                    })
                    .collect();
                let got = answers(s, len);
                let bad = got.iter().zip(&want).filter(|(g, w)| g != w).count();
                if bad > 0 || got.len() != want.len() {
                    report.push(format!(
                        "{} 2^{k} {len:?}: {bad} of {} differ",
                        mesh.name,
                        want.len()
                    ));
                }
            }
        }
    }
    assert!(report.is_empty(), "{}", report.join("\n"));
}

/// T-junctions closed by zero-area triangles, far from the origin where
/// the shear rounds: such a triangle has area only in the ray's frame, and
/// it alone covers the crack between the edge `a`–`b` on one side and
/// `a`–`m`–`b` on the other. Rejecting it (as a test that skips zero-area
/// triangles does) leaks here.
#[test]
fn t_junctions_closed_by_zero_area_triangles_never_leak() {
    let mesh = hard_meshes::with_t_junctions(&hard_meshes::lattice_ball(2));
    let mut report = Vec::new();
    for offset in [0.0, 1024.0, 131_072.0, -131_072.0] {
        let tris = mesh.triangles(1.0, offset);
        let ex = Exhaustive::new(tris.clone());
        let grid = Grid::build(tris, &GridConfig::default());
        let (mut se, mut sg) = (ex.scratch(), grid.scratch());
        for len in [DirLength::Unit, DirLength::Short, DirLength::ToTarget] {
            let rays = mesh.probe_rays(1.0, offset, len);
            let (mut leaks, mut mismatches) = (0, 0);
            for r in &rays {
                let e = closest(&ex, r, &mut se);
                leaks += usize::from(e.is_none());
                mismatches += usize::from(closest(&grid, r, &mut sg) != e);
            }
            if leaks + mismatches > 0 {
                report.push(format!(
                    "offset {offset:e} {len:?}: {leaks} leaks, {mismatches} mismatches of {}",
                    rays.len()
                ));
            }
        }
    }
    assert!(report.is_empty(), "{report:#?}");
}
