use gridrt_bbox::{Aabb, Ray, Real};

/// What a primitive reports for one ray: the distance `t` along the ray and
/// two surface parameters (barycentrics `u`, `v` for triangles; whatever the
/// primitive finds useful otherwise, or zero).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimHit {
    /// Ray parameter of the hit, in units of `ray.dir`.
    pub t: Real,
    /// First surface parameter (triangles: barycentric of vertex 1).
    pub u: Real,
    /// Second surface parameter (triangles: barycentric of vertex 2).
    pub v: Real,
    /// Which part of a compound primitive was hit (the triangle of an
    /// instanced mesh); 0 for a simple primitive.
    pub part: u32,
}

impl PrimHit {
    /// The hit of a simple primitive (`part` 0).
    #[inline]
    #[must_use]
    pub const fn new(t: Real, u: Real, v: Real) -> Self {
        Self { t, u, v, part: 0 }
    }
}

/// The answer of an accelerator's closest-hit query: the primitive's hit,
/// the primitive's index (its place in the order the accelerator was given
/// the primitives) and its slot (its place in the accelerator's own storage,
/// [`Accelerator::primitives`]).
///
/// Two hits are equal when they name the same primitive at the same point:
/// the slot says where one accelerator keeps the primitive and is left out
/// of the comparison (a grid stores its primitives in cell order, the
/// exhaustive accelerator in the given order).
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Ray parameter of the hit, in units of `ray.dir`.
    pub t: Real,
    /// First surface parameter, as the primitive reported it.
    pub u: Real,
    /// Second surface parameter, as the primitive reported it.
    pub v: Real,
    /// The part of a compound primitive, as the primitive reported it.
    pub part: u32,
    /// Index of the primitive that was hit, in the order the accelerator
    /// was given the primitives.
    pub prim: u32,
    /// Where the accelerator stores that primitive:
    /// `accel.primitives()[slot]` is the primitive hit.
    pub slot: u32,
}

impl PartialEq for Hit {
    fn eq(&self, other: &Self) -> bool {
        (self.t, self.u, self.v, self.part, self.prim)
            == (other.t, other.u, other.v, other.part, other.prim)
    }
}

impl Hit {
    /// Combines a primitive's hit with the primitive's index and slot.
    #[inline]
    #[must_use]
    pub fn new(h: PrimHit, prim: u32, slot: u32) -> Self {
        Self {
            t: h.t,
            u: h.u,
            v: h.v,
            part: h.part,
            prim,
            slot,
        }
    }

    /// The primitive's own part of the hit (what it reported).
    #[inline]
    #[must_use]
    pub fn prim_hit(&self) -> PrimHit {
        PrimHit {
            t: self.t,
            u: self.u,
            v: self.v,
            part: self.part,
        }
    }

    /// The tie rule every accelerator follows: a hit is better when it is
    /// nearer, and of two hits at the same `t` the lower primitive index wins.
    #[inline]
    #[must_use]
    pub fn is_better_than(&self, other: &Hit) -> bool {
        self.t < other.t || (self.t == other.t && self.prim < other.prim)
    }
}

/// Something a ray can hit. Accelerators are generic over it (static
/// dispatch: no `dyn` in the hot path).
///
/// Queries take a **closed** interval `[t_min, t_max]`: a hit at exactly
/// `t_min` or `t_max` counts.
///
/// A primitive's ray test may depend on values computed from the ray alone
/// (a triangle test's permutation and shear of the axes, for instance).
/// They are its [`RayData`](Self::RayData): an accelerator computes them
/// once per query with [`ray_data`](Self::ray_data) and hands them, with
/// the ray, to every test of that query. A primitive without such values
/// uses `()`. The tests must be given the data of the ray they are given.
///
/// For a grid to return exactly what [`crate::Exhaustive`] returns, an
/// implementation must behave as a function of the ray: `closest_hit`
/// returns the primitive's nearest hit with `t >= t_min`, filtered by
/// `t <= t_max` (so a smaller `t_max` never changes a hit it still admits),
/// and the reported point `ray.at(t)` lies in `bounds()` up to rounding
/// (the grid widens boxes by a few hundred ulps of the scene's coordinates,
/// which covers robust intersection routines; a ray whose origin is far
/// beyond the scene compared with that margin may see a tie resolved
/// differently near a cell plane).
pub trait Primitive: Sync {
    /// What all the primitives of one accelerator refer to, stored once by
    /// the accelerator and handed to every method: a mesh's vertex array
    /// for triangles given by vertex indices; `()` for primitives that hold
    /// all they need.
    type Shared: Sync + std::fmt::Debug;

