//! What shading reads of a mesh: its normals, colours, texture coordinates
//! and vertex indices, and which mesh triangle each grid primitive is.
//! The arrays are the scene's own, shared, or, for indexed triangles, one
//! table of the scene's vertices renumbered like the grid's vertices.

use crate::scene::{Mesh, Rgb};
use crate::texture::shade::TriFrame;
use glam::Vec2;
use gridrt_bbox::Vec3;
use std::sync::Arc;

/// Per-vertex normals of a mesh, for smooth shading, and its texture
/// coordinates with each triangle's texture frame, for texturing. The
/// arrays are shared by `Arc`; only the frames are the mesh's own.
#[derive(Clone, Debug)]
pub(crate) struct MeshShading {
    vertices: Vertices,
    /// Whether shading reads the texture coordinates (the mesh has them
    /// and a material with textures uses it).
    textured: bool,
    /// One per triangle when textured, else empty.
    pub frames: Vec<TriFrame>,
}

/// Where a mesh's per-vertex arrays are.
#[derive(Clone, Debug)]
enum Vertices {
    /// The scene's mesh, indexed by its own triangles.
    Mesh(Arc<Mesh>),
    /// The mesh's rows of a [`VertexTable`], indexed by the grid's
    /// triangles; a flag says whether the mesh has each array.
    Table {
        table: Arc<VertexTable>,
        normals: bool,
        colors: bool,
        uvs1: bool,
    },
}

/// The per-vertex arrays of several meshes in one numbering, the grid's
/// ([`MeshVertices::renumber`](crate::shapes::MeshVertices::renumber)):
/// each array is empty when no mesh has it, else one row per vertex
/// (zero for the vertices of meshes without it).
#[derive(Debug, Default)]
pub(crate) struct VertexTable {
    normals: Vec<Vec3>,
    colors: Vec<Rgb>,
    uvs: Vec<Vec2>,
    uvs1: Vec<Vec2>,
}

impl MeshShading {
    /// The shading data of `mesh`: texture frames computed when `uvs`.
    pub(crate) fn new(mesh: Arc<Mesh>, uvs: bool) -> Self {
        let frames = if uvs {
            mesh.triangles
                .iter()
                .map(|t| {
                    let p = t.map(|k| mesh.positions[k as usize]);
                    TriFrame::new(p, t.map(|k| mesh.uvs[k as usize]))
                })
                .collect()
        } else {
            Vec::new()
        };
        Self {
            vertices: Vertices::Mesh(mesh),
            textured: uvs,
            frames,
        }
    }

    /// Frees the positions and triangles of the meshes `placed` (as for
    /// [`MeshShading::renumber`]) that nothing but this shading holds any
    /// more: shading reads neither once renumbered, and indexed triangles
    /// have their own copy.
    pub(crate) fn release_positions(meshes: &mut [MeshShading], placed: &[(u32, u32)]) {
        for &(k, _) in placed {
            let Some(MeshShading {
                vertices: Vertices::Mesh(mesh),
                ..
            }) = meshes.get_mut(k as usize)
            else {
                continue;
            };
            if let Some(mesh) = Arc::get_mut(mesh) {
                mesh.positions = Vec::new();
                mesh.triangles = Vec::new();
            }
        }
    }

