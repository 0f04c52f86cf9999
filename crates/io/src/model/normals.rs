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
///
/// Lean in memory, as it runs on the largest meshes: positions are grouped
/// by sorting the vertices, not hashing the corners; the corners of each
/// position are listed in one flat array; face normals and corner angles
/// are computed where a position's corners need them, not kept for the
/// whole mesh. Beside the mesh it holds about 13 bytes per corner and 12
/// per vertex.
pub(crate) fn smooth(mesh: &mut Mesh, crease_deg: f64) {
    if !mesh.normals.is_empty() || mesh.triangles.is_empty() {
        return;
    }
    let cos_crease = crease_deg.clamp(0.0, 180.0).to_radians().cos() as Real;
    let nv = mesh.positions.len();
    let (group_of, groups) = position_groups(&mesh.positions);
    let corners = Corners::new(&mesh.triangles, &group_of, groups);
    drop(group_of);

    // One vertex per (vertex, normal): a vertex whose corners get
    // different normals is split, one copy per normal (the vertex each
    // copy copies, and its normal). NaN: no corner has set it yet.
    let mut normals = vec![Vec3::NAN; nv];
    let mut copy_of: Vec<u32> = Vec::new();
    let mut copies: HashMap<(u32, [u64; 3]), u32> = HashMap::new();
    // One position's corners: each one's face normal and weighted normal.
    let (mut own, mut weighted) = (Vec::new(), Vec::new());
    for g in 0..groups {
        let (faces, ks) = corners.of(g);
        own.clear();
        weighted.clear();
        for (&f, &k) in faces.iter().zip(ks) {
            // Corners done before may point at copies, not yet appended.
            let t = mesh.triangles[f as usize].map(|v| match (v as usize).checked_sub(nv) {
                Some(c) => copy_of[c],
                None => v,
            });
            let (n, angle) = face_corner(&mesh.positions, t, k);
            own.push(n);
            weighted.push(n * angle);
        }
        let big = faces.len() > MAX_CREASE_CORNERS;
        let mean_n = if big {
            let mean = weighted
                .iter()
                .fold(Vec3::ZERO, |s, &w| s + w)
                .normalize_or_zero();
            own.iter()
                .zip(&weighted)
                .filter(|(n, _)| n.dot(mean) >= cos_crease)
                .fold(Vec3::ZERO, |s, (_, &w)| s + w)
        } else {
            Vec3::ZERO
        };
        for (i, (&f, &k)) in faces.iter().zip(ks).enumerate() {
            let sum = if big {
                mean_n
            } else {
                own.iter()
                    .zip(&weighted)
                    .filter(|(n, _)| n.dot(own[i]) >= cos_crease)
                    .fold(Vec3::ZERO, |s, (_, &w)| s + w)
            };
            // A corner whose faces cancel out, or a degenerate face's
            // corner, takes its face's normal, or any unit vector.
            let n = sum
                .try_normalize()
                .or_else(|| own[i].try_normalize())
                .unwrap_or(Vec3::Z);
            let v = &mut mesh.triangles[f as usize][usize::from(k)];
            let slot = &mut normals[*v as usize];
            if slot.is_nan() {
                *slot = n;
            } else if *slot != n {
                let bits = n.to_array().map(|x| super::r64(x).to_bits());
                let next = (nv + copy_of.len()) as u32;
                let new = *copies.entry((*v, bits)).or_insert_with(|| {
                    copy_of.push(*v);
                    normals.push(n);
                    next
                });
                *v = new;
            }
        }
    }
    drop(corners);
    // Copies go after the vertices, with their position, texture
    // coordinates and colour; no capacity is left over.
    let has_uvs = mesh.uvs.len() == nv;
    let has_colors = mesh.colors.len() == nv;
    append_copies(&mut mesh.positions, &copy_of);
    if has_uvs {
        append_copies(&mut mesh.uvs, &copy_of);
    }
    if has_colors {
        append_copies(&mut mesh.colors, &copy_of);
    }
    // Vertices no triangle uses keep a placeholder-free unit normal.
    for n in &mut normals {
        if n.is_nan() {
            *n = Vec3::Z;
        }
    }
    normals.shrink_to_fit();
    mesh.normals = normals;
}

