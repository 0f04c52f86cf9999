use crate::{Accelerator, Counters, Hit, NoCounters, Primitive};
use gridrt_bbox::{Ray, Real};

/// The baseline: every query tests every primitive, in index order.
///
/// It is the ground truth the grid is tested against and the "exhaustive"
/// column of the speed-up table. The loop is kept plain and tight so that the
/// comparison is fair.
///
/// ```
/// use gridrt_grid::{Aabb, Accelerator, Exhaustive, PrimHit, Primitive, Ray, Real, Vec3};
///
/// /// A sphere at `c` with radius `r` (just enough for the example).
/// struct Ball(Vec3, Real);
/// impl Primitive for Ball {
///     type Shared = ();
///     type RayData = ();
///     type Four = ();
///     fn ray_data(_: &Ray) {}
///     fn bounds(&self, _: &()) -> Aabb {
///         Aabb::new(self.0 - Vec3::splat(self.1), self.0 + Vec3::splat(self.1))
///     }
///     fn closest_hit(&self, _: &(), ray: &Ray, _: &(), t0: Real, t1: Real) -> Option<PrimHit> {
///         let oc = ray.origin - self.0;
///         let (a, b, c) = (ray.dir.dot(ray.dir), oc.dot(ray.dir), oc.dot(oc) - self.1 * self.1);
///         let disc = b * b - a * c;
///         if disc < 0.0 { return None; }
///         let t = (-b - disc.sqrt()) / a;
///         (t0..=t1).contains(&t).then_some(PrimHit::new(t, 0.0, 0.0))
///     }
/// }
///
/// let acc = Exhaustive::new(vec![Ball(Vec3::new(0.0, 0.0, -5.0), 1.0), Ball(Vec3::new(0.0, 0.0, -3.0), 1.0)]);
/// let hit = acc.closest_hit(&Ray::new(Vec3::ZERO, -Vec3::Z), 0.0, Real::INFINITY, &mut ()).unwrap();
/// assert_eq!((hit.prim, hit.t), (1, 2.0));
/// ```
#[derive(Clone, Debug)]
pub struct Exhaustive<P: Primitive> {
    prims: Vec<P>,
    shared: P::Shared,
}

/// Primitives per call of [`Primitive::closest_hits`].
const BLOCK: usize = 64;

/// The references of a block: its primitives in order.
static IOTA: [u32; BLOCK] = {
    let mut a = [0; BLOCK];
    let mut i = 0;
    while i < BLOCK {
        a[i] = i as u32;
        i += 1;
    }
    a
};

impl<P: Primitive> Exhaustive<P> {
    /// Wraps the primitives; nothing is built.
    #[must_use]
    pub fn new(prims: Vec<P>) -> Self
    where
        P::Shared: Default,
    {
        Self::with_shared(prims, P::Shared::default())
    }

    /// Wraps the primitives and what they share ([`Primitive::Shared`]).
    #[must_use]
    pub fn with_shared(prims: Vec<P>, shared: P::Shared) -> Self {
        Self { prims, shared }
    }

    /// Gives the primitives back.
    #[must_use]
    pub fn into_primitives(self) -> Vec<P> {
        self.prims
    }

    /// [`Accelerator::closest_hit`] that also reports its tests to
    /// `counters` (one per primitive; no cells), for the "tests per ray"
    /// column beside the grid's [`crate::Grid::closest_hit_counted`].
    #[inline]
    pub fn closest_hit_counted<C: Counters>(
        &self,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
        counters: &mut C,
    ) -> Option<Hit> {
        counters.ray();
        if !(t_min <= t_max) {
            return None;
        }
        let data = P::ray_data(ray);
        let mut best: Option<Hit> = None;
        let mut t_far = t_max;
        // Blocks of primitives, each tested through `Primitive::closest_hits`
        // (SIMD where the primitive offers it), with references 0, 1, 2, ….
        for (b, block) in self.prims.chunks(BLOCK).enumerate() {
            counters.tests(block.len());
            let base = (b * BLOCK) as u32;
            let limit = t_far;
            P::closest_hits(
                block,
                &self.shared,
                &IOTA[..block.len()],
                ray,
                &data,
                t_min,
                limit,
                crate::NO_SLOT,
                &mut |r, h| {
                    // Strictly nearer only: on a tie in t the earlier (lower) index stays.
                    if best.is_none_or(|b| h.t < b.t) {
                        best = Some(Hit::new(h, base + r, base + r));
                        t_far = h.t;
                    }
                    t_far
                },
            );
        }
        best
    }

    /// [`Accelerator::any_hit`] that also reports its tests to `counters`.
    #[inline]
    pub fn any_hit_counted<C: Counters>(
        &self,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
        counters: &mut C,
    ) -> bool {
        counters.ray();
        if !(t_min <= t_max) {
            return false;
        }
        // Blocks as in `closest_hit_counted`, through `Primitive::any_hits`.
        let data = P::ray_data(ray);
        self.prims.chunks(BLOCK).any(|block| {
            counters.tests(block.len());
            P::any_hits(
                block,
                &self.shared,
                &IOTA[..block.len()],
                ray,
                &data,
                t_min,
                t_max,
            )
        })
    }
}

impl<P: Primitive> Accelerator for Exhaustive<P> {
    type Prim = P;
    type Scratch = ();

    fn scratch(&self) {}

    fn primitives(&self) -> &[P] {
        &self.prims
    }

    fn shared(&self) -> &P::Shared {
        &self.shared
    }

    fn primitive_id(&self, slot: u32) -> u32 {
        slot
    }

    /// The nearest hit over all primitives; an empty or NaN range gives `None`.
    #[inline]
    fn closest_hit(&self, ray: &Ray, t_min: Real, t_max: Real, _: &mut ()) -> Option<Hit> {
        self.closest_hit_counted(ray, t_min, t_max, &mut NoCounters)
    }

    /// Whether any primitive is hit; an empty or NaN range gives `false`.
    #[inline]
    fn any_hit(&self, ray: &Ray, t_min: Real, t_max: Real, _: &mut ()) -> bool {
        self.any_hit_counted(ray, t_min, t_max, &mut NoCounters)
    }
}
