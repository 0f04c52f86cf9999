//! Test-only primitives: a sphere with a robust quadratic and a watertight
//! triangle. They live under `tests/` (and are included by the benches with
//! `#[path]`) because the grid crate itself knows no shapes.

// NaN must fall on the "miss" side of each test, which `!(x >= 0)` says.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Casts between `Real` and f32/f64 are no-ops in one precision only.
#![allow(clippy::unnecessary_cast)]
// The benches use only some of the shapes.
#![allow(dead_code)]

use gridrt_bbox::math::{LaneMat, Lanes};
use gridrt_grid::{closest_hits_prefiltered, Aabb, PrimHit, Primitive, Ray, Real, Vec3};

/// A sphere. The intersection follows Haines et al., "Precision Improvements
/// for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7): the discriminant
/// is computed from the distance of the centre to the ray's line, which keeps
/// grazing hits accurate, and the second root comes from Vieta's formula.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// The centre.
    pub center: Vec3,
    /// The radius (non-negative).
    pub radius: Real,
}

impl Sphere {
    /// A sphere at `center` with `radius`.
    pub fn new(center: Vec3, radius: Real) -> Self {
        Self { center, radius }
    }
}

impl Primitive for Sphere {
    type Shared = ();
    type RayData = ();
    type Four = ();

    #[inline(always)]
    fn ray_data(_: &Ray) {}

    #[inline(always)]
    fn bounds(&self, _: &()) -> Aabb {
        let r = Vec3::splat(self.radius);
        Aabb::new(self.center - r, self.center + r)
    }

    #[inline(always)]
    fn closest_hit(&self, _: &(), ray: &Ray, _: &(), t_min: Real, t_max: Real) -> Option<PrimHit> {
        let f = ray.origin - self.center;
        let d = ray.dir;
        let a = d.dot(d);
        let b = f.dot(d);
        let r2 = self.radius * self.radius;
        // The discriminant is a·(r² − |l|²) with l = f − (b/a)·d, the vector from
        // the centre to the nearest point of the line. Its sign is that of
        // a²r² − |a·f − b·d|², which needs no division: misses (most tests)
        // return here.
        let m = f * a - d * b;
        let miss = m.dot(m) - a * a * r2;
        if !(miss <= 0.0) {
            return None;
        }
        let l = f - d * (b / a);
        let disc = a * (r2 - l.dot(l));
        if !(disc >= 0.0) {
            return None;
        }
        let c = f.dot(f) - r2;
        let q = -(b + disc.sqrt().copysign(b));
        let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
        let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        let t = if t0 >= t_min && t0 <= t_max {
            t0
        } else if t1 >= t_min && t1 <= t_max {
            t1
        } else {
            return None;
        };
        Some(PrimHit::new(t, 0.0, 0.0))
    }

    /// Four spheres at a time: the miss test above in lanes, the same
    /// operations in the same order (so bit for bit the same verdict), then
    /// `closest_hit` for the spheres it does not reject.
    #[inline(always)]
    fn closest_hits(
        prims: &[Self],
        shared: &(),
        refs: &[u32],
        ray: &Ray,
        _: &(),
        t_min: Real,
        t_max: Real,
        best: u32,
        keep: &mut impl FnMut(u32, PrimHit) -> Real,
    ) {
        let (o, d) = (ray.origin, ray.dir);
        let a = d.dot(d);
        let dl = [d.x, d.y, d.z].map(Lanes::splat);
        let (al, aa) = (Lanes::splat(a), Lanes::splat(a * a));
        closest_hits_prefiltered(
            prims,
            shared,
            refs,
            ray,
            &(),
            t_min,
            t_max,
            Some(best),
            keep,
            |four| {
                let m = LaneMat::from_cols_array_2d(
                    &four.map(|s| [s.center.x, s.center.y, s.center.z, s.radius]),
                )
                .transpose();
                let f = [
                    Lanes::splat(o.x) - m.x_axis,
                    Lanes::splat(o.y) - m.y_axis,
                    Lanes::splat(o.z) - m.z_axis,
                ];
                let b = f[0] * dl[0] + f[1] * dl[1] + f[2] * dl[2];
                let r2 = m.w_axis * m.w_axis;
                let mv = [0, 1, 2].map(|k| f[k] * al - dl[k] * b);
                let miss = (mv[0] * mv[0] + mv[1] * mv[1] + mv[2] * mv[2]) - aa * r2;
                miss.cmple(Lanes::ZERO).bitmask()
            },
        );
    }

