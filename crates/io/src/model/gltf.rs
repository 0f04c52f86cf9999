//! glTF 2.0 (`.gltf` with external or embedded buffers, and `.glb`) through
//! the gltf crate.
//!
//! The JSON is validated by gltf (except the `min`/`max` of positions, which
//! we do not need), then buffers are read here rather than by
//! `gltf::import`: images are decoded only for the textures a material uses
//! (`gltf_textures.rs`), and every accessor is bounds-checked before it is read, so a truncated or
//! inconsistent file is an error that names the node and primitive instead
//! of a panic. Cyclic node graphs are rejected.

use super::base64;
use super::gltf_accessors::{assemble, read_triangles, read_vec3};
use super::gltf_graph;
use super::gltf_textures;
use super::texture_load::TextureLoader;
use super::{check_normals, to_vec3, ModelCamera, ModelMesh, NamedMaterial, Xform};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::sandbox::{uri_path, Sandbox};
use glam::{DMat4, DQuat, DVec3};
use gltf::mesh::Mode;
use gltf::Document;
use gridrt_bbox::{Real, Vec3};
use gridrt_tracer::{Camera, Light, Material, Mesh, Projection, Rgb};
use std::borrow::Cow;
use std::collections::HashMap;
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};
use std::path::Path;
use std::rc::Rc;
use std::sync::Arc;

/// Deepest node hierarchy accepted (deeper means a cycle or a broken file).
const MAX_DEPTH: usize = 256;

/// Reads a `.gltf` or `.glb` file (`bytes`, read from `real`, named `path`
/// in messages) and its buffers, from the folders the sandbox allows a
/// model.
pub(crate) fn load(path: &Path, real: &Path, bytes: &[u8], sandbox: &Sandbox) -> Result<Model> {
    check_kind(path, bytes)?;
    let bytes = super::obj::strip_bom(bytes);
    // A GLB's binary chunk is read where it lies in the file's bytes, not
    // copied (the gltf crate's `Gltf` would copy it out).
    let (json, blob) = if bytes.starts_with(b"glTF") {
        let glb = gltf::binary::Glb::from_slice(bytes).map_err(|e| parse_error(path, e))?;
        (glb.json, glb.bin)
    } else {
        (Cow::Borrowed(bytes), None)
    };
    let gltf =
        gltf::Gltf::from_slice_without_validation(&json).map_err(|e| parse_error(path, e))?;
    drop(json);
    validate(path, &gltf.document)?;
    let doc = &gltf.document;
    let buffers = load_buffers(path, real, sandbox, doc, blob)?;

    let warnings = Vec::new();
    let mut textures = TextureLoader::new(path, real, sandbox);
    let mut materials = Vec::new();
    for m in doc.materials() {
        let name = m.name().map_or_else(
            || format!("material {}", m.index().unwrap_or(0)),
            str::to_string,
        );
        let maps = gltf_textures::maps(&m, &name, &mut textures, path, &buffers)?;
        let material = pbr_material(&m);
        materials.push(NamedMaterial {
            name,
            material,
            maps,
        });
    }

    let mut loader = Loader {
        path,
        doc,
        buffers: &buffers,
        file_name: path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        meshes: Vec::new(),
        mesh_uses: Vec::new(),
        shared: HashMap::new(),
        cameras: Vec::new(),
        lights: Vec::new(),
        warnings,
        stack: Vec::new(),
        vec3_cache: HashMap::new(),
    };
    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            // No scene: every node that is nobody's child is a root.
            let mut is_child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let root_ids: Vec<usize> = roots.iter().map(gltf::Node::index).collect();
    loader.mesh_uses =
        gltf_graph::check_expansion(path, doc.as_json(), &root_ids, &sandbox.limits)?;
    for root in roots {
        loader.visit(&root, DMat4::IDENTITY)?;
    }
    if doc.meshes().len() == 0 {
        return Err(Error::gltf(
            path,
            "",
            format!(
                "the file has no meshes ({} nodes, nothing to render): export the geometry as glTF meshes",
                doc.nodes().len()
            ),
        ));
    }
    if loader.meshes.is_empty() {
        return Err(Error::gltf(
            path,
            "",
            "no triangles: no node of the scene has a mesh with a triangle primitive",
        ));
    }
    Ok(Model {
        path: path.to_path_buf(),
        meshes: loader.meshes,
        materials,
        textures: textures.list,
        cameras: loader.cameras,
        lights: loader.lights,
        warnings: loader.warnings,
    })
}

