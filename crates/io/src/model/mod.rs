//! Models read from mesh files (OBJ through tobj, PLY through ply-rs-bw,
//! glTF 2.0 through gltf):
//! triangle meshes in the file's world space, with the file's materials and,
//! for glTF, its cameras and lights.

pub(crate) mod base64;
mod gltf;
mod gltf_accessors;
mod gltf_graph;
mod gltf_textures;
mod normals;
mod obj;
mod obj_textures;
mod ply;
pub(crate) mod texture_load;

pub(crate) use self::normals::{applied_once, AppliedCache};
pub use self::normals::{Crease, Normals, DEFAULT_CREASE_DEG};
use crate::error::{Error, Result};
use crate::sandbox::Sandbox;
use glam::{DMat3, DMat4, DVec3};
use gridrt_bbox::{Aabb, Real, Vec3};
use gridrt_tracer::{Camera, Light, Material, MaterialMaps, Mesh, Rgb, Texture};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The kinds of model file gridrt reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelFormat {
    /// Wavefront OBJ (with MTL materials).
    Obj,
    /// glTF 2.0, `.gltf` (JSON with external or embedded buffers) or `.glb`.
    Gltf,
    /// Stanford PLY, ASCII or binary (little or big endian).
    Ply,
}

impl ModelFormat {
    /// The format of `path` by its extension (case-insensitive), if it is a model.
    #[must_use]
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Self::Obj),
            "gltf" | "glb" => Some(Self::Gltf),
            "ply" => Some(Self::Ply),
            _ => None,
        }
    }
}

/// A model file's content, in the file's world space.
#[derive(Clone, Debug)]
pub struct Model {
    /// The file it came from.
    pub path: PathBuf,
    /// The meshes: OBJ groups/objects in file order, or glTF primitives in
    /// node-then-primitive order (depth first from the scene's root nodes).
    pub meshes: Vec<ModelMesh>,
    /// The file's materials, converted (see `docs/scene-format.md` for the
    /// mapping), in file order.
    pub materials: Vec<NamedMaterial>,
    /// The cameras in node order (glTF only): the first is the default view.
    pub cameras: Vec<ModelCamera>,
    /// The file's lights (glTF `KHR_lights_punctual`: directional, point and spot).
    pub lights: Vec<Light>,
    /// The file's texture images, decoded; [`NamedMaterial::maps`] refer
    /// to them by index.
    pub textures: Vec<Texture>,
    /// Things skipped or approximated while reading (points and lines,
    /// textures, a missing material library). Not errors.
    pub warnings: Vec<String>,
}

/// One mesh of a model, in the file's order (glTF: node order).
#[derive(Clone, Debug)]
pub struct ModelMesh {
    /// The triangles, vertex order as in the file: in the model's space,
    /// or, when `placement` is given, in the mesh's own space and shared
    /// with the other placements of the mesh.
    pub mesh: Arc<Mesh>,
    /// Index into [`Model::materials`]; `None` for the default material.
    pub material: Option<usize>,
    /// True when the mesh's transform mirrors space (negative determinant):
    /// the winding is reversed, so front faces turn clockwise until
    /// [`ModelMesh::oriented`] swaps them back. Always false for a placed
    /// mesh, whose mirror the renderer handles.
    pub mirrored: bool,
    /// For a mesh the file uses more than once (a glTF mesh on several
    /// nodes): where this use places it in the model's space.
    pub placement: Option<DMat4>,
}

impl ModelMesh {
    /// The mesh with counter-clockwise front faces: a mirrored mesh gets its
    /// triangles' second and third vertices swapped.
    ///
    /// Takes the mesh out of its `Arc` when this is the only reference (a
    /// mesh placed once, straight from the loader): its arrays are moved,
    /// not copied. A mesh shared with other placements or a cached model is
    /// copied.
    #[must_use]
    pub fn oriented(self) -> Mesh {
        let mut mesh = Arc::try_unwrap(self.mesh).unwrap_or_else(|shared| (*shared).clone());
        if self.mirrored {
            for t in &mut mesh.triangles {
                t.swap(1, 2);
            }
        }
        mesh
    }
}

