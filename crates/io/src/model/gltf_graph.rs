//! The glTF node graph before it is walked: checks the gltf crate would
//! otherwise panic on, cycles, and what the graph expands to.
//!
//! A node graph is a DAG in which a node may be reached along many paths
//! (node i with children `[i+1, i+1]` is reached 2^i times), and the loader
//! makes one mesh instance per path. So the expansion is counted first, in
//! one memoised pass over the nodes (linear in nodes + child links, no
//! recursion), and compared with the [`Limits`] before anything is
//! allocated or walked.

use crate::error::{Error, Result};
use crate::sandbox::Limits;
use gltf::json;
use gltf::json::validation::Checked;
use std::path::Path;

/// Checks what the gltf crate's accessors unwrap without checking (its own
/// validation does not cover them): a camera's `type` must name the
/// projection object it has.
pub(super) fn check_unchecked(path: &Path, root: &json::Root) -> Result<()> {
    use json::camera::Type;
    for (i, cam) in root.cameras.iter().enumerate() {
        let ok = match cam.type_ {
            Checked::Valid(Type::Perspective) => cam.perspective.is_some(),
            Checked::Valid(Type::Orthographic) => cam.orthographic.is_some(),
            Checked::Invalid => false,
        };
        if !ok {
            return Err(Error::gltf(
                path,
                format!("camera {i}"),
                "its `type` does not name a projection it has: a perspective camera needs a `perspective` object, an orthographic one an `orthographic` object",
            ));
        }
    }
    Ok(())
}

/// The triangles one instance of mesh `m` makes (from accessor counts,
/// before anything is read).
fn mesh_triangles(root: &json::Root, m: usize) -> u64 {
    use json::mesh::Mode;
    let Some(mesh) = root.meshes.get(m) else {
        return 0;
    };
    mesh.primitives
        .iter()
        .map(|p| {
            let count = p
                .indices
                .as_ref()
                .or_else(|| {
                    p.attributes
                        .iter()
                        .find(|(k, _)| matches!(k, Checked::Valid(json::mesh::Semantic::Positions)))
                        .map(|(_, v)| v)
                })
                .and_then(|a| root.accessors.get(a.value()))
                .map_or(0, |a| a.count.0);
            match p.mode {
                Checked::Valid(Mode::Triangles) => count / 3,
                Checked::Valid(Mode::TriangleStrip | Mode::TriangleFan) => count.saturating_sub(2),
                _ => 0,
            }
        })
        .fold(0u64, u64::saturating_add)
}

/// Checks that the graph under `roots` has no cycle and expands to at most
/// the limits' nodes and primitives, and returns how many times each mesh
/// is placed (once per path from a root to a node that uses it).
///
/// A mesh placed more than once is loaded once and shared by its
/// placements, so it counts its triangles once plus one primitive per
/// placement; a mesh placed once counts its triangles.
///
/// # Errors
/// [`Error::Gltf`] for a cycle, [`Error::Limit`] over a budget.
pub(super) fn check_expansion(
    path: &Path,
    root: &json::Root,
    roots: &[usize],
    limits: &Limits,
) -> Result<Vec<u64>> {
    const NEW: u8 = 0;
    const OPEN: u8 = 1;
    const DONE: u8 = 2;
    let n = root.nodes.len();
    let mut state = vec![NEW; n];
    // Post-order of the nodes reached: children before their parents.
    let mut order: Vec<usize> = Vec::new();
    // Iterative post-order: (node, next child to visit).
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for &r in roots {
        if r >= n || state[r] == DONE {
            continue;
        }
        state[r] = OPEN;
        stack.push((r, 0));
        while let Some(&mut (node, ref mut next)) = stack.last_mut() {
            let children = root.nodes[node].children.as_deref().unwrap_or(&[]);
            if let Some(c) = children.get(*next) {
                *next += 1;
                let c = c.value();
                if c >= n {
                    continue;
                }
                match state[c] {
                    NEW => {
                        state[c] = OPEN;
                        stack.push((c, 0));
                    }
                    OPEN => {
                        return Err(Error::gltf(
                            path,
                            format!("node {c}"),
                            "the node hierarchy is cyclic (a node is its own ancestor)",
                        ));
                    }
                    _ => {}
                }
                continue;
            }
            order.push(node);
            state[node] = DONE;
            stack.pop();
        }
    }
    // Paths from the roots to each node, parents before children.
    let mut paths = vec![0u64; n];
    for &r in roots.iter().filter(|&&r| r < n) {
        paths[r] = paths[r].saturating_add(1);
    }
    for &node in order.iter().rev() {
        for c in root.nodes[node].children.as_deref().unwrap_or(&[]) {
            if let Some(p) = paths.get(c.value()).copied() {
                paths[c.value()] = p.saturating_add(paths[node]);
            }
        }
    }
    let nodes = paths.iter().fold(0u64, |a, &p| a.saturating_add(p));
    let mut uses = vec![0u64; root.meshes.len()];
    for (node, &p) in paths.iter().enumerate() {
        if let Some(u) = root.nodes[node].mesh.and_then(|m| uses.get_mut(m.value())) {
            *u = u.saturating_add(p);
        }
    }
    let primitives = uses
        .iter()
        .enumerate()
        .map(|(m, &u)| match u {
            0 | 1 => mesh_triangles(root, m).saturating_mul(u),
            _ => mesh_triangles(root, m).saturating_add(u),
        })
        .fold(0u64, u64::saturating_add);
    if nodes > limits.max_nodes {
        return Err(Error::Limit {
            path: path.to_path_buf(),
            place: String::new(),
            msg: format!(
                "the node graph expands to {} node instances (nodes reached along several paths count once per path), over the limit of {}: raise it with --max-nodes N",
                nodes, limits.max_nodes
            ),
        });
    }
    if primitives > limits.max_primitives {
        return Err(limits.primitives_error(path, "", primitives));
    }
    Ok(uses)
}
