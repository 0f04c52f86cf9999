use super::{overlap, unit_or, LazyShear, Shear, Surface, SurfacePoint, TriangleFour};
use gridrt_bbox::math::Lanes;
use gridrt_bbox::{gamma, Aabb, Ray, Real, Vec3};
use gridrt_grid::{any_hits_prefiltered, closest_hits_prefiltered, PrimHit, Primitive};

/// A triangle given by its three vertices (counter-clockwise = front).
///
/// The ray test is **watertight** (Woop, Benthin & Wald, "Watertight
/// Ray/Triangle Intersection", JCGT 2013): the vertices are moved into the
/// ray's [`Shear`] frame, where the ray is the +z axis
/// (translate, permute so that the largest direction component is z,
/// shear), and the three 2D edge functions decide the hit by their signs. A
/// ray through an edge or vertex shared by two triangles hits at least one
/// of them, because both see the same edge function, bit for bit. When an
/// edge function is exactly 0 in `f32`, it is recomputed in `f64`, where the
/// products are exact, so its sign is right. A triangle of zero area
/// (collinear vertices) hits wherever the sheared test says it does: the
/// shear's rounding can give it a sliver of area just where its neighbours'
/// shared edges no longer meet, and rejecting it there would open a crack.
/// Its normal then faces the ray from the side its sheared winding shows
/// ([`Triangle::area_normal`] being zero). Only a triangle with two equal
/// vertices never hits ([`Triangle::is_collapsed`]); none gives a NaN.
///
/// The vertices are stored coordinate by coordinate (the three x, the
/// three y, the three z), so that the test transforms all three vertices at
/// once in 4-lane vectors: one load, subtraction and shear per coordinate,
/// and the three edge functions in one vector product. The frame depends
/// on the ray alone: an accelerator computes it once per query (it is the
/// triangle's [`Primitive::RayData`]) and hands it to every test.
///
/// A hit reports barycentrics `u`, `v`: the weights of `p1` and `p2` (the
/// hit point is `(1 − u − v)·p0 + u·p1 + v·p2`). A hit needs `t > 0` and
/// `t` in the caller's range, nothing more: no epsilon and no error bound
/// on `t`, so the answer does not depend on the scene's scale or the
/// direction's length (scaling a mesh and its rays by a power of two
/// scales nothing but the reported `t`). A ray that starts on a surface
/// leaves it because its origin is offset by the hit point's error bound.
///
/// ```
/// use gridrt_tracer::{Shear, Triangle};
/// use gridrt_grid::{Primitive, Ray, Real, Vec3};
/// let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
/// let ray = Ray::new(Vec3::new(0.25, 0.5, 1.0), -Vec3::Z);
/// // Once per ray; `Shear::new(&ray)` at the first test that needs it.
/// let shear = Triangle::ray_data(&ray);
/// let h = tri.closest_hit(&(), &ray, &shear, 0.0, Real::INFINITY).unwrap();
/// assert_eq!(*shear.of(&ray), Shear::new(&ray));
/// assert_eq!((h.t, h.u, h.v), (1.0, 0.25, 0.5));
/// assert_eq!(tri.vertices(), [Vec3::ZERO, Vec3::X, Vec3::Y]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// `x0 x1 x2 y0 y1 y2 z0 z1 z2 0`: every coordinate's three values
    /// start a 4-lane load (the last one's fourth lane is padding).
    c: [Real; 10],
}

impl Triangle {
    /// A triangle from its vertices.
    #[inline]
    #[must_use]
    pub fn new(p0: Vec3, p1: Vec3, p2: Vec3) -> Self {
        Self {
            c: [p0.x, p1.x, p2.x, p0.y, p1.y, p2.y, p0.z, p1.z, p2.z, 0.0],
        }
    }

    /// The vertices `[p0, p1, p2]`.
    #[inline]
    #[must_use]
    pub fn vertices(&self) -> [Vec3; 3] {
        let c = &self.c;
        [
            Vec3::new(c[0], c[3], c[6]),
            Vec3::new(c[1], c[4], c[7]),
            Vec3::new(c[2], c[5], c[8]),
        ]
    }

    /// `(p1 − p0) × (p2 − p0)`: twice the area, along the front normal.
    ///
    /// Evaluated in `f64` (and in the `f32` build rounded once): the
    /// differences of `f32` coordinates and their products are exact or
    /// nearly so there, so a sliver a few ulps wide and millions of ulps
    /// long keeps its true normal instead of cancelling to zero.
    #[inline]
    #[must_use]
    #[allow(clippy::cast_possible_truncation)] // the rounding to `f32` is the point
    pub fn area_normal(&self) -> Vec3 {
        area_normal(self.vertices())
    }

