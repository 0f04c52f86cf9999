//! A scene's `Mesh` objects: the model file read once per scene, and either
//! baked into world space (a file placed once) or shared by instances (a
//! file placed by several objects with the same normals: one copy of its
//! arrays, one grid in the renderer, one transform per placement).

use super::Builder;
use crate::error::{Error, Result};
use crate::model::{self, affine, texture_load, Model, NamedMaterial};
use crate::scene_transform::transform_matrix;
use crate::schema::{self, TransformDesc};
use glam::DMat4;
use gridrt_tracer::{Geometry, MaterialId, Mesh, Object};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;

/// A model file prepared for instancing: its meshes in the file's space,
/// oriented and with the requested normals, shared by every placement
/// (held by `Rc`, so that a placement does not copy the lists).
pub(super) struct SharedFile {
    /// Each mesh, its file material and its place in the file.
    meshes: Vec<(Arc<Mesh>, Option<usize>, DMat4)>,
    materials: Vec<NamedMaterial>,
    /// Where the file's textures start in the scene's texture list.
    texture_offset: u32,
}

/// The key of a `Mesh` object's shared arrays: the file as written and the
/// normals it asks for.
pub(super) fn share_key(file: &str, normals: model::Normals) -> String {
    format!("{normals:?} {file}")
}

/// What a `Mesh` object asks for.
pub(super) struct MeshDesc<'d> {
    pub file: &'d str,
    pub transform: &'d [TransformDesc],
    pub material: Option<&'d str>,
    pub overrides: &'d schema::NamedMap<String>,
    pub normals: model::Normals,
}