/// Rejects files that are neither glTF JSON nor a GLB container before the
/// parser does, with a message about what the file is rather than a JSON
/// syntax error at 1:1 (an empty file, an image renamed `.glb`).
fn check_kind(path: &Path, bytes: &[u8]) -> Result<()> {
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let first = text.iter().find(|b| !b.is_ascii_whitespace());
    if let Some(length) = bytes
        .strip_prefix(b"glTF")
        .and_then(|rest| rest.get(4..8))
        .and_then(|b| <[u8; 4]>::try_from(b).ok())
        .map(u32::from_le_bytes)
    {
        // The gltf crate subtracts the 12-byte header from this length
        // unchecked: a smaller one is refused here.
        if length < 12 {
            return Err(Error::gltf(
                path,
                "",
                format!(
                    "broken GLB header: it gives the file's length as {length} bytes, \
                     less than the header's own 12 (export the model again)"
                ),
            ));
        }
    }
    if bytes.starts_with(b"glTF") || first == Some(&b'{') {
        return Ok(());
    }
    let msg = if first.is_none() {
        "the file is empty: export the model again".to_string()
    } else {
        let glb = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
        format!(
            "not a glTF file: {} (is it really glTF?)",
            if glb {
                "a .glb file starts with the bytes `glTF`"
            } else {
                "a .gltf file is JSON text starting with `{`"
            }
        )
    };
    Err(Error::gltf(path, "", msg))
}

/// A gltf parse error as ours: JSON errors carry line and column.
fn parse_error(path: &Path, e: gltf::Error) -> Error {
    match e {
        gltf::Error::Deserialize(j) => Error::gltf(
            path,
            format!("{}:{}", j.line(), j.column()),
            format!("invalid glTF JSON: {j}"),
        ),
        gltf::Error::Binary(b) => Error::gltf(
            path,
            "",
            format!("invalid GLB container: {b} (is the file truncated?)"),
        ),
        other => Error::gltf(path, "", format!("cannot read glTF: {other}")),
    }
}

/// Runs gltf's validation, tolerating missing `min`/`max` on accessors.
fn validate(path: &Path, doc: &Document) -> Result<()> {
    use gltf::json::validation::{Error as VErr, Validate};
    let root = doc.as_json();
    // gltf-json's own validation indexes `accessors` with a primitive's
    // POSITION attribute unchecked (it panics on a bad index), so those
    // references are checked first.
    let n_acc = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let refs = prim.attributes.values().chain(prim.indices.as_ref());
            if let Some(bad) = refs.map(|i| i.value()).find(|&i| i >= n_acc) {
                return Err(Error::gltf(
                    path,
                    format!("mesh {m}, primitive {p}"),
                    format!("refers to accessor {bad}, but the file has {n_acc} accessors"),
                ));
            }
        }
    }
    gltf_graph::check_unchecked(path, root)?;
    let mut errors: Vec<String> = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |p, e| {
        let p = p();
        let s = p.as_str();
        let min_max = s.ends_with(".min") || s.ends_with(".max");
        if !(min_max && e == VErr::Missing) {
            errors.push(format!("{s}: {e}"));
        }
    });
    if errors.is_empty() {
        Ok(())
    } else {
        let n = errors.len();
        errors.truncate(3);
        Err(Error::gltf(
            path,
            "",
            format!(
                "invalid glTF ({n} problem{}): {}",
                if n == 1 { "" } else { "s" },
                errors.join("; ")
            ),
        ))
    }
}