    /// Whether the triangle has zero area (its vertices are collinear).
    /// Decided on the `f64` cross product, so a sliver is not taken for
    /// degenerate. Such a triangle is still hit where the watertight test
    /// says so (see the type's documentation).
    #[must_use]
    pub fn is_degenerate(&self) -> bool {
        area_normal_f64(self.vertices()) == glam::DVec3::ZERO
    }

    /// Whether two of the vertices are equal, in which case no ray ever
    /// hits the triangle: equal vertices shear to equal points, and the
    /// edge functions of a triangle `(a, a, c)` are `e`, `−e` (rounded
    /// alike) and exactly 0, so they either have both signs or sum to
    /// zero. Leaving it out of an accelerator changes no answer.
    #[must_use]
    pub fn is_collapsed(&self) -> bool {
        is_collapsed(self.vertices())
    }

    /// Coordinate `k` of the three vertices in lanes 0..3 (lane 3 is
    /// another value, never used).
    #[inline(always)]
    pub(super) fn lanes(&self, k: usize) -> Lanes {
        Lanes::from_slice(&self.c[3 * k..3 * k + 4])
    }

    /// Which of `four` the ray of `shear` may hit
    /// ([`Shear::triangles_may_hit`]): the prefilter of `closest_hits` and
    /// `any_hits`. The coordinates are gathered written out, since
    /// `array::map` can stay a call in the hot loop.
    #[inline(always)]
    fn may_hit_four(four: [&Self; 4], shear: &Shear) -> u32 {
        shear.triangles_may_hit(|k| {
            [
                four[0].lanes(k),
                four[1].lanes(k),
                four[2].lanes(k),
                four[3].lanes(k),
            ]
        })
    }

    /// The watertight test of the ray whose frame is `shear`
    /// ([`Shear::new`] of the ray): `(t, u, v)` of a hit with `t > 0` in
    /// `[t_min, t_max]`.
    #[inline]
    #[must_use]
    pub fn intersect(&self, shear: &Shear, t_min: Real, t_max: Real) -> Option<PrimHit> {
        intersect_lanes([0, 1, 2].map(|k| self.lanes(k)), shear, t_min, t_max)
    }
}

/// [`Triangle::is_collapsed`] of the vertices `p`.
#[must_use]
pub(crate) fn is_collapsed([p0, p1, p2]: [Vec3; 3]) -> bool {
    p0 == p1 || p1 == p2 || p2 == p0
}

/// [`Triangle::area_normal`] of the triangle `p`.
#[inline]
pub(super) fn area_normal(p: [Vec3; 3]) -> Vec3 {
    let n = area_normal_f64(p);
    Vec3::new(n.x as Real, n.y as Real, n.z as Real)
}

/// [`Triangle::area_normal`] of the triangle `p` before its rounding to
/// [`Real`]: zero exactly for a triangle of zero area.
#[inline]
#[allow(clippy::useless_conversion)] // a conversion in the `f32` build
pub(super) fn area_normal_f64(p: [Vec3; 3]) -> glam::DVec3 {
    let [p0, p1, p2] = p.map(|p| glam::DVec3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z)));
    (p1 - p0).cross(p2 - p0)
}

/// The watertight test of a triangle given coordinate by coordinate
/// (`c[k]` holds coordinate `k` of the three vertices in lanes 0..3; lane
/// 3 is never used): the test of [`Triangle::intersect`], shared with the
/// mesh triangles, which gather their vertices into the same lanes.
/// Always inlined: left to the compiler, it stayed a call per full test in
/// the grid's queries (while the exhaustive baseline inlined it).
#[inline(always)]
pub(super) fn intersect_lanes(
    c: [Lanes; 3],
    shear: &Shear,
    t_min: Real,
    t_max: Real,
) -> Option<PrimHit> {
    let (t, u, v, _) = sheared_hit(c, shear)?;
    // Only `t > 0` and the caller's range: no rejection by an error bound
    // on `t`. Such a bound (pbrt-v4 §6.8.4) grows with the triangle's
    // extent over its projected area and, written with world-unit x, y
    // beside t-unit z, with the inverse of the direction's length; it
    // rejected true hits on slivers, on short directions and in small
    // scenes, and those rays then fell through closed meshes. When every
    // vertex lies ahead of the origin (all z > 0) the sum that gives `t`
    // has terms of one sign and `t > 0` (unless the products underflow),
    // so no hit in front of the origin is lost; a surface the ray starts
    // on is left by offsetting the origin (`offset_ray_origin`), not by
    // an epsilon here.
    if !(t > 0.0 && t >= t_min && t <= t_max) {
        return None;
    }
    Some(PrimHit::new(t, u, v))
}

