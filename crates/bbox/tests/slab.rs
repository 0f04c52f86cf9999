//! Hard cases of the slab test, one named test each.
//!
//! The box is closed (faces belong to it) and the answer is conservative:
//! a true touch is never culled, the exit may be a hair late.

use crate::support::{checked_hit, unit, v, widened, SplitMix64, INF};
use gridrt_bbox::{Aabb, Ray, Real, Vec3};

// ---- Direction components of +0.0 and -0.0 -------------------------------

#[test]
fn parallel_to_slab_inside_hits_with_either_zero_sign() {
    for zero in [0.0, -0.0 as Real] {
        let r = Ray::new(v(-1.0, 0.5, 0.5), v(1.0, zero, zero));
        let h = checked_hit(&unit(), &r, 0.0, INF);
        let (t0, t1) = h.unwrap_or_else(|| panic!("miss with zero = {zero:?}"));
        assert_eq!(t0, 1.0);
        assert!(t1 >= 2.0 && t1 <= widened(2.0));
    }
}

#[test]
fn parallel_to_slab_outside_misses_with_either_zero_sign() {
    for zero in [0.0, -0.0 as Real] {
        for y in [-0.5, 1.5 as Real] {
            let r = Ray::new(v(-1.0, y, 0.5), v(1.0, zero, 0.0));
            assert_eq!(
                checked_hit(&unit(), &r, 0.0, INF),
                None,
                "y = {y}, zero = {zero:?}"
            );
        }
    }
}

#[test]
fn parallel_on_all_three_axes_is_a_point_query() {
    for zero in [0.0, -0.0 as Real] {
        let still = Vec3::splat(zero);
        let inside = Ray::new(v(0.5, 0.5, 0.5), still);
        assert_eq!(checked_hit(&unit(), &inside, 0.0, 7.0), Some((0.0, 7.0)));
        let outside = Ray::new(v(0.5, 0.5, 1.5), still);
        assert_eq!(checked_hit(&unit(), &outside, 0.0, 7.0), None);
    }
}

// ---- Origin exactly on a slab plane with a zero direction component ------
// Computing (plane - origin) · (1 / ±0) would give 0 · ±∞ = NaN.

#[test]
fn ray_lying_in_min_face_hits() {
    for zx in [0.0, -0.0 as Real] {
        for ox in [0.0, -0.0 as Real] {
            let r = Ray::new(v(ox, 0.5, -1.0), v(zx, 0.0, 1.0));
            let (t0, t1) = checked_hit(&unit(), &r, 0.0, INF)
                .unwrap_or_else(|| panic!("origin.x = {ox:?}, dir.x = {zx:?}"));
            assert_eq!(t0, 1.0);
            assert!(t1 >= 2.0 && t1 <= widened(2.0));
        }
    }
}

#[test]
fn ray_lying_in_max_face_hits() {
    for zy in [0.0, -0.0 as Real] {
        let r = Ray::new(v(3.0, 1.0, 0.25), v(-1.0, zy, 0.0));
        let (t0, t1) = checked_hit(&unit(), &r, 0.0, INF).expect("ray in face y = 1");
        assert_eq!(t0, 2.0);
        assert!(t1 >= 3.0 && t1 <= widened(3.0));
    }
}

#[test]
fn ray_lying_along_an_edge_hits() {
    // Origin on the planes x = 1 and y = 0, moving along z only.
    for (zx, zy) in [(0.0, 0.0), (-0.0, 0.0), (0.0, -0.0), (-0.0, -0.0 as Real)] {
        let r = Ray::new(v(1.0, 0.0, 2.0), v(zx, zy, -1.0));
        let (t0, _) = checked_hit(&unit(), &r, 0.0, INF).expect("ray along an edge");
        assert_eq!(t0, 1.0);
    }
}

#[test]
fn ray_in_face_plane_but_outside_face_misses() {
    for zero in [0.0, -0.0 as Real] {
        // In the plane x = 0, beside the face (y = 1.5), moving along z.
        let r = Ray::new(v(0.0, 1.5, -1.0), v(zero, zero, 1.0));
        assert_eq!(checked_hit(&unit(), &r, 0.0, INF), None);
        // In the plane x = 1, beside the face (y = -0.5), moving along y away.
        let r = Ray::new(v(1.0, -0.5, 0.5), v(zero, -1.0, zero));
        assert_eq!(checked_hit(&unit(), &r, 0.0, INF), None);
        // In the plane z = 0, level with the face, moving along x past it.
        let r = Ray::new(v(-1.0, 2.0, 0.0), v(1.0, zero, zero));
        assert_eq!(checked_hit(&unit(), &r, 0.0, INF), None);
    }
}