    /// What the ray tests compute from the ray alone, once per query
    /// (`()` when nothing).
    type RayData;

    /// The [`RayData`](Self::RayData) of `ray`.
    fn ray_data(ray: &Ray) -> Self::RayData;

    /// Four primitives laid out for [`four_may_hit`](Self::four_may_hit),
    /// coordinate by coordinate in SIMD lanes (as Embree's `Triangle4`):
    /// what an accelerator may keep beside references it tests together,
    /// so that testing four needs no gathering (a grid without cells keeps
    /// its primitives so). `()` for primitives without such a layout.
    type Four: Copy + Default + PartialEq + Send + Sync + std::fmt::Debug;

    /// Whether [`pack_four`](Self::pack_four) lays primitives out for
    /// [`four_may_hit`](Self::four_may_hit); when `false` (the default)
    /// accelerators do not call them.
    const PACKS_FOUR: bool = false;

    /// Up to four primitives (`None` past the last) as a
    /// [`Four`](Self::Four).
    #[inline]
    fn pack_four(four: [Option<&Self>; 4], shared: &Self::Shared) -> Self::Four {
        let _ = (four, shared);
        Self::Four::default()
    }

    /// Which of the primitives packed in `four` (bit `k` for the `k`-th)
    /// `ray`, whose [`RayData`](Self::RayData) is `data`, may hit; each is
    /// then tested with [`closest_hit`](Self::closest_hit) or
    /// [`any_hit`](Self::any_hit). It must never clear the bit of a
    /// primitive those would hit (the same rejection, with the same
    /// operations in the same order, guarantees it); bits past the packed
    /// primitives are ignored. The default rejects none.
    #[inline]
    fn four_may_hit(four: &Self::Four, ray: &Ray, data: &Self::RayData) -> u32 {
        let _ = (four, ray, data);
        0xf
    }

    /// A box that holds the whole primitive.
    fn bounds(&self, shared: &Self::Shared) -> Aabb;

    /// The nearest hit with `t` in `[t_min, t_max]`, if any; `data` is
    /// `Self::ray_data(ray)`.
    fn closest_hit(
        &self,
        shared: &Self::Shared,
        ray: &Ray,
        data: &Self::RayData,
        t_min: Real,
        t_max: Real,
    ) -> Option<PrimHit>;

    /// Whether there is any hit with `t` in `[t_min, t_max]` (shadow rays).
    #[inline]
    fn any_hit(
        &self,
        shared: &Self::Shared,
        ray: &Ray,
        data: &Self::RayData,
        t_min: Real,
        t_max: Real,
    ) -> bool {
        self.closest_hit(shared, ray, data, t_min, t_max).is_some()
    }

    /// Whether the primitive may touch the closed box `cell`. The default is
    /// the conservative bounds test; a primitive can answer exactly
    /// (triangle–box SAT, sphere–box distance) so that a grid built with exact
    /// insertion keeps fewer "might be in the cell" references. It must never
    /// answer `false` for a box that the primitive touches.
    #[inline]
    fn overlaps_box(&self, shared: &Self::Shared, cell: &Aabb) -> bool {
        self.bounds(shared).overlaps(cell)
    }

    /// Tests `prims[r]` for each `r` of `refs`, in order, and calls
    /// `keep(r, hit)` for each hit; `keep` returns the `t_max` for the tests
    /// that follow (a grid's cell: its references, the best hit so far).
    /// `best` is the reference whose hit set `t_max` ([`NO_SLOT`] when
    /// none): `keep` has seen that hit, so the default does not test it
    /// again (a large triangle seen in several cells is tested in the
    /// first only); an override may test it again, which changes nothing.
    ///
    /// The default calls [`closest_hit`](Self::closest_hit) one primitive at
    /// a time. An override may test several primitives at once (in SIMD
    /// lanes) against the same `t_max`, so it may report hits beyond a
    /// limit that `keep` has lowered in between (the caller discards them);
    /// otherwise it must report exactly the hits of the default (with or
    /// without that of `best`).
    #[inline]
    #[allow(clippy::too_many_arguments)] // the primitives, what they share, the references, the query
    fn closest_hits(
        prims: &[Self],
        shared: &Self::Shared,
        refs: &[u32],
        ray: &Ray,
        data: &Self::RayData,
        t_min: Real,
        t_max: Real,
        best: u32,
        keep: &mut impl FnMut(u32, PrimHit) -> Real,
    ) where
        Self: Sized,
    {
        closest_hits_each(prims, shared, refs, ray, data, t_min, t_max, best, keep);
    }