    /// The squared distance from the centre to the box against `r²`, with a
    /// little slack so that rounding never culls a touching sphere.
    fn overlaps_box(&self, _: &(), cell: &Aabb) -> bool {
        let q = self.center.clamp(cell.min, cell.max);
        let d2 = (q - self.center).length_squared();
        let r2 = self.radius * self.radius;
        d2 <= r2 * (1.0 + 1e-4) + Real::MIN_POSITIVE
    }
}

/// The frame of the watertight triangle test of a ray, computed once per
/// query (the triangle's `RayData`): the axes permuted so that the largest
/// direction component is z, `x`, `y` swapped when it is negative (the
/// winding is kept), and the shear factors that take the direction onto
/// +z; the origin's permuted coordinates and the factors also in four lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shear {
    /// `[kx, ky, kz]`.
    axes: [usize; 3],
    /// `[dir[kx]/dir[kz], dir[ky]/dir[kz], 1/dir[kz]]`.
    s: [Real; 3],
    /// `[o[kx], o[ky], o[kz]]`, each in four lanes.
    origin: [Lanes; 3],
    /// `[sx, sy]`, each in four lanes.
    s_lanes: [Lanes; 2],
}

impl Shear {
    /// The frame of `ray`.
    #[inline(always)]
    pub fn new(ray: &Ray) -> Self {
        let (d, a) = (ray.dir, ray.dir.abs());
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
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = ray.inv_dir[kz];
        let [sx, sy] = [d[kx] * sz, d[ky] * sz];
        let o = ray.origin;
        Self {
            axes: [kx, ky, kz],
            s: [sx, sy, sz],
            origin: [o[kx], o[ky], o[kz]].map(Lanes::splat),
            s_lanes: [sx, sy].map(Lanes::splat),
        }
    }

    /// Of four triangles, given per world axis `k` as each one's lanes
    /// `(v0[k], v1[k], v2[k], _)`, the mask of those whose edge functions
    /// do not have both signs with none zero: the first rejection of the
    /// scalar test, with the same operations in the same order.
    #[inline(always)]
    fn triangles_may_hit(&self, coord: impl Fn(usize) -> [Lanes; 4]) -> u32 {
        let [kx, ky, kz] = self.axes;
        let [ox, oy, oz] = self.origin;
        let [sx, sy] = self.s_lanes;
        let rows = |k: usize| {
            let [a, b, c, d] = coord(k);
            let m = LaneMat::from_cols(a, b, c, d).transpose();
            [m.x_axis, m.y_axis, m.z_axis]
        };
        let z = rows(kz).map(|c| c - oz);
        let [x, y] = [(rows(kx), ox, sx), (rows(ky), oy, sy)]
            .map(|(c, o, s)| [0, 1, 2].map(|i| (c[i] - o) - s * z[i]));
        let e = [
            x[2] * y[1] - y[2] * x[1],
            x[0] * y[2] - y[0] * x[2],
            x[1] * y[0] - y[1] * x[0],
        ];
        let (mut neg, mut pos, mut zero) = (0, 0, 0);
        for e in e {
            neg |= e.cmplt(Lanes::ZERO).bitmask();
            pos |= e.cmpgt(Lanes::ZERO).bitmask();
            zero |= e.cmpeq(Lanes::ZERO).bitmask();
        }
        !(neg & pos & !zero) & 0xf
    }
}

