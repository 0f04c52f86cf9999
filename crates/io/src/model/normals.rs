//! Vertex normals for meshes whose file has none: each corner's normal is
//! the angle-weighted average (Thürmer and Wüthrich 1998) of the normals
//! of the faces around its position that lie within a crease angle of the
//! corner's own face, so that curved surfaces shade smoothly and sharp
//! edges stay sharp (Blender's "smooth by angle", 3ds Max's smoothing
//! groups, pbrt's `plymesh` tools).
//!
//! Corners meet at a position, not at a vertex index: files that split
//! vertices at texture seams still get one smooth surface across the seam.
//! A vertex whose corners end up with different normals (on a crease) is
//! split, one copy per normal, its position and texture coordinate copied.

use gridrt_bbox::{Real, Vec3};
use gridrt_tracer::Mesh;
use serde::Deserialize;
use std::collections::HashMap;

/// The crease angle of models rendered on their own, in degrees.
pub const DEFAULT_CREASE_DEG: f64 = 60.0;

/// Which normals a mesh is shaded with (a scene `Mesh`'s `normals` field).
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Normals")]
pub enum Normals {
    /// `File`: the file's vertex normals where it has them, flat facets
    /// where it has none (the default in scene files).
    #[default]
    #[serde(alias = "file")]
    File,
    /// `Flat`: flat facets, even where the file has vertex normals.
    #[serde(alias = "flat")]
    Flat,
    /// `Smooth(60)`: the file's vertex normals where it has them, else
    /// smooth normals with this crease angle in degrees (the default for a
    /// model rendered on its own, with 60).
    #[serde(alias = "smooth")]
    Smooth(Crease),
}

/// A crease angle in degrees, in [0, 180].
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(try_from = "f64")]
pub struct Crease(pub f64);

impl TryFrom<f64> for Crease {
    type Error = String;
    fn try_from(deg: f64) -> Result<Self, String> {
        if (0.0..=180.0).contains(&deg) {
            Ok(Self(deg))
        } else {
            Err(format!(
                "the crease angle must be between 0 and 180 degrees, found {deg}"
            ))
        }
    }
}

impl Normals {
    /// Gives `mesh` the normals this asks for.
    /// `mesh` with these normals: the same shared mesh when they change
    /// nothing (file normals, flat facets of a mesh without normals,
    /// smoothing of a mesh that has normals), else a changed copy.
    #[must_use]
    pub fn applied(self, mesh: &std::sync::Arc<Mesh>) -> std::sync::Arc<Mesh> {
        let unchanged = match self {
            Self::File => true,
            Self::Flat => mesh.normals.is_empty(),
            Self::Smooth(_) => !mesh.normals.is_empty() || mesh.triangles.is_empty(),
        };
        if unchanged {
            return std::sync::Arc::clone(mesh);
        }
        let mut m = (**mesh).clone();
        self.apply(&mut m);
        std::sync::Arc::new(m)
    }

    pub fn apply(self, mesh: &mut Mesh) {
        match self {
            Self::File => {}
            Self::Flat => mesh.normals.clear(),
            Self::Smooth(Crease(deg)) => smooth(mesh, deg),
        }
    }
}

/// The cache of [`applied_once`]: by the source mesh's address, the source
/// (held, so that its address is not reused while the cache lives) and the
/// mesh with the normals applied.
pub(crate) type AppliedCache =
    std::collections::HashMap<*const Mesh, (std::sync::Arc<Mesh>, std::sync::Arc<Mesh>)>;

/// `mesh` with `normals` applied, once per shared mesh (`cache` by the
/// mesh's address), so that placements still share one copy.
pub(crate) fn applied_once(
    cache: &mut AppliedCache,
    mesh: &std::sync::Arc<Mesh>,
    normals: Normals,
) -> std::sync::Arc<Mesh> {
    let (_, applied) = cache
        .entry(std::sync::Arc::as_ptr(mesh))
        .or_insert_with(|| (std::sync::Arc::clone(mesh), normals.applied(mesh)));
    std::sync::Arc::clone(applied)
}

