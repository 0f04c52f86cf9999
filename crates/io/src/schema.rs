//! The RON scene-file schema: what a `.ron` scene may say, with its defaults
//! and the checks that need no context (ranges, finiteness).
//!
//! These types are the *file format*; `scene.rs` turns them into the tracer's
//! model. Every struct and enum denies unknown fields, so a typo is an error
//! with a line and column rather than a silently ignored setting. Values are
//! checked while they are read (through `try_from`), so a bad value's error
//! carries the position of the value. `docs/scene-format.md` documents every
//! field with an example; keep it in step.

use crate::schema_textures::TextureDesc;
use gridrt_tracer::{ConductorFresnel, Material};
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use std::fmt;

/// Largest image side in pixels.
pub(crate) const MAX_SIDE: u32 = 16_384;
/// Largest number of samples per pixel.
pub(crate) const MAX_SPP: u32 = 65_536;
/// Largest reflection/refraction depth.
pub(crate) const MAX_DEPTH: u32 = 64;
/// Most spheres one `RandomSpheres` may generate.
pub(crate) const MAX_RANDOM_SPHERES: u32 = 10_000_000;

pub(crate) use crate::schema_settings::SettingsDesc;

pub(crate) use crate::schema_values::*;

// ---------------------------------------------------------------------------
// A map from names to values that keeps file order and rejects duplicates.

/// `{ "name": value, ... }` read into a list in file order; a name given
/// twice is an error (a plain map would silently keep the last one).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct NamedMap<T>(pub Vec<(String, T)>);

impl<T> Default for NamedMap<T> {
    fn default() -> Self {
        Self(Vec::new())
    }
}

impl<T> NamedMap<T> {
    pub(crate) fn get(&self, name: &str) -> Option<&T> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for NamedMap<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> Visitor<'de> for V<T> {
            type Value = NamedMap<T>;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a map { \"name\": value, ... }")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                let mut out: Vec<(String, T)> = Vec::new();
                while let Some(name) = map.next_key::<String>()? {
                    if out.iter().any(|(n, _)| *n == name) {
                        return Err(de::Error::custom(format!(
                            "the name \"{name}\" is defined twice: give each entry its own name"
                        )));
                    }
                    let value = map.next_value::<T>()?;
                    out.push((name, value));
                }
                Ok(NamedMap(out))
            }
        }
        d.deserialize_map(V(std::marker::PhantomData))
    }
}

// ---------------------------------------------------------------------------
// The scene file.

/// A whole scene file: `Scene(camera: ..., settings: ..., materials: {...},
/// lights: [...], objects: [...])`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Scene")]
pub(crate) struct SceneFile {
    /// The camera; when absent the scene's bounds are framed automatically.
    #[serde(default)]
    pub camera: Option<CameraDesc>,
    /// Image and tracing settings.
    #[serde(default)]
    pub settings: SettingsDesc,
    /// Named materials.
    #[serde(default)]
    pub materials: NamedMap<MaterialDesc>,
    /// Light sources.
    #[serde(default)]
    pub lights: Vec<LightDesc>,
    /// The geometry.
    pub objects: Vec<ObjectDesc>,
}

/// `Camera(eye: (..), look_at: (..), up: (..), projection: ..., lens_radius: 0, focus_distance: ..)`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Camera")]
pub(crate) struct CameraDesc {
    pub eye: V3,
    pub look_at: V3,
    #[serde(default = "default_up")]
    pub up: Dir,
    #[serde(default)]
    pub projection: ProjectionDesc,
    /// The thin lens's radius (aperture), world units; 0 is a pinhole.
    #[serde(default)]
    pub lens_radius: NonNeg,
    /// Distance from the eye to the plane in focus, along the view
    /// direction (needed when `lens_radius` > 0).
    #[serde(default)]
    pub focus_distance: Option<Positive>,
}

fn default_up() -> Dir {
    Dir([0.0, 1.0, 0.0])
}

/// Camera projections.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Projection")]
pub(crate) enum ProjectionDesc {
    /// `Perspective(vfov: 45)`: vertical field of view in degrees.
    Perspective { vfov: Fov },
    /// `ViewPlane(distance: 400, pixel_size: 1)`: Suffern's pinhole.
    ViewPlane {
        distance: Positive,
        #[serde(default = "one")]
        pixel_size: Positive,
    },
    /// `Orthographic(height: 4)`: parallel rays; world height of the image.
    Orthographic { height: Positive },
}