/// The unit normal of triangle `t` (zero for a degenerate one, which then
/// gives and takes nothing) and its angle at corner `k`.
#[inline]
fn face_corner(p: &[Vec3], t: [u32; 3], k: u8) -> (Vec3, Real) {
    let [a, b, c] = t.map(|i| p[i as usize]);
    let n = (b - a).cross(c - a).normalize_or_zero();
    let angle = |o: Vec3, u: Vec3, v: Vec3| -> Real {
        let (u, v) = ((u - o).normalize_or_zero(), (v - o).normalize_or_zero());
        u.dot(v).clamp(-1.0, 1.0).acos()
    };
    let at = match k {
        0 => angle(a, b, c),
        1 => angle(b, c, a),
        _ => angle(c, a, b),
    };
    (n, at)
}

/// Appends to `v` a copy of `v[k]` for each `k` of `copy_of`, growing it
/// to exactly its new length.
fn append_copies<T: Copy>(v: &mut Vec<T>, copy_of: &[u32]) {
    v.reserve_exact(copy_of.len());
    for &k in copy_of {
        v.push(v[k as usize]);
    }
    v.shrink_to_fit();
}

/// Each vertex's position group (vertices at bitwise equal positions, -0
/// and +0 alike, are one group) and the number of groups.
fn position_groups(p: &[Vec3]) -> (Vec<u32>, usize) {
    let key = |v: Vec3| v.to_array().map(|x| (x + 0.0).to_bits());
    let mut order: Vec<u32> = (0..p.len() as u32).collect();
    order.sort_unstable_by_key(|&v| key(p[v as usize]));
    let mut group_of = vec![0u32; p.len()];
    let mut groups = 0usize;
    let mut last = None;
    for &v in &order {
        let k = key(p[v as usize]);
        if last != Some(k) {
            last = Some(k);
            groups += 1;
        }
        group_of[v as usize] = (groups - 1) as u32;
    }
    (group_of, groups)
}

/// The corners of each position group, in face order: group `g`'s are
/// `faces[start[g]..start[g + 1]]`, with their corner index in `ks`.
struct Corners {
    start: Vec<usize>,
    faces: Vec<u32>,
    ks: Vec<u8>,
}

impl Corners {
    fn new(triangles: &[[u32; 3]], group_of: &[u32], groups: usize) -> Self {
        let mut start = vec![0usize; groups + 1];
        for t in triangles {
            for &v in t {
                start[group_of[v as usize] as usize + 1] += 1;
            }
        }
        for g in 0..groups {
            start[g + 1] += start[g];
        }
        let n = start[groups];
        let (mut faces, mut ks) = (vec![0u32; n], vec![0u8; n]);
        // `start[g]` is group g's next free slot while filling, its end
        // after; shifting by one makes it its start again.
        for (f, t) in triangles.iter().enumerate() {
            for (k, &v) in t.iter().enumerate() {
                let slot = &mut start[group_of[v as usize] as usize];
                faces[*slot] = f as u32;
                ks[*slot] = k as u8;
                *slot += 1;
            }
        }
        start.copy_within(0..groups, 1);
        start[0] = 0;
        Self { start, faces, ks }
    }

    fn of(&self, g: usize) -> (&[u32], &[u8]) {
        let r = self.start[g]..self.start[g + 1];
        (&self.faces[r.clone()], &self.ks[r])
    }
}

