use crate::math::{LaneMat, Lanes, Real, Vec3};

/// A ray `origin + t·dir`.
///
/// `dir` is **not** normalised: `t` is measured in units of `dir`. The
/// reciprocal `inv_dir` is computed once when the ray is built; a zero
/// component (of either sign) gives an infinite reciprocal of the same sign,
/// which the slab test and the grid traversal handle on purpose.
///
/// The frame of the watertight ray–triangle test ([`Shear`]) is computed
/// once here too, so that a triangle test does no per-ray work.
///
/// The valid `t` range is not part of the ray: queries take it as arguments
/// (pbrt's `Intersect(ray, tMax)`), so one ray can be reused across ranges.
///
/// ```
/// use gridrt_bbox::{Ray, Vec3};
/// let r = Ray::new(Vec3::ZERO, Vec3::new(2.0, 0.0, -0.0));
/// assert_eq!(r.at(1.5), Vec3::new(3.0, 0.0, 0.0));
/// assert_eq!(r.inv_dir.z, gridrt_bbox::Real::NEG_INFINITY);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(from = "RayParts", into = "RayParts")
)]
pub struct Ray {
    /// Where the ray starts (t = 0).
    pub origin: Vec3,
    /// The direction; not normalised.
    pub dir: Vec3,
    /// `1 / dir`, per component, with IEEE semantics (`1/±0 = ±∞`).
    pub inv_dir: Vec3,
    /// The frame of the watertight triangle test.
    pub shear: Shear,
}

/// The ray's frame for the watertight ray–triangle test of Woop, Benthin &
/// Wald ("Watertight Ray/Triangle Intersection", JCGT 2013), in which the
/// ray runs along +z: the axes are permuted so that the largest direction
/// component becomes z, and x, y are sheared so that the direction has none:
/// with `(x, y, z)` the permuted `p − origin`, a point `p` sits at
/// `(x − sx·z, y − sy·z, sz·z)`, and the ray's points at `(0, 0, t)`.
///
/// ```
/// use gridrt_bbox::{Ray, Vec3};
/// let r = Ray::new(Vec3::ZERO, Vec3::new(1.0, -4.0, 2.0));
/// // y is the largest and negative: it becomes z, and x, y swap to keep the winding.
/// assert_eq!(r.shear.axes, [0, 2, 1]);
/// assert_eq!(r.shear.s, [-0.25, -0.5, -0.25]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shear {
    /// `[kx, ky, kz]`: `kz` is the axis of the largest `|dir|` component (the
    /// later axis on ties), `kx`, `ky` the next two in cyclic order, swapped
    /// when `dir[kz] < 0` so that the triangles' winding is kept.
    pub axes: [usize; 3],
    /// `[dir[kx]·sz, dir[ky]·sz, sz]` with `sz = 1 / dir[kz]`.
    pub s: [Real; 3],
}

impl Shear {
    fn new(dir: Vec3, inv_dir: Vec3) -> Self {
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
        Self {
            axes: [kx, ky, kz],
            s: [dir[kx] * sz, dir[ky] * sz, sz],
        }
    }
}

/// What a [`Ray`] is serialised as: the rest is derived from it.
#[cfg(feature = "serde")]
#[derive(serde::Serialize, serde::Deserialize)]
struct RayParts {
    origin: Vec3,
    dir: Vec3,
}

#[cfg(feature = "serde")]
impl From<RayParts> for Ray {
    fn from(p: RayParts) -> Self {
        Self::new(p.origin, p.dir)
    }
}

#[cfg(feature = "serde")]
impl From<Ray> for RayParts {
    fn from(r: Ray) -> Self {
        Self {
            origin: r.origin,
            dir: r.dir,
        }
    }
}

impl Ray {
    /// Builds a ray and precomputes the reciprocal direction.
    ///
    /// `dir` is stored as given (not normalised); it may have zero
    /// components of either sign.
    ///
    /// ```
    /// use gridrt_bbox::{Ray, Real, Vec3};
    /// let r = Ray::new(Vec3::ONE, Vec3::new(4.0, -0.0, 0.5));
    /// assert_eq!(r.inv_dir, Vec3::new(0.25, Real::NEG_INFINITY, 2.0));
    /// ```
    #[inline]
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        let inv_dir = Vec3::ONE / dir;
        Self {
            origin,
            dir,
            inv_dir,
            shear: Shear::new(dir, inv_dir),
        }
    }

    /// The point at parameter `t`: `origin + t·dir`.
    ///
    /// ```
    /// use gridrt_bbox::{Ray, Vec3};
    /// let r = Ray::new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0));
    /// assert_eq!(r.at(0.0), r.origin);
    /// assert_eq!(r.at(-0.5), Vec3::new(1.0, -1.0, 0.0));
    /// ```
    #[inline]
    #[must_use]
    pub fn at(&self, t: Real) -> Vec3 {
        self.origin + self.dir * t
    }

    /// The ray's [`Shear`] frame in four lanes, made once per ray, for
    /// testing four triangles at a time ([`ShearLanes::triangles_may_hit`]).
    #[inline]
    #[must_use]
    pub fn shear_lanes(&self) -> ShearLanes {
        let [kx, ky, kz] = self.shear.axes;
        let o: &[Real; 3] = self.origin.as_ref();
        let [sx, sy, _] = self.shear.s;
        ShearLanes {
            axes: self.shear.axes,
            origin: [o[kx], o[ky], o[kz]].map(Lanes::splat),
            s: [sx, sy].map(Lanes::splat),
        }
    }
}

