//! Scenes from files: RON scene files (the schema in `schema.rs`) and model
//! files rendered on their own, turned into the tracer's [`Scene`].

use crate::error::{Error, Result};
#[path = "scene_mesh.rs"]
mod scene_mesh;
use crate::model::{self, to_dvec3, to_vec3, Model, ModelFormat};
use crate::model_scene::{frame, scene_from_model};
use crate::ron_text::{line_col, ron_error, Outline};
use crate::sandbox::Sandbox;
use crate::scene_lights;
use crate::scene_numbers::num;
pub(crate) use crate::scene_numbers::{f32s, unit, v3};
use crate::schema::{self, CameraDesc, LightDesc, ObjectDesc, ProjectionDesc, SceneFile};
use gridrt_bbox::{Aabb, Real, Vec3};
use gridrt_tracer::{
    Camera, Geometry, Light, Material, MaterialId, Object, Projection, Rgb, Scene, Settings,
    Textures, ThinLens, Where,
};
use scene_mesh::{MeshDesc, SharedFile};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The built-in default scene (RON), rendered by `gridrt` with no scene.
pub const DEFAULT_SCENE: &str = include_str!("default_scene.ron");

/// The name the built-in scene goes by in messages.
pub const DEFAULT_SCENE_NAME: &str = "<built-in default scene>";

/// A scene read from a file, with what it took to read it.
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// The scene, ready for the renderer.
    pub scene: Scene,
    /// Where it came from: the file, or [`DEFAULT_SCENE_NAME`].
    pub source: PathBuf,
    /// Things skipped or approximated while reading (not errors).
    pub warnings: Vec<String>,
    /// True when the camera was placed automatically to frame the scene.
    pub framed_camera: bool,
    /// The named cameras of a model rendered on its own (glTF), in node
    /// order, for `--camera NAME`; empty for a scene file.
    pub cameras: Vec<(String, Camera)>,
}

/// Reads a scene: a `.ron` scene file, or an `.obj`/`.ply`/`.gltf`/`.glb` model
/// rendered on its own (see [`scene_from_model`]), reading only from the
/// scene's folder and the working directory ([`Sandbox::for_input`]).
///
/// # Errors
/// As [`load_scene_in`].
pub fn load_scene(path: &Path) -> Result<LoadedScene> {
    load_scene_in(path, &Sandbox::for_input(path))
}

/// Reads a scene under a [`Sandbox`]: the scene file itself as named, and
/// every file it names, transitively, only from the sandbox's folders.
///
/// # Errors
/// Any [`Error`] about the file or the files it refers to; an unknown
/// extension is [`Error::UnsupportedInput`], a reference outside the
/// sandbox [`Error::Denied`], a budget exceeded [`Error::Limit`].
pub fn load_scene_in(path: &Path, sandbox: &Sandbox) -> Result<LoadedScene> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref() == Some("ron") {
        let real = sandbox.top_level(path)?;
        let bytes = sandbox.read(&real).map_err(|e| e.renamed(&real, path))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let (line, col) = line_col(e.as_bytes(), e.utf8_error().valid_up_to());
            Error::Ron {
                path: path.to_path_buf(),
                line,
                col,
                msg: "the file is not UTF-8 text: save it as UTF-8".to_string(),
            }
        })?;
        parse_scene_at(&text, path, &real, sandbox)
    } else if ModelFormat::from_path(path).is_some() {
        let model = model::load_model_in(path, sandbox)?;
        check_model_budget(&model, sandbox)?;
        Ok(scene_from_model(model))
    } else {
        Err(Error::UnsupportedInput {
            path: path.to_path_buf(),
            models_only: false,
        })
    }
}

/// A model's triangles against the primitive budget.
fn check_model_budget(model: &Model, sandbox: &Sandbox) -> Result<()> {
    let n = model.triangle_count() as u64;
    if n > sandbox.limits.max_primitives {
        return Err(sandbox.limits.primitives_error(&model.path, "", n));
    }
    Ok(())
}

/// The built-in default scene.
///
/// # Errors
/// None in practice (a test parses it); the signature matches [`parse_scene`].
pub fn default_scene() -> Result<LoadedScene> {
    let path = Path::new(DEFAULT_SCENE_NAME);
    parse_scene_at(DEFAULT_SCENE, path, path, &Sandbox::working_directory())
}

