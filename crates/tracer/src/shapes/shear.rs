//! The per-ray part of the watertight ray–triangle test: the ray's shear
//! frame, computed once per query, at its first triangle test ([`LazyShear`],
//! the [`Primitive::ray_data`] of [`Triangle`], `MeshTriangle` and
//! [`Shape`]), and handed to every triangle test of that query.
//!
//! [`Primitive::ray_data`]: gridrt_grid::Primitive::ray_data
//! [`Triangle`]: super::Triangle
//! [`Shape`]: super::Shape

use gridrt_bbox::math::{LaneMat, Lanes};
use gridrt_bbox::{Ray, Real, Vec3};

/// The ray's frame for the watertight ray–triangle test of Woop, Benthin &
/// Wald ("Watertight Ray/Triangle Intersection", JCGT 2013), in which the
/// ray runs along +z: the axes are permuted so that the largest direction
/// component becomes z, and x, y are sheared so that the direction has none:
/// with `(x, y, z)` the permuted `p − origin`, a point `p` sits at
/// `(x − sx·z, y − sy·z, sz·z)`, and the ray's points at `(0, 0, t)`.
///
/// It is what [`Triangle`](super::Triangle) computes once per ray (inside
/// its [`Primitive::RayData`](gridrt_grid::Primitive::RayData), as Embree's
/// `WoopPrecalculations1`): the frame, and the origin and shear factors
/// splatted into four lanes for testing four triangles at a time
/// ([`Shear::triangles_may_hit`]).
///
/// ```
/// use gridrt_grid::{Ray, Vec3};
/// use gridrt_tracer::Shear;
/// let r = Ray::new(Vec3::ZERO, Vec3::new(1.0, -4.0, 2.0));
/// let shear = Shear::new(&r);
/// // y is the largest and negative: it becomes z, and x, y swap to keep the winding.
/// assert_eq!(shear.axes, [0, 2, 1]);
/// assert_eq!(shear.s, [-0.25, -0.5, -0.25]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shear {
    /// `[kx, ky, kz]`: `kz` is the axis of the largest `|dir|` component (the
    /// later axis on ties), `kx`, `ky` the next two in cyclic order, swapped
    /// when `dir[kz] < 0` so that the triangles' winding is kept.
    pub axes: [usize; 3],
    /// `[dir[kx]·sz, dir[ky]·sz, sz]` with `sz = 1 / dir[kz]`.
    pub s: [Real; 3],
    /// The origin's permuted coordinates `[o[kx], o[ky], o[kz]]`, each
    /// splatted into four lanes.
    pub(super) origin: [Lanes; 3],
    /// `[sx, sy, sz]`, each splatted into four lanes.
    pub(super) s_lanes: [Lanes; 3],
}

