//! What `gridrt render` and `gridrt info` say of a scene's contents,
//! taken before the renderer lets the scene's geometry go.

use gridrt_tracer::{Geometry, Scene};

/// The objects and triangles of a scene, counted.
pub(crate) struct SceneCounts {
    pub objects: usize,
    pub triangles: usize,
    /// "12 objects: 3 spheres, 1 box, 1 plane, 7 meshes (1234 triangles)".
    pub text: String,
}

impl SceneCounts {
    pub(crate) fn of(s: &Scene) -> Self {
        Self {
            objects: s.objects.len(),
            triangles: triangle_count(s),
            text: scene_counts(s),
        }
    }
}

fn triangle_count(s: &Scene) -> usize {
    s.objects
        .iter()
        .map(|o| match &o.geometry {
            Geometry::Mesh(m) => m.triangles.len(),
            Geometry::Instance { mesh, .. } => mesh.triangles.len(),
            _ => 0,
        })
        .sum()
}

/// "12 objects: 3 spheres, 1 box, 1 plane, 7 meshes (1234 triangles)".
fn scene_counts(s: &Scene) -> String {
    let (mut sp, mut bx, mut pl, mut me) = (0, 0, 0, 0);
    for o in &s.objects {
        match &o.geometry {
            Geometry::Sphere { .. } => sp += 1,
            Geometry::Spheres(set) => sp += set.spheres.len(),
            Geometry::Cuboid { .. } => bx += 1,
            Geometry::Plane { .. } => pl += 1,
            Geometry::Mesh(_) | Geometry::Instance { .. } => me += 1,
        }
    }
    let plural = |n: usize, w: &str| format!("{n} {w}{}", if n == 1 { "" } else { "s" });
    let mut parts = Vec::new();
    for (n, w) in [(sp, "sphere"), (bx, "box"), (pl, "plane"), (me, "mesh")] {
        if n > 0 {
            let word = plural(n, w);
            parts.push(if w == "box" || w == "mesh" {
                word.replace("boxs", "boxes").replace("meshs", "meshes")
            } else {
                word
            });
        }
    }
    let mut t = format!(
        "{}: {}",
        plural(s.objects.len(), "object"),
        parts.join(", ")
    );
    if me > 0 {
        t += &format!(" ({} triangles)", triangle_count(s));
    }
    t
}
