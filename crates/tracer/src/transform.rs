//! Affine transforms of instances: a 3×3 linear part and a translation,
//! applied to points, directions and normals, with pbrt-v4's bound on the
//! rounding error a transformed point carries.

use gridrt_bbox::{gamma, Aabb, Real, Vec3};

/// The map `p ↦ L·p + t` (`L` the columns `cols`, `t` the translation):
/// an instance's object-to-world transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine {
    /// The columns of the linear part: the images of the x, y and z axes.
    pub cols: [Vec3; 3],
    /// The translation: the image of the origin.
    pub translation: Vec3,
}

impl Default for Affine {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Affine {
    /// The identity.
    pub const IDENTITY: Self = Self {
        cols: [Vec3::X, Vec3::Y, Vec3::Z],
        translation: Vec3::ZERO,
    };

    /// A translation by `t`.
    #[must_use]
    pub fn translation(t: Vec3) -> Self {
        Self {
            translation: t,
            ..Self::IDENTITY
        }
    }

    /// The image of point `p`.
    #[inline]
    #[must_use]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.vector(p) + self.translation
    }

    /// The image of direction `v` (the translation left out).
    #[inline]
    #[must_use]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.cols[0] * v.x + self.cols[1] * v.y + self.cols[2] * v.z
    }

    /// `Lᵀ·v`: applied to the inverse transform, the map of normals.
    #[inline]
    #[must_use]
    pub fn transpose_vector(&self, v: Vec3) -> Vec3 {
        Vec3::new(
            self.cols[0].dot(v),
            self.cols[1].dot(v),
            self.cols[2].dot(v),
        )
    }

    /// The determinant of the linear part (negative for a mirror).
    #[must_use]
    pub fn determinant(&self) -> Real {
        self.cols[0].dot(self.cols[1].cross(self.cols[2]))
    }

    /// Whether every entry is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.cols.iter().all(|c| c.is_finite()) && self.translation.is_finite()
    }

    /// The inverse map, computed in f64; `None` when an entry is not finite
    /// or the linear part is singular relative to its scale (a zero scale,
    /// a flattening matrix).
    #[must_use]
    pub fn inverse(&self) -> Option<Affine> {
        if !self.is_finite() {
            return None;
        }
        let c = self.cols.map(to_dvec3);
        let m = glam::DMat3::from_cols(c[0], c[1], c[2]);
        let det = m.determinant();
        // Largest entries, not lengths: their squares would overflow first.
        let scale = c.iter().map(|v| v.abs().max_element()).product::<f64>();
        if det == 0.0 || !det.is_finite() || det.abs() <= scale * 1e-12 {
            return None;
        }
        let inv = m.inverse();
        let t = -(inv * to_dvec3(self.translation));
        let out = Affine {
            cols: [inv.x_axis, inv.y_axis, inv.z_axis].map(from_dvec3),
            translation: from_dvec3(t),
        };
        out.is_finite().then_some(out)
    }

    /// The image of `p` together with a per-axis bound on the image's
    /// absolute error, given the bound `p_err` on the error of `p` itself
    /// (pbrt-v4's `Transform::operator()(Point3fi)`).
    #[inline]
    #[must_use]
    pub fn point_with_error(&self, p: Vec3, p_err: Vec3) -> (Vec3, Vec3) {
        let abs = Affine {
            cols: self.cols.map(Vec3::abs),
            translation: self.translation.abs(),
        };
        let own = abs.point(p.abs()) * gamma(3);
        let carried = abs.vector(p_err) * (1.0 + gamma(3));
        (self.point(p), own + carried)
    }

    /// Whether the images of every point of `b` are finite (true for an
    /// empty box).
    #[must_use]
    pub fn keeps_finite(&self, b: &Aabb) -> bool {
        let p = self.bounds(b);
        b.is_empty() || (p.min.is_finite() && p.max.is_finite())
    }

    /// A box holding the images of every point of `b` (its eight corners'
    /// images, widened by their rounding error).
    #[must_use]
    pub fn bounds(&self, b: &Aabb) -> Aabb {
        let mut out = Aabb::EMPTY;
        for k in 0..8 {
            let pick = |bit: usize, lo: Real, hi: Real| if k & bit == 0 { lo } else { hi };
            let corner = Vec3::new(
                pick(1, b.min.x, b.max.x),
                pick(2, b.min.y, b.max.y),
                pick(4, b.min.z, b.max.z),
            );
            let (p, err) = self.point_with_error(corner, Vec3::ZERO);
            out = out.grow(p - err).grow(p + err);
        }
        out
    }
}

#[inline]
#[allow(clippy::useless_conversion)] // f64 → f64 under the `f64` feature
fn to_dvec3(v: Vec3) -> glam::DVec3 {
    glam::DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
}

#[inline]
fn from_dvec3(v: glam::DVec3) -> Vec3 {
    Vec3::new(v.x as Real, v.y as Real, v.z as Real)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Affine {
        Affine {
            cols: [
                Vec3::new(0.0, 2.0, 0.0),
                Vec3::new(-1.0, 0.0, 0.0),
                Vec3::new(0.0, 0.0, -3.0),
            ],
            translation: Vec3::new(5.0, -1.0, 2.0),
        }
    }

    #[test]
    fn inverse_undoes_the_map() {
        let a = sample();
        let inv = a.inverse().unwrap();
        for p in [
            Vec3::ZERO,
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-7.0, 0.5, 1e3),
        ] {
            let back = inv.point(a.point(p));
            assert!((back - p).abs().max_element() <= 1e-4 * (1.0 + p.abs().max_element()));
        }
        assert!(a.determinant() < 0.0);
    }

    #[test]
    fn singular_and_non_finite_maps_have_no_inverse() {
        let flat = Affine {
            cols: [Vec3::X, Vec3::Y, Vec3::ZERO],
            ..Affine::IDENTITY
        };
        assert!(flat.inverse().is_none());
        let nan = Affine::translation(Vec3::new(Real::NAN, 0.0, 0.0));
        assert!(nan.inverse().is_none());
        // Tiny but regular scales are invertible.
        let tiny = Affine {
            cols: [Vec3::X * 1e-6, Vec3::Y * 1e-6, Vec3::Z * 1e-6],
            ..Affine::IDENTITY
        };
        assert!(tiny.inverse().is_some());
    }

    #[test]
    fn normals_map_by_the_inverse_transpose() {
        // A shear along x keeps the plane z = 0 and its normal.
        let shear = Affine {
            cols: [Vec3::X, Vec3::Y, Vec3::new(3.0, 0.0, 1.0)],
            ..Affine::IDENTITY
        };
        let inv = shear.inverse().unwrap();
        // Normal of the plane x = z, i.e. (1, 0, -1): its image is the
        // normal of the image plane.
        let n = inv.transpose_vector(Vec3::new(1.0, 0.0, -1.0));
        let (p, q) = (Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 0.0));
        assert!(n.dot(shear.vector(p)).abs() < 1e-5);
        assert!(n.dot(shear.vector(q)).abs() < 1e-5);
    }

    #[test]
    fn bounds_hold_every_transformed_point() {
        let a = sample();
        let b = Aabb::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 0.5, 4.0));
        let out = a.bounds(&b);
        for k in 0..=10 {
            let f = k as Real / 10.0;
            let p = b.min + (b.max - b.min) * Vec3::new(f, 1.0 - f, f * f);
            let q = a.point(p);
            assert!(q.cmpge(out.min).all() && q.cmple(out.max).all());
        }
    }
}