/// A triangle with the watertight intersection of Woop, Benthin & Wald,
/// "Watertight Ray/Triangle Intersection" (JCGT 2013), as the tracer's
/// triangle does it: the vertices, stored coordinate by coordinate, are moved
/// in 4-lane vectors into the ray's shear frame (where it runs along +z), and
/// the edge functions are evaluated in 2D (in f64 when one comes out exactly
/// 0), so a ray through a shared edge or vertex hits exactly one of the
/// triangles around it, or all of them at the same t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// `x0 x1 x2 y0 y1 y2 z0 z1 z2 0`.
    c: [Real; 10],
}

impl Triangle {
    /// A triangle from its vertices.
    pub fn new(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Self {
            c: [a.x, b.x, c.x, a.y, b.y, c.y, a.z, b.z, c.z, 0.0],
        }
    }

    /// The three vertices.
    #[inline]
    pub fn vertices(&self) -> [Vec3; 3] {
        let c = &self.c;
        [
            Vec3::new(c[0], c[3], c[6]),
            Vec3::new(c[1], c[4], c[7]),
            Vec3::new(c[2], c[5], c[8]),
        ]
    }

    /// Coordinate `k` of the three vertices in lanes 0..3.
    #[inline(always)]
    fn lanes(&self, k: usize) -> Lanes {
        Lanes::from_slice(&self.c[3 * k..3 * k + 4])
    }
}

impl Primitive for Triangle {
    type Shared = ();
    type RayData = Shear;
    type Four = ();

    #[inline(always)]
    fn ray_data(ray: &Ray) -> Shear {
        Shear::new(ray)
    }

    #[inline(always)]
    fn bounds(&self, _: &()) -> Aabb {
        let [a, b, c] = self.vertices();
        Aabb::new(a.min(b).min(c), a.max(b).max(c))
    }

    #[inline(always)]
    fn closest_hit(
        &self,
        _: &(),
        _: &Ray,
        shear: &Shear,
        t_min: Real,
        t_max: Real,
    ) -> Option<PrimHit> {
        use glam::Vec4Swizzles;
        let [kx, ky, kz] = shear.axes;
        let [ox, oy, oz] = shear.origin;
        let [sx, sy] = shear.s_lanes;
        let sz = shear.s[2];
        let z = self.lanes(kz) - oz;
        let x = (self.lanes(kx) - ox) - sx * z;
        let y = (self.lanes(ky) - oy) - sy * z;
        // Lanes 0, 1, 2: cx·by − cy·bx, ax·cy − ay·cx, bx·ay − by·ax.
        let mut e = x.zxyw() * y.yzxw() - y.zxyw() * x.yzxw();
        let any3 = |mask: u32| mask & 7 != 0;
        // Exactly on an edge: redo the edge functions with exact signs.
        if any3(e.cmpeq(Lanes::ZERO).bitmask()) {
            let [ax, bx, cx, _] = x.to_array().map(|r| r as f64);
            let [ay, by, cy, _] = y.to_array().map(|r| r as f64);
            e = Lanes::new(
                exact_difference(cx, by, cy, bx) as Real,
                exact_difference(ax, cy, ay, cx) as Real,
                exact_difference(bx, ay, by, ax) as Real,
                0.0,
            );
        }
        // One branch for "signs differ" (the common miss).
        if any3(e.cmplt(Lanes::ZERO).bitmask()) && any3(e.cmpgt(Lanes::ZERO).bitmask()) {
            return None;
        }
        let [u, v, w, _] = e.to_array();
        let det = u + v + w;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let [az, bz, cz, _] = z.to_array();
        let t_scaled = sz * (u * az + v * bz + w * cz);
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        if !(t >= t_min && t <= t_max) {
            return None;
        }
        Some(PrimHit::new(t, v * inv, w * inv))
    }

    /// Four triangles at a time: the edge functions of `closest_hit` in
    /// lanes (one triangle a lane, the same operations in the same order),
    /// rejecting the triangles whose edge functions have both signs and
    /// none zero, as `closest_hit` does first; the others go through
    /// `closest_hit`. A ray near a mesh rejects most triangles here.
    #[inline]
    fn closest_hits(
        prims: &[Self],
        shared: &(),
        refs: &[u32],
        ray: &Ray,
        shear: &Shear,
        t_min: Real,
        t_max: Real,
        best: u32,
        keep: &mut impl FnMut(u32, PrimHit) -> Real,
    ) {
        closest_hits_prefiltered(
            prims,
            shared,
            refs,
            ray,
            shear,
            t_min,
            t_max,
            Some(best),
            keep,
            |four| shear.triangles_may_hit(|k| four.map(|t| t.lanes(k))),
        );
    }