    /// Whether any of `prims[r]`, `r` in `refs`, is hit with `t` in
    /// `[t_min, t_max]` (a grid cell's shadow-ray work).
    ///
    /// The default calls [`any_hit`](Self::any_hit) one primitive at a time
    /// and stops at the first hit; an override may reject several at once
    /// ([`any_hits_prefiltered`]), but must give the same answer.
    #[inline]
    fn any_hits(
        prims: &[Self],
        shared: &Self::Shared,
        refs: &[u32],
        ray: &Ray,
        data: &Self::RayData,
        t_min: Real,
        t_max: Real,
    ) -> bool
    where
        Self: Sized,
    {
        any_hits_each(prims, shared, refs, ray, data, t_min, t_max)
    }
}

/// The default [`Primitive::closest_hits`]: [`Primitive::closest_hit`] one
/// primitive at a time, for overrides that batch only some cells.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // those of `Primitive::closest_hits`
pub fn closest_hits_each<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    refs: &[u32],
    ray: &Ray,
    data: &P::RayData,
    t_min: Real,
    mut t_max: Real,
    best: u32,
    keep: &mut impl FnMut(u32, PrimHit) -> Real,
) {
    for &r in refs {
        if r == best {
            continue;
        }
        if let Some(h) = prims[r as usize].closest_hit(shared, ray, data, t_min, t_max) {
            t_max = keep(r, h);
        }
    }
}

/// The default [`Primitive::any_hits`]: [`Primitive::any_hit`] one
/// primitive at a time until one is hit.
#[inline(always)]
pub fn any_hits_each<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    refs: &[u32],
    ray: &Ray,
    data: &P::RayData,
    t_min: Real,
    t_max: Real,
) -> bool {
    refs.iter()
        .any(|&r| prims[r as usize].any_hit(shared, ray, data, t_min, t_max))
}

/// The `best` of [`Primitive::closest_hits`] when there is no hit yet.
pub const NO_SLOT: u32 = u32::MAX;

/// A [`Primitive::closest_hits`] for primitives with a cheap test of four
/// at once (SIMD lanes): the references are taken four at a time,
/// `may_hit` says which of the four the ray may hit (bit `k` for the `k`-th;
/// a chunk shorter than four repeats its last primitive), and
/// [`Primitive::closest_hit`] tests those, but for `best` (pass `Some` of
/// the `best` of [`Primitive::closest_hits`]; `None` for primitives seldom
/// larger than a cell, such as spheres or the triangles of a dense mesh,
/// where the comparison would cost more than it saves). `may_hit` must
/// never clear the bit of a primitive that `closest_hit` would hit:
/// computing the same rejection as `closest_hit`, with the same operations
/// in the same order, guarantees it.
///
/// ```
/// use gridrt_grid::{
///     closest_hits_prefiltered, Aabb, PrimHit, Primitive, Ray, Real, Vec3, NO_SLOT,
/// };
///
/// /// A slab `lo <= x <= hi`, hit only by rays that move along x.
/// struct Slab(Real, Real);
///
/// impl Primitive for Slab {
///     type Shared = ();
///     /// Whether the ray moves along x, decided once per query.
///     type RayData = bool;
///     type Four = ();
///     fn ray_data(ray: &Ray) -> bool {
///         ray.dir.x != 0.0
///     }
///     fn bounds(&self, _: &()) -> Aabb {
///         Aabb::new(Vec3::new(self.0, -1.0, -1.0), Vec3::new(self.1, 1.0, 1.0))
///     }
///     fn closest_hit(&self, _: &(), ray: &Ray, _: &bool, t0: Real, t1: Real) -> Option<PrimHit> {
///         let t = (self.0 - ray.origin.x) / ray.dir.x;
///         (t >= t0 && t <= t1).then_some(PrimHit::new(t, 0.0, 0.0))
///     }
///     fn closest_hits(
///         prims: &[Self],
///         shared: &(),
///         refs: &[u32],
///         ray: &Ray,
///         moving: &bool,
///         t_min: Real,
///         t_max: Real,
///         best: u32,
///         keep: &mut impl FnMut(u32, PrimHit) -> Real,
///     ) {
///         // A ray that does not move along x misses all four at once.
///         let mask = if *moving { 0b1111 } else { 0 };
///         closest_hits_prefiltered(prims, shared, refs, ray, moving, t_min, t_max, Some(best), keep, |_| mask);
///     }
/// }
///
/// let slabs = [Slab(3.0, 4.0), Slab(1.0, 2.0)];
/// let mut hits = Vec::new();
/// let ray = Ray::new(Vec3::ZERO, Vec3::X);
/// let data = Slab::ray_data(&ray); // once per query
/// let mut keep = |r, h: PrimHit| {
///     hits.push((r, h.t));
///     h.t
/// };
/// Slab::closest_hits(&slabs, &(), &[0, 1], &ray, &data, 0.0, 10.0, NO_SLOT, &mut keep);
/// // Reference 1 set the limit: another cell holding it does not test it again.
/// Slab::closest_hits(&slabs, &(), &[0, 1], &ray, &data, 0.0, 1.0, 1, &mut keep);
/// assert_eq!(hits, [(0, 3.0), (1, 1.0)]);
/// ```
#[inline(always)]
#[allow(clippy::too_many_arguments)] // those of `Primitive::closest_hits`, and `may_hit`
pub fn closest_hits_prefiltered<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    refs: &[u32],
    ray: &Ray,
    data: &P::RayData,
    t_min: Real,
    mut t_max: Real,
    best: Option<u32>,
    keep: &mut impl FnMut(u32, PrimHit) -> Real,
    mut may_hit: impl FnMut([&P; 4]) -> u32,
) {
    for chunk in refs.chunks(4) {
        let (four, n) = four_of(prims, chunk);
        let mut pass = may_hit(four) & ((1 << n) - 1);
        while pass != 0 {
            let k = pass.trailing_zeros() as usize;
            pass &= pass - 1;
            if best == Some(chunk[k]) {
                continue;
            }
            if let Some(h) = four[k].closest_hit(shared, ray, data, t_min, t_max) {
                t_max = keep(chunk[k], h);
            }
        }
    }
}