/// A material with the name the file gave it.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedMaterial {
    /// The file's name for it (unnamed glTF materials get `material N`).
    pub name: String,
    /// The converted material.
    pub material: Material,
    /// Its textures (indices into [`Model::textures`]) and alpha mode.
    pub maps: MaterialMaps,
}

/// A camera found in a model file.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelCamera {
    /// The file's name for it (unnamed glTF cameras get `camera N`, N the
    /// camera's index), for `--camera NAME`.
    pub name: String,
    /// The camera in world space.
    pub camera: Camera,
    /// Width / height, when the file gives one.
    pub aspect: Option<f64>,
}

/// Reads an OBJ, PLY or glTF file (by extension), reading only from its own
/// folder and the working directory (see [`load_model_in`]).
///
/// # Errors
/// As [`load_model_in`].
pub fn load_model(path: &Path) -> Result<Model> {
    load_model_in(path, &Sandbox::for_input(path))
}

/// Reads an OBJ, PLY or glTF file (by extension) under a [`Sandbox`]: the file
/// itself is read as named (it must be a regular file within the size
/// limit); the files it names (`mtllib`, buffers) only from its own folder
/// and the sandbox's explicitly allowed folders.
///
/// # Errors
/// [`Error::UnsupportedInput`] for another extension, [`Error::Read`] /
/// [`Error::NotRegular`] when the file cannot be read, [`Error::Denied`]
/// for a reference outside the allowed folders, [`Error::Limit`] over a
/// budget, [`Error::Obj`] / [`Error::Ply`] / [`Error::Gltf`] when it is malformed or holds
/// no triangles.
pub fn load_model_in(path: &Path, sandbox: &Sandbox) -> Result<Model> {
    if ModelFormat::from_path(path).is_none() {
        return Err(Error::UnsupportedInput {
            path: path.to_path_buf(),
            models_only: true,
        });
    }
    let real = sandbox.top_level(path)?;
    load_resolved(path, &real, sandbox)
}

/// Reads a model whose path the sandbox resolved: `path` names it in
/// messages, `real` is its canonical path.
pub(crate) fn load_resolved(path: &Path, real: &Path, sandbox: &Sandbox) -> Result<Model> {
    let bytes = sandbox.read(real).map_err(|e| e.renamed(real, path))?;
    match ModelFormat::from_path(path) {
        Some(ModelFormat::Obj) => obj::load(path, real, &bytes, sandbox),
        Some(ModelFormat::Gltf) => gltf::load(path, real, &bytes, sandbox),
        Some(ModelFormat::Ply) => ply::load(path, &bytes, sandbox),
        None => Err(Error::UnsupportedInput {
            path: path.to_path_buf(),
            models_only: true,
        }),
    }
    .map_err(|e| e.renamed(real, path))
}