/// Parses RON scene text. `path` names the scene in messages, and relative
/// mesh paths are resolved against its directory.
///
/// ```
/// let text = r#"Scene(
///     settings: Settings(width: 32, height: 24),
///     materials: { "red": Matte(color: (0.8, 0.1, 0.1)) },
///     lights: [Point(position: (0, 5, 5))],
///     objects: [Sphere(center: (0, 0, 0), radius: 1, material: "red")],
/// )"#;
/// let loaded = gridrt_io::parse_scene(text, std::path::Path::new("example.ron")).unwrap();
/// assert_eq!(loaded.scene.objects.len(), 1);
/// assert_eq!(loaded.scene.settings.width, 32);
/// assert!(loaded.framed_camera); // no camera given: one frames the sphere
/// ```
///
/// # Errors
/// [`Error::Ron`] for malformed text (with line and column),
/// [`Error::Scene`] for invalid content, [`Error::Mesh`] when a mesh file
/// cannot be loaded.
pub fn parse_scene(text: &str, path: &Path) -> Result<LoadedScene> {
    parse_scene_in(text, path, &Sandbox::for_input(path))
}

/// [`parse_scene`] under a [`Sandbox`]: mesh files are read only from its
/// folders.
///
/// # Errors
/// As [`parse_scene`], and [`Error::Denied`] for a mesh outside the
/// sandbox, [`Error::Limit`] over a budget.
pub fn parse_scene_in(text: &str, path: &Path, sandbox: &Sandbox) -> Result<LoadedScene> {
    parse_scene_at(text, path, &crate::sandbox::canonical(path), sandbox)
}

/// Parses scene text named `path` whose canonical path is `real`.
fn parse_scene_at(text: &str, path: &Path, real: &Path, sandbox: &Sandbox) -> Result<LoadedScene> {
    // A byte-order mark is not RON; editors on Windows write one.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let file: SceneFile = schema::ron_options()
        .from_str(text)
        .map_err(|e| ron_error(path, text, &e))?;
    Builder::new(path, real, text, sandbox).build(file)
}

/// Converts a schema scene into the tracer's model.
struct Builder<'a> {
    path: &'a Path,
    /// The scene file's canonical path: mesh references resolve from it.
    real: &'a Path,
    src: &'a str,
    sandbox: &'a Sandbox,
    /// Where things are in `src`, found on the first error that needs it.
    outline: std::cell::OnceCell<Outline>,
    /// The object being converted (for error places).
    current: Option<usize>,
    /// Models read so far, by canonical path: a model named by many
    /// objects is read once.
    models: HashMap<PathBuf, Model>,
    /// How many `Mesh` objects name each file with each normals setting
    /// ([`scene_mesh::share_key`]): files named more than once are shared.
    mesh_uses: HashMap<String, u32>,
    /// How many `Mesh` objects not yet converted name each file (as
    /// written): the last one takes its model out of `models`.
    file_uses: HashMap<String, u32>,
    /// Model files prepared for sharing, by canonical path and share key.
    shared: HashMap<(PathBuf, String), std::rc::Rc<SharedFile>>,
    /// Primitives so far (spheres, boxes, planes, triangles).
    primitives: u64,
    materials: Vec<Material>,
    /// Named materials: name and index into `materials`.
    names: Vec<(String, MaterialId)>,
    default_material: Option<MaterialId>,
    objects: Vec<Object>,
    textures: Textures,
    warnings: Vec<String>,
}

impl<'a> Builder<'a> {
    fn new(path: &'a Path, real: &'a Path, src: &'a str, sandbox: &'a Sandbox) -> Self {
        Self {
            path,
            real,
            src,
            sandbox,
            outline: std::cell::OnceCell::new(),
            current: None,
            models: HashMap::new(),
            mesh_uses: HashMap::new(),
            file_uses: HashMap::new(),
            shared: HashMap::new(),
            primitives: 0,
            materials: Vec::new(),
            names: Vec::new(),
            default_material: None,
            objects: Vec::new(),
            textures: Textures::default(),
            warnings: Vec::new(),
        }
    }

    /// `line:col: what` for an error about `what`: the current object
    /// (`objects[i]`, at `needle` inside it when given) or a top-level
    /// field (`camera`, `objects`); just `what` when it cannot be found.
    fn place(&self, needle: Option<&str>, what: &str) -> String {
        let o = self.outline.get_or_init(|| Outline::new(self.src));
        let at = match self.current {
            Some(i) if what.starts_with("objects[") => {
                o.objects.get(i).map(|&range| match needle {
                    Some(n) => o.find_in(self.src, range, n),
                    None => range.0,
                })
            }
            _ => o.field(what),
        };
        match at {
            Some(at) => {
                let (l, c) = line_col(self.src.as_bytes(), at);
                format!("{l}:{c}: {what}")
            }
            None => what.to_string(),
        }
    }