impl Default for ProjectionDesc {
    fn default() -> Self {
        Self::Perspective { vfov: Fov(45.0) }
    }
}

fn one() -> Positive {
    Positive(1.0)
}

/// Materials (Suffern's ray-cast and Whitted chapters).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Material")]
pub(crate) enum MaterialDesc {
    /// `Matte(color: (r, g, b), ka: 0.25, kd: 0.75)`.
    Matte {
        #[serde(default = "default_albedo")]
        color: Color,
        #[serde(default = "default_ka")]
        ka: NonNeg,
        #[serde(default = "default_kd")]
        kd: NonNeg,
        #[serde(default)]
        texture: Option<TextureDesc>,
    },
    /// `Phong(color, ka, kd, ks: 0.25, exp: 32, specular: (1, 1, 1))`.
    Phong {
        #[serde(default = "default_albedo")]
        color: Color,
        #[serde(default = "default_ka")]
        ka: NonNeg,
        #[serde(default = "default_kd")]
        kd: NonNeg,
        #[serde(default = "default_ks")]
        ks: NonNeg,
        #[serde(default = "default_exp")]
        exp: Positive,
        #[serde(default = "white")]
        specular: Color,
        #[serde(default)]
        texture: Option<TextureDesc>,
    },
    /// `Reflective(color, ka: 0, kd: 0, ks: 0, exp: 100, kr: 1, reflect: (1, 1, 1))`;
    /// the defaults make a perfect mirror.
    Reflective {
        #[serde(default = "white")]
        color: Color,
        #[serde(default = "zero")]
        ka: NonNeg,
        #[serde(default = "zero")]
        kd: NonNeg,
        #[serde(default = "zero")]
        ks: NonNeg,
        #[serde(default = "default_mirror_exp")]
        exp: Positive,
        #[serde(default = "one_nn")]
        kr: NonNeg,
        #[serde(default = "white")]
        reflect: Color,
        #[serde(default)]
        texture: Option<TextureDesc>,
    },
    /// `Dielectric(ior: 1.5, tint: (1, 1, 1), roughness: 0)`; roughness > 0
    /// is rough (frosted) glass.
    Dielectric {
        #[serde(default = "default_ior")]
        ior: Ior,
        #[serde(default = "white")]
        tint: Color,
        #[serde(default)]
        roughness: Unit,
    },
    /// `Conductor(color: (0.95, 0.64, 0.54), roughness: 0.3)` (Schlick's
    /// Fresnel from the colour at normal incidence) or
    /// `Conductor(eta: (0.2, 0.92, 1.1), k: (3.9, 2.45, 2.14), roughness: 0.3)`
    /// (a complex index of refraction).
    Conductor {
        #[serde(default)]
        color: Option<UnitColor>,
        #[serde(default)]
        eta: Option<Color>,
        #[serde(default)]
        k: Option<Color>,
        #[serde(default)]
        roughness: Unit,
    },
    /// glTF's `MetallicRoughness(base: (1, 1, 1), metallic: 1, roughness: 1)`.
    MetallicRoughness {
        #[serde(default = "unit_white")]
        base: UnitColor,
        #[serde(default = "unit_one")]
        metallic: Unit,
        #[serde(default = "unit_one")]
        roughness: Unit,
        #[serde(default)]
        texture: Option<TextureDesc>,
    },
    /// `Emissive(color: (1, 1, 1), strength: 1)`.
    Emissive {
        #[serde(default = "white")]
        color: Color,
        #[serde(default = "one_nn")]
        strength: NonNeg,
    },
}