/// The sheared test of [`intersect_lanes`] before the range of `t`:
/// `(t, u, v)` of the ray's crossing of the triangle's plane, and whether
/// the ray sees the front (the vertices counter-clockwise), or `None` when
/// the ray passes beside the triangle or sees it edge-on.
#[inline(always)]
fn sheared_hit(c: [Lanes; 3], shear: &Shear) -> Option<(Real, Real, Real, bool)> {
    use glam::Vec4Swizzles;
    // The vertices relative to the origin, permuted and sheared: lane i
    // of x, y, z is vertex i. z stays unscaled until a hit needs it.
    let [kx, ky, kz] = shear.axes;
    let [ox, oy, oz] = shear.origin;
    let [sx, sy, _] = shear.s_lanes;
    let sz = shear.s[2];
    let z = c[kz] - oz;
    let x = (c[kx] - ox) - sx * z;
    let y = (c[ky] - oy) - sy * z;
    // Scaled barycentrics, the 2D edge functions: lane 0 is
    // cx·by − cy·bx, lane 1 ax·cy − ay·cx, lane 2 bx·ay − by·ax.
    let e = x.zxyw() * y.yzxw() - y.zxyw() * x.yzxw();
    // Lanes 0..3 of a comparison mask (lane 3 holds no vertex).
    let any3 = |mask: u32| mask & 7 != 0;
    // Inside means all three of one sign (zeros allowed: edges count).
    // Rounding is monotonic, so a product difference rounds to its
    // true sign or to zero, never to the other sign: an edge function
    // of each sign rejects the triangle for certain.
    if any3(e.cmplt(Lanes::ZERO).bitmask()) && any3(e.cmpgt(Lanes::ZERO).bitmask()) {
        return None;
    }
    hit_from_edges(x, y, z, sz, e)
}

/// `(t, u, v)` of a ray that passed the sign test, from the sheared
/// vertices (`x`, `y`, and `z` before its scaling by `sz`) and their `f32`
/// edge functions `e`, and whether the ray sees the front (the edge
/// functions are positive: the frame keeps the winding), or `None` when
/// the exact signs reject it after all or the triangle is seen edge-on.
///
/// In `f32` the edge functions are evaluated again in `f64`, where the
/// products of `f32` values are exact and each difference is rounded once:
/// their signs are exact (an `f32` zero may turn out either way), and so
/// are the barycentrics to an ulp. In `f32` a sliver's edge functions
/// cancel to a fraction of their rounding, so barycentrics taken from them
/// could put the hit far outside the triangle (its `t` off by percent),
/// and then the grid, which looks for a hit only in the cells of the
/// triangle's box, could not agree with the exhaustive baseline.
#[cfg(not(feature = "f64"))]
#[inline]
#[allow(clippy::cast_possible_truncation)] // the rounding to `f32` is the point
fn hit_from_edges(
    x: Lanes,
    y: Lanes,
    z: Lanes,
    sz: Real,
    _e: Lanes,
) -> Option<(Real, Real, Real, bool)> {
    let [ax, bx, cx, _] = x.to_array().map(f64::from);
    let [ay, by, cy, _] = y.to_array().map(f64::from);
    let e = [cx * by - cy * bx, ax * cy - ay * cx, bx * ay - by * ax];
    if e.iter().any(|&e| e < 0.0) && e.iter().any(|&e| e > 0.0) {
        return None;
    }
    let det = e[0] + e[1] + e[2];
    if det == 0.0 || det.is_nan() {
        // Seen edge-on, or a zero direction.
        return None;
    }
    let sz = f64::from(sz);
    let [az, bz, cz, _] = z.to_array().map(|z| f64::from(z) * sz);
    let inv_det = 1.0 / det;
    let t = (e[0] * az + e[1] * bz + e[2] * cz) * inv_det;
    Some((
        t as Real,
        (e[1] * inv_det) as Real,
        (e[2] * inv_det) as Real,
        det > 0.0,
    ))
}