    /// `v` as a `Real` point, or an error at `field` of `what` when a
    /// coordinate is beyond the range of `Real` (f32: ±3.4e38).
    fn fit(&self, v: [f64; 3], field: &str, what: &str) -> Result<Vec3> {
        let p = v3(v);
        if p.is_finite() {
            Ok(p)
        } else {
            Err(Error::scene(
                self.path,
                self.place(Some(field), what),
                format!(
                    "{field} ({}, {}, {}) is beyond the range of {}-bit numbers (about ±{:.1e}): scale the scene down",
                    num(v[0]), num(v[1]), num(v[2]), 8 * std::mem::size_of::<Real>(), Real::MAX
                ),
            ))
        }
    }

    /// Adds `n` primitives to the count, or the budget error.
    fn count_primitives(&mut self, n: u64, what: &str) -> Result<()> {
        self.primitives = self.primitives.saturating_add(n);
        if self.primitives > self.sandbox.limits.max_primitives {
            return Err(self.sandbox.limits.primitives_error(
                self.path,
                &self.place(None, what),
                self.primitives,
            ));
        }
        Ok(())
    }

    fn build(mut self, file: SceneFile) -> Result<LoadedScene> {
        for (name, desc) in &file.materials.0 {
            let material = desc.material().map_err(|(field, msg)| {
                Error::scene(
                    self.path,
                    self.place(None, "materials"),
                    format!("material \"{name}\", field {field}: {msg}"),
                )
            })?;
            let id = self.push_material(name.clone(), material);
            if let Some(t) = desc.texture() {
                crate::schema_textures::bind(&mut self.textures, id, t);
            }
        }
        // Generated objects are counted before any is generated.
        let mut planned = 0u64;
        for (i, obj) in file.objects.iter().enumerate() {
            if let ObjectDesc::RandomSpheres { count, .. } = obj {
                planned = planned.saturating_add(u64::from(count.0));
                if planned > self.sandbox.limits.max_primitives {
                    self.current = Some(i);
                    return Err(self.sandbox.limits.primitives_error(
                        self.path,
                        &self.place(None, &format!("objects[{i}]")),
                        planned,
                    ));
                }
            }
        }
        for obj in &file.objects {
            if let ObjectDesc::Mesh { file, normals, .. } = obj {
                *self
                    .mesh_uses
                    .entry(scene_mesh::share_key(file, *normals))
                    .or_default() += 1;
                *self.file_uses.entry(file.clone()).or_default() += 1;
            }
        }
        for (i, obj) in file.objects.iter().enumerate() {
            self.object(i, obj)?;
        }
        if self.objects.is_empty() {
            return Err(Error::scene(
                self.path,
                self.place(Some("objects"), "objects"),
                "the scene has no objects: add at least one (Sphere, Box, Plane, Mesh or RandomSpheres)",
            ));
        }
        let s = &file.settings;
        let settings = Settings {
            width: s.width.0,
            height: s.height.0,
            spp: s.spp.0,
            max_depth: s.max_depth.0,
            background: model::rgb(s.background.0),
            sampler: s.sampler.kind(),
            filter: s.filter.filter(),
            integrator: s.integrator.choice(),
            path_max_depth: s
                .max_depth_given
                .map_or(Settings::default().path_max_depth, |d| d.0),
        };
        let mut lights = file
            .lights
            .iter()
            .map(scene_lights::light)
            .collect::<Vec<_>>();
        for (i, d) in file.lights.iter().enumerate() {
            if let LightDesc::Environment { image: Some(f), .. } = d {
                let place = self.place(Some(&format!("\"{f}\"")), &format!("lights[{i}]"));
                let img = scene_lights::env_image(self.path, self.real, self.sandbox, place, f)?;
                if let Light::Environment { image, .. } = &mut lights[i] {
                    *image = Some(std::sync::Arc::new(img));
                }
            }
        }
        let (camera, framed) = match &file.camera {
            Some(c) => (self.camera(c)?, false),
            None => {
                let aspect = f64::from(settings.width) / f64::from(settings.height);
                let bounds = finite_bounds(&self.objects);
                if !bounds.is_empty() && !bounds.extent().is_finite() {
                    return Err(Error::scene(
                        self.path,
                        self.place(None, "objects"),
                        format!(
                            "the objects span more than {}-bit numbers can hold (about ±{:.1e}), so no camera can frame them: scale the scene down",
                            8 * std::mem::size_of::<Real>(),
                            Real::MAX
                        ),
                    ));
                }
                if bounds.is_empty() {
                    return Err(Error::scene(
                        self.path,
                        "camera",
                        "no camera and nothing finite to frame (only planes): add a `camera: Camera(...)`",
                    ));
                }
                (frame(bounds, 45.0, aspect), true)
            }
        };
        let scene = Scene {
            textures: std::mem::take(&mut self.textures),
            camera,
            settings,
            materials: std::mem::take(&mut self.materials),
            lights,
            objects: std::mem::take(&mut self.objects),
        };
        self.ignored(&scene);
        Ok(LoadedScene {
            scene,
            source: self.path.to_path_buf(),
            warnings: self.warnings,
            framed_camera: framed,
            cameras: Vec::new(),
        })
    }