// ---- Origin exactly on the min and the max face ---------------------------

#[test]
fn origin_on_min_face_pointing_in() {
    let r = Ray::new(v(0.0, 0.5, 0.5), v(1.0, 0.0, 0.0));
    let (t0, t1) = checked_hit(&unit(), &r, 0.0, INF).expect("from the min face inwards");
    assert_eq!(t0, 0.0);
    assert!(t1 >= 1.0 && t1 <= widened(1.0));
}

#[test]
fn origin_on_min_face_pointing_out_touches_at_zero() {
    let r = Ray::new(v(0.0, 0.5, 0.5), v(-1.0, 0.0, 0.0));
    // The origin is in the closed box, so t = 0 is a hit, and nothing after.
    let (t0, t1) = checked_hit(&unit(), &r, 0.0, INF).expect("touch at t = 0");
    assert_eq!((t0, t1), (0.0, 0.0));
    assert_eq!(checked_hit(&unit(), &r, 1e-3, INF), None);
}

#[test]
fn origin_on_max_face_pointing_in() {
    let r = Ray::new(v(0.5, 0.5, 1.0), v(0.0, 0.0, -0.5));
    let (t0, t1) = checked_hit(&unit(), &r, 0.0, INF).expect("from the max face inwards");
    assert_eq!(t0, 0.0);
    assert!(t1 >= 2.0 && t1 <= widened(2.0));
}

#[test]
fn origin_on_max_face_pointing_out_touches_at_zero() {
    let r = Ray::new(v(0.5, 0.5, 1.0), v(0.0, 0.0, 2.0));
    let (t0, t1) = checked_hit(&unit(), &r, 0.0, INF).expect("touch at t = 0");
    assert_eq!((t0, t1), (0.0, 0.0));
    assert_eq!(checked_hit(&unit(), &r, 1e-3, INF), None);
    // Backwards along the ray (negative t) it does cross the box.
    let (t0, t1) = checked_hit(&unit(), &r, -INF, INF).expect("crossing at negative t");
    assert_eq!(t0, -0.5);
    assert_eq!(t1, 0.0);
}

// ---- A ray from inside always hits, entering at t_min ----------------------

#[test]
fn ray_from_inside_hits_with_t_enter_equal_to_t_min() {
    let b = Aabb::new(v(-1.0, -2.0, -3.0), v(4.0, 5.0, 6.0));
    let mut rng = SplitMix64(1);
    let dirs = [
        v(1.0, 0.0, 0.0),
        v(-0.0, -1.0, 0.0),
        v(0.0, -0.0, -1.0),
        v(1.0, -1.0, 1.0),
        v(1e-30, -1e-30, 3.0),
    ];
    for i in 0..2_000 {
        let o = v(
            rng.range(-1.0, 4.0),
            rng.range(-2.0, 5.0),
            rng.range(-3.0, 6.0),
        );
        let d = if i < dirs.len() {
            dirs[i]
        } else {
            v(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            )
        };
        let r = Ray::new(o, d);
        for t_min in [0.0, 1e-6 as Real] {
            let (t0, _) = checked_hit(&b, &r, t_min, INF)
                .unwrap_or_else(|| panic!("inside ray missed: {r:?}, t_min = {t_min}"));
            assert_eq!(t0, t_min, "{r:?}");
        }
    }
}

// ---- Empty boxes ----------------------------------------------------------

#[test]
fn empty_boxes_always_miss() {
    let boxes = [
        Aabb::EMPTY,
        // Inverted on x only; wide on y and z.
        Aabb::new(v(1.0, -10.0, -10.0), v(0.0, 10.0, 10.0)),
        // Inverted on z only, by one ulp.
        Aabb::new(v(0.0, 0.0, 1.0), v(1.0, 1.0, 1.0 - Real::EPSILON / 2.0)),
    ];
    let rays = [
        Ray::new(v(0.5, 0.5, -5.0), v(0.0, 0.0, 1.0)),
        Ray::new(v(-5.0, 0.5, 0.5), v(1.0, 0.0, 0.0)),
        Ray::new(v(0.5, 0.5, 0.5), v(1.0, 1.0, 1.0)),
        Ray::new(v(0.5, 0.5, 1.0), v(0.0, 0.0, 0.0)),
        Ray::new(v(-3.0, -3.0, -3.0), v(1.0, 1.0, 1.0)),
    ];
    for b in &boxes {
        assert!(b.is_empty());
        for r in &rays {
            assert_eq!(checked_hit(b, r, -INF, INF), None, "{b:?} {r:?}");
        }
    }
}