/// `(t, u, v)` of a ray that passed the sign test (see the `f32` version).
/// In `f64` an edge function that rounded to zero is decided again
/// exactly: its two products are equal as rounded, so its sign is that of
/// the difference of their rounding errors, which fused multiply–adds give
/// exactly. Without it a triangle seen nearly along a line through the
/// origin (all three edge functions near zero, of mixed true signs)
/// passes the test far outside itself.
#[cfg(feature = "f64")]
#[inline]
fn hit_from_edges(
    x: Lanes,
    y: Lanes,
    z: Lanes,
    sz: Real,
    e: Lanes,
) -> Option<(Real, Real, Real, bool)> {
    let [mut e0, mut e1, mut e2, _] = e.to_array();
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        let [ax, bx, cx, _] = x.to_array();
        let [ay, by, cy, _] = y.to_array();
        // `p·q − r·s` when `p·q` and `r·s` round to the same value.
        let tie = |p: f64, q: f64, r: f64, s: f64| p.mul_add(q, -(p * q)) - r.mul_add(s, -(r * s));
        if e0 == 0.0 {
            e0 = tie(cx, by, cy, bx);
        }
        if e1 == 0.0 {
            e1 = tie(ax, cy, ay, cx);
        }
        if e2 == 0.0 {
            e2 = tie(bx, ay, by, ax);
        }
        let e = [e0, e1, e2];
        if e.iter().any(|&e| e < 0.0) && e.iter().any(|&e| e > 0.0) {
            return None;
        }
    }
    let det = e0 + e1 + e2;
    if det == 0.0 || det.is_nan() {
        // Seen edge-on, or a zero direction.
        return None;
    }
    let [az, bz, cz, _] = (z * Lanes::splat(sz)).to_array();
    let inv_det = 1.0 / det;
    Some((
        (e0 * az + e1 * bz + e2 * cz) * inv_det,
        e1 * inv_det,
        e2 * inv_det,
        det > 0.0,
    ))
}

/// Asks the CPU for the triangles in slots `refs[4..]` of `prims`, before
/// a cell's triangles are tested four by four.
///
/// A group's test waits on its four triangles; tested in turn, a cell whose
/// triangles are not in the nearest caches (as for rays that bounce off a
/// mesh) pays those waits one group after the other. Asked for all at
/// once, the loads overlap. The first four are left out: their test starts
/// at once.
#[inline(always)]
fn prefetch_cell(prims: &[Triangle], refs: &[u32]) {
    gridrt_grid::mem::prefetch_elements(prims, refs.get(4..).unwrap_or_default());
}

impl Primitive for Triangle {
    /// Nothing shared: the primitive holds all it needs.
    type Shared = ();

    /// The ray's shear frame, made at the query's first triangle test
    /// ([`LazyShear`]): a ray that crosses only empty cells never pays
    /// for it.
    type RayData = LazyShear;

    /// Four triangles coordinate by coordinate.
    type Four = TriangleFour;

    const PACKS_FOUR: bool = true;

    #[inline]
    fn ray_data(_: &Ray) -> LazyShear {
        LazyShear::default()
    }

    fn pack_four(four: [Option<&Self>; 4], _: &()) -> TriangleFour {
        TriangleFour::new(four.map(|t| t.map(Self::vertices)))
    }

    /// The rejection of `closest_hits`, read from the packed rows.
    #[inline(always)]
    fn four_may_hit(four: &TriangleFour, ray: &Ray, shear: &LazyShear) -> u32 {
        shear.of(ray).four_may_hit(four)
    }

    #[inline]
    fn bounds(&self, _: &()) -> Aabb {
        let [p0, p1, p2] = self.vertices();
        Aabb::new(p0.min(p1).min(p2), p0.max(p1).max(p2))
    }

    #[inline]
    fn closest_hit(
        &self,
        _: &(),
        ray: &Ray,
        shear: &LazyShear,
        t_min: Real,
        t_max: Real,
    ) -> Option<PrimHit> {
        self.intersect(shear.of(ray), t_min, t_max)
    }

    /// Four triangles at a time: the edge functions of `closest_hit` in
    /// lanes (one triangle a lane, the same operations in the same order),
    /// rejecting the triangles whose edge functions have both signs and
    /// none zero, as `closest_hit` does first; the others go through
    /// `closest_hit`. A ray near a mesh rejects most triangles here.
    /// Always inlined into the grid's walk: left to the compiler, it stayed
    /// a call per occupied cell.
    #[inline(always)]
    fn closest_hits(
        prims: &[Self],
        shared: &(),
        refs: &[u32],
        ray: &Ray,
        lazy: &LazyShear,
        t_min: Real,
        t_max: Real,
        best: u32,
        keep: &mut impl FnMut(u32, PrimHit) -> Real,
    ) {
        if refs.is_empty() {
            // Nothing to test: the frame stays unmade.
            return;
        }
        prefetch_cell(prims, refs);
        let shear = lazy.of(ray);
        closest_hits_prefiltered(
            prims,
            shared,
            refs,
            ray,
            lazy,
            t_min,
            t_max,
            Some(best),
            keep,
            #[inline(always)]
            |four| Self::may_hit_four(four, shear),
        );
    }