impl Shear {
    /// The frame of `ray`.
    #[inline]
    #[must_use]
    pub fn new(ray: &Ray) -> Self {
        let (dir, inv_dir) = (ray.dir, ray.inv_dir);
        let a = dir.abs();
        let kz = if a.x > a.y {
            if a.x > a.z {
                0
            } else {
                2
            }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = inv_dir[kz];
        let [sx, sy] = [dir[kx] * sz, dir[ky] * sz];
        let o: &[Real; 3] = ray.origin.as_ref();
        Self {
            axes: [kx, ky, kz],
            s: [sx, sy, sz],
            origin: [o[kx], o[ky], o[kz]].map(Lanes::splat),
            s_lanes: [sx, sy, sz].map(Lanes::splat),
        }
    }

    /// Of four triangles, the mask (bit `j` for triangle `j`) of those that
    /// the watertight test's edge functions do not reject: `coord(k)` gives,
    /// for world axis `k`, each triangle's lanes `(v0[k], v1[k], v2[k], _)`,
    /// and a triangle is rejected when its three edge functions have both
    /// signs and none is zero, as the scalar test rejects it first, or when
    /// its three vertices lie behind the origin along the ray (each one's
    /// `z·sz` below zero), where the scalar test's `t` is at most zero. The
    /// edge functions are the scalar test's operations in the same order,
    /// and a product's sign is exact (or the product zero), so a triangle
    /// rejected here is one the scalar test rejects.
    ///
    /// ```
    /// use gridrt_bbox::math::Lanes;
    /// use gridrt_grid::{Ray, Real, Vec3};
    /// use gridrt_tracer::Shear;
    /// let r = Ray::new(Vec3::new(0.25, 0.25, 1.0), Vec3::new(0.0, 0.0, -1.0));
    /// // The unit right triangle in z = 0, moved along x by `dx`: per axis,
    /// // that coordinate of its three vertices.
    /// // that coordinate of its three vertices; at height `z`.
    /// let tri = |dx: Real, z: Real| {
    ///     [
    ///         Lanes::new(dx, 1.0 + dx, dx, 0.0),
    ///         Lanes::new(0.0, 0.0, 1.0, 0.0),
    ///         Lanes::splat(z),
    ///     ]
    /// };
    /// // Under the ray, beside it, under it again, above its origin.
    /// let four = [tri(0.0, 0.0), tri(2.0, 0.0), tri(-0.5, 0.0), tri(0.0, 2.0)];
    /// let mask = Shear::new(&r).triangles_may_hit(|k| four.map(|t| t[k]));
    /// assert_eq!(mask, 0b0101);
    /// ```
    #[inline(always)]
    #[must_use]
    pub fn triangles_may_hit(&self, coord: impl Fn(usize) -> [Lanes; 4]) -> u32 {
        // Coordinate `k` of vertex `i` of the four triangles: row `i`.
        self.may_hit_rows(|k| {
            let [a, b, c, d] = coord(k);
            let m = LaneMat::from_cols(a, b, c, d).transpose();
            [m.x_axis, m.y_axis, m.z_axis]
        })
    }

    /// [`Self::triangles_may_hit`] given the triangles vertex by vertex:
    /// `vertex(i)` holds vertex `i` of each of the four triangles, as
    /// `(x, y, z, any)` (a mesh's vertex array gives them so).
    #[inline(always)]
    #[must_use]
    pub fn triangles_may_hit_by_vertex(&self, vertex: impl Fn(usize) -> [Lanes; 4]) -> u32 {
        let rows = |i| {
            let [a, b, c, d] = vertex(i);
            let m = LaneMat::from_cols(a, b, c, d).transpose();
            [m.x_axis, m.y_axis, m.z_axis]
        };
        // Written out: `array::map` here stayed an out-of-line call.
        let v = [rows(0), rows(1), rows(2)];
        self.may_hit_rows(|k| [v[0][k], v[1][k], v[2][k]])
    }

    /// [`Self::triangles_may_hit`] for four triangles packed in lanes
    /// ([`TriangleFour`]): the same rows, read instead of transposed.
    #[inline(always)]
    #[must_use]
    pub fn four_may_hit(&self, four: &TriangleFour) -> u32 {
        self.may_hit_rows(|k| four.rows[k])
    }

    /// The rejection of [`Self::triangles_may_hit`] from `rows(k)`:
    /// coordinate `k` of vertices 0, 1 and 2 of the four triangles.
    #[inline(always)]
    fn may_hit_rows(&self, rows: impl Fn(usize) -> [Lanes; 3]) -> u32 {
        let [kx, ky, kz] = self.axes;
        let [ox, oy, oz] = self.origin;
        let [sx, sy, sz] = self.s_lanes;
        let z = rows(kz).map(|c| c - oz);
        let [x, y] = [(rows(kx), ox, sx), (rows(ky), oy, sy)]
            .map(|(c, o, s)| [0, 1, 2].map(|i| (c[i] - o) - s * z[i]));
        let e = [
            x[2] * y[1] - y[2] * x[1],
            x[0] * y[2] - y[0] * x[2],
            x[1] * y[0] - y[1] * x[0],
        ];
        // The signs as lane masks, combined in lanes: one bitmask in all.
        let z0 = Lanes::ZERO;
        let neg = e[0].cmplt(z0) | e[1].cmplt(z0) | e[2].cmplt(z0);
        let pos = e[0].cmpgt(z0) | e[1].cmpgt(z0) | e[2].cmpgt(z0);
        let zero = e[0].cmpeq(z0) | e[1].cmpeq(z0) | e[2].cmpeq(z0);
        // Behind the origin: every vertex's `z·sz` (its plane's `t` along
        // the ray) below zero. The hit's `t` is the barycentric mean of
        // those, each product's sign is exact (or the product zero), and
        // the full test sums the products weighted by edge functions of
        // one sign and divides by their sum: its `t` is at most zero, which
        // it rejects. A surface the ray leaves, and a large floor under
        // every bounce, end here instead of in the full test.
        let behind = (z[0] * sz).cmplt(z0) & (z[1] * sz).cmplt(z0) & (z[2] * sz).cmplt(z0);
        !((neg & pos & !zero) | behind).bitmask() & 0xf
    }
}

/// Four triangles coordinate by coordinate, for [`Shear::four_may_hit`]
/// (as Embree's `Triangle4`): row `[k][i]` holds coordinate `k` of vertex
/// `i`, triangle `j` in lane `j`, as [`Shear::triangles_may_hit`]
/// transposes them. A lane without a triangle holds zeros.
///
/// ```
/// use gridrt_grid::{Ray, Real, Vec3};
/// use gridrt_tracer::{Shear, TriangleFour};
/// let r = Ray::new(Vec3::new(0.25, 0.25, 1.0), Vec3::new(0.0, 0.0, -1.0));
/// let tri = |dx: Real| Some([Vec3::new(dx, 0.0, 0.0), Vec3::new(1.0 + dx, 0.0, 0.0), Vec3::new(dx, 1.0, 0.0)]);
/// // Under the ray, beside it, under it again, beside it.
/// let four = TriangleFour::new([tri(0.0), tri(2.0), tri(-0.5), tri(-3.0)]);
/// assert_eq!(Shear::new(&r).four_may_hit(&four), 0b0101);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriangleFour {
    rows: [[Lanes; 3]; 3],
}

