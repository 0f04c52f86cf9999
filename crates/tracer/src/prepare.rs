//! From a [`Scene`] to what the renderer runs: validation, the primitives
//! for the accelerator, and the shading data.

use crate::camera::CameraModel;
use crate::emitters::EmitterShape;
use crate::error::SceneError;
use crate::float::to_f64;
use crate::integrator::{DirectLight, MeshRef, MeshShading, PrimMaterials, SceneData};
use crate::lights::{AreaLight, Environment};
use crate::plan::{EffectPlan, IntegratorKind};
use crate::scene::{Geometry, Light, Material, MaterialId, Rgb, Scene};
use crate::shapes::{Cuboid, Plane, Shape, Sphere, Triangle};
use crate::texture::shade::{TextureData, TriFrame};
use gridrt_bbox::{Real, Vec3};

/// The largest image, in pixels, the renderer accepts (8192 × 8192).
pub const MAX_PIXELS: u64 = 1 << 26;

/// The grid primitives of a scene: spheres only gets the compact type.
#[derive(Debug)]
pub(crate) enum Prims {
    Spheres(Vec<Sphere>),
    Shapes(Vec<Shape>),
}

impl Prims {
    pub(crate) fn len(&self) -> usize {
        match self {
            Prims::Spheres(v) => v.len(),
            Prims::Shapes(v) => v.len(),
        }
    }
}

/// A validated scene, ready for an accelerator to be built over `prims`.
#[derive(Debug)]
pub(crate) struct Prepared {
    pub data: SceneData,
    pub prims: Prims,
    pub camera: CameraModel,
    pub plan: EffectPlan,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
}

fn color_ok(c: Rgb) -> bool {
    c.is_finite() && c.cmpge(Rgb::ZERO).all()
}

fn coef_ok(k: f32) -> bool {
    k.is_finite() && k >= 0.0
}

fn check_material(i: usize, m: &Material) -> Result<(), SceneError> {
    let bad = |reason| {
        Err(SceneError::BadMaterial {
            material: i,
            reason,
        })
    };
    match *m {
        Material::Matte { color, ka, kd } => {
            if !color_ok(color) {
                return bad("the colour must be finite and ≥ 0 in every channel");
            }
            if !coef_ok(ka) || !coef_ok(kd) {
                return bad("ka and kd must be finite and ≥ 0");
            }
        }
        Material::Phong {
            color,
            ka,
            kd,
            ks,
            exp,
            specular,
        } => {
            if !color_ok(color) || !color_ok(specular) {
                return bad("the colours must be finite and ≥ 0 in every channel");
            }
            if ![ka, kd, ks, exp].into_iter().all(coef_ok) {
                return bad("ka, kd, ks and exp must be finite and ≥ 0");
            }
        }
        Material::Reflective {
            color,
            ka,
            kd,
            ks,
            exp,
            kr,
            reflect,
        } => {
            if !color_ok(color) || !color_ok(reflect) {
                return bad("the colours must be finite and ≥ 0 in every channel");
            }
            if ![ka, kd, ks, exp, kr].into_iter().all(coef_ok) {
                return bad("ka, kd, ks, exp and kr must be finite and ≥ 0");
            }
        }
        Material::Dielectric { ior, tint } => {
            if !(ior.is_finite() && ior > 0.0) {
                return bad("the index of refraction must be finite and > 0 (glass is about 1.5)");
            }
            if !color_ok(tint) {
                return bad("the tint must be finite and ≥ 0 in every channel (white = clear)");
            }
        }
        Material::Emissive { color, strength } => {
            if !color_ok(color) || !coef_ok(strength) {
                return bad("the colour and strength must be finite and ≥ 0");
            }
        }
    }
    Ok(())
}

