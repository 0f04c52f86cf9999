//! The walk's set-up in lanes against the one axis at a time.

use super::*;
use gridrt_bbox::{Aabb, Vec3};
use proptest::prelude::*;

/// Every field of the walk's state, floats by their bits (so `−0.0` and
/// `+0.0`, or two NaNs, are told apart as they would act).
fn state(d: &Dda<'_>) -> impl PartialEq + std::fmt::Debug {
    (
        d.next,
        d.base,
        d.dir,
        d.org.map(Real::to_bits),
        d.inv.map(Real::to_bits),
        d.idx,
        d.neg,
        d.t_next.map(Real::to_bits),
        d.t_enter.to_bits(),
        d.t_end.to_bits(),
    )
}

/// Whether the lanes' start, where it answers, equals the exact start;
/// `Some(true)` when it answered.
fn lanes_agree(g: &Geom, ray: &Ray) -> Option<bool> {
    let (t0, t1) = g.entry.hit(ray, 0.0, Real::INFINITY)?;
    let exact = Dda::start_exact(g, ray, t0, t1);
    let lanes = Dda::start_lanes(g, ray, t0, t1);
    if let Some(l) = &lanes {
        assert_eq!(state(l), state(&exact), "ray {ray:?}");
    }
    Some(lanes.is_some())
}

/// A direction component: random, or one of the hard values (zeros of
/// both signs, a denormal whose reciprocal overflows, a tiny one).
fn component() -> impl Strategy<Value = Real> {
    prop_oneof![
        6 => -1.0 as Real..1.0,
        1 => Just(0.0 as Real),
        1 => Just(-0.0 as Real),
        1 => Just(Real::MIN_POSITIVE / 4.0),
        1 => Just(-1e-30 as Real),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// On boxes near and far from the origin, with one cell or many per
    /// axis, rays from inside and outside, aimed at random points or at
    /// cell planes (where the entry point's rounding decides the cell),
    /// the set-up in lanes gives the exact start whenever it answers.
    #[test]
    fn lanes_start_equals_exact_start(
        offset in prop_oneof![Just(0.0 as Real), -1e5 as Real..1e5],
        size in proptest::array::uniform3(1e-3 as Real..100.0),
        dims in proptest::array::uniform3(1u32..40),
        rays in proptest::collection::vec(
            (
                proptest::array::uniform3(-2.0 as Real..3.0),
                proptest::array::uniform3(component()),
                proptest::array::uniform3(0.0 as Real..1.0),
                0usize..4,
            ),
            1..48,
        ),
    ) {
        let min = Vec3::splat(offset);
        let g = Geom::new(Aabb::new(min, min + Vec3::from_array(size)), dims);
        let at = |u: [Real; 3]| min + Vec3::from_array(size) * Vec3::from_array(u);
        for (from, dir, to, plane_axis) in rays {
            let origin = at(from);
            let mut target = at(to);
            if plane_axis < 3 {
                // Onto the nearest cell plane of that axis.
                let planes = &g.planes[plane_axis];
                let k = ((to[plane_axis] * dims[plane_axis] as Real) as usize).min(planes.len() - 1);
                target[plane_axis] = planes[k];
            }
            let aim = target - origin;
            let d = Vec3::from_array(std::array::from_fn(|a| {
                if dir[a] == 0.0 || dir[a].abs() < 1e-20 { dir[a] } else { aim[a] + dir[a] * 1e-3 }
            }));
            let _ = lanes_agree(&g, &Ray::new(origin, d));
        }
    }
}

/// The lanes answer for most rays: the exact start is the exception.
#[test]
fn lanes_start_answers_most_rays() {
    let g = Geom::new(Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)), [30, 20, 10]);
    let mut s = 7u64;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 40) as Real / (1u64 << 24) as Real * 2.0 - 1.0
    };
    let (mut entered, mut answered) = (0, 0);
    for _ in 0..10_000 {
        let origin = Vec3::new(next(), next(), next()) * 3.0;
        let ray = Ray::new(origin, Vec3::new(next(), next(), next()) - origin);
        if let Some(lanes) = lanes_agree(&g, &ray) {
            entered += 1;
            answered += usize::from(lanes);
        }
    }
    assert!(
        entered > 1000 && answered * 10 > entered * 9,
        "{answered} of {entered}"
    );
}