    /// Separating-axis test of the triangle against the box (Akenine-Möller
    /// 2001), with a relative tolerance on every comparison so that it errs
    /// on the side of "overlaps".
    fn overlaps_box(&self, _: &(), cell: &Aabb) -> bool {
        if !self.bounds(&()).overlaps(cell) {
            return false;
        }
        let c = cell.centroid();
        let h = (cell.max - cell.min) * 0.5;
        let v = self.vertices().map(|p| p - c);
        let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
        let scale = v
            .iter()
            .map(|p| p.abs().max_element())
            .fold(h.max_element(), Real::max);
        let tol = 1e-4 * scale + Real::MIN_POSITIVE;
        let axes = [Vec3::X, Vec3::Y, Vec3::Z];
        let separated = |axis: Vec3| -> bool {
            // Unit axes, so the tolerance is a length.
            let Some(axis) = axis.try_normalize() else {
                return false;
            };
            let p = v.map(|q| q.dot(axis));
            let r = h.x * axis.x.abs() + h.y * axis.y.abs() + h.z * axis.z.abs();
            let lo = p[0].min(p[1]).min(p[2]);
            let hi = p[0].max(p[1]).max(p[2]);
            lo > r + tol || hi < -r - tol
        };
        for ed in &e {
            for ax in &axes {
                if separated(ed.cross(*ax)) {
                    return false;
                }
            }
        }
        !separated(e[0].cross(e[1]))
    }
}

/// Either shape, as an enum (static dispatch, like the tracer's shapes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A sphere.
    Sphere(Sphere),
    /// A triangle.
    Triangle(Triangle),
}

impl Primitive for Shape {
    /// Nothing shared: the primitive holds all it needs.
    type Shared = ();

    /// The triangles' frame; spheres need nothing.
    type RayData = Shear;
    type Four = ();

    #[inline(always)]
    fn ray_data(ray: &Ray) -> Shear {
        Shear::new(ray)
    }

    #[inline(always)]
    fn bounds(&self, _: &()) -> Aabb {
        match self {
            Shape::Sphere(s) => s.bounds(&()),
            Shape::Triangle(t) => t.bounds(&()),
        }
    }
    #[inline(always)]
    fn closest_hit(
        &self,
        _: &(),
        ray: &Ray,
        shear: &Shear,
        t_min: Real,
        t_max: Real,
    ) -> Option<PrimHit> {
        match self {
            Shape::Sphere(s) => s.closest_hit(&(), ray, &(), t_min, t_max),
            Shape::Triangle(t) => t.closest_hit(&(), ray, shear, t_min, t_max),
        }
    }
    fn overlaps_box(&self, _: &(), cell: &Aabb) -> bool {
        match self {
            Shape::Sphere(s) => s.overlaps_box(&(), cell),
            Shape::Triangle(t) => t.overlaps_box(&(), cell),
        }
    }
}

/// `p·q − r·s` with its exact sign: in `f64` the products of `f32` values
/// are exact and the difference rounds once; with `f64` values, products
/// that round to the same value differ by their rounding errors, which
/// fused multiply–adds give exactly. (Without it, three collinear
/// vertices whose edge functions round to 0, 0 and a speck pass the sign
/// test with barycentrics (0, 0, 1): a hit at one vertex's depth, outside
/// the triangle's box, where a grid cannot find it.)
fn exact_difference(p: f64, q: f64, r: f64, s: f64) -> f64 {
    let d = p * q - r * s;
    if d != 0.0 || cfg!(not(feature = "f64")) {
        return d;
    }
    p.mul_add(q, -(p * q)) - r.mul_add(s, -(r * s))
}