/// A [`Primitive::any_hits`] for primitives with a cheap test of four at
/// once: `may_hit` as in [`closest_hits_prefiltered`], and
/// [`Primitive::any_hit`] for the primitives it lets through, until one is
/// hit.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // those of `Primitive::any_hits`, and `may_hit`
pub fn any_hits_prefiltered<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    refs: &[u32],
    ray: &Ray,
    data: &P::RayData,
    t_min: Real,
    t_max: Real,
    mut may_hit: impl FnMut([&P; 4]) -> u32,
) -> bool {
    for chunk in refs.chunks(4) {
        let (four, n) = four_of(prims, chunk);
        let mut pass = may_hit(four) & ((1 << n) - 1);
        while pass != 0 {
            let k = pass.trailing_zeros() as usize;
            pass &= pass - 1;
            if four[k].any_hit(shared, ray, data, t_min, t_max) {
                return true;
            }
        }
    }
    false
}

/// The primitives of a chunk of one to four references, and its length: a
/// chunk shorter than four repeats its last primitive.
#[inline(always)]
fn four_of<'p, P>(prims: &'p [P], chunk: &[u32]) -> ([&'p P; 4], usize) {
    let n = chunk.len();
    let four = if let &[a, b, c, d] = chunk {
        // A full chunk, the common case, without the repeat's clamping.
        [a, b, c, d].map(|r| &prims[r as usize])
    } else {
        std::array::from_fn(|k| &prims[chunk[k.min(n - 1)] as usize])
    };
    (four, n)
}

/// A structure that answers ray queries over a set of primitives it owns.
///
/// Every implementation returns the same answer for the same query: the hit
/// with the smallest `t` in `[t_min, t_max]`, ties going to the lower
/// primitive index ([`Hit::is_better_than`]). A query computes the
/// primitives' [`Primitive::ray_data`] once and passes it to each test.
pub trait Accelerator: Sync {
    /// The primitive type.
    type Prim: Primitive;
    /// Per-ray working memory owned by the caller (for example a mailbox),
    /// made once per thread with [`Accelerator::scratch`] and reused.
    type Scratch: Send;

    /// Fresh working memory for one thread's queries.
    fn scratch(&self) -> Self::Scratch;

    /// The primitives, in the accelerator's storage order ([`Hit::slot`]
    /// indexes it): the given order for the exhaustive accelerator, cell
    /// order for a grid.
    fn primitives(&self) -> &[Self::Prim];

    /// What the primitives share ([`Primitive::Shared`]).
    fn shared(&self) -> &<Self::Prim as Primitive>::Shared;

    /// The primitive index (the given order) of the primitive in `slot`.
    fn primitive_id(&self, slot: u32) -> u32;

    /// The nearest hit with `t` in `[t_min, t_max]`.
    fn closest_hit(
        &self,
        ray: &Ray,
        t_min: Real,
        t_max: Real,
        scratch: &mut Self::Scratch,
    ) -> Option<Hit>;

    /// Whether anything is hit with `t` in `[t_min, t_max]`; stops at the
    /// first occluder found.
    fn any_hit(&self, ray: &Ray, t_min: Real, t_max: Real, scratch: &mut Self::Scratch) -> bool;
}
