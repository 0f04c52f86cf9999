//! Triangles that refer to a shared vertex array: the grid primitive of
//! meshes when memory matters more than the last few percent of speed.

use super::triangle::{intersect_lanes, surface_point};
use super::{overlap, LazyShear, Shear, Surface, SurfacePoint, TriangleFour};
use gridrt_bbox::math::{LaneMat, Lanes};
use gridrt_bbox::{Aabb, Ray, Real, Vec3};
use gridrt_grid::{any_hits_prefiltered, closest_hits_prefiltered, PrimHit, Primitive};

/// The vertex positions that [`MeshTriangle`]s refer to: the
/// [`Primitive::Shared`] of a grid of them, stored once beside it.
///
/// Each position takes one 4-lane vector (`x, y, z, 0`), so that the
/// triangle test loads a vertex in one aligned load.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshVertices(Vec<Lanes>);

impl MeshVertices {
    /// The vertex array of `positions`.
    #[must_use]
    pub fn new(positions: impl IntoIterator<Item = Vec3>) -> Self {
        Self(
            positions
                .into_iter()
                .map(|p| Lanes::new(p.x, p.y, p.z, 0.0))
                .collect(),
        )
    }

    /// Appends `positions` and returns the index of the first: the offset
    /// to add to the indices of the mesh they come from.
    pub fn append(&mut self, positions: &[Vec3]) -> u32 {
        let first = self.0.len() as u32;
        self.0
            .extend(positions.iter().map(|p| Lanes::new(p.x, p.y, p.z, 0.0)));
        first
    }

    /// The array renumbered ([`Self::renumber`]) in the spatial order of
    /// `tris` ([`spatial_order`](gridrt_grid::spatial_order)), `tris`
    /// rewritten to match.
    #[must_use]
    pub fn in_spatial_order(self, tris: &mut [MeshTriangle]) -> Self {
        let order = gridrt_grid::spatial_order_iter(tris, &self);
        self.renumber(tris, order).0
    }

    /// How many vertices there are.
    #[must_use]
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether there is none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Vertex `i`.
    ///
    /// # Panics
    ///
    /// If there is no vertex `i`.
    #[inline(always)]
    #[must_use]
    pub fn get(&self, i: u32) -> Vec3 {
        self.0[i as usize].truncate()
    }

    /// Vertex `i` as `(x, y, z, 0)`.
    #[inline(always)]
    fn lanes(&self, i: u32) -> Lanes {
        self.0[i as usize]
    }

    /// Asks the CPU for the vertices of the triangles in slots `refs[4..]`
    /// of `prims`, before a cell's triangles are tested four by four.
    ///
    /// Each triangle's test waits on two dependent loads, its indices and
    /// then its vertices; tested in turn, a cell whose data is not cached
    /// (as for rays that bounce off a large mesh) pays those waits one
    /// group of four after the other. Asked for all at once, the loads
    /// overlap. The first four are left out: their test starts at once.
    #[inline(always)]
    fn prefetch_cell(&self, prims: &[MeshTriangle], refs: &[u32]) {
        for &r in refs.get(4..).unwrap_or_default() {
            if let Some(t) = prims.get(r as usize) {
                for i in t.indices() {
                    // A prefetch never faults: the address need not be valid.
                    gridrt_grid::mem::prefetch_ptr(self.0.as_ptr().wrapping_add(i as usize));
                }
            }
        }
    }