    /// Moves the per-vertex arrays of the meshes `placed` (index in
    /// `meshes`, and the number of the mesh's first vertex before
    /// renumbering) into one [`VertexTable`]: old vertex `i` becomes row
    /// `new_of[i]` (`u32::MAX`: used by no triangle). The
    /// meshes then no longer hold the scene's arrays, and read their
    /// corners from the grid's triangles.
    pub(crate) fn renumber(meshes: &mut [MeshShading], placed: &[(u32, u32)], new_of: &[u32]) {
        let len = new_of.iter().filter(|&&n| n != u32::MAX).count();
        let source = |k: u32| match meshes.get(k as usize).map(|m| &m.vertices) {
            Some(Vertices::Mesh(m)) => Some(Arc::clone(m)),
            _ => None,
        };
        let sources: Vec<_> = placed
            .iter()
            .filter_map(|&(k, first)| Some((k, first, source(k)?)))
            .collect();
        let mut table = VertexTable::default();
        let any = |has: fn(&Mesh) -> bool| sources.iter().any(|(_, _, m)| has(m));
        let size = |has: bool| if has { len } else { 0 };
        table.normals = vec![Vec3::ZERO; size(any(|m| !m.normals.is_empty()))];
        table.colors = vec![Rgb::ZERO; size(any(|m| !m.colors.is_empty()))];
        table.uvs = vec![Vec2::ZERO; size(any(|m| !m.uvs.is_empty()))];
        table.uvs1 = vec![Vec2::ZERO; size(any(|m| !m.uvs1.is_empty()))];
        for (_, first, m) in &sources {
            let rows = new_of.get(*first as usize..).unwrap_or_default();
            move_rows(&mut table.normals, &m.normals, rows);
            move_rows(&mut table.colors, &m.colors, rows);
            move_rows(&mut table.uvs, &m.uvs, rows);
            move_rows(&mut table.uvs1, &m.uvs1, rows);
        }
        let table = Arc::new(table);
        for (k, _, m) in sources {
            meshes[k as usize].vertices = Vertices::Table {
                table: Arc::clone(&table),
                normals: !m.normals.is_empty(),
                colors: !m.colors.is_empty(),
                uvs1: !m.uvs1.is_empty(),
            };
        }
    }

    /// Empty (flat shading) or one per vertex.
    #[inline]
    pub(crate) fn normals(&self) -> &[Vec3] {
        match &self.vertices {
            Vertices::Mesh(m) => &m.normals,
            Vertices::Table { table, normals, .. } => when(*normals, &table.normals),
        }
    }

    /// Empty, or one albedo per vertex.
    #[inline]
    pub(crate) fn colors(&self) -> &[Rgb] {
        match &self.vertices {
            Vertices::Mesh(m) => &m.colors,
            Vertices::Table { table, colors, .. } => when(*colors, &table.colors),
        }
    }

    /// The vertex indices of triangle `tri`: the mesh's own, or `grid`
    /// (the grid primitive's) when the arrays are renumbered like it.
    #[inline]
    pub(crate) fn corners(&self, tri: u32, grid: Option<[u32; 3]>) -> Option<[u32; 3]> {
        match &self.vertices {
            Vertices::Mesh(m) => m.triangles.get(tri as usize).copied(),
            Vertices::Table { .. } => grid,
        }
    }

    /// Empty (untextured) or one per vertex.
    #[inline]
    pub(crate) fn uvs(&self) -> &[Vec2] {
        match &self.vertices {
            Vertices::Mesh(m) => when(self.textured, &m.uvs),
            Vertices::Table { table, .. } => when(self.textured, &table.uvs),
        }
    }

    /// The second texture-coordinate set: empty, or one per vertex.
    #[inline]
    pub(crate) fn uvs1(&self) -> &[Vec2] {
        match &self.vertices {
            Vertices::Mesh(m) => when(self.textured, &m.uvs1),
            Vertices::Table { table, uvs1, .. } => when(self.textured && *uvs1, &table.uvs1),
        }
    }
}

/// `rows` when `has`, else nothing.
#[inline]
fn when<T>(has: bool, rows: &[T]) -> &[T] {
    if has {
        rows
    } else {
        &[]
    }
}

/// Copies `from[i]` to `to[new_of[i]]` for every vertex `i` that has a
/// row (nothing when either array is empty).
fn move_rows<T: Copy>(to: &mut [T], from: &[T], new_of: &[u32]) {
    for (v, &n) in from.iter().zip(new_of) {
        if let Some(row) = to.get_mut(n as usize) {
            *row = *v;
        }
    }
}

/// Which mesh triangle a grid primitive is (`mesh == u32::MAX`: not a
/// smooth-shaded triangle).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct MeshRef {
    pub mesh: u32,
    pub tri: u32,
}

impl MeshRef {
    pub const NONE: Self = Self {
        mesh: u32::MAX,
        tri: 0,
    };
}

/// The [`MeshRef`] of every grid primitive, as runs: primitives
/// `first..` of a run are consecutive triangles of one mesh from `tri` on
/// (or none of a mesh's). A mesh's triangles are one run, broken only
/// where a triangle with two equal vertices is left out of the grid, so a
/// scene keeps a few runs instead of 8 bytes per primitive.
#[derive(Clone, Debug, Default)]
pub(crate) struct PrimMeshes {
    runs: Vec<Run>,
    /// Primitives recorded.
    len: u32,
}