fn unit_white() -> UnitColor {
    UnitColor([1.0; 3])
}
fn unit_one() -> Unit {
    Unit(1.0)
}
fn default_albedo() -> Color {
    gray(0.8)
}
fn white() -> Color {
    gray(1.0)
}
fn default_ka() -> NonNeg {
    NonNeg(0.25)
}
fn default_kd() -> NonNeg {
    NonNeg(0.75)
}
fn default_ks() -> NonNeg {
    NonNeg(0.25)
}
fn default_exp() -> Positive {
    Positive(32.0)
}
fn default_mirror_exp() -> Positive {
    Positive(100.0)
}
fn zero() -> NonNeg {
    NonNeg(0.0)
}
fn one_nn() -> NonNeg {
    NonNeg(1.0)
}
fn default_ior() -> Ior {
    Ior(1.5)
}
fn yes() -> bool {
    true
}

/// Ambient occlusion of an ambient light (Suffern's ambient occluder):
/// `Occlusion(samples: 16, distance: 2, min_amount: 0)`; no `distance`:
/// occluders at any distance count.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Occlusion")]
pub(crate) struct OcclusionDesc {
    #[serde(default = "sixteen")]
    pub samples: AoSamples,
    #[serde(default)]
    pub distance: Option<Positive>,
    #[serde(default)]
    pub min_amount: Unit,
}

fn sixteen() -> AoSamples {
    AoSamples(16)
}

/// Light sources.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Light")]
pub(crate) enum LightDesc {
    /// `Ambient(color: (1, 1, 1), intensity: 0.2, occlusion: Occlusion(..))`;
    /// without `occlusion` the same light reaches every point.
    Ambient {
        #[serde(default = "white")]
        color: Color,
        #[serde(default = "one_nn")]
        intensity: NonNeg,
        #[serde(default)]
        occlusion: Option<OcclusionDesc>,
    },
    /// `Point(position: (x, y, z), color, intensity: 1, inverse_square: false, shadows: true)`.
    Point {
        position: V3,
        #[serde(default = "white")]
        color: Color,
        #[serde(default = "one_nn")]
        intensity: NonNeg,
        #[serde(default)]
        inverse_square: bool,
        #[serde(default = "yes")]
        shadows: bool,
    },
    /// `Directional(direction: (x, y, z), color, intensity: 1, shadows: true)`;
    /// `direction` points towards the light.
    Directional {
        direction: Dir,
        #[serde(default = "white")]
        color: Color,
        #[serde(default = "one_nn")]
        intensity: NonNeg,
        #[serde(default = "yes")]
        shadows: bool,
    },
    /// `Spot(position: (x, y, z), direction: (x, y, z), color, intensity: 1,
    /// outer: 30, inner: outer − 5, inverse_square: false, shadows: true)`;
    /// `direction` is the cone's axis, from the light; angles are
    /// half-angles in degrees.
    Spot {
        position: V3,
        direction: Dir,
        #[serde(default = "white")]
        color: Color,
        #[serde(default = "one_nn")]
        intensity: NonNeg,
        #[serde(default = "thirty")]
        outer: Angle,
        #[serde(default)]
        inner: Option<Angle>,
        #[serde(default)]
        inverse_square: bool,
        #[serde(default = "yes")]
        shadows: bool,
    },
    /// `Rect(corner: (x, y, z), edge_u: (x, y, z), edge_v: (x, y, z), color,
    /// intensity: 1)`: an area light emitting from the side `edge_u ×
    /// edge_v` points to.
    Rect {
        corner: V3,
        edge_u: Dir,
        edge_v: Dir,
        #[serde(default = "white")]
        color: Color,
        #[serde(default = "one_nn")]
        intensity: NonNeg,
    },
    /// `Disk(center: (x, y, z), normal: (x, y, z), radius: 1, color,
    /// intensity: 1)`: an area light emitting to the side `normal` points to.
    Disk {
        center: V3,
        normal: Dir,
        radius: Positive,
        #[serde(default = "white")]
        color: Color,
        #[serde(default = "one_nn")]
        intensity: NonNeg,
    },
    /// `Environment(color: (1, 1, 1), intensity: 1, image: "sky.hdr")`:
    /// light from every direction, constant or from an equirectangular
    /// Radiance `.hdr` or OpenEXR `.exr` image.
    Environment {
        #[serde(default = "white")]
        color: Color,
        #[serde(default = "one_nn")]
        intensity: NonNeg,
        #[serde(default)]
        image: Option<String>,
    },
}

fn thirty() -> Angle {
    Angle(30.0)
}