impl TriangleFour {
    /// Up to four triangles' vertices (`None`: no triangle in that lane).
    #[must_use]
    pub fn new(four: [Option<[Vec3; 3]>; 4]) -> Self {
        let mut rows = [[Lanes::ZERO; 3]; 3];
        for (j, tri) in four.iter().enumerate() {
            for (i, p) in tri.iter().flatten().enumerate() {
                for (k, row) in rows.iter_mut().enumerate() {
                    row[i][j] = p[k];
                }
            }
        }
        Self { rows }
    }
}

/// A ray's [`Shear`], computed on first use and kept for the rest of the
/// query: the per-ray data of [`Triangle`](super::Triangle),
/// [`MeshTriangle`](super::MeshTriangle) and [`Shape`](super::Shape). A
/// ray that crosses only empty cells (most camera rays of a sparse scene
/// seen from afar), or whose grid holds no triangle, never pays for it.
pub struct LazyShear {
    made: std::cell::Cell<bool>,
    shear: std::cell::UnsafeCell<std::mem::MaybeUninit<Shear>>,
}

impl LazyShear {
    /// The shear frame of `ray` (the query's ray: every call of one query
    /// must pass the same). Made in place on first use (a `OnceCell`
    /// builds it aside, copies it in and is never inlined: 30 more
    /// instructions a ray).
    #[inline(always)]
    pub fn of(&self, ray: &Ray) -> &Shear {
        if !self.made.get() {
            // SAFETY: before `made` is set no reference to the frame has
            // been handed out, `Shear::new` cannot reach this cell, and the
            // type is not `Sync` (its `Cell`): nothing else reads or writes
            // the frame while it is written.
            unsafe { (*self.shear.get()).write(Shear::new(ray)) };
            self.made.set(true);
        }
        // SAFETY: `made` is set, so the frame is written, and it is never
        // written again.
        unsafe { (*self.shear.get()).assume_init_ref() }
    }

    /// Whether the frame has been made.
    #[must_use]
    pub fn is_made(&self) -> bool {
        self.made.get()
    }

    /// The frame, if made.
    fn get(&self) -> Option<&Shear> {
        if !self.made.get() {
            return None;
        }
        // SAFETY: as in `of`: a set `made` means a written frame, never
        // written again.
        Some(unsafe { (*self.shear.get()).assume_init_ref() })
    }
}

impl Default for LazyShear {
    #[inline(always)]
    fn default() -> Self {
        Self {
            made: std::cell::Cell::new(false),
            shear: std::cell::UnsafeCell::new(std::mem::MaybeUninit::uninit()),
        }
    }
}

impl Clone for LazyShear {
    fn clone(&self) -> Self {
        let copy = Self::default();
        if let Some(&s) = self.get() {
            // SAFETY: `copy` is new and not shared.
            unsafe { (*copy.shear.get()).write(s) };
            copy.made.set(true);
        }
        copy
    }
}