    /// A warning for each request the scene makes that its other contents
    /// make impossible ([`gridrt_tracer::ignored_effects`]).
    fn ignored(&mut self, scene: &Scene) {
        for i in gridrt_tracer::ignored_effects(scene) {
            let at = match i.at {
                Where::Light(k) => format!("lights[{k}]"),
                Where::Object(k) => {
                    self.current = Some(k);
                    self.place(None, &format!("objects[{k}]"))
                }
                Where::Setting(f) => self.place(None, "settings") + "." + f,
                _ => "scene".to_string(),
            };
            // `file:line:col: what` as errors write it, else `file: what`.
            let sep = if at.starts_with(|c: char| c.is_ascii_digit()) {
                ":"
            } else {
                ": "
            };
            let w = format!("{}{sep}{at}: {}", self.path.display(), i.message);
            self.warnings.push(w);
        }
    }

    fn camera(&self, c: &CameraDesc) -> Result<Camera> {
        let what = "camera";
        let eye = self.fit(c.eye.0, "eye", what)?;
        let at = self.fit(c.look_at.0, "look_at", what)?;
        let up = unit(c.up.0);
        let place = || self.place(None, what);
        let view = at - eye;
        if !view.is_finite() {
            return Err(Error::scene(
                self.path,
                place(),
                "eye and look_at are too far apart: their difference overflows; bring them closer",
            ));
        }
        if view == Vec3::ZERO {
            return Err(Error::scene(
                self.path,
                place(),
                "eye and look_at are the same point: move look_at to where the camera should look",
            ));
        }
        if to_dvec3(view).normalize().cross(up).length() < 1e-6 {
            return Err(Error::scene(
                self.path,
                place(),
                "up is parallel to the view direction (look_at - eye): pick an up vector across it",
            ));
        }
        let projection = match &c.projection {
            ProjectionDesc::Perspective { vfov } => Projection::Perspective {
                vfov_deg: vfov.0 as Real,
            },
            ProjectionDesc::ViewPlane {
                distance,
                pixel_size,
            } => Projection::ViewPlane {
                distance: distance.0 as Real,
                pixel_size: pixel_size.0 as Real,
            },
            ProjectionDesc::Orthographic { height } => Projection::Orthographic {
                height: height.0 as Real,
            },
        };
        let lens = if c.lens_radius.0 > 0.0 {
            let Some(focus) = c.focus_distance else {
                return Err(Error::scene(
                    self.path,
                    self.place(Some("lens_radius"), what),
                    "lens_radius > 0 needs focus_distance (the distance to the plane in focus, > 0); \
                     use lens_radius: 0 for a pinhole",
                ));
            };
            Some(ThinLens {
                radius: c.lens_radius.0 as Real,
                focus_distance: focus.0 as Real,
            })
        } else {
            None
        };
        Ok(Camera {
            eye,
            look_at: at,
            up: to_vec3(up),
            projection,
            lens,
        })
    }

    /// The scene material called `name`, or the default material.
    fn material_id(&mut self, name: Option<&str>, what: &str) -> Result<MaterialId> {
        let Some(name) = name else {
            return Ok(self.default_material());
        };
        match self.names.iter().find(|(n, _)| n == name) {
            Some((_, id)) => Ok(*id),
            None => {
                let defined = if self.names.is_empty() {
                    "none are defined".to_string()
                } else {
                    let names: Vec<&str> = self.names.iter().map(|(n, _)| n.as_str()).collect();
                    format!("defined: {}", names.join(", "))
                };
                let needle = format!("\"{name}\"");
                Err(Error::scene(
                    self.path,
                    self.place(Some(&needle), what),
                    format!(
                        "unknown material \"{name}\" ({defined}): define it under `materials` or fix the name"
                    ),
                ))
            }
        }
    }