/// Objects. Variant names are PascalCase; the snake_case spelling
/// (`random_spheres`) is accepted too.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Object")]
pub(crate) enum ObjectDesc {
    /// `Sphere(center: (x, y, z), radius: 1, material: "name")`.
    #[serde(alias = "sphere")]
    Sphere {
        center: V3,
        radius: Positive,
        #[serde(default)]
        material: Option<String>,
    },
    /// `Box(min: (x, y, z), max: (x, y, z), material: "name")`.
    #[serde(alias = "box", alias = "Cuboid", alias = "cuboid")]
    Box {
        min: V3,
        max: V3,
        #[serde(default)]
        material: Option<String>,
    },
    /// `Plane(point: (x, y, z), normal: (x, y, z), material: "name")`.
    #[serde(alias = "plane")]
    Plane {
        point: V3,
        normal: Dir,
        #[serde(default)]
        material: Option<String>,
    },
    /// `Mesh(file: "model.obj", transform: [...], material: "name", materials: {"file name": "scene name"}, normals: Smooth(60))`.
    #[serde(alias = "mesh")]
    Mesh {
        file: String,
        #[serde(default)]
        transform: Vec<TransformDesc>,
        #[serde(default)]
        material: Option<String>,
        #[serde(default)]
        materials: NamedMap<String>,
        #[serde(default)]
        normals: crate::model::Normals,
    },
    /// `RandomSpheres(count: 1000, seed: 15, radius: 0.01, bounds: ((-1, -1, -1), (1, 1, 1)), material: "name")`.
    #[serde(alias = "random_spheres")]
    RandomSpheres {
        count: Count,
        #[serde(default)]
        seed: u64,
        #[serde(default)]
        radius: Option<Positive>,
        #[serde(default)]
        bounds: Option<(V3, V3)>,
        #[serde(default)]
        material: Option<String>,
    },
}

/// One step of a mesh transform; a list of steps applies in order.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Transform")]
pub(crate) enum TransformDesc {
    /// `Translate((x, y, z))`.
    #[serde(alias = "translate")]
    Translate(V3),
    /// `Scale(2)` or `Scale((sx, sy, sz))`; no zero factor.
    #[serde(alias = "scale")]
    Scale(ScaleDesc),
    /// `Rotate(axis: (x, y, z), degrees: 30)`: right-handed, about the origin.
    #[serde(alias = "rotate")]
    Rotate { axis: Dir, degrees: Finite },
    /// `Euler(x: 0, y: 30, z: 0)`: degrees about the world x, then y, then z axis.
    #[serde(alias = "euler")]
    Euler {
        #[serde(default = "zero_f")]
        x: Finite,
        #[serde(default = "zero_f")]
        y: Finite,
        #[serde(default = "zero_f")]
        z: Finite,
    },
    /// `Matrix(((m00, m01, m02, m03), ..., (0, 0, 0, 1)))`: row-major affine 4×4.
    #[serde(alias = "matrix")]
    Matrix(MatrixDesc),
}

fn zero_f() -> Finite {
    Finite(0.0)
}

/// A uniform or per-axis scale, all factors finite and non-zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ScaleDesc(pub [f64; 3]);