fn check_light(i: usize, l: &Light) -> Result<(), SceneError> {
    let bad = |reason| Err(SceneError::BadLight { light: i, reason });
    let (color, intensity) = match *l {
        Light::Ambient { color, intensity } => (color, intensity),
        Light::Point {
            position,
            color,
            intensity,
            ..
        } => {
            if !position.is_finite() {
                return bad("the position is not finite; give finite coordinates");
            }
            (color, intensity)
        }
        Light::Directional {
            direction,
            color,
            intensity,
            ..
        } => {
            if !direction.is_finite() || direction.try_normalize().is_none() {
                return bad("the direction is zero or not finite; give the (non-zero) direction towards the light");
            }
            (color, intensity)
        }
        Light::Spot {
            position,
            direction,
            color,
            intensity,
            inner_deg,
            outer_deg,
            ..
        } => {
            if !position.is_finite() {
                return bad("the position is not finite; give finite coordinates");
            }
            if !direction.is_finite() || direction.try_normalize().is_none() {
                return bad("the direction is zero or not finite; give the (non-zero) direction the spot points to");
            }
            if !(outer_deg > 0.0 && outer_deg <= 180.0) {
                return bad("the outer angle must be in (0, 180] degrees");
            }
            if !(inner_deg >= 0.0 && inner_deg <= outer_deg) {
                return bad("the inner angle must be in [0, outer angle] degrees");
            }
            (color, intensity)
        }
        Light::Rect {
            corner,
            edge_u,
            edge_v,
            color,
            intensity,
        } => {
            if !corner.is_finite() || !edge_u.is_finite() || !edge_v.is_finite() {
                return bad("the corner and edges must be finite");
            }
            if AreaLight::rect(corner, edge_u, edge_v, 0).is_none() {
                return bad("the edges are zero or parallel; give two edges that span a rectangle");
            }
            (color, intensity)
        }
        Light::Disk {
            center,
            normal,
            radius,
            color,
            intensity,
        } => {
            if !center.is_finite() || !normal.is_finite() {
                return bad("the centre and normal must be finite");
            }
            if normal.try_normalize().is_none() {
                return bad("the normal is zero; give the side the disk emits to");
            }
            if !(radius > 0.0) || !radius.is_finite() {
                return bad("the radius must be finite and > 0");
            }
            (color, intensity)
        }
        Light::Environment {
            color,
            intensity,
            ref image,
        } => {
            if let Some(img) = image {
                let n = u64::from(img.width) * u64::from(img.height);
                if n == 0 || img.pixels.len() as u64 != n {
                    return bad(
                        "the environment image is empty or its pixel count is not width × height",
                    );
                }
                if n > MAX_PIXELS {
                    return bad("the environment image has more than 2^26 pixels; scale it down");
                }
                if !img.pixels.iter().all(|&p| color_ok(p)) {
                    return bad("the environment image has negative or non-finite pixels");
                }
            }
            (color, intensity)
        }
    };
    if !color_ok(color) || !coef_ok(intensity) {
        return bad("the colour and intensity must be finite and ≥ 0");
    }
    Ok(())
}

/// Many spheres that share one material, given as arrays rather than as
/// [`Scene`] objects: 16 bytes per sphere (`f32`) plus 12 per colour instead
/// of an object and a material each. It is how huge sphere scenes (Suffern's
/// benchmark with a million spheres) are built and rendered without the
/// memory traffic of a million `Object`s; see [`crate::Renderer::with_spheres`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SphereSet {
    /// The spheres (radius > 0, finite).
    pub spheres: Vec<Sphere>,
    /// Empty, or one colour per sphere that replaces the albedo (`color`) of
    /// the material when it is Matte, Phong or Reflective.
    pub colors: Vec<Rgb>,
    /// Index into [`Scene::materials`] shared by all the spheres.
    pub material: MaterialId,
}

/// Validates the scene (and the sphere set, which comes after the scene's
/// objects in primitive order) and converts it. Triangles of zero area are
/// left out of the grid (they can never be hit).
pub(crate) fn prepare(scene: &Scene, set: Option<SphereSet>) -> Result<Prepared, SceneError> {
    let (count, all_spheres) = validate(scene, set.as_ref())?;
    let plan = EffectPlan::derive(scene, set.as_ref().map(|s| (s.spheres.len(), s.material)));
    let s = &scene.settings;
    let camera = CameraModel::new(&scene.camera, s.width, s.height)?;
    let mut plan = plan;
    let mut data = shading_data(scene, &plan);
    data.tex = texture_data(scene, camera.footprint());
    let prims = convert(
        scene,
        set,
        count,
        all_spheres,
        plan.light_sampling,
        &mut data,
    );
    data.emitters.finish(prims.len());
    plan.area_lights = data.emitters.list.len() as u32;
    // The path tracer samples the image; Whitted only sees it.
    let env_sampled = plan.integrator == IntegratorKind::Path
        && data.env.as_ref().is_some_and(Environment::sampled);
    data.env_pick = match (env_sampled, data.emitters.is_empty()) {
        (false, _) => 0.0,
        (true, true) => 1.0,
        (true, false) => 0.5,
    };
    plan.env_sampling = env_sampled;
    plan.light_sampling = plan.area_lights > 0 || env_sampled;
    if plan.integrator == IntegratorKind::Path {
        let emits = scene.objects.iter().any(|o| {
            scene
                .materials
                .get(o.material as usize)
                .is_some_and(|m| emission(m) != Rgb::ZERO)
        });
        let emits = emits || !data.area_lights.is_empty() || data.env.is_some();
        if !emits && data.lights.is_empty() && s.background == Rgb::ZERO {
            return Err(SceneError::NothingEmits);
        }
    }
    Ok(Prepared {
        data,
        prims,
        camera,
        plan,
        width: s.width,
        height: s.height,
        spp: s.spp,
    })
}