#[derive(Clone, Copy, Debug)]
struct Run {
    first: u32,
    mesh: u32,
    tri: u32,
}

impl PrimMeshes {
    /// Records the next `n` primitives: triangles `r.tri..r.tri + n` of
    /// mesh `r.mesh`, or none of a mesh's when `r.mesh == u32::MAX`.
    pub(crate) fn extend(&mut self, n: usize, r: MeshRef) {
        let Ok(n) = u32::try_from(n) else {
            return;
        };
        if n == 0 {
            return;
        }
        let first = self.len;
        self.len = self.len.saturating_add(n);
        let none = r.mesh == u32::MAX;
        if let Some(last) = self.runs.last() {
            let continues = if none {
                last.mesh == u32::MAX
            } else {
                last.mesh == r.mesh && last.tri.wrapping_add(first - last.first) == r.tri
            };
            if continues {
                return;
            }
        }
        self.runs.push(Run {
            first,
            mesh: r.mesh,
            tri: if none { 0 } else { r.tri },
        });
    }

    /// The mesh triangle of primitive `prim`; `None` when nothing was
    /// recorded for it.
    #[inline]
    pub(crate) fn get(&self, prim: u32) -> Option<MeshRef> {
        if prim >= self.len {
            return None;
        }
        let k = self
            .runs
            .partition_point(|r| r.first <= prim)
            .checked_sub(1)?;
        let r = self.runs.get(k)?;
        Some(if r.mesh == u32::MAX {
            MeshRef::NONE
        } else {
            MeshRef {
                mesh: r.mesh,
                tri: r.tri + (prim - r.first),
            }
        })
    }

    /// Heap bytes.
    #[cfg(test)]
    pub(crate) fn bytes(&self) -> usize {
        self.runs.capacity() * std::mem::size_of::<Run>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_give_back_every_primitives_triangle() {
        let mut p = PrimMeshes::default();
        let mut want = Vec::new();
        let mut push = |p: &mut PrimMeshes, n: usize, r: MeshRef| {
            p.extend(n, r);
            for k in 0..n as u32 {
                want.push(if r.mesh == u32::MAX {
                    MeshRef::NONE
                } else {
                    MeshRef {
                        mesh: r.mesh,
                        tri: r.tri + k,
                    }
                });
            }
        };
        push(&mut p, 3, MeshRef::NONE);
        push(
            &mut p,
            2,
            MeshRef {
                mesh: u32::MAX,
                tri: 7,
            },
        );
        // Mesh 0, triangles 0..5 and 6..9 (5 degenerate, left out).
        for t in (0..5).chain(6..9) {
            push(&mut p, 1, MeshRef { mesh: 0, tri: t });
        }
        push(&mut p, 1, MeshRef::NONE);
        push(&mut p, 4, MeshRef { mesh: 1, tri: 0 });
        push(&mut p, 0, MeshRef { mesh: 2, tri: 0 });
        for (k, w) in want.iter().enumerate() {
            assert_eq!(p.get(k as u32), Some(*w), "primitive {k}");
        }
        assert_eq!(p.get(want.len() as u32), None);
        // None, mesh 0 twice (the gap), none, mesh 1.
        assert_eq!(p.runs.len(), 5);
        assert!(p.bytes() < 8 * want.len());
        assert_eq!(PrimMeshes::default().get(0), None);
    }

    #[test]
    fn only_meshes_held_by_shading_alone_give_up_their_positions() {
        let mesh = || {
            Arc::new(Mesh {
                positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
                normals: vec![Vec3::Z; 3],
                triangles: vec![[0, 1, 2]],
                ..Mesh::default()
            })
        };
        let kept = mesh();
        let mut meshes = vec![
            MeshShading::new(mesh(), false),
            MeshShading::new(Arc::clone(&kept), false),
        ];
        MeshShading::release_positions(&mut meshes, &[(0, 0), (1, 3)]);
        let arrays = |m: &MeshShading| match &m.vertices {
            Vertices::Mesh(m) => (m.positions.len(), m.triangles.len(), m.normals.len()),
            Vertices::Table { .. } => unreachable!(),
        };
        assert_eq!(arrays(&meshes[0]), (0, 0, 3));
        assert_eq!(arrays(&meshes[1]), (3, 1, 3));
    }
}