impl<'de> Deserialize<'de> for ScaleDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl V {
            fn check<E: de::Error>(s: [f64; 3]) -> Result<ScaleDesc, E> {
                if s.iter().all(|x| x.is_finite() && *x != 0.0) {
                    Ok(ScaleDesc(s))
                } else {
                    Err(E::custom(format!(
                        "scale factors must be finite and non-zero, found ({}, {}, {})",
                        s[0], s[1], s[2]
                    )))
                }
            }
        }
        impl<'de> Visitor<'de> for V {
            type Value = ScaleDesc;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number or (sx, sy, sz)")
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<ScaleDesc, E> {
                Self::check([x; 3])
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<ScaleDesc, E> {
                Self::check([x as f64; 3])
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<ScaleDesc, E> {
                Self::check([x as f64; 3])
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut s: A) -> Result<ScaleDesc, A::Error> {
                let mut v = [0.0; 3];
                for (i, c) in v.iter_mut().enumerate() {
                    *c = s
                        .next_element()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                if s.next_element::<f64>()?.is_some() {
                    return Err(de::Error::invalid_length(4, &self));
                }
                Self::check(v)
            }
        }
        d.deserialize_any(V)
    }
}

/// A row-major 4×4 affine matrix: finite, last row `(0, 0, 0, 1)`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "[[f64; 4]; 4]")]
pub(crate) struct MatrixDesc(pub [[f64; 4]; 4]);

impl TryFrom<[[f64; 4]; 4]> for MatrixDesc {
    type Error = String;
    fn try_from(m: [[f64; 4]; 4]) -> Result<Self, String> {
        if !m.iter().flatten().all(|x| x.is_finite()) {
            return Err("matrix entries must be finite".to_string());
        }
        if m[3] != [0.0, 0.0, 0.0, 1.0] {
            return Err(format!(
                "the last row of a transform matrix must be (0, 0, 0, 1) (rows are written \
                 first: translation goes in the last column), found ({}, {}, {}, {})",
                m[3][0], m[3][1], m[3][2], m[3][3]
            ));
        }
        Ok(Self(m))
    }
}

/// Parses RON text with the options every gridrt scene uses
/// (`implicit_some`, so `material: "red"` needs no `Some(...)`).
pub(crate) fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

impl MaterialDesc {
    /// The tracer's material.
    /// The procedural texture multiplying the colour, if any.
    pub(crate) fn texture(&self) -> Option<&TextureDesc> {
        match self {
            MaterialDesc::Matte { texture, .. }
            | MaterialDesc::Phong { texture, .. }
            | MaterialDesc::Reflective { texture, .. }
            | MaterialDesc::MetallicRoughness { texture, .. } => texture.as_ref(),
            MaterialDesc::Dielectric { .. }
            | MaterialDesc::Conductor { .. }
            | MaterialDesc::Emissive { .. } => None,
        }
    }

    /// The tracer's material, or the field that is wrong and why.
    pub(crate) fn material(&self) -> Result<Material, (&'static str, String)> {
        Ok(match self {
            MaterialDesc::Matte { color, ka, kd, .. } => Material::Matte {
                color: rgb(color.0),
                ka: f64_to_f32(ka.0),
                kd: f64_to_f32(kd.0),
            },
            MaterialDesc::Phong {
                color,
                ka,
                kd,
                ks,
                exp,
                specular,
                ..
            } => Material::Phong {
                color: rgb(color.0),
                ka: f64_to_f32(ka.0),
                kd: f64_to_f32(kd.0),
                ks: f64_to_f32(ks.0),
                exp: f64_to_f32(exp.0),
                specular: rgb(specular.0),
            },
            MaterialDesc::Reflective {
                color,
                ka,
                kd,
                ks,
                exp,
                kr,
                reflect,
                ..
            } => Material::Reflective {
                color: rgb(color.0),
                ka: f64_to_f32(ka.0),
                kd: f64_to_f32(kd.0),
                ks: f64_to_f32(ks.0),
                exp: f64_to_f32(exp.0),
                kr: f64_to_f32(kr.0),
                reflect: rgb(reflect.0),
            },
            MaterialDesc::Dielectric {
                ior,
                tint,
                roughness,
            } => {
                if roughness.0 > 0.0 {
                    Material::RoughDielectric {
                        ior: f64_to_f32(ior.0),
                        tint: rgb(tint.0),
                        roughness: f64_to_f32(roughness.0),
                    }
                } else {
                    Material::Dielectric {
                        ior: f64_to_f32(ior.0),
                        tint: rgb(tint.0),
                    }
                }
            }
            MaterialDesc::Conductor {
                color,
                eta,
                k,
                roughness,
            } => {
                let fresnel =
                    match (color, eta, k) {
                        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => return Err((
                            "color",
                            "give either color (Schlick) or eta and k (a complex index), not both"
                                .into(),
                        )),
                        (None, None, Some(_)) => {
                            return Err(("k", "k needs eta (the real part of the index)".into()))
                        }
                        (_, Some(eta), k) => {
                            if eta.0.iter().any(|&x| x <= 0.0) {
                                return Err(("eta", "every component of eta must be > 0".into()));
                            }
                            ConductorFresnel::Complex {
                                eta: rgb(eta.0),
                                k: rgb(k.map_or([0.0; 3], |k| k.0)),
                            }
                        }
                        (c, None, None) => ConductorFresnel::Schlick {
                            f0: rgb(c.map_or([0.9; 3], |c| c.0)),
                        },
                    };
                Material::Conductor {
                    fresnel,
                    roughness: f64_to_f32(roughness.0),
                }
            }
            MaterialDesc::MetallicRoughness {
                base,
                metallic,
                roughness,
                ..
            } => Material::MetallicRoughness {
                base: rgb(base.0),
                metallic: f64_to_f32(metallic.0),
                roughness: f64_to_f32(roughness.0),
            },
            MaterialDesc::Emissive { color, strength } => Material::Emissive {
                color: rgb(color.0),
                strength: f64_to_f32(strength.0),
            },
        })
    }
}

fn f64_to_f32(x: f64) -> f32 {
    x as f32
}

fn rgb(c: [f64; 3]) -> gridrt_tracer::Rgb {
    crate::model::rgb(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse<T: for<'de> Deserialize<'de>>(s: &str) -> Result<T, ron::error::SpannedError> {
        ron_options().from_str(s)
    }

    #[test]
    fn minimal_scene_takes_defaults() {
        let s: SceneFile = parse("(objects: [Sphere(center: (0, 0, 0), radius: 1)])").unwrap();
        assert_eq!(s.camera, None);
        assert_eq!(s.settings, SettingsDesc::default());
        assert_eq!(s.objects.len(), 1);
    }

    #[test]
    fn scale_takes_a_number_or_a_vector() {
        let t: Vec<TransformDesc> = parse("[Scale(2), Scale(0.5), Scale((1, 2, 3))]").unwrap();
        assert_eq!(t[0], TransformDesc::Scale(ScaleDesc([2.0; 3])));
        assert_eq!(t[1], TransformDesc::Scale(ScaleDesc([0.5; 3])));
        assert_eq!(t[2], TransformDesc::Scale(ScaleDesc([1.0, 2.0, 3.0])));
        assert!(parse::<Vec<TransformDesc>>("[Scale(0)]").is_err());
        assert!(parse::<Vec<TransformDesc>>("[Scale((1, 2))]").is_err());
    }

    #[test]
    fn checks_carry_positions() {
        let e = parse::<SceneFile>("(objects: [\n  Sphere(center: (0, 0, 0), radius: -1)])")
            .unwrap_err();
        assert_eq!(e.position.line, 2);
        assert!(
            e.to_string().contains("expected a number > 0, found -1"),
            "{e}"
        );
    }

    #[test]
    fn settings_check_the_pixel_count() {
        assert!(parse::<SettingsDesc>("(width: 16384, height: 4096)").is_ok());
        let e = parse::<SettingsDesc>("(width: 16384, height: 4097)").unwrap_err();
        assert!(e.to_string().contains("too large"), "{e}");
        assert!(parse::<SettingsDesc>("(width: 0)").is_err());
        assert!(parse::<SettingsDesc>("(spp: 0)").is_err());
    }

    #[test]
    fn named_maps_reject_duplicates_and_keep_order() {
        let m: NamedMap<f64> = parse(r#"{"b": 1, "a": 2}"#).unwrap();
        assert_eq!(m.0, vec![("b".to_string(), 1.0), ("a".to_string(), 2.0)]);
        let e = parse::<NamedMap<f64>>(r#"{"a": 1, "a": 2}"#).unwrap_err();
        assert!(e.to_string().contains("defined twice"), "{e}");
    }

    #[test]
    fn snake_case_object_names_are_accepted() {
        let o: ObjectDesc = parse("random_spheres(count: 10, seed: 3)").unwrap();
        assert!(matches!(o, ObjectDesc::RandomSpheres { .. }));
    }

    #[test]
    fn matrices_must_be_affine() {
        assert!(parse::<MatrixDesc>("((1,0,0,5),(0,1,0,0),(0,0,1,0),(0,0,0,1))").is_ok());
        assert!(parse::<MatrixDesc>("((1,0,0,0),(0,1,0,0),(0,0,1,0),(5,0,0,1))").is_err());
    }
}
