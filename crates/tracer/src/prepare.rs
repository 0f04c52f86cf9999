//! From a [`Scene`] to what the renderer runs: validation, the primitives
//! for the accelerator, and the shading data.

use crate::camera::CameraModel;
use crate::emitters::EmitterShape;
use crate::error::SceneError;
use crate::float::to_f64;
use crate::integrator::{DirectLight, MeshRef, MeshShading, PrimColors, PrimMaterials, SceneData};
use crate::lights::{AreaLight, Environment};
use crate::plan::{EffectPlan, IntegratorKind};
use crate::scene::{Geometry, Light, Material, Rgb, Scene, SphereSet};
use crate::shapes::{Cuboid, Plane, Shape, Sphere, Triangle};
use crate::texture::shade::{TextureData, TriFrame};
use gridrt_bbox::{Real, Vec3};
use std::sync::Arc;

/// The largest image, in pixels, the renderer accepts (8192 × 8192).
pub const MAX_PIXELS: u64 = 1 << 26;

/// The grid primitives of a scene: spheres only gets the compact type.
#[derive(Debug)]
pub(crate) enum Prims {
    Spheres(Vec<Sphere>),
    /// A scene's only primitives: one sphere set, shared with the scene
    /// (the grid copies each sphere once, straight into cell order).
    Set(Arc<SphereSet>),
    Shapes(Vec<Shape>),
}

