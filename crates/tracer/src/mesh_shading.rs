//! What shading reads of a mesh: its normals, colours, texture coordinates
//! and vertex indices (the scene's own arrays, shared, not copied), and
//! which mesh triangle each grid primitive is.

use crate::scene::{Mesh, Rgb};
use crate::texture::shade::TriFrame;
use gridrt_bbox::Vec3;
use std::sync::Arc;

/// Per-vertex normals of a mesh, for smooth shading, and its texture
/// coordinates with each triangle's texture frame, for texturing. The
/// arrays are the scene's mesh, shared by `Arc`; only the frames are
/// the renderer's own.
#[derive(Clone, Debug)]
pub(crate) struct MeshShading {
    mesh: Arc<Mesh>,
    /// Whether shading reads the texture coordinates (the mesh has them
    /// and a material with textures uses it).
    textured: bool,
    /// One per triangle when textured, else empty.
    pub frames: Vec<TriFrame>,
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
            mesh,
            textured: uvs,
            frames,
        }
    }

    /// Empty (flat shading) or one per vertex.
    #[inline]
    pub(crate) fn normals(&self) -> &[Vec3] {
        &self.mesh.normals
    }

    /// Empty, or one albedo per vertex.
    #[inline]
    pub(crate) fn colors(&self) -> &[Rgb] {
        &self.mesh.colors
    }

    /// Vertex indices of each triangle.
    #[inline]
    pub(crate) fn triangles(&self) -> &[[u32; 3]] {
        &self.mesh.triangles
    }

    /// Empty (untextured) or one per vertex.
    #[inline]
    pub(crate) fn uvs(&self) -> &[glam::Vec2] {
        if self.textured {
            &self.mesh.uvs
        } else {
            &[]
        }
    }

    /// The second texture-coordinate set: empty, or one per vertex.
    #[inline]
    pub(crate) fn uvs1(&self) -> &[glam::Vec2] {
        if self.textured {
            &self.mesh.uvs1
        } else {
            &[]
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
/// where a degenerate triangle is left out of the grid, so a scene keeps a
/// few runs instead of 8 bytes per primitive.
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
}
