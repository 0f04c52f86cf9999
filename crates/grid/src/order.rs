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
///     fn ray_data(_: &Ray) {}
///     fn bounds(&self, _: &()) -> Aabb { Aabb::new(self.0, self.0) }
///     fn closest_hit(&self, _: &(), _: &Ray, _: &(), _: Real, _: Real) -> Option<PrimHit> { None }
/// }
/// let dots = [Dot(Vec3::ONE), Dot(Vec3::ZERO), Dot(Vec3::new(1.0, 0.0, 0.0))];
/// assert_eq!(spatial_order(&dots, &()), vec![1, 2, 0]);
/// ```
#[must_use]
pub fn spatial_order<P: Primitive>(prims: &[P], shared: &P::Shared) -> Vec<u32> {
    let boxes: Vec<Aabb> = prims.iter().map(|p| p.bounds(shared)).collect();
    let scene = boxes
        .iter()
        .filter(|b| crate::geom::is_gridded(b))
        .fold(Aabb::EMPTY, |a, b| a.union(*b));
    let ext = scene.extent();
    let scale = ext.max_element();
    let mut keyed: Vec<(u64, u32)> = boxes
        .iter()
        .enumerate()
        .map(|(i, b)| {
            if !crate::geom::is_gridded(b) {
                return (u64::MAX, i as u32);
            }
            let q = if scale > 0.0 {
                (b.centroid() - scene.min) / scale * 1023.0
            } else {
                b.centroid() * 0.0
            };
            let c = |x: gridrt_bbox::Real| x.clamp(0.0, 1023.0) as u32;
            (crate::morton::encode3(c(q.x), c(q.y), c(q.z)), i as u32)
        })
        .collect();
    keyed.sort_by_key(|k| k.0);
    keyed.into_iter().map(|k| k.1).collect()
}
