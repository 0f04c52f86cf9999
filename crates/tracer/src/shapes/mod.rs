//! Shapes: the primitives the grid holds ([`Sphere`], [`Cuboid`],
//! [`Triangle`], and their enum [`Shape`]) and the unbounded [`Plane`], which
//! stays outside the grid.
//!
//! Every bounded shape implements [`gridrt_grid::Primitive`] (bounds, closest
//! hit, any hit, exact box overlap), so any accelerator can hold it. The
//! renderer also needs, after a hit, the surface point with a bound on its
//! rounding error and the geometric normal; that is the crate-private
//! [`Surface`] trait.

mod cuboid;
mod instance;
mod mesh_triangle;
mod overlap;
mod plane;
mod shear;
mod sphere;
mod triangle;
mod triangle_mt;

pub use cuboid::Cuboid;
pub use instance::{Instance, MeshGrid};
pub use mesh_triangle::{MeshTriangle, MeshVertices};
pub use plane::Plane;
pub use shear::{LazyShear, Shear, TriangleFour};
pub use sphere::{Sphere, SphereFour, SphereRay};
pub(crate) use triangle::is_collapsed;
pub use triangle::Triangle;
pub use triangle_mt::{MtTriangle, MT_EPSILON};

use gridrt_bbox::{Aabb, Ray, Real, Vec3};
use gridrt_grid::{
    any_hits_each, any_hits_prefiltered, closest_hits_each, closest_hits_prefiltered, PrimHit,
    Primitive,
};

/// A surface point found by a ray, as shading and secondary rays need it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SurfacePoint {
    /// The point (on the surface up to `p_err`).
    pub p: Vec3,
    /// A bound, per axis, on the absolute rounding error of `p`.
    pub p_err: Vec3,
    /// Unit geometric normal on the shape's front (outward) side.
    pub n: Vec3,
}

/// What the renderer asks a primitive after the accelerator found a hit.
pub(crate) trait Surface: Primitive {
    /// The surface point of a hit this primitive reported from
    /// [`Primitive::closest_hit`] (`t`, its own `u`, `v`, and the part hit,
    /// such as the triangle of an instance); `shared` is what the
    /// accelerator keeps for all its primitives ([`Primitive::Shared`]).
    fn surface(&self, shared: &Self::Shared, ray: &Ray, h: &PrimHit) -> SurfacePoint;

    /// The instance this primitive is, if it is one.
    #[inline]
    fn instance(&self) -> Option<&Instance> {
        None
    }

    /// The vertex indices of this primitive, if it is an indexed triangle.
    #[inline]
    fn vertex_indices(&self) -> Option<[u32; 3]> {
        None
    }
}

/// The bounded shapes in one enum, for scenes that mix them (static
/// dispatch, pbrt's `TaggedPointer` idea without the pointer). A scene of
/// spheres only is rendered with a grid of [`Sphere`] instead, and one of
/// mesh triangles only (planes aside) with a grid of [`Triangle`] (40
/// bytes a primitive against the enum's 48, and no tag to match): both
/// more compact.
#[derive(Clone, Debug)]
pub enum Shape {
    /// A sphere.
    Sphere(Sphere),
    /// An axis-aligned box.
    Cuboid(Cuboid),
    /// A triangle (of a mesh).
    Triangle(Triangle),
    /// A triangle tested with Möller–Trumbore instead of the watertight
    /// test (`TriangleTest::MollerTrumbore`).
    MtTriangle(MtTriangle),
    /// A placement of a shared mesh (its grid, entered through a transform).
    Instance(std::sync::Arc<Instance>),
}

impl Primitive for Shape {
    /// Nothing shared: the primitive holds all it needs.
    type Shared = ();

    /// The shear frame of the watertight triangles, made when the ray
    /// first meets one: rays through spheres and boxes alone never pay
    /// for it.
    type RayData = LazyShear;
    type Four = ();

    #[inline]
    fn ray_data(_: &Ray) -> LazyShear {
        LazyShear::default()
    }

    #[inline]
    fn bounds(&self, _: &()) -> Aabb {
        match self {
            Shape::Sphere(s) => s.bounds(&()),
            Shape::Cuboid(c) => c.bounds(&()),
            Shape::Triangle(t) => t.bounds(&()),
            Shape::MtTriangle(t) => t.bounds(&()),
            Shape::Instance(i) => i.bounds(&()),
        }
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
        match self {
            Shape::Sphere(s) => s.closest_hit(&(), ray, &Sphere::ray_data(ray), t_min, t_max),
            Shape::Cuboid(c) => c.closest_hit(&(), ray, &(), t_min, t_max),
            Shape::Triangle(t) => t.closest_hit(&(), ray, shear, t_min, t_max),
            Shape::MtTriangle(t) => t.closest_hit(&(), ray, &(), t_min, t_max),
            Shape::Instance(i) => i.closest_hit(&(), ray, &(), t_min, t_max),
        }
    }

