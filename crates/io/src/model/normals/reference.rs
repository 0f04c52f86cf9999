//! The first implementation of [`super::smooth`], straightforward and
//! memory-hungry (a hash map over corners, a vector per position, every
//! corner's normal at once): the oracle the lean one is checked against.

use super::MAX_CREASE_CORNERS;
use gridrt_bbox::{Real, Vec3};
use gridrt_tracer::Mesh;
use std::collections::HashMap;

/// Fills `mesh.normals` with smooth normals, unless it already has some.
/// `crease_deg` is the largest angle, in degrees, between two faces that
/// are shaded as one smooth surface (0 gives flat facets, 180 smooths
/// everything).
pub(super) fn smooth_reference(mesh: &mut Mesh, crease_deg: f64) {
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
                    let bits = n.to_array().map(|x| crate::model::r64(x).to_bits());
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