impl Model {
    /// The number of triangles over all meshes.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.mesh.triangles.len()).sum()
    }

    /// What the model costs in primitives: the triangles of its baked
    /// meshes, those of each shared mesh once, and one per placement.
    #[must_use]
    pub fn primitive_count(&self) -> usize {
        let mut seen = std::collections::HashSet::new();
        self.meshes
            .iter()
            .map(|m| match m.placement {
                None => m.mesh.triangles.len(),
                Some(_) if seen.insert(Arc::as_ptr(&m.mesh)) => m.mesh.triangles.len() + 1,
                Some(_) => 1,
            })
            .sum()
    }

    /// The box around every triangle, placements applied.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.triangles().flatten().fold(Aabb::EMPTY, Aabb::grow)
    }

    /// Every triangle's corners, meshes in order and triangles in file order:
    /// the `n`-th item is triangle index `n` of `gridrt rays`.
    pub fn triangles(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        self.meshes.iter().flat_map(|m| {
            let p = &m.mesh.positions;
            let place = m.placement;
            let at = move |k: u32| match place {
                None => p[k as usize],
                Some(w) => to_vec3(w.transform_point3(to_dvec3(p[k as usize]))),
            };
            m.mesh.triangles.iter().map(move |t| t.map(at))
        })
    }

    /// The triangles of [`Self::triangles`] as one vertex array and the
    /// vertex indices of each triangle (in the same order): every mesh's
    /// positions once per placement, placements applied.
    #[must_use]
    pub fn indexed(&self) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut positions = Vec::new();
        let mut triangles =
            Vec::with_capacity(self.meshes.iter().map(|m| m.mesh.triangles.len()).sum());
        for m in &self.meshes {
            let base = positions.len() as u32;
            let p = &m.mesh.positions;
            match m.placement {
                None => positions.extend_from_slice(p),
                Some(w) => {
                    positions.extend(p.iter().map(|&q| to_vec3(w.transform_point3(to_dvec3(q)))))
                }
            }
            triangles.extend(m.mesh.triangles.iter().map(|t| t.map(|k| base + k)));
        }
        (positions, triangles)
    }

    pub(crate) fn transform(&mut self, m: &DMat4) -> std::result::Result<(), String> {
        let xf = Xform::new(m)?;
        for (i, mm) in self.meshes.iter_mut().enumerate() {
            if let Some(p) = &mut mm.placement {
                *p = xf.m * *p;
                continue;
            }
            xf.apply(Arc::make_mut(&mut mm.mesh))
                .map_err(|e| format!("mesh {i} \"{}\": {e}", mm.mesh.name))?;
            mm.mirrored ^= xf.mirrors;
        }
        for c in &mut self.cameras {
            c.camera.eye = to_vec3(xf.m.transform_point3(to_dvec3(c.camera.eye)));
            c.camera.look_at = to_vec3(xf.m.transform_point3(to_dvec3(c.camera.look_at)));
            c.camera.up = to_vec3(xf.m.transform_vector3(to_dvec3(c.camera.up)));
        }
        for l in &mut self.lights {
            match l {
                Light::Point { position, .. } => {
                    *position = to_vec3(xf.m.transform_point3(to_dvec3(*position)));
                }
                Light::Directional { direction, .. } => {
                    *direction = to_vec3(xf.normal.mul_vec3(to_dvec3(*direction)));
                }
                Light::Spot {
                    position,
                    direction,
                    ..
                } => {
                    *position = to_vec3(xf.m.transform_point3(to_dvec3(*position)));
                    *direction = to_vec3(xf.m.transform_vector3(to_dvec3(*direction)));
                }
                Light::Rect {
                    corner,
                    edge_u,
                    edge_v,
                    ..
                } => {
                    *corner = to_vec3(xf.m.transform_point3(to_dvec3(*corner)));
                    *edge_u = to_vec3(xf.m.transform_vector3(to_dvec3(*edge_u)));
                    *edge_v = to_vec3(xf.m.transform_vector3(to_dvec3(*edge_v)));
                }
                Light::Disk { center, normal, .. } => {
                    // A uniform scale keeps a disk a disk; the radius is
                    // left as given.
                    *center = to_vec3(xf.m.transform_point3(to_dvec3(*center)));
                    *normal = to_vec3(xf.normal.mul_vec3(to_dvec3(*normal)));
                }
                // Directions of an environment stay in world space.
                Light::Ambient { .. } | Light::Environment { .. } => {}
            }
        }
        Ok(())
    }
}

/// An affine transform ready to apply to points and normals.
pub(crate) struct Xform {
    /// The matrix.
    pub m: DMat4,
    /// Inverse transpose of its upper 3×3: transforms normals.
    pub normal: DMat3,
    /// Whether it mirrors space (negative determinant).
    pub mirrors: bool,
}