/// Reads every buffer: the GLB binary chunk, a `data:` URI, or a file the
/// sandbox lets the model read (the URI percent-decoded first, then
/// resolved against the glTF file's folder, then checked).
fn load_buffers<'a>(
    path: &Path,
    real: &Path,
    sandbox: &Sandbox,
    doc: &Document,
    mut blob: Option<Cow<'a, [u8]>>,
) -> Result<Vec<Cow<'a, [u8]>>> {
    let dir = path.parent().unwrap_or_else(|| Path::new(""));
    let mut out = Vec::new();
    for b in doc.buffers() {
        let place = match b.source() {
            gltf::buffer::Source::Uri(u) if !u.starts_with("data:") => {
                format!("buffer {} (\"{u}\")", b.index())
            }
            _ => format!("buffer {}", b.index()),
        };
        let data = match b.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                Error::gltf(
                    path,
                    &place,
                    "refers to the GLB binary chunk, which is missing (is the file truncated?)",
                )
            })?,
            gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let payload = rest.split_once(";base64,").map(|(_, d)| d).ok_or_else(|| {
                        Error::gltf(path, &place, "only base64 data: URIs are supported")
                    })?;
                    Cow::Owned(base64::decode(payload).map_err(|e| Error::gltf(path, &place, e))?)
                } else {
                    let rel = uri_path(uri).map_err(|e| Error::gltf(path, &place, e))?;
                    let file = sandbox.resolve(real, &rel, true).map_err(|e| match e {
                        Error::Denied { .. } => e,
                        other => Error::gltf(
                            path,
                            &place,
                            format!("{other} (the .bin must sit where the .gltf's URI says)"),
                        ),
                    })?;
                    Cow::Owned(sandbox.read(&file).map_err(|e| {
                        Error::gltf(path, &place, e.renamed(&file, &dir.join(&rel)).to_string())
                    })?)
                }
            }
        };
        if data.len() < b.length() {
            return Err(Error::gltf(
                path,
                &place,
                format!(
                    "holds {} bytes but the file declares {} (truncated?)",
                    data.len(),
                    b.length()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// State of the depth-first walk over the node graph.
struct Loader<'a> {
    path: &'a Path,
    doc: &'a Document,
    buffers: &'a [Cow<'a, [u8]>],
    file_name: String,
    meshes: Vec<ModelMesh>,
    /// How many times each mesh is placed (paths to nodes using it).
    mesh_uses: Vec<u64>,
    /// The primitives of shared meshes, in the mesh's own space, by mesh
    /// and primitive index (`None`: skipped, with a warning given once).
    shared: HashMap<(usize, usize), Option<Arc<Mesh>>>,
    cameras: Vec<ModelCamera>,
    lights: Vec<Light>,
    warnings: Vec<String>,
    /// Nodes on the current path, to detect cycles.
    stack: Vec<usize>,
    /// VEC3 accessors read so far: an accessor shared by many primitives
    /// or instances (a sparse one without a buffer view included) is
    /// decoded once.
    vec3_cache: HashMap<usize, Rc<AccessorResult<[f32; 3]>>>,
}

/// A decoded accessor, or why it could not be read.
type AccessorResult<T> = std::result::Result<Vec<T>, String>;

/// A glTF float triple in the tracer's precision.
fn to_real(p: [f32; 3]) -> Vec3 {
    Vec3::new(p[0] as Real, p[1] as Real, p[2] as Real)
}

/// `node 3 "name"`.
fn node_label(node: &gltf::Node) -> String {
    match node.name() {
        Some(n) => format!("node {} \"{n}\"", node.index()),
        None => format!("node {}", node.index()),
    }
}

/// A node's local transform in f64; `None` when it is not finite or the
/// rotation is not a quaternion.
fn local_matrix(node: &gltf::Node) -> Option<DMat4> {
    let m = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)))
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let q = DQuat::from_array(rotation.map(f64::from));
            let len = q.length();
            if !(len.is_finite() && len > 1e-12) {
                return None;
            }
            let q = q / len;
            DMat4::from_scale_rotation_translation(
                DVec3::from_array(scale.map(f64::from)),
                q,
                DVec3::from_array(translation.map(f64::from)),
            )
        }
    };
    m.is_finite().then_some(m)
}

