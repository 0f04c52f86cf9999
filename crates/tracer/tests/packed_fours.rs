//! A grid without cells keeps triangles and spheres packed four by four
//! (`Primitive::Four`) and tests them from the packing: its answers are
//! bit for bit those of `Exhaustive`, which gathers them, on lattice
//! scenes where rays pass through vertices and along edges and where
//! hits tie.

use gridrt_bbox::math::Lanes;
use gridrt_grid::{Accelerator, Exhaustive, Grid, GridConfig, Primitive, Ray, Real, Vec3};
use gridrt_tracer::{MeshTriangle, MeshVertices, Shear, Sphere, Triangle, TriangleFour};
use proptest::prelude::*;

/// A coordinate on a coarse lattice, so that vertices, edges and origins
/// coincide and direction components are exactly zero.
fn lattice() -> impl Strategy<Value = Real> {
    (-3i32..=3).prop_map(|i| i as Real * 0.5)
}

fn point() -> impl Strategy<Value = Vec3> {
    [lattice(), lattice(), lattice()].prop_map(Vec3::from_array)
}

fn ray() -> impl Strategy<Value = Ray> {
    (point(), point())
        .prop_filter("a direction", |(_, d)| *d != Vec3::ZERO)
        .prop_map(|(o, d)| Ray::new(o * 3.0, d))
}

/// A sound grid (its packing included) with the same answers, hit for
/// hit: primitive, `t`, `u` and `v` bit for bit, and the same any-hit
/// verdicts over two ranges.
fn same<P: Primitive>(
    grid: &Grid<P>,
    ex: &Exhaustive<P>,
    rays: &[Ray],
) -> Result<(), TestCaseError> {
    prop_assert_eq!(grid.check_invariants(), Ok(()));
    let (mut gs, mut es) = (grid.scratch(), ex.scratch());
    for r in rays {
        let g = grid.closest_hit(r, 0.0, Real::INFINITY, &mut gs);
        let e = ex.closest_hit(r, 0.0, Real::INFINITY, &mut es);
        let bits = |h: Option<gridrt_grid::Hit>| {
            h.map(|h| (h.prim, h.t.to_bits(), h.u.to_bits(), h.v.to_bits()))
        };
        prop_assert_eq!(bits(g), bits(e), "closest hit of {:?}", r);
        for t_max in [1.0, Real::INFINITY] {
            prop_assert_eq!(
                grid.any_hit(r, 0.0, t_max, &mut gs),
                ex.any_hit(r, 0.0, t_max, &mut es),
                "any hit of {:?} up to {}",
                r,
                t_max
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn packed_triangles_answer_as_exhaustive(
        tris in prop::collection::vec([point(), point(), point()], 1..=40),
        rays in prop::collection::vec(ray(), 32),
    ) {
        let prims: Vec<Triangle> = tris.iter().map(|&[a, b, c]| Triangle::new(a, b, c)).collect();
        let grid = Grid::build(prims.clone(), &GridConfig::default());
        prop_assert_eq!(grid.stats().cells, 1);
        same(&grid, &Exhaustive::new(prims), &rays)?;
    }

    #[test]
    fn packed_mesh_triangles_answer_as_exhaustive(
        verts in prop::collection::vec(point(), 3..=12),
        faces in prop::collection::vec([0u32..12, 0u32..12, 0u32..12], 1..=40),
        rays in prop::collection::vec(ray(), 32),
    ) {
        let n = verts.len() as u32;
        let verts = MeshVertices::new(verts);
        let faces: Vec<[u32; 3]> = faces.iter().map(|f| f.map(|i| i % n)).collect();
        let tris = MeshTriangle::from_indices(&verts, &faces).unwrap();
        let grid = Grid::build_shared(tris.clone(), verts.clone(), &GridConfig::default());
        same(&grid, &Exhaustive::with_shared(tris, verts), &rays)?;
    }

    #[test]
    fn packed_spheres_answer_as_exhaustive(
        balls in prop::collection::vec((point(), 1i32..=4), 1..=40),
        rays in prop::collection::vec(ray(), 32),
    ) {
        let prims: Vec<Sphere> = balls.iter().map(|&(c, r)| Sphere::new(c, r as Real * 0.25)).collect();
        let grid = Grid::build(prims.clone(), &GridConfig::default());
        same(&grid, &Exhaustive::new(prims), &rays)?;
    }

    /// The packed rows give, lane by lane, the verdict of the gathered
    /// ones (`Shear::triangles_may_hit`); a lane without a triangle may
    /// say anything (callers mask it).
    #[test]
    fn packed_rows_reject_as_gathered_ones(
        tris in prop::collection::vec([point(), point(), point()], 1..=4),
        r in ray(),
    ) {
        let shear = Shear::new(&r);
        let packed = shear.four_may_hit(&TriangleFour::new(std::array::from_fn(|j| tris.get(j).copied())));
        let gathered = shear.triangles_may_hit(|k| {
            std::array::from_fn(|j| {
                let [a, b, c] = tris[j.min(tris.len() - 1)];
                Lanes::new(a[k], b[k], c[k], 0.0)
            })
        });
        let lanes = (1u32 << tris.len()) - 1;
        prop_assert_eq!(packed & lanes, gathered & lanes);
    }
}