impl Xform {
    /// Checks that `m` is finite and invertible.
    pub(crate) fn new(m: &DMat4) -> std::result::Result<Self, String> {
        if !m.is_finite() {
            return Err("the transform has a non-finite entry".to_string());
        }
        let m3 = DMat3::from_mat4(*m);
        let det = m3.determinant();
        // Relative to the scale of the matrix, so tiny but valid scales pass.
        // Largest entries, not lengths: their squares would overflow first.
        let scale = m3.x_axis.abs().max_element()
            * m3.y_axis.abs().max_element()
            * m3.z_axis.abs().max_element();
        if det == 0.0 || !det.is_finite() || det.abs() <= scale * 1e-12 {
            return Err(
                "the transform is singular (a zero scale or a flattening matrix): it must be invertible"
                    .to_string(),
            );
        }
        Ok(Self {
            m: *m,
            normal: m3.inverse().transpose(),
            mirrors: det < 0.0,
        })
    }

    /// Transforms a mesh in place.
    pub(crate) fn apply(&self, mesh: &mut Mesh) -> std::result::Result<(), String> {
        for (k, p) in mesh.positions.iter_mut().enumerate() {
            let q = to_vec3(self.m.transform_point3(to_dvec3(*p)));
            if !q.is_finite() {
                return Err(format!(
                    "vertex {k} becomes non-finite ({q}) under the transform: use a smaller scale or translation"
                ));
            }
            *p = q;
        }
        let mut bad_normal = false;
        for n in &mut mesh.normals {
            match self.normal.mul_vec3(to_dvec3(*n)).try_normalize() {
                Some(v) => *n = to_vec3(v),
                None => bad_normal = true,
            }
        }
        if bad_normal {
            mesh.normals.clear();
        }
        Ok(())
    }
}

/// `Real` (f32 or f64) to f64.
#[inline]
#[allow(clippy::useless_conversion)] // f64 → f64 under the `f64` feature
pub(crate) fn r64(x: Real) -> f64 {
    f64::from(x)
}

/// `Vec3` (f32 or f64) to `DVec3`.
/// The object-to-world map of an affine transform matrix.
pub(crate) fn affine(m: &DMat4) -> gridrt_tracer::Affine {
    let r = |v: glam::DVec4| Vec3::new(v.x as Real, v.y as Real, v.z as Real);
    gridrt_tracer::Affine {
        cols: [r(m.x_axis), r(m.y_axis), r(m.z_axis)],
        translation: r(m.w_axis),
    }
}

#[inline]
pub(crate) fn to_dvec3(v: Vec3) -> DVec3 {
    DVec3::new(r64(v.x), r64(v.y), r64(v.z))
}

/// `DVec3` to `Vec3` (rounded to `Real`).
#[inline]
pub(crate) fn to_vec3(v: DVec3) -> Vec3 {
    Vec3::new(v.x as Real, v.y as Real, v.z as Real)
}

/// `[f64; 3]` to an f32 colour.
#[inline]
pub(crate) fn rgb(c: [f64; 3]) -> Rgb {
    Rgb::new(c[0] as f32, c[1] as f32, c[2] as f32)
}

/// The material of meshes that have none: a light grey matte.
#[must_use]
pub fn default_material() -> Material {
    Material::Matte {
        color: Rgb::splat(0.7),
        ka: 0.25,
        kd: 0.75,
    }
}