impl Loader<'_> {
    /// A VEC3 accessor, read once.
    fn vec3(&mut self, acc: &gltf::Accessor) -> Rc<AccessorResult<[f32; 3]>> {
        let buffers = self.buffers;
        self.vec3_cache
            .entry(acc.index())
            .or_insert_with(|| Rc::new(read_vec3(acc, buffers)))
            .clone()
    }

    fn visit(&mut self, node: &gltf::Node, parent: DMat4) -> Result<()> {
        let label = node_label(node);
        if self.stack.contains(&node.index()) || self.stack.len() >= MAX_DEPTH {
            return Err(Error::gltf(
                self.path,
                label,
                "the node hierarchy is cyclic or deeper than 256 levels",
            ));
        }
        let local = local_matrix(node).ok_or_else(|| {
            Error::gltf(
                self.path,
                &label,
                "the node's transform is not finite or its rotation is not a quaternion",
            )
        })?;
        let world = parent * local;
        self.stack.push(node.index());

        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                let place = format!(
                    "{label}, mesh {}{}, primitive {}",
                    mesh.index(),
                    mesh.name()
                        .map_or_else(String::new, |n| format!(" \"{n}\"")),
                    prim.index()
                );
                if self.mesh_uses.get(mesh.index()).is_some_and(|&u| u >= 2) {
                    self.shared_primitive(&prim, &world, &place, &mesh, node)?;
                } else {
                    self.primitive(&prim, &world, &place, &mesh, node)?;
                }
            }
        }
        if let Some(cam) = node.camera().and_then(|c| camera(&c, &world)) {
            self.cameras.push(cam);
        }
        self.light(node, &world);
        for child in node.children() {
            self.visit(&child, world)?;
        }
        self.stack.pop();
        Ok(())
    }

    /// A primitive of a mesh placed once: baked into world space.
    fn primitive(
        &mut self,
        prim: &gltf::Primitive,
        world: &DMat4,
        place: &str,
        mesh: &gltf::Mesh,
        node: &gltf::Node,
    ) -> Result<()> {
        let Some(mut tmesh) = self.read_primitive(prim, place, mesh, node)? else {
            return Ok(());
        };
        let err = |msg: String| Error::gltf(self.path, place, msg);
        let xf = Xform::new(world).map_err(|e| err(format!("node transform: {e}")))?;
        xf.apply(&mut tmesh).map_err(err)?;
        check_normals(&mut tmesh, &mut self.warnings);
        self.meshes.push(ModelMesh {
            mesh: Arc::new(tmesh),
            material: prim.material().index(),
            mirrored: xf.mirrors,
            placement: None,
        });
        Ok(())
    }

    /// A primitive of a mesh placed by several nodes: read once in the
    /// mesh's own space, shared, and placed by the node's transform.
    fn shared_primitive(
        &mut self,
        prim: &gltf::Primitive,
        world: &DMat4,
        place: &str,
        mesh: &gltf::Mesh,
        node: &gltf::Node,
    ) -> Result<()> {
        Xform::new(world)
            .map_err(|e| Error::gltf(self.path, place, format!("node transform: {e}")))?;
        let key = (mesh.index(), prim.index());
        let shared = match self.shared.get(&key) {
            Some(s) => s.clone(),
            None => {
                let read = self.read_primitive(prim, place, mesh, node)?.map(|mut m| {
                    check_normals(&mut m, &mut self.warnings);
                    Arc::new(m)
                });
                self.shared.insert(key, read.clone());
                read
            }
        };
        if let Some(m) = shared {
            self.meshes.push(ModelMesh {
                mesh: m,
                material: prim.material().index(),
                mirrored: false,
                placement: Some(*world),
            });
        }
        Ok(())
    }

    /// A triangle primitive's mesh in the mesh's own space; `None` (with a
    /// warning) for a primitive that is not made of triangles or has none.
    fn read_primitive(
        &mut self,
        prim: &gltf::Primitive,
        place: &str,
        mesh: &gltf::Mesh,
        node: &gltf::Node,
    ) -> Result<Option<Mesh>> {
        let err = |msg: String| Error::gltf(self.path, place, msg);
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            self.warnings.push(format!(
                "{}: {place}: skipped a {mode:?} primitive (only triangles are rendered)",
                self.path.display()
            ));
            return Ok(None);
        }
        let pos_acc = prim
            .get(&gltf::Semantic::Positions)
            .ok_or_else(|| err("the primitive has no POSITION attribute".into()))?;
        let raw = self.vec3(&pos_acc);
        let raw = raw
            .as_ref()
            .as_ref()
            .map_err(|e| err(format!("POSITION: {e}")))?;
        if let Some(k) = raw.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(err(format!(
                "vertex {k} has a non-finite position (NaN or infinity): fix the exporter's output"
            )));
        }
        let n = raw.len();
        let triangles = match prim.indices() {
            Some(acc) => read_triangles(&acc, mode, self.buffers)
                .map_err(|e| err(format!("indices: {e}")))?,
            None => assemble(&(0..n as u32).collect::<Vec<_>>(), mode),
        };
        if let Some(&bad) = triangles.iter().flatten().find(|&&i| i as usize >= n) {
            return Err(err(format!(
                "index {bad} is out of range: the primitive has {n} vertices"
            )));
        }
        if triangles.is_empty() {
            self.warnings.push(format!(
                "{}: {place}: no triangles (too few indices), skipped",
                self.path.display()
            ));
            return Ok(None);
        }
        let normals = match prim.get(&gltf::Semantic::Normals) {
            Some(acc) => match self.vec3(&acc).as_ref() {
                Ok(v) if v.len() == n => v.iter().map(|&p| to_real(p)).collect(),
                _ => {
                    self.warnings.push(format!(
                        "{}: {place}: unreadable NORMAL attribute, using flat normals",
                        self.path.display()
                    ));
                    Vec::new()
                }
            },
            None => Vec::new(),
        };
        let [uvs, uvs1] = gltf_textures::primitive_uvs(
            prim,
            n,
            self.buffers,
            (self.path, place),
            &mut self.warnings,
        );
        let tmesh = Mesh {
            name: format!(
                "{}:{}/{}/{}",
                self.file_name,
                node.name()
                    .map_or_else(|| format!("node{}", node.index()), str::to_string),
                mesh.name()
                    .map_or_else(|| format!("mesh{}", mesh.index()), str::to_string),
                prim.index()
            ),
            positions: raw.iter().map(|&p| to_real(p)).collect(),
            normals,
            uvs,
            uvs1,
            colors: Vec::new(),
            triangles,
        };
        Ok(Some(tmesh))
    }

    /// Records a `KHR_lights_punctual` light of the node, if any.
    fn light(&mut self, node: &gltf::Node, world: &DMat4) {
        use gltf::json::extensions::scene::khr_lights_punctual::Type;
        use gltf::json::validation::Checked;
        let root = self.doc.as_json();
        let Some(index) = root
            .nodes
            .get(node.index())
            .and_then(|n| n.extensions.as_ref())
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .map(|l| l.light.value())
        else {
            return;
        };
        let Some(l) = root
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .and_then(|k| k.lights.get(index))
        else {
            return;
        };
        let color = Rgb::from_array(l.color);
        let intensity = if l.intensity.is_finite() {
            l.intensity.max(0.0)
        } else {
            1.0
        };
        let position = to_vec3(world.transform_point3(DVec3::ZERO));
        // Lights shine along their local −z axis.
        let dir = world.transform_vector3(DVec3::NEG_Z).try_normalize();
        match (&l.type_, dir) {
            (Checked::Valid(Type::Directional), Some(d)) => self.lights.push(Light::Directional {
                direction: to_vec3(-d),
                color,
                intensity,
                shadows: true,
            }),
            (Checked::Valid(Type::Point), _) => self.lights.push(Light::Point {
                position,
                color,
                intensity,
                inverse_square: true,
                shadows: true,
            }),
            (Checked::Valid(Type::Spot), Some(d)) => {
                // Cone angles in radians, 0 ≤ inner < outer ≤ π/2 by the
                // specification; out-of-range values are clamped into it.
                let (inner, outer) = l.spot.as_ref().map_or((0.0, FRAC_PI_4), |s| {
                    (s.inner_cone_angle, s.outer_cone_angle)
                });
                let finite_or = |x: f32, d: f32| if x.is_finite() { x } else { d };
                let outer = finite_or(outer, FRAC_PI_4).clamp(1e-4, FRAC_PI_2);
                let inner = finite_or(inner, 0.0).clamp(0.0, outer);
                self.lights.push(Light::Spot {
                    position,
                    direction: to_vec3(d),
                    color,
                    intensity,
                    inner_deg: inner.to_degrees(),
                    outer_deg: outer.to_degrees(),
                    inverse_square: true,
                    shadows: true,
                });
            }
            _ => self.warnings.push(format!(
                "{}: {}: light skipped (unknown type or degenerate transform)",
                self.path.display(),
                node_label(node)
            )),
        }
    }
}

