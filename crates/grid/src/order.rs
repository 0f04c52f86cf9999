//! A spatial order for primitives, for callers that may reorder their scene.

use crate::Primitive;
use gridrt_bbox::Aabb;

/// A permutation of `0..prims.len()` (which refer to `shared`) that visits the primitives in Morton
/// (Z-curve) order of their box centres, 10 bits per axis over the scene's
/// box; primitives with non-finite boxes come last, in their original order.
///
/// The grid stores its own primitives in cell order, but hit indices stay
/// the caller's, so whatever the caller keeps per primitive (colours,
/// materials) is still read in the scene's order; a scene whose primitives
/// come in random order (as Suffern's random spheres do) makes those reads
/// likely cache misses once the scene outgrows the cache. Reordering the
/// scene in this order (and remapping what the caller keeps per primitive)
/// makes neighbours in space neighbours in memory there too.
///
/// ```
/// use gridrt_grid::{spatial_order, Aabb, PrimHit, Primitive, Ray, Real, Vec3};
/// struct Dot(Vec3);
/// impl Primitive for Dot {
///     type Shared = ();
///     type RayData = ();
///     type Four = ();
///     fn ray_data(_: &Ray) {}
///     fn bounds(&self, _: &()) -> Aabb { Aabb::new(self.0, self.0) }
///     fn closest_hit(&self, _: &(), _: &Ray, _: &(), _: Real, _: Real) -> Option<PrimHit> { None }
/// }
/// let dots = [Dot(Vec3::ONE), Dot(Vec3::ZERO), Dot(Vec3::new(1.0, 0.0, 0.0))];
/// assert_eq!(spatial_order(&dots, &()), vec![1, 2, 0]);
/// ```
#[must_use]
pub fn spatial_order<P: Primitive>(prims: &[P], shared: &P::Shared) -> Vec<u32> {
    spatial_order_iter(prims, shared).collect()
}

/// [`spatial_order`] as it is read, for callers that go through it once:
/// it holds one sorted 8-byte key per primitive and no second array, where
/// `spatial_order` briefly needs both (12 bytes a primitive at the peak).
pub fn spatial_order_iter<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
) -> impl ExactSizeIterator<Item = u32> {
    // The boxes are computed twice rather than stored: the order is for
    // large scenes, whose peak memory it should not raise.
    let scene = prims
        .iter()
        .map(|p| p.bounds(shared))
        .filter(crate::geom::is_gridded)
        .fold(Aabb::EMPTY, |a, b| a.union(b));
    let scale = scene.extent().max_element();
    // The Morton code (30 bits) above the index: sorting the pairs as
    // numbers orders by code, then index, with no buffer of its own.
    let mut keyed: Vec<u64> = prims
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let b = p.bounds(shared);
            let code = if !crate::geom::is_gridded(&b) {
                u32::MAX
            } else {
                let q = if scale > 0.0 {
                    (b.centroid() - scene.min) / scale * 1023.0
                } else {
                    b.centroid() * 0.0
                };
                let c = |x: gridrt_bbox::Real| x.clamp(0.0, 1023.0) as u32;
                crate::morton::encode3(c(q.x), c(q.y), c(q.z)) as u32
            };
            (u64::from(code) << 32) | i as u64
        })
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|k| k as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{PrimHit, Ray, Real, Vec3};
    use proptest::prelude::*;

    #[derive(Debug)]
    struct Dot(Vec3);

    impl Primitive for Dot {
        type Shared = ();
        type RayData = ();
        type Four = ();
        fn ray_data(_: &Ray) {}
        fn bounds(&self, _: &()) -> Aabb {
            Aabb::new(self.0, self.0)
        }
        fn closest_hit(&self, _: &(), _: &Ray, _: &(), _: Real, _: Real) -> Option<PrimHit> {
            None
        }
    }

    proptest! {
        /// The order is a permutation that sorts by the Morton code of
        /// the quantised centre, ties and unplaceable (NaN) dots in their
        /// given order, the latter last.
        #[test]
        fn sorts_by_code_then_index(
            dots in prop::collection::vec(
                (0u8..8, 0u8..8, 0u8..8, prop::bool::weighted(0.1)),
                0..200,
            ),
        ) {
            let dots: Vec<Dot> = dots
                .iter()
                .map(|&(x, y, z, nan)| {
                    let p = Vec3::new(x.into(), y.into(), z.into());
                    Dot(if nan { Vec3::NAN } else { p })
                })
                .collect();
            let order = spatial_order(&dots, &());
            let mut seen = order.clone();
            seen.sort_unstable();
            prop_assert_eq!(seen, (0..dots.len() as u32).collect::<Vec<_>>());
            let scale = dots
                .iter()
                .filter(|d| !d.0.is_nan())
                .fold(Aabb::EMPTY, |a, d| a.union(d.bounds(&())));
            let key = |i: u32| {
                let p = dots[i as usize].0;
                if p.is_nan() {
                    return (u64::MAX, i);
                }
                let q = (p - scale.min) / scale.extent().max_element().max(Real::MIN_POSITIVE)
                    * 1023.0;
                let c = |x: Real| x.clamp(0.0, 1023.0) as u32;
                (crate::morton::encode3(c(q.x), c(q.y), c(q.z)), i)
            };
            for w in order.windows(2) {
                prop_assert!(key(w[0]) < key(w[1]), "{:?} before {:?}", key(w[0]), key(w[1]));
            }
        }
    }
}