    #[inline]
    fn any_hit(&self, _: &(), ray: &Ray, shear: &LazyShear, t_min: Real, t_max: Real) -> bool {
        match self {
            Shape::Sphere(s) => s.any_hit(&(), ray, &Sphere::ray_data(ray), t_min, t_max),
            Shape::Cuboid(c) => c.any_hit(&(), ray, &(), t_min, t_max),
            Shape::Triangle(t) => t.any_hit(&(), ray, shear, t_min, t_max),
            Shape::MtTriangle(t) => t.any_hit(&(), ray, &(), t_min, t_max),
            Shape::Instance(i) => i.any_hit(&(), ray, &(), t_min, t_max),
        }
    }

    /// Four at a time where all four are watertight triangles (see
    /// `Shape::may_hit`); a cell of fewer than four one at a time.
    #[inline]
    fn closest_hits(
        prims: &[Self],
        shared: &(),
        refs: &[u32],
        ray: &Ray,
        shear: &LazyShear,
        t_min: Real,
        t_max: Real,
        best: u32,
        keep: &mut impl FnMut(u32, PrimHit) -> Real,
    ) {
        if refs.len() < 4 {
            // Too few for the four-lane filter to pay for its set-up.
            return closest_hits_each(prims, shared, refs, ray, shear, t_min, t_max, best, keep);
        }
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
            #[inline(always)]
            |four| Shape::may_hit(ray, shear, four),
        );
    }

    /// Four at a time where all four are watertight triangles; a cell of
    /// fewer than four one at a time.
    #[inline]
    fn any_hits(
        prims: &[Self],
        shared: &(),
        refs: &[u32],
        ray: &Ray,
        shear: &LazyShear,
        t_min: Real,
        t_max: Real,
    ) -> bool {
        if refs.len() < 4 {
            return any_hits_each(prims, shared, refs, ray, shear, t_min, t_max);
        }
        any_hits_prefiltered(
            prims,
            shared,
            refs,
            ray,
            shear,
            t_min,
            t_max,
            #[inline(always)]
            |four| Shape::may_hit(ray, shear, four),
        )
    }

    #[inline]
    fn overlaps_box(&self, _: &(), cell: &Aabb) -> bool {
        match self {
            Shape::Sphere(s) => s.overlaps_box(&(), cell),
            Shape::Cuboid(c) => c.overlaps_box(&(), cell),
            Shape::Triangle(t) => t.overlaps_box(&(), cell),
            Shape::MtTriangle(t) => t.overlaps_box(&(), cell),
            Shape::Instance(i) => i.overlaps_box(&(), cell),
        }
    }
}

impl Shape {
    /// Of four shapes, those a ray may hit (bit `k` for the `k`-th): when
    /// all four are watertight triangles, their edge functions in lanes
    /// reject most of a cell's triangles at once, as [`Triangle`]'s own
    /// queries do; mixed chunks are all tested one shape at a time.
    #[inline(always)]
    fn may_hit(ray: &Ray, shear: &LazyShear, four: [&Shape; 4]) -> u32 {
        match four {
            [Shape::Triangle(a), Shape::Triangle(b), Shape::Triangle(c), Shape::Triangle(d)] => {
                shear
                    .of(ray)
                    .triangles_may_hit(|k| [a, b, c, d].map(|t| t.lanes(k)))
            }
            _ => 0b1111,
        }
    }
}

impl Surface for Shape {
    #[inline]
    fn surface(&self, _: &(), ray: &Ray, h: &PrimHit) -> SurfacePoint {
        match self {
            Shape::Sphere(s) => s.surface(&(), ray, h),
            Shape::Cuboid(c) => c.surface(&(), ray, h),
            Shape::Triangle(tr) => tr.surface(&(), ray, h),
            Shape::MtTriangle(tr) => tr.surface(&(), ray, h),
            Shape::Instance(i) => i.surface_part(h, ray),
        }
    }

    #[inline]
    fn instance(&self) -> Option<&Instance> {
        match self {
            Shape::Instance(i) => Some(i),
            _ => None,
        }
    }
}

impl From<Sphere> for Shape {
    fn from(s: Sphere) -> Self {
        Shape::Sphere(s)
    }
}

impl From<Cuboid> for Shape {
    fn from(c: Cuboid) -> Self {
        Shape::Cuboid(c)
    }
}

impl From<Triangle> for Shape {
    fn from(t: Triangle) -> Self {
        Shape::Triangle(t)
    }
}

/// `v` with its length set to 1, or `fallback` when `v` is zero or not finite.
#[inline]
pub(crate) fn unit_or(v: Vec3, fallback: Vec3) -> Vec3 {
    v.try_normalize().unwrap_or(fallback)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_stays_compact() {
        // The enum is as large as its largest member (the triangle's three
        // vertices and one padding coordinate) plus a tag, padded to the
        // alignment of an instance's pointer; keep it that way.
        let real = std::mem::size_of::<Real>();
        assert_eq!(std::mem::size_of::<Sphere>(), 4 * real);
        assert!(std::mem::size_of::<Shape>() <= 10 * real + real.max(8));
    }
}
