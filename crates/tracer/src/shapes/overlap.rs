//! Triangle–box overlap by the separating-axis theorem (Akenine-Möller,
//! "Fast 3D Triangle-Box Overlap Testing", JGT 2001).

use gridrt_bbox::{gamma, Aabb, Real, Vec3};

/// Whether the triangle `(p0, p1, p2)` touches the closed box.
///
/// Thirteen candidate axes: the box's three face normals, the triangle's
/// normal and the nine cross products of box axes with triangle edges. Any
/// axis on which the projections separate proves there is no overlap, even if
/// the axis itself was computed with rounding; only the projections must be
/// conservative, so each separation must exceed a rounding margin. The test
/// therefore never says `false` for a touching box (it may say `true` for a
/// box a few ULPs away).
#[must_use]
pub(crate) fn triangle_box(p0: Vec3, p1: Vec3, p2: Vec3, cell: &Aabb) -> bool {
    if cell.is_empty() {
        return false;
    }
    // Box face normals first: the triangle's bounds against the box (exact,
    // no arithmetic).
    let tmin = p0.min(p1).min(p2);
    let tmax = p0.max(p1).max(p2);
    if tmin.cmpgt(cell.max).any() || tmax.cmplt(cell.min).any() {
        return false;
    }
    let c = cell.centroid();
    let h = (cell.max - cell.min) * 0.5;
    let v = [p0 - c, p1 - c, p2 - c];
    // Size of the numbers involved, for the margins: the translation adds
    // γ(1)·(|p| + |c|) per coordinate.
    let mag = v[0].abs().max(v[1].abs()).max(v[2].abs()) + c.abs() + h;
    let separated = |axis: Vec3| -> bool {
        let p = [v[0].dot(axis), v[1].dot(axis), v[2].dot(axis)];
        let r = h.dot(axis.abs());
        let lo = p[0].min(p[1]).min(p[2]);
        let hi = p[0].max(p[1]).max(p[2]);
        let margin = gamma(8) * mag.dot(axis.abs()) + Real::MIN_POSITIVE;
        lo > r + margin || hi < -r - margin
    };
    let edges = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    for e in edges {
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            if separated(e.cross(axis)) {
                return false;
            }
        }
    }
    !separated(edges[0].cross(edges[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Aabb {
        Aabb::new(Vec3::ZERO, Vec3::ONE)
    }

    #[test]
    fn inside_touching_and_apart() {
        let b = unit();
        let inside = [
            Vec3::splat(0.2),
            Vec3::new(0.8, 0.2, 0.2),
            Vec3::new(0.2, 0.8, 0.5),
        ];
        assert!(triangle_box(inside[0], inside[1], inside[2], &b));
        // Lying in the face z = 1: touching counts.
        let face = [
            Vec3::new(0.2, 0.2, 1.0),
            Vec3::new(2.0, 0.2, 1.0),
            Vec3::new(0.2, 2.0, 1.0),
        ];
        assert!(triangle_box(face[0], face[1], face[2], &b));
        // A big triangle cutting through the box with every vertex outside.
        let cut = [
            Vec3::new(-5.0, -5.0, 0.5),
            Vec3::new(5.0, -5.0, 0.5),
            Vec3::new(0.0, 5.0, 0.5),
        ];
        assert!(triangle_box(cut[0], cut[1], cut[2], &b));
        // A triangle whose bounds overlap the box but which passes by a
        // corner: separated by its own plane x + y + z = 3.5.
        let corner = [
            Vec3::new(1.5, 1.0, 1.0),
            Vec3::new(1.0, 1.5, 1.0),
            Vec3::new(1.0, 1.0, 1.5),
        ];
        let tb = Aabb::from_points(corner);
        assert!(tb.overlaps(&b));
        assert!(!triangle_box(corner[0], corner[1], corner[2], &b));
    }

    proptest::proptest! {
        /// Never `false` for a box the triangle touches: any point of the
        /// triangle (sampled on a barycentric lattice) inside the box forces
        /// `true`.
        #[test]
        fn conservative_on_random_triangles(
            q in proptest::array::uniform9(-2.0f32..2.0),
            lo in proptest::array::uniform3(-1.0f32..0.5),
            size in proptest::array::uniform3(0.0f32..1.0),
        ) {
            let p = |i: usize| Vec3::new(q[3 * i] as Real, q[3 * i + 1] as Real, q[3 * i + 2] as Real);
            let lo = Vec3::new(lo[0] as Real, lo[1] as Real, lo[2] as Real);
            let b = Aabb::new(lo, lo + Vec3::new(size[0] as Real, size[1] as Real, size[2] as Real));
            let (p0, p1, p2) = (p(0), p(1), p(2));
            const N: u32 = 24;
            let mut touched = false;
            for i in 0..=N {
                for j in 0..=(N - i) {
                    let (u, v) = (i as Real / N as Real, j as Real / N as Real);
                    let x = p0 * (1.0 - u - v) + p1 * u + p2 * v;
                    touched |= b.contains(x);
                }
            }
            if touched {
                proptest::prop_assert!(triangle_box(p0, p1, p2, &b));
            }
        }
    }

    #[test]
    fn touching_a_corner_counts() {
        let b = unit();
        let t = [
            Vec3::ONE,
            Vec3::new(2.0, 1.0, 1.0),
            Vec3::new(1.0, 2.0, 3.0),
        ];
        assert!(triangle_box(t[0], t[1], t[2], &b));
        assert!(!triangle_box(t[0], t[1], t[2], &Aabb::EMPTY));
    }
}