    /// The material used when an object names none: the scene's "default"
    /// material if it defines one, else a light grey matte.
    fn default_material(&mut self) -> MaterialId {
        if let Some(id) = self.default_material {
            return id;
        }
        let id = match self.names.iter().find(|(n, _)| n == "default") {
            Some((_, id)) => *id,
            None => self.push_material("default".to_string(), model::default_material()),
        };
        self.default_material = Some(id);
        id
    }

    fn push_material(&mut self, name: String, m: Material) -> MaterialId {
        self.materials.push(m);
        let id = (self.materials.len() - 1) as MaterialId;
        self.names.push((name, id));
        id
    }

    fn object(&mut self, i: usize, obj: &ObjectDesc) -> Result<()> {
        let what = format!("objects[{i}]");
        self.current = Some(i);
        if !matches!(
            obj,
            ObjectDesc::Mesh { .. } | ObjectDesc::RandomSpheres { .. }
        ) {
            self.count_primitives(1, &what)?;
        }
        match obj {
            ObjectDesc::Sphere {
                center,
                radius,
                material,
            } => {
                let c = self.fit(center.0, "center", &what)?;
                let r = radius.0;
                let (lo, hi) = (0..3).fold((f64::MAX, f64::MIN), |(lo, hi), a| {
                    (lo.min(center.0[a] - r), hi.max(center.0[a] + r))
                });
                self.fit([r, lo, hi], "radius", &what).map_err(|_| {
                    Error::scene(
                        self.path,
                        self.place(Some("radius"), &what),
                        format!(
                            "radius {} takes the sphere beyond the range of {}-bit numbers (about ±{:.1e}): scale the scene down",
                            num(r),
                            8 * std::mem::size_of::<Real>(),
                            Real::MAX
                        ),
                    )
                })?;
                let material = self.material_id(material.as_deref(), &what)?;
                self.objects.push(Object {
                    geometry: Geometry::Sphere {
                        center: c,
                        radius: r as Real,
                    },
                    material,
                });
            }
            ObjectDesc::Box { min, max, material } => {
                if (0..3).any(|a| min.0[a] > max.0[a]) {
                    return Err(Error::scene(
                        self.path,
                        self.place(Some("min"), &what),
                        format!(
                            "box min {:?} is above max {:?} on some axis: swap the corners",
                            min.0, max.0
                        ),
                    ));
                }
                let (lo, hi) = (
                    self.fit(min.0, "min", &what)?,
                    self.fit(max.0, "max", &what)?,
                );
                let material = self.material_id(material.as_deref(), &what)?;
                self.objects.push(Object {
                    geometry: Geometry::Cuboid { min: lo, max: hi },
                    material,
                });
            }
            ObjectDesc::Plane {
                point,
                normal,
                material,
            } => {
                let p = self.fit(point.0, "point", &what)?;
                let material = self.material_id(material.as_deref(), &what)?;
                self.objects.push(Object {
                    geometry: Geometry::Plane {
                        point: p,
                        normal: to_vec3(unit(normal.0)),
                    },
                    material,
                });
            }
            ObjectDesc::Mesh {
                file,
                transform,
                material,
                materials,
                normals,
            } => self.mesh(
                &what,
                &MeshDesc {
                    file,
                    transform,
                    material: material.as_deref(),
                    overrides: materials,
                    normals: *normals,
                },
            )?,
            ObjectDesc::RandomSpheres {
                count,
                seed,
                radius,
                bounds,
                material,
            } => {
                // Without a material, one white matte material that each
                // sphere's random colour tints, as in the benchmark; with
                // one, the spheres take it as it is.
                let forced = match material {
                    Some(m) => Some(self.material_id(Some(m), &what)?),
                    None => None,
                };
                let (lo, hi) = match bounds {
                    Some((lo, hi)) => {
                        self.fit(lo.0, "bounds", &what)?;
                        self.fit(hi.0, "bounds", &what)?;
                        if (0..3).any(|a| lo.0[a] >= hi.0[a]) {
                            return Err(Error::scene(
                                self.path,
                                self.place(Some("bounds"), &what),
                                "RandomSpheres bounds must be (min, max) with min < max on every axis",
                            ));
                        }
                        (lo.0, hi.0)
                    }
                    None => ([-1.0; 3], [1.0; 3]),
                };
                self.count_primitives(u64::from(count.0), &what)?;
                let mut set = crate::random::spheres(count.0, *seed, radius.map(|r| r.0), lo, hi);
                let material = match forced {
                    Some(m) => {
                        set.colors = gridrt_tracer::SphereColors::None;
                        m
                    }
                    None => {
                        self.materials.push(Material::Matte {
                            color: Rgb::ONE,
                            ka: 0.25,
                            kd: 0.75,
                        });
                        (self.materials.len() - 1) as MaterialId
                    }
                };
                self.objects.push(Object {
                    geometry: Geometry::Spheres(Arc::new(set)),
                    material,
                });
            }
        }
        Ok(())
    }
}