// ---- Zero-thickness boxes -------------------------------------------------

#[test]
fn flat_box_is_hit_by_a_crossing_ray() {
    let flat = Aabb::new(v(0.0, 0.0, 0.5), v(1.0, 1.0, 0.5));
    let r = Ray::new(v(0.25, 0.75, -1.0), v(0.0, 0.0, 1.0));
    let (t0, t1) = checked_hit(&flat, &r, 0.0, INF).expect("crossing a flat box");
    assert_eq!(t0, 1.5);
    assert!(t1 >= 1.5 && t1 <= widened(1.5));
    // A slanted ray whose crossing is not exact in binary.
    let r = Ray::new(v(0.1, 0.2, 0.3), v(0.3, 0.1, 0.7));
    assert!(checked_hit(&flat, &r, 0.0, INF).is_some());
    // From the other side, going away: miss.
    let r = Ray::new(v(0.25, 0.75, 1.0), v(0.0, 0.0, 1.0));
    assert_eq!(checked_hit(&flat, &r, 0.0, INF), None);
}

#[test]
fn point_box_is_hit_by_a_ray_through_it() {
    let p = v(1.0, 2.0, 3.0);
    let r = Ray::new(Vec3::ZERO, p);
    let (t0, t1) = checked_hit(&Aabb::new(p, p), &r, 0.0, INF).expect("through the point");
    assert_eq!(t0, 1.0);
    assert!(t1 >= 1.0 && t1 <= widened(1.0));
}

#[test]
fn point_boxes_at_inexact_positions_are_hit() {
    // The ray passes exactly through p at t = 1 (dir = p − 0), but each axis
    // computes p·(1/p) with its own rounding: only the widening makes all
    // three agree on a non-empty interval.
    let mut rng = SplitMix64(2);
    for _ in 0..20_000 {
        let p = v(
            rng.range(0.1, 10.0),
            rng.range(0.1, 10.0),
            rng.range(0.1, 10.0),
        );
        let r = Ray::new(Vec3::ZERO, p);
        let (t0, t1) =
            checked_hit(&Aabb::new(p, p), &r, 0.0, INF).unwrap_or_else(|| panic!("missed {p:?}"));
        assert!((t0 - 1.0).abs() <= 4.0 * Real::EPSILON && (t1 - 1.0).abs() <= 4.0 * Real::EPSILON);
    }
}

// ---- Large coordinates ------------------------------------------------------

#[test]
fn box_at_1e7_is_hit_from_far_away() {
    // At 1e7 the f32 spacing is 1, so the box [1e7, 1e7 + 1]³ is one ulp wide.
    let lo = 1.0e7 as Real;
    let b = Aabb::new(Vec3::splat(lo), Vec3::splat(lo + 1.0));
    // This ray passes exactly through the centre (1e7 + 0.5)³ at t = 2e6 + 0.5;
    // every input below is exact in f32.
    let r = Ray::new(v(3_999_999.0, 5_999_999.5, 8_000_000.0), v(3.0, 2.0, 1.0));
    let (t0, t1) = checked_hit(&b, &r, 0.0, INF).expect("slanted ray from 6e6 away");
    assert!(t0.is_finite() && t1.is_finite() && t0 <= t1);
    assert!(t0 <= 2_000_000.5 && 2_000_000.5 <= t1, "({t0}, {t1})");
    // Along the main diagonal from −1e7: enters at the corner lo at t = 2e7.
    let r = Ray::new(Vec3::splat(-lo), Vec3::ONE);
    let (t0, t1) = checked_hit(&b, &r, 0.0, INF).expect("diagonal from -1e7");
    assert!(t0.is_finite() && t1.is_finite() && t0 <= t1);
    assert_eq!(t0, 2.0 * lo);
    assert!(t1 >= 2.0 * lo + 1.0);
    // And the same box is missed by a ray that passes 2 units beside it.
    let r = Ray::new(v(-lo, lo + 3.0, lo), v(1.0, 0.0, 0.0));
    assert_eq!(checked_hit(&b, &r, 0.0, INF), None);
}