/// Checks everything; returns the number of grid primitives and whether
/// they are all spheres.
fn validate(scene: &Scene, set: Option<&SphereSet>) -> Result<(usize, bool), SceneError> {
    let s = &scene.settings;
    if s.width == 0 || s.height == 0 {
        return Err(SceneError::EmptyImage {
            width: s.width,
            height: s.height,
        });
    }
    if u64::from(s.width) * u64::from(s.height) > MAX_PIXELS {
        return Err(SceneError::ImageTooLarge {
            width: s.width,
            height: s.height,
            max: MAX_PIXELS,
        });
    }
    if s.spp == 0 {
        return Err(SceneError::ZeroSamples);
    }
    if !s.filter.is_valid() {
        return Err(SceneError::BadFilter {
            filter: s.filter.describe(),
        });
    }
    if !s.background.is_finite() {
        return Err(SceneError::SettingNotFinite { what: "background" });
    }
    CameraModel::new(&scene.camera, s.width, s.height)?;
    for (i, m) in scene.materials.iter().enumerate() {
        check_material(i, m)?;
    }
    for (i, l) in scene.lights.iter().enumerate() {
        check_light(i, l)?;
        if matches!(l, Light::Environment { .. })
            && scene.lights[..i]
                .iter()
                .any(|l| matches!(l, Light::Environment { .. }))
        {
            return Err(SceneError::BadLight {
                light: i,
                reason: "a second Environment light: a scene has at most one",
            });
        }
    }
    scene
        .textures
        .check(scene.materials.len())
        .map_err(|reason| SceneError::BadTextures { reason })?;

    // Validate objects and count primitives.
    let mut all_spheres = true;
    let mut count = 0usize;
    for (i, o) in scene.objects.iter().enumerate() {
        if o.material as usize >= scene.materials.len() {
            return Err(SceneError::MaterialOutOfRange {
                object: i,
                material: o.material,
                count: scene.materials.len(),
            });
        }
        match &o.geometry {
            Geometry::Sphere { center, radius } => {
                if !center.is_finite() {
                    return Err(SceneError::NotFinite {
                        object: i,
                        what: "sphere centre",
                    });
                }
                if !(*radius > 0.0 && radius.is_finite()) {
                    return Err(SceneError::BadRadius {
                        object: i,
                        radius: to_f64(*radius),
                    });
                }
                count += 1;
            }
            Geometry::Cuboid { min, max } => {
                if !min.is_finite() || !max.is_finite() {
                    return Err(SceneError::NotFinite {
                        object: i,
                        what: "box corner",
                    });
                }
                if min.cmpgt(*max).any() {
                    return Err(SceneError::InvertedCuboid { object: i });
                }
                all_spheres = false;
                count += 1;
            }
            Geometry::Plane { point, normal } => {
                if !point.is_finite() || !normal.is_finite() {
                    return Err(SceneError::NotFinite {
                        object: i,
                        what: "plane point or normal",
                    });
                }
                if normal.try_normalize().is_none() {
                    return Err(SceneError::ZeroNormal { object: i });
                }
            }
            Geometry::Mesh(m) => {
                let nv = m.positions.len();
                let name = || m.name.clone();
                let counts = [
                    ("normals", m.normals.len()),
                    ("uvs", m.uvs.len()),
                    ("colors", m.colors.len()),
                ];
                for (attribute, n) in counts {
                    if n != 0 && n != nv {
                        return Err(SceneError::MeshAttributeCount {
                            object: i,
                            mesh: name(),
                            attribute,
                            count: n,
                            vertices: nv,
                        });
                    }
                }
                for (attribute, list) in [("position", &m.positions), ("normal", &m.normals)] {
                    if let Some(v) = list.iter().position(|p| !p.is_finite()) {
                        return Err(SceneError::MeshNotFinite {
                            object: i,
                            mesh: name(),
                            attribute,
                            vertex: v,
                        });
                    }
                }
                if let Some(v) = m.colors.iter().position(|c| !color_ok(*c)) {
                    return Err(SceneError::MeshNotFinite {
                        object: i,
                        mesh: name(),
                        attribute: "colour (or a negative one)",
                        vertex: v,
                    });
                }
                for (t, tri) in m.triangles.iter().enumerate() {
                    if let Some(&index) = tri.iter().find(|&&k| k as usize >= nv) {
                        return Err(SceneError::MeshIndexOutOfRange {
                            object: i,
                            mesh: name(),
                            triangle: t,
                            index,
                            vertices: nv,
                        });
                    }
                }
                all_spheres = false;
                count += m.triangles.len();
            }
        }
    }
    if let Some(set) = set {
        check_set(scene, set)?;
        count += set.spheres.len();
    }
    if count > u32::MAX as usize {
        return Err(SceneError::TooManyPrimitives { count });
    }
    Ok((count, all_spheres))
}

