//! Which instance objects keep their mesh shared, and the world-space copy
//! of those that do not.
//!
//! A mesh placed by two or more [`Geometry::Instance`] objects gets one grid
//! of its own, shared by its placements, each of which is one primitive of
//! the scene's grid: memory grows with the number of distinct meshes, not
//! with the number of placements. A mesh placed once is flattened instead
//! (its triangles carried to world space and put in the scene's grid, as a
//! [`Geometry::Mesh`] is): one grid level fewer, and no transform per ray.
//! Emissive placements are flattened too, so that their triangles can be
//! sampled as area lights.

use crate::scene::{Geometry, Material, Mesh, Object, Scene};
use crate::transform::Affine;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

/// What instancing kept shared, for reports and tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InstancingStats {
    /// Meshes with a grid of their own, shared by their placements.
    pub shared_meshes: usize,
    /// Placements of those meshes: one primitive each in the scene's grid.
    pub instances: usize,
    /// Heap bytes of the shared grids (their triangles included) and of the
    /// placements; the meshes' own arrays are the scene's and not counted.
    pub bytes: usize,
}

/// The meshes that stay shared: placed by at least two instance objects
/// whose material does not emit.
pub(crate) struct SharedMeshes(HashSet<*const Mesh>);

impl SharedMeshes {
    pub(crate) fn of(scene: &Scene) -> Self {
        let mut uses: HashMap<*const Mesh, u32> = HashMap::new();
        for o in &scene.objects {
            if let Geometry::Instance { mesh, .. } = &o.geometry {
                if !emits(scene, o) {
                    *uses.entry(Arc::as_ptr(mesh)).or_default() += 1;
                }
            }
        }
        uses.retain(|_, n| *n >= 2);
        Self(uses.into_keys().collect())
    }

    /// No mesh shared: every placement baked.
    pub(crate) fn none() -> Self {
        Self(HashSet::new())
    }

    /// Whether object `o` is placed through a shared grid (else its
    /// triangles go into the scene's grid).
    pub(crate) fn keeps(&self, scene: &Scene, o: &Object) -> bool {
        match &o.geometry {
            Geometry::Instance { mesh, .. } => {
                self.0.contains(&Arc::as_ptr(mesh)) && !emits(scene, o)
            }
            _ => false,
        }
    }
}

fn emits(scene: &Scene, o: &Object) -> bool {
    matches!(
        scene.materials.get(o.material as usize),
        Some(Material::Emissive { .. })
    )
}

/// `mesh` carried to world space by `to_world`: positions mapped, normals
/// by the inverse transpose, and, under a mirror, each triangle's winding
/// reversed so that its front stays on the same side of the surface.
/// `None` when the map is not invertible (validation refuses it first).
pub(crate) fn flattened(mesh: &Mesh, to_world: &Affine) -> Option<Mesh> {
    let to_object = to_world.inverse()?;
    let mut out = mesh.clone();
    for p in &mut out.positions {
        *p = to_world.point(*p);
    }
    for n in &mut out.normals {
        *n = to_object.transpose_vector(*n).normalize_or_zero();
    }
    if to_world.determinant() < 0.0 {
        for t in &mut out.triangles {
            t.swap(1, 2);
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Rgb;
    use gridrt_bbox::Vec3;

    fn tri() -> Arc<Mesh> {
        Arc::new(Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            triangles: vec![[0, 1, 2]],
            ..Mesh::default()
        })
    }

    fn placed(mesh: &Arc<Mesh>, material: u32) -> Object {
        Object {
            geometry: Geometry::Instance {
                mesh: Arc::clone(mesh),
                to_world: Box::new(Affine::translation(Vec3::X)),
            },
            material,
        }
    }

    #[test]
    fn meshes_placed_twice_stay_shared_unless_they_emit() {
        let (a, b) = (tri(), tri());
        let mut scene = crate::suffern::scene(0);
        scene.materials.push(Material::Emissive {
            color: Rgb::ONE,
            strength: 1.0,
        });
        scene.objects = vec![placed(&a, 0), placed(&a, 0), placed(&b, 0), placed(&b, 1)];
        let shared = SharedMeshes::of(&scene);
        let keeps: Vec<_> = scene
            .objects
            .iter()
            .map(|o| shared.keeps(&scene, o))
            .collect();
        assert_eq!(keeps, [true, true, false, false]);
    }

    #[test]
    fn a_mirrored_flat_copy_keeps_its_front() {
        let mirror = Affine {
            cols: [-Vec3::X, Vec3::Y, Vec3::Z],
            translation: Vec3::ZERO,
        };
        let m = flattened(&tri(), &mirror).unwrap();
        let [a, b, c] = m.triangles[0].map(|k| m.positions[k as usize]);
        // The triangle faced +z and still does.
        assert!((b - a).cross(c - a).z > 0.0);
        assert_eq!(m.normals[0], Vec3::Z);
    }
}
