//! Scenes from files: RON scene files (the schema in `schema.rs`) and model
//! files rendered on their own, turned into the tracer's [`Scene`].

use crate::error::{Error, Result};
use crate::model::{self, load_model, to_dvec3, to_vec3, Model, ModelFormat};
use crate::schema::{
    self, CameraDesc, LightDesc, MaterialDesc, ObjectDesc, ProjectionDesc, SceneFile, TransformDesc,
};
use glam::{DMat4, DQuat, DVec3};
use gridrt_bbox::{Aabb, Real, Vec3};
use gridrt_tracer::{
    Camera, Geometry, Light, Material, MaterialId, Object, Projection, Rgb, Scene, Settings,
};
use std::path::{Path, PathBuf};

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
}

/// Reads a scene: a `.ron` scene file, or an `.obj`/`.gltf`/`.glb` model
/// rendered on its own (see [`scene_from_model`]).
///
/// # Errors
/// Any [`Error`] about the file or the files it refers to; an unknown
/// extension is [`Error::UnsupportedInput`].
pub fn load_scene(path: &Path) -> Result<LoadedScene> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref() == Some("ron") {
        let bytes = std::fs::read(path).map_err(|e| Error::read(path, e))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let (line, col) = line_col(e.as_bytes(), e.utf8_error().valid_up_to());
            Error::Ron {
                path: path.to_path_buf(),
                line,
                col,
                msg: "the file is not UTF-8 text: save it as UTF-8".to_string(),
            }
        })?;
        parse_scene(&text, path)
    } else if ModelFormat::from_path(path).is_some() {
        Ok(scene_from_model(load_model(path)?))
    } else {
        Err(Error::UnsupportedInput {
            path: path.to_path_buf(),
            models_only: false,
        })
    }
}

/// The built-in default scene.
///
/// # Errors
/// None in practice (a test parses it); the signature matches [`parse_scene`].
pub fn default_scene() -> Result<LoadedScene> {
    parse_scene(DEFAULT_SCENE, Path::new(DEFAULT_SCENE_NAME))
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
    let file: SceneFile = schema::ron_options()
        .from_str(text)
        .map_err(|e| ron_error(path, &e))?;
    Builder::new(path, text).build(file)
}

/// A RON error in our words.
fn ron_error(path: &Path, e: &ron::error::SpannedError) -> Error {
    use ron::Error as R;
    let list = |names: &[&str]| {
        // Hide the snake_case aliases when the PascalCase name is listed.
        let shown: Vec<String> = names
            .iter()
            .filter(|n| {
                !(n.starts_with(|c: char| c.is_ascii_lowercase())
                    && names
                        .iter()
                        .any(|m| m.to_ascii_lowercase() == n.replace('_', "") && m != *n))
            })
            .map(|n| format!("`{n}`"))
            .collect();
        shown.join(", ")
    };
    let msg = match &e.code {
        R::NoSuchStructField {
            expected,
            found,
            outer,
        } => format!(
            "unknown field `{found}`{}; expected one of {}",
            outer
                .as_ref()
                .map_or_else(String::new, |o| format!(" in `{o}`")),
            list(expected)
        ),
        R::NoSuchEnumVariant {
            expected,
            found,
            outer,
        } => format!(
            "unknown {} `{found}`; expected one of {}",
            outer
                .as_ref()
                .map_or_else(|| "variant".to_string(), |o| format!("`{o}` kind")),
            list(expected)
        ),
        R::MissingStructField { field, outer } => format!(
            "missing field `{field}`{}: add `{field}: ...`",
            outer
                .as_ref()
                .map_or_else(String::new, |o| format!(" in `{o}`"))
        ),
        R::Message(m) => m.clone(),
        other => format!("{other} (see docs/scene-format.md)"),
    };
    Error::Ron {
        path: path.to_path_buf(),
        line: e.position.line,
        col: e.position.col,
        msg,
    }
}

/// The 1-based line and column of the first occurrence of `needle` that is
/// not in a `//` comment.
fn locate(src: &str, needle: &str) -> Option<(usize, usize)> {
    src.match_indices(needle).find_map(|(at, _)| {
        let before = &src[..at];
        let line_start = before.rfind('\n').map_or(0, |nl| nl + 1);
        if before[line_start..].contains("//") {
            return None;
        }
        Some((before.matches('\n').count() + 1, at - line_start + 1))
    })
}