/// A ray's [`Shear`] frame splatted into four lanes ([`Ray::shear_lanes`]).
#[derive(Clone, Copy, Debug)]
pub struct ShearLanes {
    axes: [usize; 3],
    /// The origin's permuted coordinates.
    origin: [Lanes; 3],
    /// `[sx, sy]`.
    s: [Lanes; 2],
}

impl ShearLanes {
    /// Of four triangles, the mask (bit `j` for triangle `j`) of those that
    /// the watertight test's edge functions do not reject: `coord(k)` gives,
    /// for world axis `k`, each triangle's lanes `(v0[k], v1[k], v2[k], _)`,
    /// and a triangle is rejected when its three edge functions have both
    /// signs and none is zero, as the scalar test rejects it first.
    /// The operations are the scalar test's, in the same order, so each
    /// lane's verdict is bit for bit the scalar one.
    ///
    /// ```
    /// use gridrt_bbox::math::Lanes;
    /// use gridrt_bbox::{Ray, Real, Vec3};
    /// let r = Ray::new(Vec3::new(0.25, 0.25, 1.0), Vec3::new(0.0, 0.0, -1.0));
    /// // The unit right triangle in z = 0, moved along x by `dx`: per axis,
    /// // that coordinate of its three vertices.
    /// let tri = |dx: Real| {
    ///     [
    ///         Lanes::new(dx, 1.0 + dx, dx, 0.0),
    ///         Lanes::new(0.0, 0.0, 1.0, 0.0),
    ///         Lanes::ZERO,
    ///     ]
    /// };
    /// // Under the ray, beside it, under it again, beside it.
    /// let four = [tri(0.0), tri(2.0), tri(-0.5), tri(-3.0)];
    /// let mask = r.shear_lanes().triangles_may_hit(|k| four.map(|t| t[k]));
    /// assert_eq!(mask, 0b0101);
    /// ```
    #[inline(always)]
    #[must_use]
    pub fn triangles_may_hit(&self, coord: impl Fn(usize) -> [Lanes; 4]) -> u32 {
        let [kx, ky, kz] = self.axes;
        let [ox, oy, oz] = self.origin;
        let [sx, sy] = self.s;
        // Coordinate `k` of vertex `i` of the four triangles: row `i`.
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
        let [neg, pos, zero] = [Lanes::cmplt, Lanes::cmpgt, Lanes::cmpeq]
            .map(|f| e.iter().fold(0, |m, &e| m | f(e, Lanes::ZERO).bitmask()));
        !(neg & pos & !zero) & 0xf
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inv_dir_keeps_the_sign_of_zero() {
        let r = Ray::new(Vec3::ZERO, Vec3::new(0.0, -0.0, 2.0));
        assert_eq!(r.inv_dir.x, Real::INFINITY);
        assert_eq!(r.inv_dir.y, Real::NEG_INFINITY);
        assert_eq!(r.inv_dir.z, 0.5);
    }

    #[test]
    fn inv_dir_of_a_tiny_denormal_overflows_to_infinity() {
        let tiny = Real::MIN_POSITIVE / 16.0;
        assert!(tiny > 0.0 && !tiny.is_normal());
        let r = Ray::new(Vec3::ZERO, Vec3::new(tiny, -tiny, 1.0));
        assert_eq!(r.inv_dir.x, Real::INFINITY);
        assert_eq!(r.inv_dir.y, Real::NEG_INFINITY);
    }

    /// `p` in the shear frame, as the watertight triangle test computes it.
    fn sheared(r: &Ray, p: Vec3) -> [Real; 3] {
        let [kx, ky, kz] = r.shear.axes;
        let [sx, sy, sz] = r.shear.s;
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
            let [kx, ky, kz] = r.shear.axes;
            let mut k = r.shear.axes;
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

    #[test]
    fn dir_is_not_normalised_and_at_follows_it() {
        let d = Vec3::new(3.0, 0.0, 4.0);
        let r = Ray::new(Vec3::new(1.0, 1.0, 1.0), d);
        assert_eq!(r.dir, d);
        assert_eq!(r.at(2.0), Vec3::new(7.0, 1.0, 9.0));
        assert_eq!(r.at(0.0), r.origin);
    }
}
