//! An instance: one placement of a shared mesh. The mesh's triangles live
//! once, in object space, in a grid of their own ([`MeshGrid`]); the scene's
//! grid holds each instance as a single primitive whose box is the mesh's
//! box carried to world space, and a ray that reaches it is carried into
//! object space and traced through the shared grid (Suffern's compound
//! objects with `Instance`, pbrt-v4's object instances).
//!
//! An affine map keeps the ray parameter: the point at `t` along the object
//! ray is the image of the point at `t` along the world ray, so hits compare
//! by `t` across instances and with the scene's other primitives.

use super::triangle::surface_point;
use super::{unit_or, SurfacePoint, Triangle};
use crate::scene::Mesh;
use crate::texture::shade::TriFrame;
use crate::transform::Affine;
use gridrt_bbox::{gamma, Aabb, Ray, Real, Vec3};
use gridrt_grid::{Accelerator, Grid, GridConfig, GridScratch, PrimHit, Primitive};
use std::sync::Arc;

/// The shared part of the instances of one mesh: the mesh and a grid of
/// its non-degenerate triangles in object space.
#[derive(Debug)]
pub struct MeshGrid {
    /// The mesh, as the scene holds it (not copied).
    mesh: Arc<Mesh>,
    grid: Grid<Triangle>,
    /// The mesh's index of each triangle given to the grid.
    tri: Vec<u32>,
    /// Index of the mesh's shading data (normals, colours, texture
    /// coordinates) in the renderer's tables, `u32::MAX` for none.
    pub(crate) shading: u32,
}

impl MeshGrid {
    /// Builds the grid of `mesh`'s triangles with `config` (mailboxing is
    /// turned off: instances are queried without per-thread scratch).
    #[must_use]
    pub(crate) fn new(mesh: Arc<Mesh>, config: &GridConfig, shading: u32) -> Self {
        let mut tris = Vec::with_capacity(mesh.triangles.len());
        let mut tri = Vec::with_capacity(mesh.triangles.len());
        for (k, t) in mesh.triangles.iter().enumerate() {
            let p = t.map(|i| mesh.positions[i as usize]);
            let t = Triangle::new(p[0], p[1], p[2]);
            if !t.is_collapsed() {
                tris.push(t);
                tri.push(k as u32);
            }
        }
        let config = GridConfig {
            mailbox: false,
            ..*config
        };
        Self {
            grid: Grid::build(tris, &config),
            tri,
            mesh,
            shading,
        }
    }

    /// Heap bytes of the grid, its triangles and its index table (the
    /// mesh's own arrays are the scene's and are not counted).
    #[must_use]
    pub(crate) fn bytes(&self) -> usize {
        self.grid.stats().bytes + std::mem::size_of_val(self.grid.primitives()) + self.tri.len() * 4
    }
}

/// One placement of a [`MeshGrid`]: a primitive of the scene's grid.
#[derive(Debug)]
pub struct Instance {
    to_world: Affine,
    to_object: Affine,
    bounds: Aabb,
    shared: Arc<MeshGrid>,
}

impl Instance {
    /// `shared` placed by `to_world`; `None` when the map is not invertible.
    #[must_use]
    pub(crate) fn new(shared: Arc<MeshGrid>, to_world: Affine) -> Option<Self> {
        let to_object = to_world.inverse()?;
        let bounds = to_world.bounds(&shared.mesh.bounds());
        Some(Self {
            to_world,
            to_object,
            bounds,
            shared,
        })
    }

    /// The shared mesh and grid.
    #[must_use]
    pub(crate) fn shared(&self) -> &MeshGrid {
        &self.shared
    }

    /// The object-space ray of a world ray (same parameter `t`).
    #[inline]
    fn object_ray(&self, ray: &Ray) -> Ray {
        Ray::new(
            self.to_object.point(ray.origin),
            self.to_object.vector(ray.dir),
        )
    }

    /// A world-space direction of the object-space normal `n` (unit length,
    /// not oriented).
    #[inline]
    pub(crate) fn normal_to_world(&self, n: Vec3) -> Vec3 {
        self.to_object.transpose_vector(n)
    }

    /// A texture frame of the mesh carried to world space: its derivatives
    /// mapped, its texel density scaled by the change of the triangle's
    /// area.
    #[inline]
    pub(crate) fn frame_to_world(&self, f: TriFrame) -> TriFrame {
        let (dpdu, dpdv) = (self.to_world.vector(f.dpdu), self.to_world.vector(f.dpdv));
        let (before, after) = (f.dpdu.cross(f.dpdv).length(), dpdu.cross(dpdv).length());
        let area_scale = if before > 0.0 && after > 0.0 {
            after / before
        } else {
            // No frame to measure with: the mean area scale.
            self.to_world.determinant().abs().powf(2.0 / 3.0)
        };
        TriFrame {
            dpdu,
            dpdv,
            density: f.density / crate::float::to_f32(area_scale.sqrt()),
        }
    }
}

impl Primitive for Instance {
    /// Nothing shared: the primitive holds all it needs.
    type Shared = ();

    /// Nothing is computed once per world-space ray: the mesh's grid
    /// computes its triangles' data for the object-space ray.
    type RayData = ();
    type Four = ();

    #[inline]
    fn ray_data(_: &Ray) {}