    /// Four triangles at a time, rejected by their edge functions in lanes
    /// as in `closest_hits`, and always inlined as it is: a shadow ray's
    /// occupied cells would otherwise each cost a call.
    #[inline(always)]
    fn any_hits(
        prims: &[Self],
        shared: &(),
        refs: &[u32],
        ray: &Ray,
        lazy: &LazyShear,
        t_min: Real,
        t_max: Real,
    ) -> bool {
        if refs.is_empty() {
            // Nothing to test: the frame stays unmade.
            return false;
        }
        prefetch_cell(prims, refs);
        let shear = lazy.of(ray);
        any_hits_prefiltered(
            prims,
            shared,
            refs,
            ray,
            lazy,
            t_min,
            t_max,
            #[inline(always)]
            |four| Self::may_hit_four(four, shear),
        )
    }

    /// The separating-axis test of Akenine-Möller (2001), with a rounding
    /// margin so that a touching box is never rejected.
    #[inline]
    fn overlaps_box(&self, _: &(), cell: &Aabb) -> bool {
        let [p0, p1, p2] = self.vertices();
        overlap::triangle_box(p0, p1, p2, cell)
    }
}

impl Surface for Triangle {
    #[inline]
    fn surface(&self, _: &(), ray: &Ray, h: &PrimHit) -> SurfacePoint {
        surface_point(self.vertices(), h, || *ray)
    }
}

/// The point from the barycentrics as `p0 + u·(p1 − p0) + v·(p2 − p0)`,
/// with a bound on its distance from the triangle's plane: a few ulps
/// of the two edge terms (small near `p0`, and scaled with the
/// triangle, not with its distance from the world origin) plus two
/// ulps of the point's coordinates for the final additions. Far from
/// the origin this is about a third of pbrt-v4's γ(7)·Σ|bᵢ·pᵢ|, so
/// secondary rays start within the rounding of the geometry. The normal
/// is the unit [`Triangle::area_normal`], or [`facing_normal`] for the
/// ray that hit (asked of `ray` only then) when the area does not resolve.
#[inline]
pub(super) fn surface_point(
    [p0, p1, p2]: [Vec3; 3],
    h: &PrimHit,
    ray: impl FnOnce() -> Ray,
) -> SurfacePoint {
    let (u, v) = (h.u, h.v);
    let a = (p1 - p0) * u;
    let b = (p2 - p0) * v;
    let s = p0 + a;
    let p = s + b;
    // A secondary ray leaving the point is tested against this triangle
    // again, and that test rounds the vertices' depths along the ray's
    // major axis, which need not be the normal's: its error is a few
    // ulps of the triangle's extent in every direction. The origin must
    // clear that too, or points whose own rounding is exact (a triangle
    // in a coordinate plane) hit their own triangle at random (acne).
    let extent = (p1 - p0).abs().max((p2 - p0).abs()).max_element();
    let p_err = (a.abs() + b.abs()) * gamma(3)
        + (p0.abs() + s.abs() + p.abs()) * gamma(1)
        + Vec3::splat(extent * gamma(16));
    SurfacePoint {
        p,
        p_err,
        n: area_normal([p0, p1, p2])
            .try_normalize()
            .unwrap_or_else(|| facing_normal([p0, p1, p2], &ray())),
    }
}