/// Line and column of byte offset `at`.
fn line_col(bytes: &[u8], at: usize) -> (usize, usize) {
    let before = &bytes[..at.min(bytes.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    (line, at - start + 1)
}

/// Converts a schema scene into the tracer's model.
struct Builder<'a> {
    path: &'a Path,
    src: &'a str,
    base: PathBuf,
    materials: Vec<Material>,
    /// Named materials: name and index into `materials`.
    names: Vec<(String, MaterialId)>,
    default_material: Option<MaterialId>,
    objects: Vec<Object>,
    warnings: Vec<String>,
}

fn v3(v: [f64; 3]) -> Vec3 {
    Vec3::new(v[0] as Real, v[1] as Real, v[2] as Real)
}

fn f32s(x: f64) -> f32 {
    x as f32
}

impl<'a> Builder<'a> {
    fn new(path: &'a Path, src: &'a str) -> Self {
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self {
            path,
            src,
            base,
            materials: Vec::new(),
            names: Vec::new(),
            default_material: None,
            objects: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// `line:col: what` when `needle` is found in the source, else `what`.
    fn place(&self, needle: Option<&str>, what: &str) -> String {
        match needle.and_then(|n| locate(self.src, n)) {
            Some((l, c)) => format!("{l}:{c}: {what}"),
            None => what.to_string(),
        }
    }

    fn build(mut self, file: SceneFile) -> Result<LoadedScene> {
        for (name, desc) in &file.materials.0 {
            self.push_material(name.clone(), material(desc));
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
        };
        let lights = file.lights.iter().map(light).collect::<Vec<_>>();
        if lights.is_empty() {
            self.warnings.push(format!(
                "{}: the scene has no lights: only emissive materials will show",
                self.path.display()
            ));
        }
        let (camera, framed) = match &file.camera {
            Some(c) => (self.camera(c)?, false),
            None => {
                let aspect = f64::from(settings.width) / f64::from(settings.height);
                let bounds = finite_bounds(&self.objects);
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
        Ok(LoadedScene {
            scene: Scene {
                camera,
                settings,
                materials: self.materials,
                lights,
                objects: self.objects,
            },
            source: self.path.to_path_buf(),
            warnings: self.warnings,
            framed_camera: framed,
        })
    }

    fn camera(&self, c: &CameraDesc) -> Result<Camera> {
        let eye = DVec3::from_array(c.eye.0);
        let at = DVec3::from_array(c.look_at.0);
        let up = DVec3::from_array(c.up.0);
        let place = self.place(Some("camera"), "camera");
        let view = at - eye;
        if view.length_squared() == 0.0 {
            return Err(Error::scene(
                self.path,
                place,
                "eye and look_at are the same point: move look_at to where the camera should look",
            ));
        }
        if view.normalize().cross(up.normalize()).length() < 1e-6 {
            return Err(Error::scene(
                self.path,
                place,
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
        Ok(Camera {
            eye: v3(c.eye.0),
            look_at: v3(c.look_at.0),
            up: v3(c.up.0),
            projection,
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
        match obj {
            ObjectDesc::Sphere {
                center,
                radius,
                material,
            } => {
                let material = self.material_id(material.as_deref(), &what)?;
                self.objects.push(Object {
                    geometry: Geometry::Sphere {
                        center: v3(center.0),
                        radius: radius.0 as Real,
                    },
                    material,
                });
            }
            ObjectDesc::Box { min, max, material } => {
                if (0..3).any(|a| min.0[a] > max.0[a]) {
                    return Err(Error::scene(
                        self.path,
                        self.place(None, &what),
                        format!(
                            "box min {:?} is above max {:?} on some axis: swap the corners",
                            min.0, max.0
                        ),
                    ));
                }
                let material = self.material_id(material.as_deref(), &what)?;
                self.objects.push(Object {
                    geometry: Geometry::Cuboid {
                        min: v3(min.0),
                        max: v3(max.0),
                    },
                    material,
                });
            }
            ObjectDesc::Plane {
                point,
                normal,
                material,
            } => {
                let material = self.material_id(material.as_deref(), &what)?;
                self.objects.push(Object {
                    geometry: Geometry::Plane {
                        point: v3(point.0),
                        normal: v3(normal.0),
                    },
                    material,
                });
            }
            ObjectDesc::Mesh {
                file,
                transform,
                material,
                materials,
            } => self.mesh(&what, file, transform, material.as_deref(), materials)?,
            ObjectDesc::RandomSpheres {
                count,
                seed,
                radius,
                bounds,
                material,
            } => {
                // Without a material each sphere gets a matte material in its
                // random colour, as in the benchmark.
                let forced = match material {
                    Some(m) => Some(self.material_id(Some(m), &what)?),
                    None => None,
                };
                let (lo, hi) = match bounds {
                    Some((lo, hi)) => {
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
                let spheres = crate::random::spheres(count.0, *seed, radius.map(|r| r.0), lo, hi);
                for (center, radius, color) in spheres {
                    let material = match forced {
                        Some(m) => m,
                        None => {
                            self.materials.push(Material::Matte {
                                color,
                                ka: 0.25,
                                kd: 0.75,
                            });
                            (self.materials.len() - 1) as MaterialId
                        }
                    };
                    self.objects.push(Object {
                        geometry: Geometry::Sphere { center, radius },
                        material,
                    });
                }
            }
        }
        Ok(())
    }

    fn mesh(
        &mut self,
        what: &str,
        file: &str,
        transform: &[TransformDesc],
        material: Option<&str>,
        overrides: &schema::NamedMap<String>,
    ) -> Result<()> {
        let needle = format!("\"{file}\"");
        let place = self.place(Some(&needle), what);
        let fpath = self.base.join(file);
        let mut model = load_model(&fpath).map_err(|e| Error::Mesh {
            scene: self.path.to_path_buf(),
            place: place.clone(),
            source: Box::new(e),
        })?;
        if !transform.is_empty() {
            let m = transform
                .iter()
                .fold(DMat4::IDENTITY, |acc, op| transform_matrix(op) * acc);
            model.transform(&m).map_err(|e| {
                Error::scene(
                    self.path,
                    place.clone(),
                    format!("transform of \"{file}\": {e}"),
                )
            })?;
        }
        for (from, _) in &overrides.0 {
            if !model.materials.iter().any(|m| &m.name == from) {
                let have: Vec<&str> = model.materials.iter().map(|m| m.name.as_str()).collect();
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
        let forced = match material {
            Some(name) => Some(self.material_id(Some(name), what)?),
            None => None,
        };
        // File material index → scene material id, filled as meshes use them.
        let mut mapped: Vec<Option<MaterialId>> = vec![None; model.materials.len()];
        let stem = Path::new(file)
            .file_name()
            .map_or_else(|| file.to_string(), |n| n.to_string_lossy().into_owned());
        for mm in &model.meshes {
            let id = match mm.material {
                Some(k) => {
                    if let Some(id) = mapped[k] {
                        id
                    } else {
                        let fm = &model.materials[k];
                        let id = match overrides.get(&fm.name) {
                            Some(to) => self.material_id(Some(to), what)?,
                            None => match forced {
                                Some(f) => f,
                                None => self.push_material(
                                    format!("{stem}:{}", fm.name),
                                    fm.material.clone(),
                                ),
                            },
                        };
                        mapped[k] = Some(id);
                        id
                    }
                }
                None => match forced {
                    Some(f) => f,
                    None => self.default_material(),
                },
            };
            self.objects.push(Object {
                geometry: Geometry::Mesh(Box::new(mm.oriented())),
                material: id,
            });
        }
        // A scene uses the meshes only, not the file's lights.
        self.warnings.extend(
            model
                .warnings
                .drain(..)
                .filter(|w| !w.contains(model::SPOT_WARNING)),
        );
        Ok(())
    }
}

/// One transform step as a matrix.
fn transform_matrix(op: &TransformDesc) -> DMat4 {
    match op {
        TransformDesc::Translate(t) => DMat4::from_translation(DVec3::from_array(t.0)),
        TransformDesc::Scale(s) => DMat4::from_scale(DVec3::from_array(s.0)),
        TransformDesc::Rotate { axis, degrees } => DMat4::from_axis_angle(
            DVec3::from_array(axis.0).normalize(),
            degrees.0.to_radians(),
        ),
        TransformDesc::Euler { x, y, z } => DMat4::from_quat(DQuat::from_euler(
            glam::EulerRot::ZYX,
            z.0.to_radians(),
            y.0.to_radians(),
            x.0.to_radians(),
        )),
        TransformDesc::Matrix(m) => {
            // Rows in the file; glam wants columns.
            DMat4::from_cols_array_2d(&m.0).transpose()
        }
    }
}

fn material(d: &MaterialDesc) -> Material {
    match d {
        MaterialDesc::Matte { color, ka, kd } => Material::Matte {
            color: model::rgb(color.0),
            ka: f32s(ka.0),
            kd: f32s(kd.0),
        },
        MaterialDesc::Phong {
            color,
            ka,
            kd,
            ks,
            exp,
            specular,
        } => Material::Phong {
            color: model::rgb(color.0),
            ka: f32s(ka.0),
            kd: f32s(kd.0),
            ks: f32s(ks.0),
            exp: f32s(exp.0),
            specular: model::rgb(specular.0),
        },
        MaterialDesc::Reflective {
            color,
            ka,
            kd,
            ks,
            exp,
            kr,
            reflect,
        } => Material::Reflective {
            color: model::rgb(color.0),
            ka: f32s(ka.0),
            kd: f32s(kd.0),
            ks: f32s(ks.0),
            exp: f32s(exp.0),
            kr: f32s(kr.0),
            reflect: model::rgb(reflect.0),
        },
        MaterialDesc::Dielectric { ior, tint } => Material::Dielectric {
            ior: f32s(ior.0),
            tint: model::rgb(tint.0),
        },
        MaterialDesc::Emissive { color, strength } => Material::Emissive {
            color: model::rgb(color.0),
            strength: f32s(strength.0),
        },
    }
}

fn light(d: &LightDesc) -> Light {
    match d {
        LightDesc::Ambient { color, intensity } => Light::Ambient {
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
        },
        LightDesc::Point {
            position,
            color,
            intensity,
            inverse_square,
            shadows,
        } => Light::Point {
            position: v3(position.0),
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
            inverse_square: *inverse_square,
            shadows: *shadows,
        },
        LightDesc::Directional {
            direction,
            color,
            intensity,
            shadows,
        } => Light::Directional {
            direction: v3(direction.0),
            color: model::rgb(color.0),
            intensity: f32s(intensity.0),
            shadows: *shadows,
        },
    }
}

/// The box around every bounded object (planes are infinite and left out).
fn finite_bounds(objects: &[Object]) -> Aabb {
    objects.iter().fold(Aabb::EMPTY, |b, o| match &o.geometry {
        Geometry::Sphere { center, radius } => b.union(Aabb::new(
            *center - Vec3::splat(*radius),
            *center + Vec3::splat(*radius),
        )),
        Geometry::Cuboid { min, max } => b.union(Aabb::new(*min, *max)),
        Geometry::Plane { .. } => b,
        Geometry::Mesh(m) => m
            .triangles
            .iter()
            .flatten()
            .fold(b, |b, &i| b.grow(m.positions[i as usize])),
    })
}

/// A perspective camera that sees the whole box: it looks at the centre from
/// the front (+z), a little to the right and above, far enough back for the
/// bounding sphere to fit both the vertical and the horizontal field of view.
#[must_use]
pub fn frame(bounds: Aabb, vfov_deg: f64, aspect: f64) -> Camera {
    let c = to_dvec3(bounds.centroid());
    let r = (0.5 * to_dvec3(bounds.extent()).length())
        .max(1e-6 * c.abs().max_element())
        .max(1e-9);
    let half_v = (vfov_deg * 0.5).to_radians();
    let half_h = (half_v.tan() * aspect.max(1e-3)).atan();
    let dist = r / half_v.min(half_h).sin() * 1.05;
    let dir = DVec3::new(0.35, 0.3, 1.0).normalize();
    Camera {
        eye: to_vec3(c + dir * dist),
        look_at: to_vec3(c),
        up: Vec3::Y,
        projection: Projection::Perspective {
            vfov_deg: vfov_deg as Real,
        },
    }
}

/// Default image width of a model rendered on its own.
const MODEL_WIDTH: u32 = 640;
/// Default image height of a model rendered on its own.
const MODEL_HEIGHT: u32 = 480;

/// A scene that shows a model on its own: the file's camera (or one framing
/// the model's bounds), the file's lights (or an ambient light plus a
/// directional light from over the camera's shoulder, with shadows), the
/// file's materials, 640×480 (or the file camera's aspect ratio), 1 spp.
#[must_use]
pub fn scene_from_model(model: Model) -> LoadedScene {
    let mut materials: Vec<Material> = model.materials.iter().map(|m| m.material.clone()).collect();
    let default_id = materials.len() as MaterialId;
    let mut need_default = false;
    let objects: Vec<Object> = model
        .meshes
        .iter()
        .map(|mm| Object {
            geometry: Geometry::Mesh(Box::new(mm.oriented())),
            material: mm.material.map_or_else(
                || {
                    need_default = true;
                    default_id
                },
                |k| k as MaterialId,
            ),
        })
        .collect();
    if need_default {
        materials.push(model::default_material());
    }
    let (width, height) = match model.camera.as_ref().and_then(|c| c.aspect) {
        Some(a) if a >= 1.0 => (
            MODEL_WIDTH,
            ((f64::from(MODEL_WIDTH) / a).round() as u32).max(1),
        ),
        Some(a) => (
            ((f64::from(MODEL_HEIGHT) * a).round() as u32).max(1),
            MODEL_HEIGHT,
        ),
        None => (MODEL_WIDTH, MODEL_HEIGHT),
    };
    let framed = model.camera.is_none();
    let camera = match &model.camera {
        Some(c) => c.camera.clone(),
        None => frame(model.bounds(), 40.0, f64::from(width) / f64::from(height)),
    };
    let lights = if model.lights.is_empty() {
        default_lights(&camera)
    } else {
        model.lights.clone()
    };
    LoadedScene {
        scene: Scene {
            camera,
            settings: Settings {
                width,
                height,
                spp: 1,
                max_depth: 5,
                background: Rgb::new(0.12, 0.13, 0.16),
            },
            materials,
            lights,
            objects,
        },
        source: model.path.clone(),
        warnings: model.warnings,
        framed_camera: framed,
    }
}

/// Lights for a model without its own: a dim ambient light and a
/// directional light from above and behind the camera's right shoulder.
fn default_lights(camera: &Camera) -> Vec<Light> {
    let back = to_dvec3(camera.eye - camera.look_at).normalize_or(DVec3::Z);
    let up = to_dvec3(camera.up).normalize_or(DVec3::Y);
    let right = up.cross(back).normalize_or(DVec3::X);
    let toward = (back + up * 0.9 + right * 0.5).normalize_or(DVec3::Y);
    vec![
        Light::Ambient {
            color: Rgb::ONE,
            intensity: 0.25,
        },
        Light::Directional {
            direction: to_vec3(toward),
            color: Rgb::ONE,
            intensity: 3.0,
            shadows: true,
        },
    ]
}

/// Applies command-line overrides of the image size and sample count. With
/// only one of width and height given, the other follows the scene's aspect
/// ratio.
///
/// # Errors
/// [`Error::Arg`] for a value out of range (sides 1..=16384, at most 2^26
/// pixels, spp 1..=65536).
pub fn apply_overrides(
    settings: &mut Settings,
    width: Option<u32>,
    height: Option<u32>,
    spp: Option<u32>,
) -> Result<()> {
    if let Some(w) = width {
        schema::check_side(w).map_err(|m| Error::arg("--width", m))?;
    }
    if let Some(h) = height {
        schema::check_side(h).map_err(|m| Error::arg("--height", m))?;
    }
    let aspect = f64::from(settings.width.max(1)) / f64::from(settings.height.max(1));
    let (w, h) = match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (
            w,
            ((f64::from(w) / aspect).round() as u32).clamp(1, schema::MAX_SIDE),
        ),
        (None, Some(h)) => (
            ((f64::from(h) * aspect).round() as u32).clamp(1, schema::MAX_SIDE),
            h,
        ),
        (None, None) => (settings.width, settings.height),
    };
    schema::check_pixels(w, h).map_err(|m| Error::arg("--width/--height", m))?;
    settings.width = w;
    settings.height = h;
    if let Some(s) = spp {
        settings.spp = schema::check_spp(s).map_err(|m| Error::arg("--spp", m))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn locate_finds_line_and_column() {
        assert_eq!(locate("ab\ncd \"x\"", "\"x\""), Some((2, 4)));
        assert_eq!(locate("\"x\"", "\"x\""), Some((1, 1)));
        assert_eq!(locate("abc", "z"), None);
        assert_eq!(locate("// \"x\"\n  \"x\"", "\"x\""), Some((2, 3)));
        assert_eq!(line_col(b"ab\ncd", 4), (2, 2));
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

    #[test]
    fn framing_sees_the_whole_box() {
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let cam = frame(b, 45.0, 4.0 / 3.0);
        let d = to_dvec3(cam.eye - cam.look_at).length();
        assert!(d > 3.0_f64.sqrt() / (22.5_f64.to_radians().sin()), "{d}");
    }

    #[test]
    fn overrides_keep_the_aspect_ratio_and_check_ranges() {
        let mut s = Settings {
            width: 640,
            height: 480,
            ..Settings::default()
        };
        apply_overrides(&mut s, Some(64), None, Some(4)).unwrap();
        assert_eq!((s.width, s.height, s.spp), (64, 48, 4));
        assert!(apply_overrides(&mut s, Some(0), None, None).is_err());
        assert!(apply_overrides(&mut s, None, None, Some(0)).is_err());
        let e = apply_overrides(&mut s, Some(16384), Some(16384), None).unwrap_err();
        assert!(e.to_string().contains("too large"), "{e}");
    }
}