/// The box around every bounded object (planes are infinite and left out).
fn finite_bounds(objects: &[Object]) -> Aabb {
    objects
        .iter()
        .fold(Aabb::EMPTY, |b, o| b.union(o.geometry.bounds()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_transform::transform_matrix;
    use crate::schema::TransformDesc;
    use glam::{DMat4, DVec3};

    fn parse(text: &str) -> Result<LoadedScene> {
        parse_scene(text, Path::new("t.ron"))
    }

    #[test]
    fn default_scene_parses() {
        let s = default_scene().unwrap();
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        assert!(!s.framed_camera);
        assert!(s.scene.objects.len() >= 4);
    }

    #[test]
    fn unknown_material_names_the_place_and_the_choices() {
        let e = parse(
            "(materials: {\"red\": Matte()},\n objects: [\n  Sphere(center: (0,0,0), radius: 1, material: \"blue\")])",
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("t.ron:3:"), "{e}");
        assert!(e.contains("objects[0]"), "{e}");
        assert!(e.contains("unknown material \"blue\""), "{e}");
        assert!(e.contains("defined: red"), "{e}");
    }

    #[test]
    fn objects_without_material_share_a_default() {
        let s = parse(
            "(objects: [Sphere(center: (0,0,0), radius: 1), Box(min: (1,1,1), max: (2,2,2))])",
        )
        .unwrap();
        assert_eq!(s.scene.materials.len(), 1);
        assert!(s.scene.objects.iter().all(|o| o.material == 0));
    }

    #[test]
    fn ron_errors_are_reworded() {
        let e = parse("(objects: [Sphere(center: (0,0,0), radius: 1, colour: 2)])")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.ron:1:"), "{e}");
        assert!(e.contains("unknown field `colour` in `Sphere`"), "{e}");
        let e = parse("(objects: [Cone()])").unwrap_err().to_string();
        assert!(e.contains("unknown `Object` kind `Cone`"), "{e}");
        assert!(e.contains("`RandomSpheres`"), "{e}");
        assert!(!e.contains("`random_spheres`"), "{e}");
        let e = parse("(objects: [Sphere(center: (0,0,0))])")
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing field `radius`"), "{e}");
    }

    #[test]
    fn transforms_compose_in_order() {
        // Scale then translate: the point (1, 0, 0) goes to (2, 0, 0) then (2, 5, 0).
        let ops = [
            TransformDesc::Scale(schema::ScaleDesc([2.0; 3])),
            TransformDesc::Translate(schema::V3([0.0, 5.0, 0.0])),
        ];
        let m = ops
            .iter()
            .fold(DMat4::IDENTITY, |acc, op| transform_matrix(op) * acc);
        assert_eq!(m.transform_point3(DVec3::X), DVec3::new(2.0, 5.0, 0.0));
        // A row-major matrix with translation in the last column.
        let mat = TransformDesc::Matrix(schema::MatrixDesc([
            [1.0, 0.0, 0.0, 3.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]));
        assert_eq!(
            transform_matrix(&mat).transform_point3(DVec3::ZERO),
            DVec3::new(3.0, 0.0, 0.0)
        );
        // Euler angles about x, then y, then z.
        let e = TransformDesc::Euler {
            x: schema::Finite(90.0),
            y: schema::Finite(90.0),
            z: schema::Finite(0.0),
        };
        let p = transform_matrix(&e).transform_point3(DVec3::Y);
        // Rx(90°) takes +y to +z; Ry(90°) takes +z to +x.
        assert!((p - DVec3::X).length() < 1e-12, "{p}");
    }
}