    /// Bytes of the array.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.0.len() * std::mem::size_of::<Lanes>()
    }

    /// The vertices in the order in which `tris`, taken in `order` (a
    /// permutation of their indices, such as
    /// [`spatial_order`](gridrt_grid::spatial_order)), first use them,
    /// with the triangles' indices rewritten to match; unused vertices are
    /// dropped. Returns the new array and the new index of each old vertex
    /// (`u32::MAX` for a dropped one), for whatever else is kept per
    /// vertex (normals, texture coordinates).
    ///
    /// In a spatial order, the vertices of neighbouring triangles end up
    /// side by side, so that the triangles of one grid cell load few
    /// cache lines, whatever order the file had. The vertices move in
    /// place, and `order` (read once, as
    /// [`spatial_order_iter`](gridrt_grid::spatial_order_iter) gives it) is
    /// freed before they do: no second array is made.
    ///
    /// # Panics
    ///
    /// If a triangle does not belong to this array.
    #[must_use]
    pub fn renumber(
        mut self,
        tris: &mut [MeshTriangle],
        order: impl IntoIterator<Item = u32>,
    ) -> (Self, Vec<u32>) {
        let mut new_of = vec![u32::MAX; self.0.len()];
        let mut kept = 0;
        for t in order {
            let t = &mut tris[t as usize];
            t.v = t.v.map(|i| {
                let n = &mut new_of[i as usize];
                if *n == u32::MAX {
                    *n = kept;
                    kept += 1;
                }
                *n
            });
        }
        // Swaps along the permutation's cycles: each swap puts one vertex
        // in its place for good; dropped vertices end up past the kept.
        let mut to = new_of.clone();
        for i in 0..to.len() {
            while to[i] != u32::MAX && to[i] as usize != i {
                let j = to[i] as usize;
                self.0.swap(i, j);
                to.swap(i, j);
            }
        }
        self.0.truncate(kept as usize);
        self.0.shrink_to_fit();
        (self, new_of)
    }
}

/// A triangle given by the indices of its vertices in a [`MeshVertices`]
/// (12 bytes, where a [`Triangle`](super::Triangle) holds its own 40):
/// the triangle of pbrt-v4 and of Embree's indexed meshes.
///
/// Its ray test is the watertight test of [`Triangle`](super::Triangle),
/// bit for bit: the vertices are gathered into the same lanes and go
/// through the same operations, so a grid of mesh triangles answers
/// exactly what a grid of their copies does.
///
/// ```
/// use gridrt_grid::{Accelerator, Grid, GridConfig, Ray, Real, Vec3};
/// use gridrt_tracer::{MeshTriangle, MeshVertices};
/// // A unit square of two triangles sharing an edge.
/// let verts = MeshVertices::new([Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]);
/// let tris = MeshTriangle::from_indices(&verts, &[[0, 1, 2], [0, 2, 3]]).unwrap();
/// let grid = Grid::build_shared(tris, verts, &GridConfig::default());
/// let ray = Ray::new(Vec3::new(0.25, 0.5, 1.0), -Vec3::Z);
/// let hit = grid.closest_hit(&ray, 0.0, Real::INFINITY, &mut grid.scratch()).unwrap();
/// assert_eq!((hit.prim, hit.t), (1, 1.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshTriangle {
    /// The vertex indices.
    v: [u32; 3],
}

impl MeshTriangle {
    /// The most vertices a mesh of them may have (`u32::MAX` is kept for
    /// "no vertex" in [`MeshVertices::renumber`]).
    pub const MAX_VERTICES: usize = u32::MAX as usize;

    /// The triangle with vertices `v` of `verts`, or `None` if an index is
    /// out of range or the array has more than [`Self::MAX_VERTICES`].
    #[must_use]
    pub fn new(verts: &MeshVertices, v: [u32; 3]) -> Option<Self> {
        if verts.len() > Self::MAX_VERTICES || v.iter().any(|&i| i as usize >= verts.len()) {
            return None;
        }
        Some(Self { v })
    }

    /// The triangles of an index array, or `None` if an index is out of
    /// range (see [`Self::new`]).
    #[must_use]
    pub fn from_indices(verts: &MeshVertices, indices: &[[u32; 3]]) -> Option<Vec<Self>> {
        indices.iter().map(|&v| Self::new(verts, v)).collect()
    }

    /// The vertex indices.
    #[inline]
    #[must_use]
    pub fn indices(&self) -> [u32; 3] {
        self.v
    }

    /// The vertices, from the array the triangle was made with.
    #[inline]
    #[must_use]
    pub fn vertices(&self, verts: &MeshVertices) -> [Vec3; 3] {
        self.indices().map(|i| verts.get(i))
    }

