//! Scenes without a scene file: a model rendered on its own (its camera or
//! one that frames it, its lights or default ones), and the command line's
//! overrides of the image size and sample count.

use crate::error::{Error, Result};
use crate::model::{self, to_dvec3, to_vec3, Model};
use crate::model_view;
use crate::scene::LoadedScene;
use crate::schema;
use glam::DVec3;
use gridrt_bbox::{Aabb, Real, Vec3};
use gridrt_tracer::{
    Camera, Geometry, Material, MaterialId, Object, Projection, Rgb, Scene, Settings, Textures,
};

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
        lens: None,
    }
}

/// A model's mesh as rendered on its own: oriented, and smooth where the
/// file has no normals (crease angle [`model::DEFAULT_CREASE_DEG`]).
fn smoothed(mm: model::ModelMesh) -> gridrt_tracer::Mesh {
    let mut mesh = mm.oriented();
    model::Normals::Smooth(model::Crease(model::DEFAULT_CREASE_DEG)).apply(&mut mesh);
    mesh
}

/// Default image width of a model rendered on its own.
const MODEL_WIDTH: u32 = 640;
/// Default image height of a model rendered on its own.
const MODEL_HEIGHT: u32 = 480;
/// Default samples per pixel of a model rendered on its own: a 3 × 3
/// stratified pattern, enough for smooth edges.
const MODEL_SPP: u32 = 9;

/// A scene that shows a model on its own: the file's camera (or one framing
/// the model's bounds), the file's lights (or an ambient light plus a
/// directional light from over the camera's shoulder, with shadows), the
/// file's materials, 640×480 (or the file camera's aspect ratio), 1 spp.
#[must_use]
pub fn scene_from_model(model: Model) -> LoadedScene {
    let (width, height) = match model.cameras.first().and_then(|c| c.aspect) {
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
    let framed = model.cameras.is_empty();
    let bounds = model.bounds();
    let aspect = f64::from(width) / f64::from(height);
    let room = if framed {
        model_view::room_opening(&model)
    } else {
        None
    };
    let camera = match (model.cameras.first(), room) {
        (Some(c), _) => c.camera.clone(),
        (None, Some(open)) => model_view::room_camera(bounds, open, aspect),
        (None, None) => frame(bounds, 40.0, aspect),
    };
    // The model is taken apart from here on: its meshes are moved into the
    // scene, not copied.
    let Model {
        path,
        meshes,
        materials: named,
        cameras,
        lights,
        textures,
        warnings,
    } = model;
    let mut materials: Vec<Material> = named.iter().map(|m| m.material.clone()).collect();
    let default_id = materials.len() as MaterialId;
    let mut need_default = false;
    let mut material_of = |k: Option<usize>| {
        k.map_or_else(
            || {
                need_default = true;
                default_id
            },
            |k| k as MaterialId,
        )
    };
    // Shared meshes are smoothed once each, then placed.
    let smooth = model::Normals::Smooth(model::Crease(model::DEFAULT_CREASE_DEG));
    let mut once = model::AppliedCache::new();
    let mut objects: Vec<Object> = meshes
        .into_iter()
        .map(|mm| Object {
            material: material_of(mm.material),
            geometry: match mm.placement {
                Some(p) => Geometry::Instance {
                    mesh: model::applied_once(&mut once, &mm.mesh, smooth),
                    to_world: Box::new(model::affine(&p)),
                },
                None => Geometry::Mesh(std::sync::Arc::new(smoothed(mm))),
            },
        })
        .collect();
    drop(once);
    if need_default {
        materials.push(model::default_material());
    }
    let lights = if !lights.is_empty() {
        lights
    } else if room.is_some() {
        model_view::room_lights(bounds)
    } else {
        model_view::object_lights(&camera)
    };
    if framed && room.is_none() {
        let (point, ground) = model_view::ground(bounds);
        objects.push(Object {
            geometry: Geometry::Plane {
                point,
                normal: Vec3::Y,
            },
            material: materials.len() as MaterialId,
        });
        materials.push(ground);
    }
    // The model's materials keep their indices: their maps do too.
    let textures = Textures {
        list: textures,
        maps: named.into_iter().map(|m| m.maps).collect(),
    };
    LoadedScene {
        scene: Scene {
            textures,
            camera,
            settings: Settings {
                width,
                height,
                spp: MODEL_SPP,
                max_depth: 5,
                background: Rgb::new(0.12, 0.13, 0.16),
                ..Settings::default()
            },
            materials,
            lights,
            objects,
        },
        source: path,
        warnings,
        framed_camera: framed,
        cameras: cameras.into_iter().map(|c| (c.name, c.camera)).collect(),
    }
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