/// A node camera in world space: it looks along its local −z with +y up.
fn camera(cam: &gltf::Camera, world: &DMat4) -> Option<ModelCamera> {
    let eye = world.transform_point3(DVec3::ZERO);
    let fwd = world.transform_vector3(DVec3::NEG_Z).try_normalize()?;
    let up = world.transform_vector3(DVec3::Y).try_normalize()?;
    let (projection, aspect) = match cam.projection() {
        gltf::camera::Projection::Perspective(p) => {
            let vfov = f64::from(p.yfov()).to_degrees();
            if !(vfov > 0.0 && vfov < 180.0) {
                return None;
            }
            (
                Projection::Perspective {
                    vfov_deg: vfov as Real,
                },
                p.aspect_ratio().map(f64::from),
            )
        }
        gltf::camera::Projection::Orthographic(o) => {
            let h = 2.0 * f64::from(o.ymag()).abs();
            let x = f64::from(o.xmag()).abs();
            if !(h > 0.0 && h.is_finite()) {
                return None;
            }
            (
                Projection::Orthographic { height: h as Real },
                (x > 0.0).then(|| 2.0 * x / h),
            )
        }
    };
    Some(ModelCamera {
        name: cam
            .name()
            .map_or_else(|| format!("camera {}", cam.index()), str::to_string),
        camera: Camera {
            eye: to_vec3(eye),
            look_at: to_vec3(eye + fwd),
            up: to_vec3(up),
            projection,
            lens: None,
        },
        aspect: aspect.filter(|a| a.is_finite() && *a > 0.0),
    })
}