// ---- t range edge cases -----------------------------------------------------

fn through_unit_z() -> Ray {
    // Inside the unit box for t in [1, 2].
    Ray::new(v(0.5, 0.5, -1.0), v(0.0, 0.0, 1.0))
}

#[test]
fn t_min_equal_t_max_inside_the_box_hits() {
    for t in [1.0, 1.5, 2.0 as Real] {
        assert_eq!(
            checked_hit(&unit(), &through_unit_z(), t, t),
            Some((t, t)),
            "t = {t}"
        );
    }
}

#[test]
fn t_min_equal_t_max_outside_the_box_misses() {
    for t in [0.0, 0.5, 0.999, 2.001, 3.0 as Real] {
        assert_eq!(
            checked_hit(&unit(), &through_unit_z(), t, t),
            None,
            "t = {t}"
        );
    }
}

#[test]
fn t_range_entirely_before_the_box_misses() {
    assert_eq!(checked_hit(&unit(), &through_unit_z(), 0.0, 0.99), None);
    assert_eq!(checked_hit(&unit(), &through_unit_z(), -INF, 0.5), None);
}

#[test]
fn t_range_entirely_after_the_box_misses() {
    assert_eq!(checked_hit(&unit(), &through_unit_z(), 2.01, INF), None);
    assert_eq!(checked_hit(&unit(), &through_unit_z(), 3.0, 4.0), None);
}

#[test]
fn reversed_t_range_misses() {
    assert_eq!(checked_hit(&unit(), &through_unit_z(), 1.75, 1.25), None);
}

// ---- Denormal and tiny direction components ----------------------------------

#[test]
fn denormal_direction_with_infinite_reciprocal_is_parallel() {
    // MIN_POSITIVE / 16 is denormal in f32 and f64 and 1 / it overflows.
    let tiny = Real::MIN_POSITIVE / 16.0;
    assert!(!tiny.is_normal() && (1.0 / tiny).is_infinite());
    for d in [tiny, -tiny] {
        let r = Ray::new(v(0.5, 0.5, -1.0), v(d, d, 1.0));
        let (t0, t1) = checked_hit(&unit(), &r, 0.0, INF).expect("crosses along z");
        assert_eq!(t0, 1.0);
        assert!(t1 >= 2.0 && t1 <= widened(2.0));
        let beside = Ray::new(v(1.5, 0.5, -1.0), v(d, d, 1.0));
        assert_eq!(checked_hit(&unit(), &beside, 0.0, INF), None);
    }
}

#[test]
fn denormal_direction_with_finite_reciprocal_never_gives_nan() {
    // MIN_POSITIVE / 2 is denormal but 1 / it is finite (≈ 1.7e38 in f32):
    // slab t values overflow to ±∞ and must stay ordered.
    let tiny = Real::MIN_POSITIVE / 2.0;
    assert!(!tiny.is_normal() && (1.0 / tiny).is_finite());
    let b = unit();
    for (ox, d) in [(-10.0, tiny), (10.0, -tiny), (10.0, tiny), (-10.0, -tiny)] {
        let r = Ray::new(v(ox, 0.5, 0.5), v(d, 0.0, 0.0));
        for t_max in [1.0, 1e30, INF] {
            let _ = checked_hit(&b, &r, 0.0, t_max);
        }
    }
}

#[test]
fn tiny_direction_moving_away_from_box_misses() {
    // Regression: with the box behind, both x-slab t values overflow to −∞,
    // and the old widening `far + |far|·w` turned −∞ into NaN, which the
    // comparisons skipped: a false hit.
    let tiny = Real::MIN_POSITIVE / 2.0;
    let r = Ray::new(v(10.0, 0.5, 0.5), v(tiny, 0.0, 0.0));
    assert_eq!(checked_hit(&unit(), &r, 0.0, INF), None);
    let r = Ray::new(v(-10.0, 0.5, 0.5), v(-tiny, 1.0, 0.0));
    assert_eq!(checked_hit(&unit(), &r, 0.0, INF), None);
}