fn check_set(scene: &Scene, set: &SphereSet) -> Result<(), SceneError> {
    let object = scene.objects.len();
    if set.material as usize >= scene.materials.len() {
        return Err(SceneError::MaterialOutOfRange {
            object,
            material: set.material,
            count: scene.materials.len(),
        });
    }
    if !set.colors.is_empty() && set.colors.len() != set.spheres.len() {
        return Err(SceneError::SphereSetColors {
            colors: set.colors.len(),
            spheres: set.spheres.len(),
        });
    }
    // Branch-free tests (`&`, not `&&`), so that one pass over a million
    // spheres vectorises; the loop naming the first bad one runs only when
    // there is one.
    let center_ok =
        |s: &Sphere| s.center.x.is_finite() & s.center.y.is_finite() & s.center.z.is_finite();
    let radius_ok = |s: &Sphere| (s.radius > 0.0) & s.radius.is_finite();
    if !set
        .spheres
        .iter()
        .fold(true, |ok, s| ok & center_ok(s) & radius_ok(s))
    {
        for (i, s) in set.spheres.iter().enumerate() {
            if !center_ok(s) {
                return Err(SceneError::NotFinite {
                    object: object + i,
                    what: "sphere centre",
                });
            }
            if !radius_ok(s) {
                return Err(SceneError::BadRadius {
                    object: object + i,
                    radius: to_f64(s.radius),
                });
            }
        }
    }
    if !set.colors.iter().fold(true, |ok, &c| ok & color_ok(c)) {
        return Err(SceneError::BadMaterial {
            material: set.material as usize,
            reason: "a sphere-set colour is negative or not finite",
        });
    }
    Ok(())
}

/// The material with its colour left out, for materials whose colour a
/// per-primitive colour may replace (`None` for the others).
fn uncolored(m: &Material) -> Option<Material> {
    let mut m = m.clone();
    match &mut m {
        Material::Matte { color, .. }
        | Material::Phong { color, .. }
        | Material::Reflective { color, .. } => *color = Rgb::ZERO,
        Material::Dielectric { .. } | Material::Emissive { .. } => return None,
    }
    Some(m)
}

/// The albedo of a material, as a per-primitive colour table records it.
pub(crate) fn albedo(m: &Material) -> Rgb {
    match *m {
        Material::Matte { color, .. }
        | Material::Phong { color, .. }
        | Material::Reflective { color, .. } => color,
        Material::Dielectric { .. } | Material::Emissive { .. } => Rgb::ONE,
    }
}

