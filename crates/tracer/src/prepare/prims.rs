//! The primitives `prepare` makes for the accelerator: what a scene's
//! objects become, by kind, and the builder that collects them.

use crate::scene::SphereSet;
use crate::shapes::{is_collapsed, MeshTriangle, MeshVertices, Shape, Sphere, Triangle};
use gridrt_bbox::Vec3;
use std::sync::Arc;

/// The grid primitives of a scene: spheres only gets the compact type.
#[derive(Debug)]
pub(crate) enum Prims {
    Spheres(Vec<Sphere>),
    /// A scene's only primitives: one sphere set, shared with the scene
    /// (the grid copies each sphere once, straight into cell order).
    Set(Arc<SphereSet>),
    /// Mesh triangles only (meshes, flattened instances, planes aside):
    /// the compact type, with no enum tag.
    Triangles(Vec<Triangle>),
    /// The same, as indices into one array of the meshes' vertices
    /// ([`TriangleStorage::Indexed`](crate::TriangleStorage::Indexed)).
    Mesh(MeshVertices, Vec<MeshTriangle>),
    Shapes(Vec<Shape>),
}

impl Prims {
    pub(crate) fn len(&self) -> usize {
        match self {
            Prims::Spheres(v) => v.len(),
            Prims::Set(s) => s.spheres.len(),
            Prims::Triangles(v) => v.len(),
            Prims::Mesh(_, v) => v.len(),
            Prims::Shapes(v) => v.len(),
        }
    }
}

/// The grid primitives of a scene that is not all spheres, as they are
/// made: mesh triangles alone (copied or indexed), or shapes of every kind.
pub(super) enum Out {
    Triangles(Vec<Triangle>),
    Mesh(MeshVertices, Vec<MeshTriangle>),
    Shapes(Vec<Shape>),
}

impl Out {
    pub(super) fn len(&self) -> usize {
        match self {
            Out::Triangles(v) => v.len(),
            Out::Mesh(_, v) => v.len(),
            Out::Shapes(v) => v.len(),
        }
    }

    /// Takes in a mesh's vertices; returns the offset of its indices.
    pub(super) fn add_vertices(&mut self, positions: &[Vec3]) -> u32 {
        match self {
            Out::Mesh(verts, _) => verts.append(positions),
            _ => 0,
        }
    }

    /// Adds the triangle with vertices `v` of `positions` (whose indices
    /// start at `first`, from [`Out::add_vertices`]), unless two of its
    /// vertices are equal (no ray hits it: [`Triangle::is_collapsed`]); returns
    /// whether it was added. Other zero-area triangles stay: they close
    /// cracks the shear's rounding opens between their neighbours.
    pub(super) fn push_triangle(&mut self, positions: &[Vec3], first: u32, v: [u32; 3]) -> bool {
        let p = v.map(|k| positions[k as usize]);
        if is_collapsed(p) {
            return false;
        }
        let copy = || Triangle::new(p[0], p[1], p[2]);
        match self {
            Out::Triangles(all) => all.push(copy()),
            Out::Shapes(all) => all.push(Shape::from(copy())),
            Out::Mesh(verts, all) => match MeshTriangle::new(verts, v.map(|k| k + first)) {
                Some(t) => all.push(t),
                None => return false,
            },
        }
        true
    }

    /// Adds a shape; triangles so far become shapes if it is not one (the
    /// scene's objects decide up front, so this does not happen).
    pub(super) fn push(&mut self, s: Shape) {
        match (&mut *self, s) {
            (Out::Triangles(v), Shape::Triangle(t)) => v.push(t),
            (Out::Triangles(v), s) => {
                let mut all: Vec<Shape> = v.drain(..).map(Shape::from).collect();
                all.push(s);
                *self = Out::Shapes(all);
            }
            (Out::Mesh(verts, v), s) => {
                let mut all: Vec<Shape> = (0..v.len()).map(|k| mesh_shape(verts, v, k)).collect();
                all.push(s);
                *self = Out::Shapes(all);
            }
            (Out::Shapes(v), s) => v.push(s),
        }
    }

    /// Primitive `k` as a shape.
    pub(super) fn shape(&self, k: usize) -> Shape {
        match self {
            Out::Triangles(v) => Shape::Triangle(v[k]),
            Out::Mesh(verts, v) => mesh_shape(verts, v, k),
            Out::Shapes(v) => v[k].clone(),
        }
    }

    /// The primitives (indexed triangles keep the numbering of their
    /// vertices as they came: [`super::Prepared::numbered`] orders
    /// them).
    pub(super) fn finish(self) -> Prims {
        match self {
            Out::Triangles(v) => Prims::Triangles(v),
            Out::Mesh(verts, v) => Prims::Mesh(verts, v),
            Out::Shapes(v) => Prims::Shapes(v),
        }
    }
}

/// Indexed triangle `k` of `tris` as a shape.
fn mesh_shape(verts: &MeshVertices, tris: &[MeshTriangle], k: usize) -> Shape {
    Shape::Triangle(tris[k].to_triangle(verts))
}