/// Maps a glTF metallic-roughness material to ours:
///
/// - emissive factor non-zero without an emissive texture → Emissive;
/// - `KHR_materials_transmission` with a factor of at least ½ on a
///   material that is not mostly metal → glass: [`Material::Dielectric`],
///   or [`Material::RoughDielectric`] when rough, of the index of
///   `KHR_materials_ior` (1.5 by default) and the absorption of
///   `KHR_materials_volume` (Beer's law: `attenuationColor` remains after
///   `attenuationDistance`; clear without it). The blend of a partial
///   transmission with the opaque BRDF is not modelled: below ½ the
///   material stays opaque;
/// - otherwise [`Material::MetallicRoughness`]: the specification's BRDF
///   (a Lambertian base and a GGX lobe with `α = roughness²`, blended by
///   metalness), its factors multiplied by the metallic-roughness texture
///   (blue = metallic, green = roughness) when there is one.
///
/// Textures, emission maps and alpha modes are the material's maps
/// (`gltf_textures::maps`).
fn pbr_material(m: &gltf::Material) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let finite01 = |x: f32| {
        if x.is_finite() {
            x.clamp(0.0, 1.0)
        } else {
            1.0
        }
    };
    let bc = pbr.base_color_factor();
    let base = Rgb::new(finite01(bc[0]), finite01(bc[1]), finite01(bc[2]));
    let metallic = finite01(pbr.metallic_factor());
    let roughness = finite01(pbr.roughness_factor());
    let e = m
        .emissive_factor()
        .map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 });
    // KHR_materials_emissive_strength scales the factor (HDR emission).
    let strength = m
        .emissive_strength()
        .filter(|s| s.is_finite() && *s >= 0.0)
        .unwrap_or(1.0);
    let emissive = Rgb::from_array(e) * strength;
    let max_e = emissive.max_element();
    // An emissive texture is a map (the surface reflects too); alpha below
    // 1 is the material's alpha mode (cut-outs or blending).
    if max_e > 0.0 && m.emissive_texture().is_none() {
        return Material::Emissive {
            color: emissive / max_e,
            strength: max_e,
        };
    }
    let transmission = m
        .transmission()
        .map_or(0.0, |t| finite01(t.transmission_factor()));
    if transmission >= 0.5 && metallic < 0.5 {
        return glass(m, roughness);
    }
    Material::MetallicRoughness {
        base,
        metallic,
        roughness,
    }
}