    /// The triangle as a [`Triangle`](super::Triangle) holding copies of
    /// its vertices.
    #[must_use]
    pub fn to_triangle(&self, verts: &MeshVertices) -> super::Triangle {
        let [a, b, c] = self.vertices(verts);
        super::Triangle::new(a, b, c)
    }

    /// Vertex `i` (0, 1 or 2) as `(x, y, z, 0)`.
    #[inline(always)]
    fn vertex_lanes(&self, verts: &MeshVertices, i: usize) -> Lanes {
        verts.lanes(self.v[i])
    }

    /// Which of `four` the ray of `shear` may hit
    /// ([`Shear::triangles_may_hit_by_vertex`]): the prefilter of
    /// `closest_hits` and `any_hits`. The vertices are gathered written
    /// out, since `array::map` can stay a call in the hot loop.
    #[inline(always)]
    fn may_hit_four(four: [&Self; 4], verts: &MeshVertices, shear: &Shear) -> u32 {
        shear.triangles_may_hit_by_vertex(|i| {
            [
                four[0].vertex_lanes(verts, i),
                four[1].vertex_lanes(verts, i),
                four[2].vertex_lanes(verts, i),
                four[3].vertex_lanes(verts, i),
            ]
        })
    }
}

impl Primitive for MeshTriangle {
    /// The vertex array.
    type Shared = MeshVertices;

    /// The ray's shear frame, made at the query's first triangle test
    /// ([`LazyShear`]).
    type RayData = LazyShear;

    /// Four triangles' vertices coordinate by coordinate.
    type Four = TriangleFour;

    const PACKS_FOUR: bool = true;

    #[inline]
    fn ray_data(_: &Ray) -> LazyShear {
        LazyShear::default()
    }

    fn pack_four(four: [Option<&Self>; 4], verts: &MeshVertices) -> TriangleFour {
        TriangleFour::new(four.map(|t| t.map(|t| t.vertices(verts))))
    }

    /// The rejection of `closest_hits`, read from the packed rows.
    #[inline(always)]
    fn four_may_hit(four: &TriangleFour, ray: &Ray, shear: &LazyShear) -> u32 {
        shear.of(ray).four_may_hit(four)
    }

    #[inline]
    fn bounds(&self, verts: &MeshVertices) -> Aabb {
        let [p0, p1, p2] = self.vertices(verts);
        Aabb::new(p0.min(p1).min(p2), p0.max(p1).max(p2))
    }

    /// [`Triangle::intersect`](super::Triangle::intersect) on the gathered
    /// vertices.
    #[inline]
    fn closest_hit(
        &self,
        verts: &MeshVertices,
        ray: &Ray,
        shear: &LazyShear,
        t_min: Real,
        t_max: Real,
    ) -> Option<PrimHit> {
        let shear = shear.of(ray);
        let [a, b, c] = [
            self.vertex_lanes(verts, 0),
            self.vertex_lanes(verts, 1),
            self.vertex_lanes(verts, 2),
        ];
        let m = LaneMat::from_cols(a, b, c, Lanes::ZERO).transpose();
        let coords = [m.x_axis, m.y_axis, m.z_axis];
        intersect_lanes(coords, shear, t_min, t_max)
    }

    /// Four at a time, rejected by their edge functions in lanes as
    /// [`Triangle`](super::Triangle)'s are, from the vertices gathered
    /// four by four.
    #[inline]
    fn closest_hits(
        prims: &[Self],
        verts: &MeshVertices,
        refs: &[u32],
        ray: &Ray,
        lazy: &LazyShear,
        t_min: Real,
        t_max: Real,
        _best: u32,
        keep: &mut impl FnMut(u32, PrimHit) -> Real,
    ) {
        if refs.is_empty() {
            // Nothing to test: the frame stays unmade.
            return;
        }
        verts.prefetch_cell(prims, refs);
        let shear = lazy.of(ray);
        closest_hits_prefiltered(
            prims,
            verts,
            refs,
            ray,
            lazy,
            t_min,
            t_max,
            None,
            keep,
            #[inline(always)]
            |four| Self::may_hit_four(four, verts, shear),
        );
    }