impl Builder<'_> {
    pub(super) fn mesh(&mut self, what: &str, d: &MeshDesc) -> Result<()> {
        let file = d.file;
        let needle = format!("\"{file}\"");
        let shown = self
            .path
            .parent()
            .map_or_else(|| PathBuf::from(file), |dir| dir.join(file));
        let real = self
            .sandbox
            .resolve(self.real, Path::new(file), false)
            .map_err(|e| self.mesh_error(&needle, what, e))?;
        let m = d
            .transform
            .iter()
            .fold(DMat4::IDENTITY, |acc, op| transform_matrix(op) * acc);
        let transform_error = |b: &Self, e: String| {
            Error::scene(
                b.path,
                b.place(Some(&needle), what),
                format!("transform of \"{file}\": {e}"),
            )
        };
        // The last object that names the file may take its model out of
        // the cache (its meshes are then moved, not copied).
        let last = self.file_uses.get_mut(file).is_none_or(|n| {
            *n = n.saturating_sub(1);
            *n == 0
        });
        let key = share_key(file, d.normals);
        if self.mesh_uses.get(&key).is_some_and(|&n| n >= 2) {
            let shared = match self.shared.get(&(real.clone(), key.clone())) {
                Some(s) => Rc::clone(s),
                None => {
                    let n = self.model(&shown, &real, &needle, what)?.primitive_count();
                    self.count_primitives(n as u64, what)?;
                    let model = &self.models[&real];
                    let mut cache = model::AppliedCache::new();
                    let meshes = model
                        .meshes
                        .iter()
                        .map(|mm| match mm.placement {
                            Some(p) => (
                                model::applied_once(&mut cache, &mm.mesh, d.normals),
                                mm.material,
                                p,
                            ),
                            None => {
                                let mut mesh = mm.clone().oriented();
                                d.normals.apply(&mut mesh);
                                (Arc::new(mesh), mm.material, DMat4::IDENTITY)
                            }
                        })
                        .collect();
                    let (materials, textures) = (model.materials.clone(), model.textures.clone());
                    self.warnings.extend(model.warnings.iter().cloned());
                    let s = Rc::new(SharedFile {
                        meshes,
                        materials,
                        texture_offset: texture_load::append(&mut self.textures, &textures),
                    });
                    self.shared.insert((real.clone(), key), Rc::clone(&s));
                    s
                }
            };
            if last {
                self.models.remove(&real);
            }
            self.count_primitives(shared.meshes.len() as u64, what)?;
            model::Xform::new(&m).map_err(|e| transform_error(self, e))?;
            let mut fm = self.file_materials(what, d, &shared.materials, shared.texture_offset)?;
            for (k, (mesh, material, local)) in shared.meshes.iter().enumerate() {
                let to_world = affine(&(m * *local));
                if !to_world.keeps_finite(&mesh.bounds()) {
                    return Err(transform_error(
                        self,
                        format!(
                            "mesh {k} \"{}\": its vertices become non-finite under the transform: use a smaller scale or translation",
                            mesh.name
                        ),
                    ));
                }
                let id = self.model_material(what, d, &mut fm, &shared.materials, *material)?;
                self.objects.push(Object {
                    geometry: Geometry::Instance {
                        mesh: Arc::clone(mesh),
                        to_world: Box::new(to_world),
                    },
                    material: id,
                });
            }
            return Ok(());
        }
        self.model(&shown, &real, &needle, what)?;
        let mut model = match self.models.remove(&real) {
            Some(m) if last => m,
            Some(m) => {
                let copy = m.clone();
                self.models.insert(real.clone(), m);
                copy
            }
            None => self.model(&shown, &real, &needle, what)?.clone(),
        };
        self.count_primitives(model.primitive_count() as u64, what)?;
        if !d.transform.is_empty() {
            model.transform(&m).map_err(|e| transform_error(self, e))?;
        }
        let offset = texture_load::append(&mut self.textures, &model.textures);
        let mut fm = self.file_materials(what, d, &model.materials, offset)?;
        let mut cache = model::AppliedCache::new();
        for mm in std::mem::take(&mut model.meshes) {
            let id = self.model_material(what, d, &mut fm, &model.materials, mm.material)?;
            let geometry = match mm.placement {
                Some(p) => Geometry::Instance {
                    mesh: model::applied_once(&mut cache, &mm.mesh, d.normals),
                    to_world: Box::new(affine(&p)),
                },
                None => {
                    let mut mesh = mm.oriented();
                    d.normals.apply(&mut mesh);
                    Geometry::Mesh(Arc::new(mesh))
                }
            };
            self.objects.push(Object {
                geometry,
                material: id,
            });
        }
        self.warnings.append(&mut model.warnings);
        Ok(())
    }

    /// The model at `real`, read on first use.
    fn model(&mut self, shown: &Path, real: &Path, needle: &str, what: &str) -> Result<&Model> {
        if !self.models.contains_key(real) {
            let m = model::load_resolved(shown, real, self.sandbox)
                .map_err(|e| self.mesh_error(needle, what, e))?;
            self.models.insert(real.to_path_buf(), m);
        }
        Ok(&self.models[real])
    }

    /// An error of the mesh file, placed at the object's `file` field.
    fn mesh_error(&self, needle: &str, what: &str, e: Error) -> Error {
        let place = self.place(Some(needle), what);
        match e {
            Error::Denied {
                reference, model, ..
            } if !model => Error::Denied {
                path: self.path.to_path_buf(),
                place,
                reference,
                model,
            },
            e => Error::Mesh {
                scene: self.path.to_path_buf(),
                place,
                source: Box::new(e),
            },
        }
    }

    /// Checks that every override of `d` names one of the file's
    /// `materials`, and prepares their mapping to scene materials.
    fn file_materials(
        &mut self,
        what: &str,
        d: &MeshDesc,
        materials: &[NamedMaterial],
        texture_offset: u32,
    ) -> Result<FileMaterials> {
        let file = d.file;
        for (from, _) in &d.overrides.0 {
            if !materials.iter().any(|m| &m.name == from) {
                let have: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
                return Err(Error::scene(
                    self.path,
                    self.place(Some(&format!("\"{from}\"")), what),
                    format!(
                        "\"{file}\" has no material \"{from}\" to override; its materials are: {}",
                        if have.is_empty() {
                            "(none)".to_string()
                        } else {
                            have.join(", ")
                        }
                    ),
                ));
            }
        }
        let forced = match d.material {
            Some(name) => Some(self.material_id(Some(name), what)?),
            None => None,
        };
        Ok(FileMaterials {
            mapped: vec![None; materials.len()],
            forced,
            stem: Path::new(file)
                .file_name()
                .map_or_else(|| file.to_string(), |n| n.to_string_lossy().into_owned()),
            texture_offset,
        })
    }

    /// The scene material of a mesh whose file material is `k`: overridden
    /// by name, forced by the object's `material`, or added to the scene as
    /// `file:name` with its texture maps on first use.
    fn model_material(
        &mut self,
        what: &str,
        d: &MeshDesc,
        fm: &mut FileMaterials,
        materials: &[NamedMaterial],
        k: Option<usize>,
    ) -> Result<MaterialId> {
        let Some(k) = k.filter(|&k| k < materials.len()) else {
            return Ok(match fm.forced {
                Some(f) => f,
                None => self.default_material(),
            });
        };
        if let Some(id) = fm.mapped[k] {
            return Ok(id);
        }
        let m = &materials[k];
        let id = match d.overrides.get(&m.name) {
            Some(to) => self.material_id(Some(to), what)?,
            None => match fm.forced {
                Some(f) => f,
                None => {
                    let name = format!("{}:{}", fm.stem, m.name);
                    let id = self.push_material(name, m.material.clone());
                    texture_load::bind(&mut self.textures, id, &m.maps, fm.texture_offset);
                    id
                }
            },
        };
        fm.mapped[k] = Some(id);
        Ok(id)
    }
}

/// How one object maps its file's materials to the scene's.
struct FileMaterials {
    /// File material index → scene material, filled as meshes use them.
    mapped: Vec<Option<MaterialId>>,
    /// The object's `material`, which replaces the file's not overridden.
    forced: Option<MaterialId>,
    /// The file's name, prefixed to the names of its materials.
    stem: String,
    texture_offset: u32,
}