/// The glass of a transmitting glTF material ([`pbr_material`]).
fn glass(m: &gltf::Material, roughness: f32) -> Material {
    // glTF allows an index of 1 and up (0 is a legacy "no index").
    let ior = m
        .ior()
        .filter(|i| i.is_finite() && (1.0..=10.0).contains(i))
        .unwrap_or(1.5);
    let tint = m.volume().map_or(Rgb::ONE, |v| {
        let d = v.attenuation_distance();
        let c = Rgb::from_array(v.attenuation_color().map(|x| {
            if x.is_finite() {
                x.clamp(0.0, 1.0)
            } else {
                1.0
            }
        }));
        if d.is_finite() && d > 0.0 {
            c.powf(1.0 / d)
        } else {
            Rgb::ONE
        }
    });
    if roughness > 0.0 {
        Material::RoughDielectric {
            ior,
            tint,
            roughness,
        }
    } else {
        Material::Dielectric { ior, tint }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans() {
        assert_eq!(
            assemble(&[0, 1, 2, 3], Mode::TriangleStrip),
            vec![[0, 1, 2], [2, 1, 3]]
        );
        assert_eq!(
            assemble(&[0, 1, 2, 3], Mode::TriangleFan),
            vec![[0, 1, 2], [0, 2, 3]]
        );
        assert_eq!(assemble(&[0, 1, 2, 3], Mode::Triangles), vec![[0, 1, 2]]);
        assert!(assemble(&[0, 1], Mode::TriangleStrip).is_empty());
    }

    /// A GLB whose header gives a length below its own 12 bytes is an
    /// error, not an overflow inside the gltf crate (found by fuzzing).
    #[test]
    fn a_glb_length_below_its_header_is_an_error() {
        for length in [0u32, 11] {
            let mut bytes = b"glTF".to_vec();
            bytes.extend(2u32.to_le_bytes());
            bytes.extend(length.to_le_bytes());
            bytes.extend([0u8; 20]);
            let e = check_kind(Path::new("m.glb"), &bytes)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("m.glb") && e.contains("broken GLB header"),
                "{e}"
            );
        }
        let mut ok = b"glTF".to_vec();
        ok.extend(2u32.to_le_bytes());
        ok.extend(12u32.to_le_bytes());
        assert!(check_kind(Path::new("m.glb"), &ok).is_ok());
    }
}