/// Materials, lights and background for shading.
fn shading_data(scene: &Scene, plan: &EffectPlan) -> SceneData {
    let mut data = SceneData {
        materials: scene.materials.clone(),
        background: scene.settings.background,
        max_depth: plan.max_depth,
        path_depth: scene.settings.path_max_depth,
        ..SceneData::default()
    };
    for l in &scene.lights {
        match *l {
            Light::Ambient { color, intensity } => data.ambient += color * intensity,
            Light::Point {
                position,
                color,
                intensity,
                inverse_square,
                shadows,
            } => data.lights.push(DirectLight::Point {
                position,
                radiance: color * intensity,
                inverse_square,
                shadows: shadows && plan.shadows,
            }),
            Light::Directional {
                direction,
                color,
                intensity,
                shadows,
            } => data.lights.push(DirectLight::Directional {
                dir: direction.normalize(),
                radiance: color * intensity,
                shadows: shadows && plan.shadows,
            }),
            Light::Spot {
                position,
                direction,
                color,
                intensity,
                inner_deg,
                outer_deg,
                inverse_square,
                shadows,
            } => data.lights.push(DirectLight::Spot {
                position,
                axis: direction.normalize(),
                radiance: color * intensity,
                cos_inner: Real::from(inner_deg).to_radians().cos(),
                cos_outer: Real::from(outer_deg).to_radians().cos(),
                inverse_square,
                shadows: shadows && plan.shadows,
            }),
            Light::Rect {
                corner,
                edge_u,
                edge_v,
                color,
                intensity,
            } => {
                let material = data.materials.len() as u32;
                if let Some(l) = AreaLight::rect(corner, edge_u, edge_v, material) {
                    data.materials.push(Material::Emissive {
                        color,
                        strength: intensity,
                    });
                    data.area_lights.push(l);
                }
            }
            Light::Disk {
                center,
                normal,
                radius,
                color,
                intensity,
            } => {
                let material = data.materials.len() as u32;
                if let Some(l) = AreaLight::disk(center, normal, radius, material) {
                    data.materials.push(Material::Emissive {
                        color,
                        strength: intensity,
                    });
                    data.area_lights.push(l);
                }
            }
            // Set up below, once the plan says it is in use.
            Light::Environment { .. } => {}
        }
    }
    if plan.environment {
        for l in &scene.lights {
            if let Light::Environment {
                color,
                intensity,
                ref image,
            } = *l
            {
                data.env = Some(Environment::new(color * intensity, image.clone()));
            }
        }
    }
    if plan.light_sampling {
        for l in &mut data.area_lights {
            let radiance = match data.materials[l.material as usize] {
                Material::Emissive { color, strength } => color * strength,
                _ => Rgb::ZERO,
            };
            l.emitter = data
                .emitters
                .push_shape(l.emitter_shape(), radiance)
                .unwrap_or(u32::MAX);
        }
    }
    if plan.direct_lights == 0 {
        // Nothing reacts to them: no light loop at all.
        data.lights.clear();
    }
    // Lights of zero radiance only cost time.
    data.lights.retain(|l| l.radiance() != Rgb::ZERO);

    data
}

/// The scene's textures as shading reads them.
fn texture_data(scene: &Scene, footprint: [f32; 2]) -> TextureData {
    let t = &scene.textures;
    let maps: Vec<_> = (0..scene.materials.len())
        .map(|i| t.maps.get(i).filter(|m| m.is_active()).cloned())
        .collect();
    let alpha = maps
        .iter()
        .flatten()
        .any(|m| m.alpha_mode != crate::texture::AlphaMode::Opaque);
    TextureData {
        list: t.list.clone(),
        maps,
        footprint,
        alpha,
    }
}

/// The emitted radiance of a material (zero for non-emitters).
fn emission(m: &Material) -> Rgb {
    match *m {
        Material::Emissive { color, strength } => color * strength,
        _ => Rgb::ZERO,
    }
}

/// Adds primitive `prim` to the area lights when its material emits.
fn add_emitter(data: &mut SceneData, prim: usize, shape: &Shape, material: u32) {
    let radiance = data
        .materials
        .get(material as usize)
        .map_or(Rgb::ZERO, emission);
    if radiance == Rgb::ZERO {
        return;
    }
    let shape = match *shape {
        Shape::Triangle(t) | Shape::MtTriangle(crate::shapes::MtTriangle(t)) => {
            let [p0, p1, p2] = t.vertices();
            let (e1, e2) = (p1 - p0, p2 - p0);
            let Some(n) = e1.cross(e2).try_normalize() else {
                return;
            };
            EmitterShape::Triangle { p0, e1, e2, n }
        }
        Shape::Sphere(sp) => EmitterShape::Sphere {
            center: sp.center,
            radius: sp.radius,
        },
        // Boxes are not sampled; paths that hit them still see their light.
        Shape::Cuboid(_) => return,
    };
    data.emitters.push(prim, shape, radiance);
}

