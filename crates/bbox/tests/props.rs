//! Property tests (proptest) for boxes and the slab test, with a fixed seed.

use crate::support::{checked_hit, widened, INF};
use gridrt_bbox::{Aabb, Ray, Real, Vec3};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// Deterministic runs: a fixed seed, and no regression files written.
fn config() -> Config {
    Config {
        cases: 512,
        rng_seed: RngSeed::Fixed(0x6772_6964_7274), // "gridrt"
        failure_persistence: None,
        ..Config::default()
    }
}

fn coord() -> impl Strategy<Value = Real> {
    prop_oneof![
        4 => (-100.0f64..100.0).prop_map(|x| x as Real),
        // Small integers, so faces and origins often coincide exactly.
        1 => (-4i32..=4).prop_map(|x| x as Real),
    ]
}

fn point() -> impl Strategy<Value = Vec3> {
    (coord(), coord(), coord()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A non-empty box (possibly flat or a point when the corners share coordinates).
fn aabb() -> impl Strategy<Value = Aabb> {
    (point(), point()).prop_map(|(a, b)| Aabb::new(a.min(b), a.max(b)))
}

/// Any box, empty ones included (corners taken unsorted).
fn any_aabb() -> impl Strategy<Value = Aabb> {
    prop_oneof![
        3 => aabb(),
        1 => (point(), point()).prop_map(|(a, b)| Aabb::new(a, b)),
        1 => Just(Aabb::EMPTY),
    ]
}

fn dir_component() -> impl Strategy<Value = Real> {
    prop_oneof![
        6 => (-1.0f64..1.0).prop_map(|x| x as Real),
        1 => Just(0.0 as Real),
        1 => Just(-0.0 as Real),
    ]
}

fn dir() -> impl Strategy<Value = Vec3> {
    (dir_component(), dir_component(), dir_component()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A point of the closed box `b` at fractions `u` of its extent per axis.
fn inside(b: &Aabb, u: Vec3) -> Vec3 {
    (b.min + (b.max - b.min) * u).clamp(b.min, b.max)
}

fn unit_fractions() -> impl Strategy<Value = Vec3> {
    (0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.0)
        .prop_map(|(x, y, z)| Vec3::new(x as Real, y as Real, z as Real))
}

/// The largest magnitude among the inputs: the scale of rounding errors.
fn scale(b: &Aabb, r: &Ray, t: Real) -> Real {
    let m = b
        .min
        .abs()
        .max(b.max.abs())
        .max(r.origin.abs())
        .max((r.dir * t).abs());
    m.max_element().max(1.0)
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn hit_midpoint_lies_in_the_box(b in aabb(), o in point(), d in dir()) {
        let r = Ray::new(o, d);
        if let Some((t0, t1)) = checked_hit(&b, &r, 0.0, 1e6) {
            let m = r.at(0.5 * (t0 + t1));
            let tol = Vec3::splat(1e-4 * scale(&b, &r, t1));
            prop_assert!(
                Aabb::new(b.min - tol, b.max + tol).contains(m),
                "midpoint {:?} of ({}, {}) outside {:?}", m, t0, t1, b
            );
        }
    }

    #[test]
    fn ray_from_inside_always_hits_at_t_min(b in aabb(), u in unit_fractions(), d in dir()) {
        let r = Ray::new(inside(&b, u), d);
        let h = checked_hit(&b, &r, 0.0, INF);
        prop_assert!(matches!(h, Some((t0, _)) if t0 == 0.0), "{:?} for {:?} in {:?}", h, r, b);
    }

    #[test]
    fn hit_agrees_with_sampling(b in aabb(), o in point(), d in dir()) {
        // If some sampled point of the ray lies inside the box with a margin,
        // the slab test must report a hit covering that t.
        let r = Ray::new(o, d);
        let t_max = 400.0 as Real;
        let h = checked_hit(&b, &r, 0.0, t_max);
        let margin = Vec3::splat(1e-3 * scale(&b, &r, t_max));
        let shrunk = Aabb::new(b.min + margin, b.max - margin);
        for i in 0..=400 {
            let t = i as Real;
            if shrunk.contains(r.at(t)) {
                let (t0, t1) = h.ok_or_else(|| {
                    TestCaseError::fail(format!("t = {t} is inside but hit missed: {r:?} {b:?}"))
                })?;
                prop_assert!(t0 <= t && t <= t1, "t = {} outside ({}, {})", t, t0, t1);
            }
        }
    }

    #[test]
    fn union_contains_both_boxes(a in any_aabb(), b in any_aabb(), u in unit_fractions()) {
        let c = a.union(b);
        for x in [a, b] {
            if !x.is_empty() {
                prop_assert!(c.contains(x.min) && c.contains(x.max) && c.contains(inside(&x, u)));
            }
        }
        // And it is the smallest such box.
        match (a.is_empty(), b.is_empty()) {
            (true, true) => prop_assert!(c.is_empty()),
            (true, false) => prop_assert_eq!(c, b),
            (false, true) => prop_assert_eq!(c, a),
            (false, false) => prop_assert_eq!(c, Aabb::new(a.min.min(b.min), a.max.max(b.max))),
        }
    }

    #[test]
    fn grow_contains_the_point_and_the_box(a in any_aabb(), p in point()) {
        let g = a.grow(p);
        prop_assert!(g.contains(p));
        if !a.is_empty() {
            prop_assert!(g.contains(a.min) && g.contains(a.max));
        }
        prop_assert_eq!(g, a.union(Aabb::new(p, p)));
    }

    #[test]
    fn from_points_is_the_tight_box(ps in prop::collection::vec(point(), 0..24)) {
        let b = Aabb::from_points(ps.iter().copied());
        prop_assert_eq!(b.is_empty(), ps.is_empty());
        for p in &ps {
            prop_assert!(b.contains(*p));
        }
        // Tight: every face is touched by some point.
        for axis in 0..3 {
            if !ps.is_empty() {
                prop_assert!(ps.iter().any(|p| p[axis] == b.min[axis]));
                prop_assert!(ps.iter().any(|p| p[axis] == b.max[axis]));
            }
        }
    }

    #[test]
    fn overlaps_is_symmetric_and_matches_the_intersection(a in any_aabb(), b in any_aabb()) {
        prop_assert_eq!(a.overlaps(&b), b.overlaps(&a));
        let meet = Aabb::new(a.min.max(b.min), a.max.min(b.max));
        let expected = !a.is_empty() && !b.is_empty() && !meet.is_empty();
        prop_assert_eq!(a.overlaps(&b), expected);
        prop_assert_eq!(a.overlaps(&a), !a.is_empty());
    }
}

// ---- An exact oracle on a lattice ----------------------------------------------

/// Integer lattice coordinates and dyadic directions: every slab t value is
/// exact in binary, so the slab test must agree with an exact computation
/// (apart from the conservative widening of the exit).
fn lattice() -> impl Strategy<Value = Real> {
    (-4i32..=4).prop_map(|x| x as Real)
}

fn lattice_point() -> impl Strategy<Value = Vec3> {
    (lattice(), lattice(), lattice()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn dyadic_dir() -> impl Strategy<Value = Vec3> {
    let c = prop::sample::select(vec![-2.0, -1.0, -0.5, -0.0, 0.0, 0.5, 1.0, 2.0 as Real]);
    (c.clone(), c.clone(), c).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// The exact interval, by division and an explicit `d == 0` case. On this
/// lattice every operation below is exact, in f32 as in f64.
fn oracle(b: &Aabb, o: Vec3, d: Vec3, t_min: Real, t_max: Real) -> Option<(Real, Real)> {
    let (mut t0, mut t1) = (t_min, t_max);
    for a in 0..3 {
        let (lo, hi, o, d) = (b.min[a], b.max[a], o[a], d[a]);
        if d == 0.0 {
            if o < lo || o > hi {
                return None;
            }
        } else {
            let (p, q) = ((lo - o) / d, (hi - o) / d);
            t0 = t0.max(p.min(q));
            t1 = t1.min(p.max(q));
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

proptest! {
    #![proptest_config(Config { cases: 4096, ..config() })]

    #[test]
    fn lattice_rays_match_the_exact_oracle(
        p in lattice_point(),
        q in lattice_point(),
        o in lattice_point(),
        d in dyadic_dir(),
        range in prop::sample::select(vec![(0.0, INF), (-INF, INF), (0.0, 2.0), (1.5, 1.5), (2.0, 1.0 as Real)]),
    ) {
        let b = Aabb::new(p.min(q), p.max(q));
        let r = Ray::new(o, d);
        let (t_min, t_max) = range;
        let got = checked_hit(&b, &r, t_min, t_max);
        let want = oracle(&b, o, d, t_min, t_max);
        match (got, want) {
            (None, None) => {}
            (Some((t0, t1)), Some((w0, w1))) => {
                prop_assert_eq!(t0, w0);
                prop_assert!(t1 >= w1 && t1 <= widened(w1), "{} vs {}", t1, w1);
            }
            _ => prop_assert!(false, "got {:?}, exact {:?} for {:?} {:?}", got, want, r, b),
        }
    }
}

/// The slab test one axis at a time, with scalar arithmetic: what
/// [`Aabb::hit`] computes in SIMD lanes.
fn hit_axis_by_axis(b: &Aabb, ray: &Ray, t_min: Real, t_max: Real) -> Option<(Real, Real)> {
    let widen = 2.0 * gridrt_bbox::gamma(3);
    let (mut t0, mut t1, mut empty) = (t_min, t_max, false);
    for a in 0..3 {
        let (lo, hi, o, inv) = (b.min[a], b.max[a], ray.origin[a], ray.inv_dir[a]);
        empty |= lo > hi;
        let (near, far) = if inv.is_infinite() {
            if lo <= o && o <= hi {
                (-INF, INF)
            } else {
                (INF, -INF)
            }
        } else {
            let (t_lo, t_hi) = ((lo - o) * inv, (hi - o) * inv);
            let (near, far) = if t_lo > t_hi {
                (t_hi, t_lo)
            } else {
                (t_lo, t_hi)
            };
            (near, far.max(far + far.abs() * widen))
        };
        t0 = if near > t0 { near } else { t0 };
        t1 = if far < t1 { far } else { t1 };
    }
    (!empty && t0 <= t1).then_some((t0, t1))
}

/// A direction component, with the hard ones: zeros of both signs, a
/// denormal whose reciprocal overflows, a tiny one whose crossings do
/// (to `−∞`, which the exit's widening turns into NaN).
fn hard_dir_component() -> impl Strategy<Value = Real> {
    prop_oneof![
        4 => (-1.0f64..1.0).prop_map(|x| x as Real),
        1 => Just(0.0 as Real),
        1 => Just(-0.0 as Real),
        1 => Just(Real::MIN_POSITIVE / 8.0),
        1 => Just(-8.0 * Real::MIN_POSITIVE),
        1 => Just(Real::NAN),
    ]
}

proptest! {
    #![proptest_config(config())]

    /// The lanes give the very values of the scalar test, for boxes empty,
    /// flat or not, rays parallel to faces, lying in them or with
    /// overflowing crossings, NaN directions, and any range.
    #[test]
    fn hit_in_lanes_equals_hit_axis_by_axis(
        b in any_aabb(),
        o in point(),
        d in (hard_dir_component(), hard_dir_component(), hard_dir_component()),
        range in prop_oneof![Just((0.0 as Real, INF)), (coord(), coord())],
    ) {
        let r = Ray::new(o, Vec3::new(d.0, d.1, d.2));
        let bits = |h: Option<(Real, Real)>| h.map(|(a, b)| (a.to_bits(), b.to_bits()));
        prop_assert_eq!(
            bits(b.hit(&r, range.0, range.1)),
            bits(hit_axis_by_axis(&b, &r, range.0, range.1)),
            "{:?} {:?} {:?}", b, r, range
        );
    }
}
