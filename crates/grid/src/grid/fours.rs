//! A direct grid's primitives packed four by four ([`Primitive::Four`]):
//! a grid without cells tests every primitive for every ray that meets its
//! box, and with the primitives laid out coordinate by coordinate in lanes
//! the test of four reads four rows instead of gathering four primitives
//! and transposing them.

use super::query::{prim_id, Closest};
use crate::counters::Counters;
use crate::{Hit, Primitive};
use gridrt_bbox::{Ray, Real};

/// `refs` (slots of `prims`) packed four by four, in order; the last four
/// may hold fewer.
pub(super) fn pack_fours<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    refs: &[u32],
) -> Box<[P::Four]> {
    refs.chunks(4)
        .map(|c| {
            P::pack_four(
                std::array::from_fn(|k| c.get(k).map(|&r| &prims[r as usize])),
                shared,
            )
        })
        .collect()
}

/// The slots of `refs` (at most four, packed in `four`) that the
/// packing's rejection ([`Primitive::four_may_hit`]) keeps, in order.
#[inline(always)]
fn kept<'a, P: Primitive>(
    four: &P::Four,
    ray: &Ray,
    data: &P::RayData,
    refs: &'a [u32],
) -> impl Iterator<Item = u32> + 'a {
    let mut pass = P::four_may_hit(four, ray, data) & ((1u32 << refs.len().min(4)) - 1);
    std::iter::from_fn(move || {
        (pass != 0).then(|| {
            let r = refs[pass.trailing_zeros() as usize];
            pass &= pass - 1;
            r
        })
    })
}

impl<P: Primitive, C: Counters, const MB: bool> Closest<'_, P, C, MB> {
    /// Tests the slots `refs`, packed four by four in `fours`
    /// ([`pack_fours`]): the fours' rejection, then the primitive test of
    /// each one it keeps, against the best hit so far.
    #[inline(always)]
    pub(super) fn test_fours(&mut self, fours: &[P::Four], refs: &[u32]) {
        self.counters.tests(refs.len());
        for (four, chunk) in fours.iter().zip(refs.chunks(4)) {
            for r in kept::<P>(four, self.ray, self.data, chunk) {
                // The body of `Closest::test` without its count, written out:
                // a helper shared with `test` compiled to 10% more
                // instructions on the Cornell box's camera rays.
                // SAFETY: every stored reference is a valid index into
                // `prims` (checked by `check_invariants`).
                let prim = unsafe { self.prims.get_unchecked(r as usize) };
                if let Some(h) =
                    prim.closest_hit(self.shared, self.ray, self.data, self.t_min, self.t_lim)
                {
                    self.keep(Hit::new(h, prim_id(self.ids, r), r));
                }
            }
        }
    }
}

/// Whether the ray hits any of the slots `refs`, packed four by four in
/// `fours` ([`pack_fours`]), within `[t_min, t_max]`.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // the primitives, what they share, their packing and the query
pub(super) fn any_in_fours<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    fours: &[P::Four],
    refs: &[u32],
    ray: &Ray,
    data: &P::RayData,
    t_min: Real,
    t_max: Real,
) -> bool {
    fours.iter().zip(refs.chunks(4)).any(|(four, chunk)| {
        kept::<P>(four, ray, data, chunk)
            .any(|r| prims[r as usize].any_hit(shared, ray, data, t_min, t_max))
    })
}