#[test]
fn tiny_direction_towards_box_reaches_it_only_beyond_finite_t() {
    // The true entry is at t = 10 / tiny, beyond the largest finite Real.
    let tiny = Real::MIN_POSITIVE / 2.0;
    let r = Ray::new(v(-10.0, 0.5, 0.5), v(tiny, 0.0, 0.0));
    assert_eq!(checked_hit(&unit(), &r, 0.0, Real::MAX), None);
    assert_eq!(checked_hit(&unit(), &r, 0.0, INF), Some((INF, INF)));
}

// ---- Conservative widening ----------------------------------------------------

/// A box whose corner `c = s·d` the ray `0 + t·d` touches exactly at t = s:
/// the ray leaves the x slab where it enters the y and z slabs.
fn corner_touch(d: Vec3, s: Real) -> (Aabb, Ray) {
    let c = d * s; // exact: s is a power of two
    let b = Aabb::new(v(-1.0, c.y, c.z), v(c.x, c.y + 1.0, c.z + 1.0));
    (b, Ray::new(Vec3::ZERO, d))
}

#[test]
fn grazing_corner_where_exit_equals_entry_hits() {
    let mut rng = SplitMix64(3);
    for i in 0..20_000 {
        let d = v(
            rng.range(0.1, 10.0),
            rng.range(0.1, 10.0),
            rng.range(0.1, 10.0),
        );
        let s = (1u32 << (i % 8)) as Real;
        let (b, r) = corner_touch(d, s);
        let (t0, t1) = checked_hit(&b, &r, 0.0, INF)
            .unwrap_or_else(|| panic!("grazing corner culled: d = {d:?}, s = {s}"));
        let tol = 4.0 * Real::EPSILON * s;
        assert!(
            (t0 - s).abs() <= tol && (t1 - s).abs() <= tol,
            "({t0}, {t1}) vs {s}"
        );
    }
}

#[test]
fn grazing_edge_where_exit_equals_entry_hits() {
    // As above but the ray is parallel to z and lies within the z slab.
    let mut rng = SplitMix64(4);
    for _ in 0..20_000 {
        let d = v(rng.range(0.1, 10.0), rng.range(0.1, 10.0), 0.0);
        let c = d * 4.0;
        let b = Aabb::new(v(-1.0, c.y, -1.0), v(c.x, c.y + 1.0, 1.0));
        let r = Ray::new(Vec3::ZERO, d);
        assert!(
            checked_hit(&b, &r, 0.0, INF).is_some(),
            "grazing edge culled: d = {d:?}"
        );
    }
}

#[test]
fn a_clear_gap_is_still_a_miss() {
    // The widening is tiny: moving the grazing box by 1e-3 of its distance
    // turns the touch into a miss.
    let mut rng = SplitMix64(5);
    for _ in 0..2_000 {
        let d = v(
            rng.range(0.1, 10.0),
            rng.range(0.1, 10.0),
            rng.range(0.1, 10.0),
        );
        let (mut b, r) = corner_touch(d, 1.0);
        b.min.y += 1e-3 * d.y;
        assert_eq!(checked_hit(&b, &r, 0.0, INF), None, "d = {d:?}");
    }
}

// ---- The interval is never NaN ------------------------------------------------

#[test]
fn interval_is_never_nan_over_special_values() {
    // Every combination of awkward origin and direction components against a
    // box with faces on 0 and 1: origins on the planes, zeros of both signs,
    // denormals, huge and infinite directions.
    let tiny = Real::MIN_POSITIVE / 2.0;
    let tinier = Real::MIN_POSITIVE / 16.0;
    let origins = [-1.0, -0.0, 0.0, 0.5, 1.0, 2.0, 1e7 as Real];
    let dirs = [-1.0, -0.0, 0.0, 1.0, tiny, -tinier, 1e30, Real::MAX, INF];
    let boxes = [
        unit(),
        Aabb::new(Vec3::ZERO, v(1.0, 0.0, 1.0)),
        Aabb::new(Vec3::ONE, Vec3::ONE),
    ];
    let ranges = [(0.0, INF), (-INF, INF), (0.5, 0.5), (0.0, 1.0)];
    let mut hits = 0usize;
    for b in &boxes {
        for &ox in &origins {
            for &oy in &origins {
                for &oz in &origins {
                    for &dx in &dirs {
                        for &dy in &dirs {
                            for &dz in &dirs {
                                let r = Ray::new(v(ox, oy, oz), v(dx, dy, dz));
                                for &(t_min, t_max) in &ranges {
                                    hits += usize::from(checked_hit(b, &r, t_min, t_max).is_some());
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(hits > 0);
}