/// Corners around one position beyond which the crease test, which is
/// quadratic in them, gives way to one average over all faces within the
/// crease angle of their mean normal (a fan of thousands of slivers).
const MAX_CREASE_CORNERS: usize = 512;

/// Fills `mesh.normals` with smooth normals, unless it already has some.
/// `crease_deg` is the largest angle, in degrees, between two faces that
/// are shaded as one smooth surface (0 gives flat facets, 180 smooths
/// everything).
pub(crate) fn smooth(mesh: &mut Mesh, crease_deg: f64) {
    if !mesh.normals.is_empty() || mesh.triangles.is_empty() {
        return;
    }
    let cos_crease = crease_deg.clamp(0.0, 180.0).to_radians().cos() as Real;
    let p = &mesh.positions;

    // Unit face normals (zero for degenerate faces, which then give and
    // take nothing) and each corner's angle.
    let mut face_n = Vec::with_capacity(mesh.triangles.len());
    let mut angles = Vec::with_capacity(mesh.triangles.len());
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| p[i as usize]);
        face_n.push((b - a).cross(c - a).normalize_or_zero());
        let angle = |o: Vec3, u: Vec3, v: Vec3| -> Real {
            let (u, v) = ((u - o).normalize_or_zero(), (v - o).normalize_or_zero());
            u.dot(v).clamp(-1.0, 1.0).acos()
        };
        angles.push([angle(a, b, c), angle(b, c, a), angle(c, a, b)]);
    }

    // Corners grouped by position (bitwise equal; -0 and +0 alike).
    let key = |v: Vec3| v.to_array().map(|x| (x + 0.0).to_bits());
    let mut group_of: HashMap<_, u32> = HashMap::with_capacity(p.len());
    let mut groups: Vec<Vec<(u32, u8)>> = Vec::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        for (k, &v) in t.iter().enumerate() {
            let next = groups.len() as u32;
            let g = *group_of.entry(key(p[v as usize])).or_insert(next);
            if g == next {
                groups.push(Vec::new());
            }
            groups[g as usize].push((f as u32, k as u8));
        }
    }

    // Each corner's normal.
    let mut corner_n = vec![[Vec3::ZERO; 3]; mesh.triangles.len()];
    for corners in &groups {
        let weighted = |f: u32, k: u8| face_n[f as usize] * angles[f as usize][k as usize];
        if corners.len() > MAX_CREASE_CORNERS {
            let mean = corners
                .iter()
                .fold(Vec3::ZERO, |s, &(f, k)| s + weighted(f, k))
                .normalize_or_zero();
            let n = corners
                .iter()
                .filter(|&&(f, _)| face_n[f as usize].dot(mean) >= cos_crease)
                .fold(Vec3::ZERO, |s, &(f, k)| s + weighted(f, k));
            for &(f, k) in corners {
                corner_n[f as usize][k as usize] = n;
            }
            continue;
        }
        for &(f, k) in corners {
            let own = face_n[f as usize];
            corner_n[f as usize][k as usize] = corners
                .iter()
                .filter(|&&(g, _)| face_n[g as usize].dot(own) >= cos_crease)
                .fold(Vec3::ZERO, |s, &(g, j)| s + weighted(g, j));
        }
    }

    // One vertex per (vertex, normal): split where the normals differ.
    let mut normals: Vec<Option<Vec3>> = vec![None; p.len()];
    let mut copies: HashMap<(u32, [u64; 3]), u32> = HashMap::new();
    let has_uvs = mesh.uvs.len() == p.len();
    let has_colors = mesh.colors.len() == p.len();
    for (f, t) in mesh.triangles.iter_mut().enumerate() {
        for (k, v) in t.iter_mut().enumerate() {
            // A corner whose faces cancel out, or a degenerate face's
            // corner, takes its face's normal, or any unit vector.
            let n = corner_n[f][k]
                .try_normalize()
                .or_else(|| face_n[f].try_normalize())
                .unwrap_or(Vec3::Z);
            let slot = &mut normals[*v as usize];
            match slot {
                None => *slot = Some(n),
                Some(m) if *m == n => {}
                Some(_) => {
                    let bits = n.to_array().map(|x| super::r64(x).to_bits());
                    let new = *copies.entry((*v, bits)).or_insert_with(|| {
                        mesh.positions.push(mesh.positions[*v as usize]);
                        if has_uvs {
                            mesh.uvs.push(mesh.uvs[*v as usize]);
                        }
                        if has_colors {
                            mesh.colors.push(mesh.colors[*v as usize]);
                        }
                        normals.push(Some(n));
                        (mesh.positions.len() - 1) as u32
                    });
                    *v = new;
                }
            }
        }
    }
    // Vertices no triangle uses keep a placeholder-free unit normal.
    mesh.normals = normals.into_iter().map(|n| n.unwrap_or(Vec3::Z)).collect();
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube, 8 shared corners, 12 triangles, counter-clockwise outside.
    fn cube() -> Mesh {
        let positions = (0..8)
            .map(|i| {
                Vec3::new(
                    (i & 1) as Real,
                    ((i >> 1) & 1) as Real,
                    ((i >> 2) & 1) as Real,
                )
            })
            .collect();
        let quads = [
            [0, 2, 3, 1], // z = 0
            [4, 5, 7, 6], // z = 1
            [0, 1, 5, 4], // y = 0
            [2, 6, 7, 3], // y = 1
            [0, 4, 6, 2], // x = 0
            [1, 3, 7, 5], // x = 1
        ];
        let triangles = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        Mesh {
            name: "cube".into(),
            positions,
            normals: vec![],
            uvs: vec![],
            uvs1: vec![],
            colors: vec![],
            triangles,
        }
    }

    #[test]
    fn a_cube_below_its_crease_angle_keeps_flat_faces() {
        let mut m = cube();
        smooth(&mut m, 60.0);
        // Every corner gets its own face's normal: 6 faces × 4 corners.
        assert_eq!(m.positions.len(), 24);
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let face = (b - a).cross(c - a).normalize();
            for &i in t {
                assert!((m.normals[i as usize] - face).length() < 1e-6);
            }
        }
    }

    #[test]
    fn a_cube_above_its_crease_angle_is_one_smooth_surface() {
        let mut m = cube();
        smooth(&mut m, 180.0);
        assert_eq!(m.positions.len(), 8);
        for (p, n) in m.positions.iter().zip(&m.normals) {
            // Angle weighting makes a cube corner's normal the diagonal.
            let want = (*p - Vec3::splat(0.5)).normalize();
            assert!((*n - want).length() < 1e-5, "{p} {n}");
        }
    }

    #[test]
    fn a_seam_split_by_index_is_smoothed_by_position() {
        // Two triangles of a tent  whose shared edge is stored
        // twice, as a UV seam would store it; the faces are 53° apart.
        let mut m = Mesh {
            name: "tent".into(),
            positions: vec![
                Vec3::new(-1.0, 0.0, 0.0),
                Vec3::new(0.0, 0.5, 0.0),
                Vec3::new(0.0, 0.5, 1.0),
                Vec3::new(0.0, 0.5, 0.0),
                Vec3::new(0.0, 0.5, 1.0),
                Vec3::new(1.0, 0.0, 0.0),
            ],
            normals: vec![],
            uvs: vec![],
            uvs1: vec![],
            colors: vec![],
            triangles: vec![[0, 2, 1], [3, 4, 5]],
        };
        smooth(&mut m, 60.0);
        let ridge = m.normals[1];
        assert!((ridge - Vec3::Y).length() < 1e-6, "{ridge}");
        assert_eq!(m.normals[1], m.normals[3]);
    }

    #[test]
    fn existing_normals_are_kept() {
        let mut m = cube();
        m.normals = vec![Vec3::X; 8];
        smooth(&mut m, 60.0);
        assert_eq!(m.normals, vec![Vec3::X; 8]);
    }
}