    /// Four at a time, as in `closest_hits`.
    #[inline]
    fn any_hits(
        prims: &[Self],
        verts: &MeshVertices,
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
        verts.prefetch_cell(prims, refs);
        let shear = lazy.of(ray);
        any_hits_prefiltered(
            prims,
            verts,
            refs,
            ray,
            lazy,
            t_min,
            t_max,
            #[inline(always)]
            |four| Self::may_hit_four(four, verts, shear),
        )
    }

    #[inline]
    fn overlaps_box(&self, verts: &MeshVertices, cell: &Aabb) -> bool {
        let [p0, p1, p2] = self.vertices(verts);
        overlap::triangle_box(p0, p1, p2, cell)
    }
}

impl Surface for MeshTriangle {
    /// [`Triangle`](super::Triangle)'s surface point, from the gathered
    /// vertices.
    #[inline]
    fn surface(&self, verts: &MeshVertices, ray: &Ray, h: &PrimHit) -> SurfacePoint {
        surface_point(self.vertices(verts), h, || *ray)
    }

    #[inline]
    fn vertex_indices(&self) -> Option<[u32; 3]> {
        Some(self.indices())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::Triangle;
    use gridrt_grid::{Accelerator, Exhaustive, Grid, GridConfig};
    use proptest::prelude::*;

    #[test]
    fn renumbering_follows_first_use_and_keeps_the_triangles() {
        // Vertex 5 is used by no triangle.
        let verts = MeshVertices::new([Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE, Vec3::Z, -Vec3::X]);
        let mut tris =
            MeshTriangle::from_indices(&verts, &[[0, 1, 2], [3, 2, 1], [0, 1, 0]]).unwrap();
        let before: Vec<_> = tris.iter().map(|t| t.vertices(&verts)).collect();
        let (v2, new_of) = verts.renumber(&mut tris, vec![1, 2, 0]);
        assert_eq!(new_of, [3, 2, 1, 0, u32::MAX, u32::MAX]);
        assert_eq!(v2.len(), 4);
        assert_eq!(tris[1].indices(), [0, 1, 2]);
        assert_eq!(tris[2].indices(), [3, 2, 3]);
        for (t, b) in tris.iter().zip(&before) {
            assert_eq!(t.vertices(&v2), *b);
        }
    }

    #[test]
    fn the_frame_is_made_at_the_first_triangle_test_only() {
        let verts = MeshVertices::new([Vec3::ZERO, Vec3::X, Vec3::Y]);
        let tris = MeshTriangle::from_indices(&verts, &[[0, 1, 2]]).unwrap();
        let r = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
        let data = MeshTriangle::ray_data(&r);
        let any = |refs: &[u32]| MeshTriangle::any_hits(&tris, &verts, refs, &r, &data, 0.0, 9.0);
        assert!(!any(&[]));
        assert!(!data.is_made());
        assert!(any(&[0]));
        assert!(data.is_made());
    }

    #[test]
    fn bad_indices_are_refused() {
        let verts = MeshVertices::new([Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X * 2.0]);
        assert_eq!(MeshTriangle::new(&verts, [0, 1, 4]), None);
        let flat = MeshTriangle::new(&verts, [0, 1, 3]).unwrap();
        assert_eq!(flat.indices(), [0, 1, 3]);
        let ok = MeshTriangle::new(&verts, [0, 1, 2]).unwrap();
        assert_eq!(ok.vertices(&verts), [Vec3::ZERO, Vec3::X, Vec3::Y]);
    }

    /// A small mesh: a grid of `n`×`n` quads on a bumpy surface, two
    /// triangles each, with the vertices at coordinates from `seed`.
    fn bumpy(n: u32, scale: Real, offset: Real, seed: u64) -> (MeshVertices, Vec<[u32; 3]>) {
        let mut s = seed;
        let mut rnd = || {
            s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (s >> 40) as Real / (1u64 << 24) as Real
        };
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let h = rnd() * 0.3;
                p.push(Vec3::new(i as Real, h, j as Real) * scale + Vec3::splat(offset));
            }
        }
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut idx = Vec::new();
        for j in 0..n {
            for i in 0..n {
                idx.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                idx.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        (MeshVertices::new(p), idx)
    }

    proptest! {
        /// Renumbering in any order keeps every triangle's vertices, keeps
        /// exactly the used vertices, numbered by first use, and agrees
        /// with the new index it reports for each old vertex.
        #[test]
        fn renumbering_keeps_every_triangle(
            n in 3usize..40,
            idx in prop::collection::vec(prop::array::uniform3(0u32..40), 1..30),
            order_seed in any::<u64>(),
        ) {
            let p: Vec<Vec3> = (0..n).map(|i| Vec3::new(i as Real, (i * i) as Real, 1.0)).collect();
            let idx: Vec<[u32; 3]> = idx.iter().map(|t| t.map(|i| i % n as u32)).collect();
            let verts = MeshVertices::new(p.clone());
            let mut tris = MeshTriangle::from_indices(&verts, &idx).unwrap();
            let mut order: Vec<u32> = (0..tris.len() as u32).collect();
            let mut s = order_seed;
            for i in (1..order.len()).rev() {
                s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                order.swap(i, (s >> 33) as usize % (i + 1));
            }
            let (v2, new_of) = verts.renumber(&mut tris, order.clone());
            let used: std::collections::BTreeSet<u32> = idx.iter().flatten().copied().collect();
            prop_assert_eq!(v2.len(), used.len());
            for (t, old) in tris.iter().zip(&idx) {
                prop_assert_eq!(t.vertices(&v2), old.map(|i| p[i as usize]));
                prop_assert_eq!(t.indices(), old.map(|i| new_of[i as usize]));
            }
            let mut seen = 0;
            for &k in &order {
                for i in tris[k as usize].indices() {
                    prop_assert!(i <= seen);
                    seen = seen.max(i + 1);
                }
            }
            for (i, &n) in new_of.iter().enumerate() {
                prop_assert_eq!(n == u32::MAX, !used.contains(&(i as u32)));
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        /// A grid of mesh triangles answers exactly what the exhaustive
        /// test of their copies answers, closest and any hit, for rays
        /// from anywhere (through vertices and edges included).
        #[test]
        fn same_answers_as_copied_triangles(
            seed in any::<u64>(),
            scale in prop::sample::select(vec![1e-3 as Real, 1.0, 64.0]),
            offset in prop::sample::select(vec![0.0 as Real, 1e4]),
            rays in prop::collection::vec(
                (prop::array::uniform3(-2.0 as Real..10.0), prop::array::uniform3(-1.0 as Real..1.0), any::<bool>()),
                64,
            ),
        ) {
            let (verts, idx) = bumpy(8, scale, offset, seed);
            let copies: Vec<Triangle> = idx
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| verts.get(i));
                    Triangle::new(a, b, c)
                })
                .collect();
            let mesh = MeshTriangle::from_indices(&verts, &idx).unwrap();
            let flat = Exhaustive::with_shared(mesh.clone(), verts.clone());
            let copied = Exhaustive::new(copies);
            let grid = Grid::build_shared(mesh, verts.clone(), &GridConfig::default());
            let mut sc = grid.scratch();
            for (o, d, at_vertex) in rays {
                let o = Vec3::from(o) * scale + Vec3::splat(offset);
                // Half the rays aim at a vertex: the hardest case for ties.
                let d = if at_vertex {
                    verts.get((seed % verts.len() as u64) as u32) - o
                } else {
                    Vec3::from(d)
                };
                let ray = Ray::new(o, d);
                let want = copied.closest_hit(&ray, 0.0, Real::INFINITY, &mut ());
                prop_assert_eq!(flat.closest_hit(&ray, 0.0, Real::INFINITY, &mut ()), want);
                prop_assert_eq!(grid.closest_hit(&ray, 0.0, Real::INFINITY, &mut sc), want);
                let t = want.map_or(1.0, |h| h.t * 0.999);
                let any = copied.any_hit(&ray, 0.0, t, &mut ());
                prop_assert_eq!(grid.any_hit(&ray, 0.0, t, &mut sc), any);
            }
        }
    }
}
