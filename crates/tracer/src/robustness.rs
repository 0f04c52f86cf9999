//! Switches that turn the renderer's robust defaults off, so that what
//! each costs, and what it saves, can be measured: the triangle test and
//! the offset of secondary rays' origins. (The slab test, mailboxing and
//! exact insertion are the grid's: [`gridrt_grid::GridConfig`].)
//!
//! Each is chosen once per render: the triangle test by the primitive type
//! the accelerator is built over, the offset by one branch on a constant
//! per secondary ray (no dynamic dispatch).

use crate::float::offset_ray_origin;
use crate::prepare::Prims;
use crate::shapes::{MtTriangle, Shape};
use gridrt_bbox::{Real, Vec3};

/// Which ray–triangle test the renderer uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TriangleTest {
    /// The watertight test of Woop, Benthin & Wald ([`crate::Triangle`]):
    /// no ray passes between triangles that share an edge, at any scale
    /// and direction length. The default.
    #[default]
    Watertight,
    /// Möller & Trumbore's test with its fixed epsilon ([`MtTriangle`]):
    /// rays through shared edges and vertices can leak, and triangles whose
    /// determinant is below 10⁻⁶ (small or thin triangles, short
    /// directions) are missed.
    MollerTrumbore,
}

/// How a secondary ray's origin leaves the surface it starts on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum RayOffset {
    /// Along the normal by a bound on the hit point's rounding error, plus
    /// one ulp (pbrt-v4's `OffsetRayOrigin`): scales with the geometry, so
    /// no acne and no leak at any scale or distance from the origin. The
    /// default.
    #[default]
    ErrorBound,
    /// Along the normal by this fixed distance in world units, the
    /// textbook `kEpsilon`. Too small for the scene's coordinates (far from
    /// the origin, or large scenes): the ray starts under the surface and
    /// hits it again (shadow acne, black speckles). Too large for its
    /// details (small scenes, thin objects): the ray starts beyond a nearby
    /// occluder or through a thin wall (light leaks, lost contact shadows).
    Fixed(Real),
}

impl RayOffset {
    /// The origin of a ray leaving the surface point `p` (error bound
    /// `p_err`, geometric normal `n` of either orientation) along `w`.
    #[inline]
    #[must_use]
    pub(crate) fn origin(self, p: Vec3, p_err: Vec3, n: Vec3, w: Vec3) -> Vec3 {
        match self {
            RayOffset::ErrorBound => offset_ray_origin(p, p_err, n, w),
            RayOffset::Fixed(eps) => {
                let side = if w.dot(n) < 0.0 { -eps } else { eps };
                p + n * side
            }
        }
    }
}

/// The primitives with the triangles of `test`: with Möller–Trumbore every
/// [`Shape::Triangle`] becomes a [`Shape::MtTriangle`].
pub(crate) fn with_triangle_test(prims: Prims, test: TriangleTest) -> Prims {
    match (prims, test) {
        (Prims::Triangles(v), TriangleTest::MollerTrumbore) => Prims::Shapes(
            v.into_iter()
                .map(|t| Shape::MtTriangle(MtTriangle(t)))
                .collect(),
        ),
        (Prims::Mesh(verts, v), TriangleTest::MollerTrumbore) => Prims::Shapes(
            v.iter()
                .map(|t| Shape::MtTriangle(MtTriangle(t.to_triangle(&verts))))
                .collect(),
        ),
        (Prims::Shapes(v), TriangleTest::MollerTrumbore) => Prims::Shapes(
            v.into_iter()
                .map(|s| match s {
                    Shape::Triangle(t) => Shape::MtTriangle(MtTriangle(t)),
                    other => other,
                })
                .collect(),
        ),
        (p, _) => p,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_offset_moves_by_eps_to_the_side_of_w() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let n = Vec3::Y;
        let up = RayOffset::Fixed(0.5).origin(p, Vec3::ZERO, n, Vec3::new(0.3, 1.0, 0.0));
        assert_eq!(up, Vec3::new(1.0, 2.5, 3.0));
        let down = RayOffset::Fixed(0.5).origin(p, Vec3::ZERO, -n, -Vec3::Y);
        assert_eq!(down, Vec3::new(1.0, 1.5, 3.0));
        // The error bound moves by the bound and one ulp.
        let e = RayOffset::ErrorBound.origin(p, Vec3::ZERO, n, Vec3::Y);
        assert!(e.y > 2.0 && e.y - 2.0 < 1e-5 && e.x == 1.0 && e.z == 3.0);
    }
}