impl std::fmt::Debug for LazyShear {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("LazyShear").field(&self.get()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridrt_bbox::Vec3;

    #[test]
    fn lazy_shear_is_the_rays_shear_made_once() {
        let r = Ray::new(Vec3::new(0.5, -2.0, 3.0), Vec3::new(-0.3, 0.2, -1.0));
        let lazy = LazyShear::default();
        assert!(!lazy.is_made());
        let first: *const Shear = lazy.of(&r);
        assert!(lazy.is_made());
        assert_eq!(*lazy.of(&r), Shear::new(&r));
        assert!(std::ptr::eq(first, lazy.of(&r)));
    }

    /// `p` in the shear frame, as the watertight triangle test computes it.
    fn sheared(r: &Ray, p: Vec3) -> [Real; 3] {
        let shear = Shear::new(r);
        let [kx, ky, kz] = shear.axes;
        let [sx, sy, sz] = shear.s;
        let d = p - r.origin;
        [d[kx] - sx * d[kz], d[ky] - sy * d[kz], sz * d[kz]]
    }

    #[test]
    fn shear_puts_the_ray_on_the_z_axis_and_keeps_the_winding() {
        let dirs = [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-3.0, 1.0, 2.0),
            Vec3::new(0.5, -4.0, 0.25),
            Vec3::new(0.0, -0.0, -2.0),
            Vec3::new(-1.0, 0.0, 0.0),
            // Ties go to the later axis.
            Vec3::new(2.0, 2.0, -2.0),
        ];
        for d in dirs {
            let r = Ray::new(Vec3::new(0.5, -1.5, 2.0), d);
            let shear = Shear::new(&r);
            let [kx, ky, kz] = shear.axes;
            let mut k = shear.axes;
            k.sort_unstable();
            assert_eq!(k, [0, 1, 2], "{d}: not a permutation");
            assert!(d.abs().max_element() == d[kz].abs(), "{d}: kz = {kz}");
            // Points on the ray (exact multiples here) land on +z at t.
            for t in [0.0, 0.5, 2.0, 8.0] {
                assert_eq!(sheared(&r, r.at(t)), [0.0, 0.0, t], "{d} at {t}");
            }
            // A right-handed frame: the unit vectors of kx and ky, taken
            // as a triangle with the origin, keep their orientation.
            let (ex, ey) = (Vec3::AXES[kx], Vec3::AXES[ky]);
            let ez = ex.cross(ey);
            assert_eq!(ez.dot(d).signum(), 1.0, "{d}: winding flipped");
        }
    }

    /// A coordinate on a lattice, so that vertices, origins and
    /// directions tie and lie on each other's planes.
    fn lattice() -> impl proptest::strategy::Strategy<Value = Real> {
        use proptest::strategy::Strategy;
        (-4i32..=4).prop_map(|i| i as Real * 0.5)
    }

    fn point() -> impl proptest::strategy::Strategy<Value = Vec3> {
        use proptest::strategy::Strategy;
        proptest::array::uniform3(lattice()).prop_map(Vec3::from_array)
    }

    proptest::proptest! {
        /// The four-lane rejection drops no triangle that the full test
        /// hits, whether the triangle lies ahead of the origin, behind it,
        /// or through it, at any scale and offset.
        #[test]
        fn four_lane_rejection_keeps_every_hit(
            tris in proptest::collection::vec(proptest::array::uniform3(point()), 4),
            o in point(),
            d in point(),
            scale in proptest::sample::select(vec![1.0 as Real, 1e-3, 3e4]),
            offset in proptest::sample::select(vec![0.0 as Real, 1e5]),
        ) {
            let at = |p: Vec3| p * scale + offset;
            let four: Vec<_> = tris
                .iter()
                .map(|&[a, b, c]| super::super::Triangle::new(at(a), at(b), at(c)))
                .collect();
            let shear = Shear::new(&Ray::new(at(o), d));
            let mask = shear.triangles_may_hit(|k| std::array::from_fn(|j| four[j].lanes(k)));
            for (j, tri) in four.iter().enumerate() {
                if mask >> j & 1 == 0 {
                    proptest::prop_assert!(
                        tri.intersect(&shear, 0.0, Real::INFINITY).is_none(),
                        "triangle {} rejected but hit", j
                    );
                }
            }
        }
    }

    #[test]
    fn lanes_hold_the_permuted_origin_and_the_shear_factors() {
        let r = Ray::new(Vec3::new(0.5, -1.5, 2.0), Vec3::new(1.0, -4.0, 2.0));
        let shear = Shear::new(&r);
        let [kx, ky, kz] = shear.axes;
        let o = r.origin;
        assert_eq!(shear.origin, [o[kx], o[ky], o[kz]].map(Lanes::splat));
        assert_eq!(shear.s_lanes, shear.s.map(Lanes::splat));
    }
}