/// Drops per-vertex normals that are unusable (wrong count, non-finite,
/// zero), with a warning; returns the cleaned mesh.
pub(crate) fn check_normals(mesh: &mut Mesh, warnings: &mut Vec<String>) {
    if mesh.normals.is_empty() {
        return;
    }
    let ok = mesh.normals.len() == mesh.positions.len()
        && mesh
            .normals
            .iter()
            .all(|n| n.is_finite() && n.length_squared() > 0.0);
    if ok {
        for n in &mut mesh.normals {
            *n = n.normalize();
        }
    } else {
        warnings.push(format!(
            "mesh \"{}\": its vertex normals are incomplete, zero or not finite; using flat normals",
            mesh.name
        ));
        mesh.normals.clear();
    }
    if !mesh.uvs.is_empty() && mesh.uvs.len() != mesh.positions.len() {
        mesh.uvs.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri_mesh() -> Mesh {
        Mesh {
            name: "t".into(),
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: vec![],
            uvs1: vec![],
            colors: vec![],
            triangles: vec![[0, 1, 2]],
        }
    }

    #[test]
    fn normals_use_the_inverse_transpose() {
        // Shear x by y: the plane z = 0 keeps normal +z; a plane x = y gets tilted.
        let mut mesh = tri_mesh();
        mesh.normals = vec![Vec3::new(1.0, -1.0, 0.0).normalize(); 3];
        let shear = DMat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, //
            1.0, 1.0, 0.0, 0.0, // y axis maps to (1, 1, 0)
            0.0, 0.0, 1.0, 0.0, //
            0.0, 0.0, 0.0, 1.0,
        ]);
        Xform::new(&shear).unwrap().apply(&mut mesh).unwrap();
        // A surface point p with n·p = 0 maps to M p; the new normal must be
        // orthogonal to M t for every tangent t with n·t = 0.
        let t = DVec3::new(1.0, 1.0, 0.0);
        let mt = shear.transform_vector3(t);
        let n = to_dvec3(mesh.normals[0]);
        assert!(n.dot(mt).abs() < 1e-6, "{n} · {mt}");
    }

    #[test]
    fn mirroring_is_detected_and_oriented_swaps() {
        let mut model = Model {
            path: "x".into(),
            meshes: vec![ModelMesh {
                mesh: Arc::new(tri_mesh()),
                material: None,
                mirrored: false,
                placement: None,
            }],
            materials: vec![],
            cameras: vec![],
            lights: vec![],
            textures: Vec::new(),
            warnings: vec![],
        };
        model
            .transform(&DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0)))
            .unwrap();
        assert!(model.meshes[0].mirrored);
        assert_eq!(model.meshes[0].mesh.positions[1], -Vec3::X);
        let mm = model.meshes.swap_remove(0);
        assert_eq!(mm.oriented().triangles, vec![[0, 2, 1]]);
    }

    #[test]
    fn singular_and_overflowing_transforms_are_errors() {
        assert!(Xform::new(&DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0))).is_err());
        let mut mesh = tri_mesh();
        let huge = DMat4::from_scale(DVec3::splat(1e300));
        let r = Xform::new(&huge).and_then(|x| x.apply(&mut mesh));
        if r64(Real::MAX) < 1e300 {
            assert!(r.is_err());
        }
    }

    #[test]
    fn oriented_moves_a_mesh_it_holds_alone_and_copies_a_shared_one() {
        let placed = |mesh: Arc<Mesh>, mirrored| ModelMesh {
            mesh,
            material: None,
            mirrored,
            placement: None,
        };
        for mirrored in [false, true] {
            let mesh = Arc::new(tri_mesh());
            let ptrs = (mesh.positions.as_ptr(), mesh.triangles.as_ptr());
            let m = placed(mesh, mirrored).oriented();
            // Held alone: the same arrays, the winding swapped in place.
            assert_eq!((m.positions.as_ptr(), m.triangles.as_ptr()), ptrs);
            let want = if mirrored { [0, 2, 1] } else { [0, 1, 2] };
            assert_eq!(m.triangles, vec![want]);
        }
        // Shared: a copy, and the other holder's mesh is left as it was.
        let mesh = Arc::new(tri_mesh());
        let m = placed(Arc::clone(&mesh), true).oriented();
        assert_ne!(m.triangles.as_ptr(), mesh.triangles.as_ptr());
        assert_eq!((m.triangles[0], mesh.triangles[0]), ([0, 2, 1], [0, 1, 2]));
    }
}