/// A mesh's shading data: its normals, and its texture coordinates with
/// each triangle's texture frame when `uvs`.
fn mesh_shading(m: &crate::scene::Mesh, uvs: bool) -> MeshShading {
    let (uv, frames) = if uvs {
        let frames = m
            .triangles
            .iter()
            .map(|t| {
                let p = t.map(|k| m.positions[k as usize]);
                TriFrame::new(p, t.map(|k| m.uvs[k as usize]))
            })
            .collect();
        (m.uvs.clone(), frames)
    } else {
        (Vec::new(), Vec::new())
    };
    MeshShading {
        normals: m.normals.clone(),
        colors: m.colors.clone(),
        triangles: m.triangles.clone(),
        uvs: uv,
        frames,
    }
}

/// Fills `data` with the primitives' materials and returns the primitives.
fn convert(
    scene: &Scene,
    set: Option<SphereSet>,
    count: usize,
    all_spheres: bool,
    sample_lights: bool,
    data: &mut SceneData,
) -> Prims {
    let set_material = set.as_ref().map(|s| s.material);
    let set_len = set.as_ref().map_or(0, |s| s.spheres.len());
    let mut set_colors = set.as_ref().is_some_and(|s| !s.colors.is_empty());
    // One material for every primitive: no per-primitive table.
    let materials = || {
        scene
            .objects
            .iter()
            .filter(|o| !matches!(o.geometry, Geometry::Plane { .. }))
            .map(|o| o.material)
            .chain(set_material.filter(|_| set_len > 0))
    };
    let first = materials().next();
    let mut uniform = match first {
        None => Some(0),
        Some(first) => materials().all(|m| m == first).then_some(first),
    };
    // Materials that differ only in their colour (a million matte spheres
    // in random colours, as `RandomSpheres` makes them) become one material
    // and a colour per primitive, as a `SphereSet`'s: shading then reads
    // one small colour per hit instead of a material id and a material.
    // Textured materials keep their identity (their maps differ).
    let textured = data.tex.maps.iter().any(Option::is_some);
    let recolor = uniform.is_none() && !textured && {
        let key = |m: MaterialId| uncolored(&scene.materials[m as usize]);
        first
            .and_then(key)
            .is_some_and(|k| materials().all(|m| key(m).as_ref() == Some(&k)))
    };
    if recolor {
        uniform = first;
        set_colors = true;
    }
    let mut per_prim = Vec::new();
    if uniform.is_none() {
        per_prim.reserve(count);
    }
    let mut albedos = Vec::new();
    if set_colors && count > set_len {
        albedos.reserve(count);
    }
    let smooth = textured
        || scene
            .objects
            .iter()
            .any(|o| matches!(&o.geometry, Geometry::Mesh(m) if !m.normals.is_empty() || !m.colors.is_empty()));
    let mut record = |material: u32, mesh: MeshRef, data: &mut SceneData| {
        if uniform.is_none() {
            per_prim.push(material);
        }
        if set_colors {
            albedos.push(albedo(&scene.materials[material as usize]));
        }
        if smooth {
            data.prim_mesh.push(mesh);
        }
    };
    for o in &scene.objects {
        if let Geometry::Plane { point, normal } = o.geometry {
            data.planes.push(Plane::new(point, normal));
            data.plane_material.push(o.material);
        }
    }
    let prims = if all_spheres {
        let mut spheres = Vec::with_capacity(count - set_len);
        for o in &scene.objects {
            if let Geometry::Sphere { center, radius } = o.geometry {
                let sphere = Sphere::new(center, radius);
                if sample_lights {
                    add_emitter(data, spheres.len(), &Shape::Sphere(sphere), o.material);
                }
                spheres.push(sphere);
                record(o.material, MeshRef::NONE, data);
            }
        }
        if let Some(set) = set {
            // Take the set's vectors as they are when nothing comes before
            // them: no copy of a million spheres.
            if spheres.is_empty() {
                spheres = set.spheres;
            } else {
                spheres.extend_from_slice(&set.spheres);
            }
            if albedos.is_empty() {
                albedos = set.colors;
            } else {
                albedos.extend_from_slice(&set.colors);
            }
            if uniform.is_none() {
                per_prim.resize(count, set.material);
            }
        }
        Prims::Spheres(spheres)
    } else {
        let mut shapes = Vec::with_capacity(count);
        for o in &scene.objects {
            match &o.geometry {
                Geometry::Sphere { center, radius } => {
                    let shape = Shape::from(Sphere::new(*center, *radius));
                    if sample_lights {
                        add_emitter(data, shapes.len(), &shape, o.material);
                    }
                    shapes.push(shape);
                    record(o.material, MeshRef::NONE, data);
                }
                Geometry::Cuboid { min, max } => {
                    shapes.push(Cuboid::new(*min, *max).into());
                    record(o.material, MeshRef::NONE, data);
                }
                Geometry::Plane { .. } => {}
                Geometry::Mesh(m) => {
                    let uvs = textured && !m.uvs.is_empty() && data.tex.of(o.material).is_some();
                    let mesh_id = if m.normals.is_empty() && m.colors.is_empty() && !uvs {
                        u32::MAX
                    } else {
                        data.meshes.push(mesh_shading(m, uvs));
                        (data.meshes.len() - 1) as u32
                    };
                    for (t, &[a, b, c]) in m.triangles.iter().enumerate() {
                        let p = |k: u32| -> Vec3 { m.positions[k as usize] };
                        let tri = Triangle::new(p(a), p(b), p(c));
                        if tri.is_degenerate() {
                            continue;
                        }
                        let shape = Shape::from(tri);
                        if sample_lights {
                            add_emitter(data, shapes.len(), &shape, o.material);
                        }
                        shapes.push(shape);
                        let mesh = MeshRef {
                            mesh: mesh_id,
                            tri: t as u32,
                        };
                        record(o.material, mesh, data);
                    }
                }
            }
        }
        if let Some(set) = set {
            let n = set.spheres.len();
            shapes.extend(set.spheres.into_iter().map(Shape::from));
            albedos.extend_from_slice(&set.colors);
            if uniform.is_none() {
                per_prim.resize(per_prim.len() + n, set.material);
            }
            if smooth {
                data.prim_mesh
                    .resize(data.prim_mesh.len() + n, MeshRef::NONE);
            }
        }
        Prims::Shapes(shapes)
    };
    // A set without colours of its own after recoloured objects: its
    // material's colour.
    if let Some(m) = set_material.filter(|_| set_colors && albedos.len() < prims.len()) {
        albedos.resize(prims.len(), albedo(&scene.materials[m as usize]));
    }
    data.prim_material = match uniform {
        Some(m) => PrimMaterials::Uniform(m),
        None => PrimMaterials::PerPrim(per_prim),
    };
    data.prim_albedo = albedos;
    prims
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::PrimMaterials;
    use crate::suffern;

    /// Each object's albedo, as its own material gives it.
    fn own_albedos(scene: &Scene) -> Vec<Rgb> {
        let m = |o: &crate::Object| albedo(&scene.materials[o.material as usize]);
        scene.objects.iter().map(m).collect()
    }

    #[test]
    fn materials_differing_only_in_colour_become_one_and_colours() {
        let scene = suffern::scene(50);
        let first = scene.objects[0].material;
        assert!(scene.objects.iter().any(|o| o.material != first));
        let p = prepare(&scene, None).unwrap();
        assert!(matches!(p.data.prim_material, PrimMaterials::Uniform(m) if m == first));
        assert_eq!(p.data.prim_albedo, own_albedos(&scene));

        // A set without colours after them takes its material's colour.
        let set = SphereSet {
            spheres: suffern::sphere_set(7, 3).spheres,
            colors: Vec::new(),
            material: first + 1,
        };
        let p = prepare(&scene, Some(set)).unwrap();
        let mut want = own_albedos(&scene);
        want.resize(57, albedo(&scene.materials[first as usize + 1]));
        assert_eq!(p.data.prim_albedo, want);
        assert!(matches!(p.data.prim_material, PrimMaterials::Uniform(m) if m == first));
    }

    #[test]
    fn materials_differing_otherwise_keep_their_table() {
        let mut scene = suffern::scene(50);
        let last = scene.objects[49].material as usize;
        if let Material::Matte { ka, .. } = &mut scene.materials[last] {
            *ka = 0.5;
        }
        let p = prepare(&scene, None).unwrap();
        let ids: Vec<u32> = scene.objects.iter().map(|o| o.material).collect();
        assert!(matches!(&p.data.prim_material, PrimMaterials::PerPrim(v) if *v == ids));
        assert!(p.data.prim_albedo.is_empty());
    }
}