    #[inline]
    fn bounds(&self, _: &()) -> Aabb {
        self.bounds
    }

    #[inline]
    fn closest_hit(&self, _: &(), ray: &Ray, _: &(), t_min: Real, t_max: Real) -> Option<PrimHit> {
        let r = self.object_ray(ray);
        let h = self
            .shared
            .grid
            .closest_hit(&r, t_min, t_max, &mut GridScratch::default())?;
        Some(PrimHit {
            t: h.t,
            u: h.u,
            v: h.v,
            part: self.shared.tri[h.prim as usize],
        })
    }

    #[inline]
    fn any_hit(&self, _: &(), ray: &Ray, _: &(), t_min: Real, t_max: Real) -> bool {
        let r = self.object_ray(ray);
        self.shared
            .grid
            .any_hit(&r, t_min, t_max, &mut GridScratch::default())
    }
}

impl Instance {
    /// The world-space surface point of a hit on triangle `h.part` of the
    /// mesh. Its error bound holds the object-space point's, carried
    /// through the map, plus the rounding of carrying a secondary ray's
    /// origin back into object space, so that rays leaving the point clear
    /// the triangle there too. `ray` is the world-space ray that hit.
    #[inline]
    pub(crate) fn surface_part(&self, h: &PrimHit, ray: &Ray) -> SurfacePoint {
        let m = &self.shared.mesh;
        let p = m.triangles[h.part as usize].map(|k| m.positions[k as usize]);
        let obj = surface_point(p, h, || self.object_ray(ray));
        let (p, mut p_err) = self.to_world.point_with_error(obj.p, obj.p_err);
        let abs = |a: &Affine| Affine {
            cols: a.cols.map(Vec3::abs),
            translation: a.translation.abs(),
        };
        let back = abs(&self.to_object).point(p.abs() + p_err) * gamma(3);
        p_err += abs(&self.to_world).vector(back) * (1.0 + gamma(3));
        SurfacePoint {
            p,
            p_err,
            n: unit_or(self.normal_to_world(obj.n), Vec3::Z),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> Arc<Mesh> {
        Arc::new(Mesh {
            name: "quad".into(),
            positions: vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            ..Mesh::default()
        })
    }

    fn placed(to_world: Affine) -> Instance {
        let shared = Arc::new(MeshGrid::new(quad(), &GridConfig::default(), u32::MAX));
        Instance::new(shared, to_world).unwrap()
    }

    #[test]
    fn a_moved_and_scaled_quad_is_hit_where_it_was_put() {
        let to_world = Affine {
            cols: [Vec3::X * 2.0, Vec3::Y * 2.0, Vec3::Z * 2.0],
            translation: Vec3::new(10.0, 0.0, -5.0),
        };
        let inst = placed(to_world);
        let ray = Ray::new(Vec3::new(11.0, 1.0, 5.0), Vec3::new(0.0, 0.0, -2.0));
        let h = inst
            .closest_hit(&(), &ray, &(), 0.0, Real::INFINITY)
            .unwrap();
        assert!((h.t - 5.0).abs() < 1e-5, "{h:?}");
        // (11, 1) is (0.5, 0.5) in object space: the second triangle.
        assert_eq!(h.part, 0);
        let sp = inst.surface_part(&h, &ray);
        assert!(
            (sp.p - Vec3::new(11.0, 1.0, -5.0)).abs().max_element()
                <= sp.p_err.max_element() + 1e-5
        );
        assert!((sp.n - Vec3::Z).length() < 1e-6);
        assert!(inst.any_hit(&(), &ray, &(), 0.0, 6.0));
        assert!(!inst.any_hit(&(), &ray, &(), 0.0, 4.0));
        let miss = Ray::new(Vec3::new(13.0, 1.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(inst
            .closest_hit(&(), &miss, &(), 0.0, Real::INFINITY)
            .is_none());
    }

    #[test]
    fn a_mirror_keeps_the_front_side() {
        let mirror = Affine {
            cols: [Vec3::X, Vec3::Y, -Vec3::Z],
            translation: Vec3::ZERO,
        };
        let inst = placed(mirror);
        let ray = Ray::new(Vec3::new(0.2, -0.5, 3.0), Vec3::new(0.0, 0.0, -1.0));
        let h = inst
            .closest_hit(&(), &ray, &(), 0.0, Real::INFINITY)
            .unwrap();
        let sp = inst.surface_part(&h, &ray);
        // The quad faced +z; mirrored in z its front faces −z.
        assert!((sp.n + Vec3::Z).length() < 1e-6, "{:?}", sp.n);
        assert_eq!(h.part, 0);
        let other = Ray::new(Vec3::new(-0.5, 0.2, 3.0), Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(
            inst.closest_hit(&(), &other, &(), 0.0, Real::INFINITY)
                .unwrap()
                .part,
            1
        );
    }

    #[test]
    fn bounds_hold_the_placed_mesh() {
        let rot = Affine {
            cols: [Vec3::Y, -Vec3::X, Vec3::Z],
            translation: Vec3::new(0.0, 0.0, 100.0),
        };
        let b = placed(rot).bounds(&());
        for p in [Vec3::new(-1.0, -1.0, 100.0), Vec3::new(1.0, 1.0, 100.0)] {
            assert!(p.cmpge(b.min).all() && p.cmple(b.max).all());
        }
    }
}