impl Prims {
    pub(crate) fn len(&self) -> usize {
        match self {
            Prims::Spheres(v) => v.len(),
            Prims::Set(s) => s.spheres.len(),
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

/// Validates the scene and converts it. Triangles of zero area are left
/// out of the grid (they can never be hit).
pub(crate) fn prepare(scene: &Scene) -> Result<Prepared, SceneError> {
    let (count, all_spheres) = validate(scene)?;
    let s = &scene.settings;
    let camera = CameraModel::new(&scene.camera, s.width, s.height)?;
    let mut plan = EffectPlan::for_scene(scene);
    let mut data = shading_data(scene, &plan);
    data.tex = texture_data(scene, camera.footprint());
    let prims = convert(scene, count, all_spheres, plan.light_sampling, &mut data);
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
fn validate(scene: &Scene) -> Result<(usize, bool), SceneError> {
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
            Geometry::Spheres(set) => {
                check_set(i, set)?;
                count += set.spheres.len();
            }
        }
    }
    if count > u32::MAX as usize {
        return Err(SceneError::TooManyPrimitives { count });
    }
    Ok((count, all_spheres))
}

fn check_set(object: usize, set: &SphereSet) -> Result<(), SceneError> {
    if !set.colors.is_empty() && set.colors.len() != set.spheres.len() {
        return Err(SceneError::SphereSetColors {
            object,
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
        for (sphere, s) in set.spheres.iter().enumerate() {
            let bad = |reason| SceneError::BadSetSphere {
                object,
                sphere,
                reason,
            };
            if !center_ok(s) {
                return Err(bad("the centre is not finite; give finite coordinates"));
            }
            if !radius_ok(s) {
                return Err(bad("the radius must be finite and > 0"));
            }
        }
    }
    if !set.colors.iter().fold(true, |ok, &c| ok & color_ok(c)) {
        let sphere = set.colors.iter().position(|&c| !color_ok(c)).unwrap_or(0);
        return Err(SceneError::BadSetSphere {
            object,
            sphere,
            reason: "the colour must be finite and ≥ 0 in every channel",
        });
    }
    Ok(())
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

/// Fills `data` with the primitives' materials and returns the primitives:
/// each object's in turn (a sphere set's in the set's order, a mesh's in
/// triangle order without the degenerate ones).
fn convert(
    scene: &Scene,
    count: usize,
    all_spheres: bool,
    sample_lights: bool,
    data: &mut SceneData,
) -> Prims {
    // One material for every primitive: no per-primitive table.
    let materials = || {
        scene
            .objects
            .iter()
            .filter(|o| match &o.geometry {
                Geometry::Plane { .. } => false,
                Geometry::Spheres(set) => !set.spheres.is_empty(),
                _ => true,
            })
            .map(|o| o.material)
    };
    let uniform = match materials().next() {
        None => Some(0),
        Some(first) => materials().all(|m| m == first).then_some(first),
    };
    // Textured materials need the meshes' texture coordinates.
    let textured = data.tex.maps.iter().any(Option::is_some);
    // A colour per primitive as soon as one sphere set has colours.
    let colored = scene
        .objects
        .iter()
        .any(|o| matches!(&o.geometry, Geometry::Spheres(set) if !set.colors.is_empty()));
    let smooth = textured
        || scene.objects.iter().any(|o| {
            matches!(&o.geometry, Geometry::Mesh(m) if !m.normals.is_empty() || !m.colors.is_empty())
        });
    let mut per_prim = Vec::new();
    if uniform.is_none() {
        per_prim.reserve(count);
    }
    let mut albedos = Vec::new();
    if colored {
        albedos.reserve(count);
    }
    // The tables of `n` primitives of `material`, with `colors` (empty, or
    // one per primitive).
    let mut record = |material: u32, n: usize, colors: &[Rgb], data: &mut SceneData| {
        if uniform.is_none() {
            per_prim.resize(per_prim.len() + n, material);
        }
        if colored {
            if colors.is_empty() {
                let a = albedo(&data.materials[material as usize]);
                albedos.resize(albedos.len() + n, a);
            } else {
                albedos.extend_from_slice(colors);
            }
        }
        if smooth {
            data.prim_mesh
                .resize(data.prim_mesh.len() + n, MeshRef::NONE);
        }
    };
    for o in &scene.objects {
        if let Geometry::Plane { point, normal } = o.geometry {
            data.planes.push(Plane::new(point, normal));
            data.plane_material.push(o.material);
        }
    }
    // A scene whose primitives are all one sphere set's: the set as it is.
    let mut sources = scene.objects.iter().filter(|o| match &o.geometry {
        Geometry::Sphere { .. } => true,
        Geometry::Spheres(set) => !set.spheres.is_empty(),
        _ => false,
    });
    if let (true, Some(o), None) = (all_spheres, sources.next(), sources.next()) {
        if let Geometry::Spheres(set) = &o.geometry {
            if sample_lights {
                for (k, &sp) in set.spheres.iter().enumerate() {
                    add_emitter(data, k, &Shape::Sphere(sp), o.material);
                }
            }
            data.prim_material = PrimMaterials::Uniform(o.material);
            if !set.colors.is_empty() {
                data.prim_albedo = PrimColors::Set(Arc::clone(set));
            }
            return Prims::Set(Arc::clone(set));
        }
    }
    let prims = if all_spheres {
        let mut spheres: Vec<Sphere> = Vec::with_capacity(count);
        for o in &scene.objects {
            let first = spheres.len();
            match &o.geometry {
                Geometry::Sphere { center, radius } => {
                    spheres.push(Sphere::new(*center, *radius));
                    record(o.material, 1, &[], data);
                }
                Geometry::Spheres(set) => {
                    spheres.extend_from_slice(&set.spheres);
                    record(o.material, set.spheres.len(), &set.colors, data);
                }
                _ => {}
            }
            if sample_lights {
                for (k, &sp) in spheres.iter().enumerate().skip(first) {
                    add_emitter(data, k, &Shape::Sphere(sp), o.material);
                }
            }
        }
        Prims::Spheres(spheres)
    } else {
        let mut shapes: Vec<Shape> = Vec::with_capacity(count);
        for o in &scene.objects {
            let first = shapes.len();
            match &o.geometry {
                Geometry::Sphere { center, radius } => {
                    shapes.push(Sphere::new(*center, *radius).into());
                    record(o.material, 1, &[], data);
                }
                Geometry::Spheres(set) => {
                    shapes.extend(set.spheres.iter().map(|&sp| Shape::from(sp)));
                    record(o.material, set.spheres.len(), &set.colors, data);
                }
                Geometry::Cuboid { min, max } => {
                    shapes.push(Cuboid::new(*min, *max).into());
                    record(o.material, 1, &[], data);
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
                        shapes.push(Shape::from(tri));
                        record(o.material, 1, &[], data);
                        if smooth {
                            if let Some(last) = data.prim_mesh.last_mut() {
                                *last = MeshRef {
                                    mesh: mesh_id,
                                    tri: t as u32,
                                };
                            }
                        }
                    }
                }
            }
            if sample_lights {
                for (k, shape) in shapes.iter().enumerate().skip(first) {
                    add_emitter(data, k, shape, o.material);
                }
            }
        }
        Prims::Shapes(shapes)
    };
    data.prim_material = match uniform {
        Some(m) => PrimMaterials::Uniform(m),
        None => PrimMaterials::PerPrim(per_prim),
    };
    data.prim_albedo = PrimColors::Own(albedos);
    prims
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::PrimMaterials;
    use crate::scene::Object;
    use crate::suffern;
    use std::sync::Arc;

    fn set_object(set: SphereSet, material: u32) -> Object {
        Object {
            geometry: Geometry::Spheres(Arc::new(set)),
            material,
        }
    }

    #[test]
    fn a_coloured_set_is_one_material_and_its_colours() {
        let scene = suffern::scene(50);
        let p = prepare(&scene).unwrap();
        assert!(matches!(p.data.prim_material, PrimMaterials::Uniform(0)));
        let Geometry::Spheres(set) = &scene.objects[0].geometry else {
            panic!("the benchmark is one sphere set");
        };
        assert_eq!(*p.data.prim_albedo, set.colors);
        // The set itself, shared with the scene: no copy.
        assert!(matches!(&p.prims, Prims::Set(s) if Arc::ptr_eq(s, set)));
    }

    #[test]
    fn objects_around_a_set_take_their_materials_colour() {
        let mut scene = suffern::scene(5);
        let red = Rgb::new(0.8, 0.1, 0.1);
        scene.materials.push(Material::Matte {
            color: red,
            ka: 0.25,
            kd: 0.75,
        });
        let sphere = |x| Object {
            geometry: Geometry::Sphere {
                center: Vec3::new(x, 0.0, 0.0),
                radius: 0.5,
            },
            material: 1,
        };
        scene.objects.insert(0, sphere(-3.0));
        // A set without colours takes its material's.
        let plain = SphereSet {
            spheres: suffern::sphere_set(3, 7).spheres,
            colors: Vec::new(),
        };
        scene.objects.push(set_object(plain, 1));
        let p = prepare(&scene).unwrap();
        let Geometry::Spheres(set) = &scene.objects[1].geometry else {
            panic!("object 1 is the benchmark's set");
        };
        let mut want = vec![red];
        want.extend_from_slice(&set.colors);
        want.extend([red; 3]);
        assert_eq!(*p.data.prim_albedo, want);
        let mut ids = vec![1];
        ids.extend([0; 5]);
        ids.extend([1; 3]);
        assert!(matches!(&p.data.prim_material, PrimMaterials::PerPrim(v) if *v == ids));
        assert_eq!(p.prims.len(), 9);
    }

    #[test]
    fn uncoloured_scenes_keep_no_colour_table() {
        let mut scene = suffern::scene(0);
        scene.objects.push(set_object(
            SphereSet {
                spheres: suffern::sphere_set(4, 3).spheres,
                colors: Vec::new(),
            },
            0,
        ));
        let p = prepare(&scene).unwrap();
        assert!(p.data.prim_albedo.is_empty());
        assert!(matches!(p.data.prim_material, PrimMaterials::Uniform(0)));
        assert_eq!(p.prims.len(), 4);
    }
}