/// The normal of a triangle `p` whose area does not resolve (collinear
/// vertices, or a cross product that underflows) at a hit of `ray`: along
/// the ray, on the side the ray sees by the winding of the triangle's
/// sheared projection, the only area it has. In a closed, consistently
/// wound mesh such a triangle is hit only where the shear's rounding
/// opened a crack between its neighbours, and its projection covers that
/// crack with their winding, so the ray leaves or enters as it would
/// through them.
#[cold]
fn facing_normal(p: [Vec3; 3], ray: &Ray) -> Vec3 {
    let d = unit_or(ray.dir, Vec3::Z);
    let c = [0, 1, 2].map(|k| Lanes::new(p[0][k], p[1][k], p[2][k], 0.0));
    match sheared_hit(c, &Shear::new(ray)) {
        Some((.., false)) => d,
        _ => -d,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_grid::NO_SLOT;

    fn ray(o: [Real; 3], d: [Real; 3]) -> Ray {
        Ray::new(Vec3::from_array(o), Vec3::from_array(d))
    }

    /// The shear frame of the ray from `o` along `d`.
    fn frame(o: [Real; 3], d: [Real; 3]) -> Shear {
        Shear::new(&ray(o, d))
    }

    #[test]
    fn the_frame_is_made_at_the_first_triangle_test_only() {
        let tris = [Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y)];
        let r = ray([0.25, 0.25, 1.0], [0.0, 0.0, -1.0]);
        let data = Triangle::ray_data(&r);
        let mut keep = |_: u32, h: PrimHit| h.t;
        // A cell without references, as the walk's empty list of
        // unbounded primitives, tests nothing.
        Triangle::closest_hits(&tris, &(), &[], &r, &data, 0.0, 9.0, NO_SLOT, &mut keep);
        assert!(!Triangle::any_hits(&tris, &(), &[], &r, &data, 0.0, 9.0));
        assert!(!data.is_made());
        assert!(Triangle::any_hits(&tris, &(), &[0], &r, &data, 0.0, 9.0));
        assert!(data.is_made());
        assert_eq!(*data.of(&r), Shear::new(&r));
    }

    #[test]
    fn barycentrics_are_weights_of_p1_and_p2() {
        let tri = Triangle::new(
            Vec3::new(0.0, 0.0, -2.0),
            Vec3::new(4.0, 0.0, -2.0),
            Vec3::new(0.0, 4.0, -2.0),
        );
        let h = tri
            .intersect(
                &frame([1.0, 2.0, 0.0], [0.0, 0.0, -1.0]),
                0.0,
                Real::INFINITY,
            )
            .unwrap();
        assert_eq!((h.t, h.u, h.v), (2.0, 0.25, 0.5));
        // Either winding, either side.
        let [p0, p1, p2] = tri.vertices();
        let back = Triangle::new(p0, p2, p1);
        let h = back
            .intersect(
                &frame([1.0, 2.0, -5.0], [0.0, 0.0, 1.0]),
                0.0,
                Real::INFINITY,
            )
            .unwrap();
        assert_eq!((h.t, h.u, h.v), (3.0, 0.5, 0.25));
    }

    #[test]
    fn range_is_closed_and_misses_are_misses() {
        let tri = Triangle::new(
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(0.0, 1.0, -1.0),
        );
        let r = frame([0.0, 0.0, 0.0], [0.0, 0.0, -1.0]);
        assert!(tri.intersect(&r, 0.0, 1.0).is_some());
        assert!(tri.intersect(&r, 1.0, 1.0).is_some());
        assert!(tri.intersect(&r, 0.0, 0.999).is_none());
        assert!(tri
            .intersect(&frame([5.0, 0.0, 0.0], [0.0, 0.0, -1.0]), 0.0, 10.0)
            .is_none());
        // Behind the origin.
        assert!(tri
            .intersect(&frame([0.0, 0.0, -3.0], [0.0, 0.0, -1.0]), 0.0, 10.0)
            .is_none());
    }

    #[test]
    fn degenerate_triangles_and_bad_rays_miss_without_nan() {
        let line = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0));
        let point = Triangle::new(Vec3::ONE, Vec3::ONE, Vec3::ONE);
        assert!(line.is_degenerate() && point.is_degenerate());
        assert!(point.is_collapsed() && !line.is_collapsed());
        for d in [
            [0.0, 0.0, -1.0],
            [0.0, -1.0, 0.0],
            [0.3, -1.0, 0.1],
            [1.0, 0.0, 0.0],
        ] {
            for o in [
                [0.5, 0.0, 1.0],
                [0.5, 1.0, 0.0],
                [0.0, 0.0, 0.0],
                [1.0, 2.0, 1.0],
            ] {
                let r = frame(o, d);
                assert!(line
                    .intersect(&r, -Real::INFINITY, Real::INFINITY)
                    .is_none());
                assert!(point
                    .intersect(&r, -Real::INFINITY, Real::INFINITY)
                    .is_none());
            }
        }
        let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!(tri
            .intersect(&frame([0.1, 0.1, 1.0], [0.0, 0.0, 0.0]), 0.0, 10.0)
            .is_none());
        // A ray in the triangle's plane sees it edge-on.
        assert!(tri
            .intersect(&frame([-1.0, 0.1, 0.0], [1.0, 0.0, 0.0]), 0.0, 10.0)
            .is_none());
    }

    #[test]
    fn the_facing_normal_is_on_the_side_the_area_normal_gives() {
        // Random triangles and rays from random origins through random
        // points of them: the side the sheared winding shows is the side
        // of the front normal, whatever the ray's axes and signs.
        let mut rng = crate::hard_meshes::SplitMix(7);
        let mut rnd = || (rng.next() >> 40) as Real / (1u64 << 24) as Real * 2.0 - 1.0;
        let mut seen = [0, 0];
        for _ in 0..2000 {
            let p = [(); 3].map(|()| Vec3::new(rnd(), rnd(), rnd()));
            let n = area_normal(p);
            let (a, b) = (rnd().abs(), rnd().abs());
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            let target = p[0] + (p[1] - p[0]) * a + (p[2] - p[0]) * b;
            let origin = Vec3::new(rnd(), rnd(), rnd()) * 4.0;
            let r = Ray::new(origin, target - origin);
            if n.dot(r.dir).abs() < 1e-3 * n.length() * r.dir.length() {
                continue; // nearly edge-on
            }
            let facing = facing_normal(p, &r);
            assert!(facing.dot(n) > 0.0, "{p:?} {r:?}");
            seen[usize::from(n.dot(r.dir) < 0.0)] += 1;
        }
        // Both sides were seen, often.
        assert!(seen[0] > 500 && seen[1] > 500, "{seen:?}");
    }

    #[test]
    fn a_zero_area_hit_gets_a_unit_normal_facing_the_ray() {
        // Collinear vertices (exactly: steps of (3, 5, 7)/16 from a point
        // far from the origin), seen from many directions: the shear's
        // rounding gives the projection a sliver of area, and where the
        // sheared test reports a hit, the normal is a unit vector along
        // the ray.
        let base = Vec3::new(-1000.0, 700.0, 300.0);
        let step = Vec3::new(3.0, 5.0, 7.0) / 16.0;
        let line = Triangle::new(base, base + step, base + step * 3.0);
        assert!(line.is_degenerate() && !line.is_collapsed());
        let mut hits = 0;
        for k in 0..4000 {
            let x = k as Real / 4000.0;
            let dir = Vec3::new(0.3 + x, -1.0, 0.5 - x);
            let target = base + step * (3.0 * x);
            let r = Ray::new(target - dir * 7.0, dir);
            if let Some(h) = line.closest_hit(&(), &r, &Triangle::ray_data(&r), 0.0, Real::INFINITY)
            {
                hits += 1;
                let n = line.surface(&(), &r, &h).n;
                assert!((n.length() - 1.0).abs() < 1e-5, "{n}");
                assert!(n.cross(r.dir).length() < 1e-5 * r.dir.length(), "{n} {r:?}");
            }
        }
        // A few of the rays meet such a sliver (4 in `f32`, 2 in `f64`).
        assert!(hits > 0);
    }

    #[test]
    fn shared_edge_is_hit_by_one_triangle_at_least() {
        // Two triangles sharing the diagonal of a square; rays straight
        // through points of the diagonal.
        let a = Triangle::new(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        );
        let b = Triangle::new(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        for i in 0..=1000 {
            let s = i as Real / 1000.0;
            let r = ray([s, s, 3.0], [0.0137, -0.021, -1.0]);
            let o = Vec3::new(s, s, 0.0) - r.dir * 3.0;
            let shear = Shear::new(&Ray::new(o, r.dir));
            assert!(
                a.intersect(&shear, 0.0, 10.0).is_some()
                    || b.intersect(&shear, 0.0, 10.0).is_some(),
                "fell through the shared edge at s = {s}"
            );
        }
    }

    #[test]
    fn self_hit_is_rejected_at_the_origin() {
        let tri = Triangle::new(
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        // A ray starting on the triangle and leaving it at a slant.
        let r = ray([0.1, 0.1, 0.0], [0.3, 0.2, 1.0]);
        assert!(tri.intersect(&Shear::new(&r), 0.0, 10.0).is_none());
    }

    #[test]
    fn surface_gives_front_normal_and_error() {
        let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let r = ray([0.2, 0.3, 5.0], [0.0, 0.0, -1.0]);
        let h = tri.intersect(&Shear::new(&r), 0.0, 10.0).unwrap();
        let sp = tri.surface(&(), &r, &h);
        assert_eq!(sp.n, Vec3::Z);
        assert!((sp.p - Vec3::new(0.2, 0.3, 0.0)).length() < 1e-6);
    }

    proptest::proptest! {
        /// The four-lane sign test keeps exactly the triangles the scalar
        /// test hits, in full and partial chunks, on triangles over a small
        /// lattice (shared edges and vertices) and rays through lattice
        /// points (edge functions exactly zero).
        #[test]
        fn four_at_a_time_equals_one_at_a_time(
            corners in proptest::collection::vec(proptest::array::uniform3(0usize..18), 1..12),
            o in proptest::array::uniform3(-4i32..=4),
            through in proptest::array::uniform3(-2i32..=2),
        ) {
            let p = |i: usize| Vec3::new((i % 3) as Real - 1.0, ((i / 3) % 3) as Real - 1.0, (i / 9) as Real);
            let tris: Vec<Triangle> = corners.iter().map(|c| Triangle::new(p(c[0]), p(c[1]), p(c[2]))).collect();
            let refs: Vec<u32> = (0..tris.len() as u32).collect();
            let origin = Vec3::new(o[0] as Real, o[1] as Real, o[2] as Real + 5.0);
            let target = Vec3::new(through[0] as Real, through[1] as Real, through[2] as Real) * 0.5;
            let r = Ray::new(origin, target - origin);
            let shear = Triangle::ray_data(&r);
            // `best`: the reference whose hit was seen before, not tested again.
            let all = |batched: bool, best: u32| {
                let mut hits = Vec::new();
                let mut keep = |i: u32, h: PrimHit| {
                    hits.push((i, h));
                    Real::INFINITY
                };
                if batched {
                    Triangle::closest_hits(&tris, &(), &refs, &r, &shear, 0.0, Real::INFINITY, best, &mut keep);
                } else {
                    for (i, t) in tris.iter().enumerate() {
                        if i as u32 == best {
                            continue;
                        }
                        if let Some(h) = t.closest_hit(&(), &r, &shear, 0.0, Real::INFINITY) {
                            keep(i as u32, h);
                        }
                    }
                }
                hits
            };
            let each = all(false, NO_SLOT);
            proptest::prop_assert_eq!(all(true, NO_SLOT), each.clone());
            if let Some(&(first, _)) = each.first() {
                proptest::prop_assert_eq!(all(true, first), all(false, first));
                proptest::prop_assert_eq!(all(true, first).len(), each.len() - 1);
            }
            // Shadow rays: the batched any-hit answers as one at a time,
            // over the segment up to each hit and beyond.
            for t_max in [Real::INFINITY, 5.0, 4.5] {
                let one = tris.iter().any(|t| t.any_hit(&(), &r, &shear, 0.0, t_max));
                proptest::prop_assert_eq!(Triangle::any_hits(&tris, &(), &refs, &r, &shear, 0.0, t_max), one);
            }
        }

        /// Through the `Shape` enum, with spheres mixed in so that some
        /// chunks of four hold only triangles and others do not, the
        /// batched queries answer as the shapes one at a time.
        #[test]
        fn shapes_four_at_a_time_equal_one_at_a_time(
            corners in proptest::collection::vec(proptest::array::uniform3(0usize..18), 1..14),
            spheres in proptest::collection::vec(0usize..14, 0..3),
            o in proptest::array::uniform3(-4i32..=4),
            through in proptest::array::uniform3(-2i32..=2),
        ) {
            use crate::shapes::{Shape, Sphere};
            let p = |i: usize| Vec3::new((i % 3) as Real - 1.0, ((i / 3) % 3) as Real - 1.0, (i / 9) as Real);
            let mut shapes: Vec<Shape> = corners.iter().map(|c| Shape::Triangle(Triangle::new(p(c[0]), p(c[1]), p(c[2])))).collect();
            for &k in &spheres {
                let at = k.min(shapes.len());
                shapes.insert(at, Shape::Sphere(Sphere::new(p(k % 18), 0.4)));
            }
            let refs: Vec<u32> = (0..shapes.len() as u32).collect();
            let origin = Vec3::new(o[0] as Real, o[1] as Real, o[2] as Real + 5.0);
            let target = Vec3::new(through[0] as Real, through[1] as Real, through[2] as Real) * 0.5;
            let r = Ray::new(origin, target - origin);
            let shear = Shape::ray_data(&r);
            let mut batched = Vec::new();
            Shape::closest_hits(&shapes, &(), &refs, &r, &shear, 0.0, Real::INFINITY, NO_SLOT, &mut |i, h| {
                batched.push((i, h));
                Real::INFINITY
            });
            let one: Vec<(u32, PrimHit)> = shapes
                .iter()
                .enumerate()
                .filter_map(|(i, s)| s.closest_hit(&(), &r, &shear, 0.0, Real::INFINITY).map(|h| (i as u32, h)))
                .collect();
            proptest::prop_assert_eq!(batched, one);
            for t_max in [Real::INFINITY, 5.0, 4.5] {
                let one = shapes.iter().any(|s| s.any_hit(&(), &r, &shear, 0.0, t_max));
                proptest::prop_assert_eq!(Shape::any_hits(&shapes, &(), &refs, &r, &shear, 0.0, t_max), one);
            }
        }
    }
}