#[cfg(test)]
mod reference;

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

    /// Runs the lean and the reference smoothing on copies of `m` and
    /// checks that every corner ends up with the same position, normal,
    /// texture coordinate and colour, bit for bit, and that both split the
    /// same number of vertices.
    fn same_as_reference(m: &Mesh, crease: f64) {
        let (mut lean, mut reference) = (m.clone(), m.clone());
        smooth(&mut lean, crease);
        reference::smooth_reference(&mut reference, crease);
        assert_eq!(lean.positions.len(), reference.positions.len());
        assert_eq!(lean.normals.len(), reference.normals.len());
        assert_eq!(lean.uvs.len(), reference.uvs.len());
        assert_eq!(lean.colors.len(), reference.colors.len());
        let bits = |v: Vec3| v.to_array().map(|x| crate::model::r64(x).to_bits());
        for (a, b) in lean.triangles.iter().zip(&reference.triangles) {
            for (&i, &j) in a.iter().zip(b) {
                let (i, j) = (i as usize, j as usize);
                assert_eq!(bits(lean.positions[i]), bits(reference.positions[j]));
                assert_eq!(bits(lean.normals[i]), bits(reference.normals[j]));
                if !m.uvs.is_empty() {
                    assert_eq!(lean.uvs[i], reference.uvs[j]);
                }
                if !m.colors.is_empty() {
                    assert_eq!(lean.colors[i], reference.colors[j]);
                }
            }
        }
        // Nothing is kept beyond the arrays' lengths.
        assert_eq!(lean.positions.capacity(), lean.positions.len());
        assert_eq!(lean.normals.capacity(), lean.normals.len());
    }

    /// A bumpy grid of `n` × `n` quads whose vertices are stored twice
    /// along a seam, with a few degenerate faces, texture coordinates and
    /// colours.
    fn bumpy(n: u32) -> Mesh {
        let mut seed = 0x9E37_79B9_7F4A_7C15_u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 40) as Real / (1u64 << 24) as Real
        };
        let mut positions = Vec::new();
        for y in 0..=n {
            for x in 0..=n {
                let h = if (x + y) % 7 == 0 { 0.8 } else { 0.1 * rnd() };
                positions.push(Vec3::new(x as Real, h, y as Real));
            }
        }
        let at = |x: u32, y: u32| y * (n + 1) + x;
        let seam = positions.len() as u32;
        // The column x = n / 2 again, for the quads right of it.
        for y in 0..=n {
            positions.push(positions[at(n / 2, y) as usize]);
        }
        let mut triangles = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let v = |dx: u32, dy: u32| {
                    if x + dx == n / 2 && dx == 0 && x > 0 {
                        seam + y + dy
                    } else {
                        at(x + dx, y + dy)
                    }
                };
                triangles.push([v(0, 0), v(0, 1), v(1, 1)]);
                triangles.push([v(0, 0), v(1, 1), v(1, 0)]);
            }
        }
        triangles.push([0, 0, 1]);
        triangles.push([2, 2, 2]);
        let k = positions.len();
        let uvs = (0..k).map(|i| glam::Vec2::new(i as f32, 0.5)).collect();
        let colors = (0..k)
            .map(|i| gridrt_tracer::Rgb::splat(i as f32 / k as f32))
            .collect();
        Mesh {
            name: "bumpy".into(),
            positions,
            normals: vec![],
            uvs,
            uvs1: vec![],
            colors,
            triangles,
        }
    }

    /// A fan of `n` thin triangles around the origin: more corners at one
    /// position than the crease test takes one by one.
    fn fan(n: u32) -> Mesh {
        let mut positions = vec![Vec3::ZERO];
        for i in 0..=n {
            let a = i as Real * 0.01;
            positions.push(Vec3::new(a.cos(), 0.3 * (i % 3) as Real, a.sin()));
        }
        Mesh {
            name: "fan".into(),
            positions,
            normals: vec![],
            uvs: vec![],
            uvs1: vec![],
            colors: vec![],
            triangles: (1..=n).map(|i| [0, i, i + 1]).collect(),
        }
    }

    #[test]
    fn the_lean_smoothing_matches_the_reference() {
        for crease in [0.0, 30.0, 60.0, 89.0, 180.0] {
            same_as_reference(&cube(), crease);
            same_as_reference(&bumpy(12), crease);
            same_as_reference(&fan(600), crease);
        }
        let teapot = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fixtures/meshes/teapot/teapot.obj"
        );
        let model = crate::load_model(std::path::Path::new(teapot)).unwrap();
        for mm in &model.meshes {
            let mut m = (*mm.mesh).clone();
            m.normals.clear();
            same_as_reference(&m, DEFAULT_CREASE_DEG);
        }
    }
}
