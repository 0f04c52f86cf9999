//! What a scene asks for that the rest of it makes impossible: requests the
//! renderer ignores, each with the reason and what to change. A scene
//! reader shows them as warnings; the image is the same with or without
//! the ignored request.

use crate::plan::{EffectPlan, IntegratorKind};
use crate::sampling::Filter;
use crate::scene::{Geometry, Light, Material, Rgb, Scene};

/// Where in a scene an ignored request sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Where {
    /// `scene.lights[i]`.
    Light(usize),
    /// `scene.objects[i]`.
    Object(usize),
    /// A field of the settings, by its scene-file name.
    Setting(&'static str),
    /// The scene as a whole.
    Scene,
}

/// A request of a scene that has no effect on the image, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Ignored {
    /// What is ignored.
    pub at: Where,
    /// Why, and what to change (a sentence, no trailing period).
    pub message: String,
}

/// The requests of `scene` that cannot have an effect, in scene order
/// (lights, objects, settings). Empty for a scene whose every part plays
/// its role. They follow the effect plan ([`EffectPlan::for_scene`]):
///
/// - `Ambient` lights under the path tracer, which gathers no ambient
///   light (its indirect light takes that role);
/// - ambient occlusion on an ambient light that is black, or that no
///   material in use takes (no ambient term: `ka = 0` everywhere);
/// - emissive boxes and planes under the Whitted tracer: they glow but are
///   not sampled as lights, so they light nothing;
/// - `max_depth: 0` with mirrors, glass or metals in use: every ray ends
///   at its first hit, so they show no reflection or refraction;
/// - a reconstruction filter at 1 sample per pixel, where the sample goes
///   through the pixel centre and no filter weight is computed;
/// - objects with neither a light nor an emissive object to light them:
///   their materials are never seen, only black (and the background).
#[must_use]
pub fn ignored_effects(scene: &Scene) -> Vec<Ignored> {
    let plan = EffectPlan::for_scene(scene);
    let path = plan.integrator == IntegratorKind::Path;
    let mut out = Vec::new();
    let mut say = |at, message: String| out.push(Ignored { at, message });
    for (i, l) in scene.lights.iter().enumerate() {
        if let Light::Ambient {
            color,
            intensity,
            occlusion,
        } = *l
        {
            let black = color * intensity == Rgb::ZERO;
            let what = if occlusion.is_some() {
                "an Ambient light and its occlusion"
            } else {
                "an Ambient light"
            };
            if path && !black {
                say(Where::Light(i), format!("the path tracer does not use {what}: its indirect light takes the place of ambient light; use `integrator: Whitted` for ambient light and ambient occlusion"));
            } else if occlusion.is_some() && black {
                say(Where::Light(i), "occlusion on a black ambient light (intensity 0 or colour black) is never computed: give it an intensity, or remove the occlusion".into());
            } else if occlusion.is_some() && !path && !plan.ambient {
                say(Where::Light(i), "no material in use has an ambient term (`ka` > 0 on Matte, Phong or Reflective, or a MetallicRoughness that is not fully metallic), so the occlusion is never computed: give a material `ka` > 0".into());
            }
        }
    }
    let emissive = |o: &crate::scene::Object| {
        scene.materials.get(o.material as usize).is_some_and(
            |m| matches!(*m, Material::Emissive { color, strength } if color * strength != Rgb::ZERO),
        )
    };
    if !path {
        for (i, o) in scene.objects.iter().enumerate() {
            let kind = match o.geometry {
                Geometry::Cuboid { .. } => "Box",
                Geometry::Plane { .. } => "Plane",
                _ => continue,
            };
            if emissive(o) {
                say(Where::Object(i), format!("an emissive {kind} glows but is not sampled as a light, so the Whitted tracer lights nothing with it: use a Rect or Disk light, an emissive Sphere or Mesh, or `integrator: Path`"));
            }
        }
    }
    let depth = if path {
        scene.settings.path_max_depth
    } else {
        scene.settings.max_depth
    };
    if depth == 0 && crate::plan::uses_secondary_rays(scene) {
        say(Where::Setting("max_depth"), "`max_depth: 0` ends every ray at its first hit, so mirrors, glass and metals in use show no reflection or refraction (glass is black): raise max_depth".into());
    }
    if scene.lights.is_empty() && !scene.objects.is_empty() && !scene.objects.iter().any(emissive) {
        say(Where::Scene, "nothing lights the objects (no light and no emissive object), so they render black against the background: add a light or an Emissive material".into());
    }
    if scene.settings.spp == 1 && scene.settings.filter != Filter::Box {
        say(Where::Setting("filter"), format!("at 1 sample per pixel the sample goes through the pixel centre, so the {} filter is not used: raise spp (or `--spp`) for filtered antialiasing", scene.settings.filter.describe()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Camera, IntegratorChoice, Object, Occlusion, Projection, Settings};
    use gridrt_bbox::{Real, Vec3};

    fn scene(materials: Vec<Material>, lights: Vec<Light>) -> Scene {
        Scene {
            textures: Default::default(),
            camera: Camera {
                eye: Vec3::new(0.0, 1.0, 5.0),
                look_at: Vec3::ZERO,
                up: Vec3::Y,
                projection: Projection::Perspective { vfov_deg: 40.0 },
                lens: None,
            },
            settings: Settings::default(),
            materials,
            lights,
            objects: vec![
                Object {
                    geometry: Geometry::Sphere {
                        center: Vec3::ZERO,
                        radius: 1.0,
                    },
                    material: 0,
                },
                Object {
                    geometry: Geometry::Plane {
                        point: Vec3::ZERO,
                        normal: Vec3::Y,
                    },
                    material: 0,
                },
            ],
        }
    }

    fn matte(ka: f32) -> Material {
        Material::Matte {
            color: Rgb::splat(0.5),
            ka,
            kd: 0.8,
        }
    }

    fn ambient(intensity: f32, occluded: bool) -> Light {
        Light::Ambient {
            color: Rgb::ONE,
            intensity,
            occlusion: occluded.then_some(Occlusion {
                samples: 8,
                distance: Real::INFINITY,
                min_amount: 0.0,
            }),
        }
    }

    fn point() -> Light {
        Light::Point {
            position: Vec3::new(0.0, 5.0, 0.0),
            color: Rgb::ONE,
            intensity: 1.0,
            inverse_square: false,
            shadows: true,
        }
    }

    fn ats(s: &Scene) -> Vec<Where> {
        ignored_effects(s).into_iter().map(|i| i.at).collect()
    }

    #[test]
    fn a_scene_whose_parts_all_play_a_role_ignores_nothing() {
        let s = scene(vec![matte(0.2)], vec![ambient(0.5, true), point()]);
        assert_eq!(ignored_effects(&s), vec![]);
        assert!(EffectPlan::for_scene(&s).ambient_occlusion);
    }

    #[test]
    fn occlusion_that_cannot_run_is_named() {
        // No ambient term anywhere.
        let s = scene(vec![matte(0.0)], vec![point(), ambient(0.5, true)]);
        assert_eq!(ats(&s), vec![Where::Light(1)]);
        // A black ambient light.
        let s = scene(vec![matte(0.2)], vec![ambient(0.0, true), point()]);
        assert_eq!(ats(&s), vec![Where::Light(0)]);
        // Plain ambient light without a taker is not a request for an effect.
        let s = scene(vec![matte(0.0)], vec![ambient(0.5, false), point()]);
        assert_eq!(ats(&s), vec![]);
    }

    #[test]
    fn the_path_tracer_names_ambient_lights_it_does_not_use() {
        for occluded in [false, true] {
            let mut s = scene(vec![matte(0.2)], vec![point(), ambient(0.5, occluded)]);
            s.settings.integrator = IntegratorChoice::Path;
            let i = ignored_effects(&s);
            assert_eq!(i.len(), 1, "{i:?}");
            assert_eq!(i[0].at, Where::Light(1));
            assert_eq!(i[0].message.contains("its occlusion"), occluded);
        }
    }

    #[test]
    fn an_environment_lights_both_integrators() {
        let env = Light::Environment {
            color: Rgb::ONE,
            intensity: 1.0,
            image: None,
        };
        let mut s = scene(vec![matte(0.2)], vec![env]);
        for integrator in [IntegratorChoice::Whitted, IntegratorChoice::Auto] {
            s.settings.integrator = integrator;
            assert_eq!(ats(&s), vec![], "{integrator:?}");
        }
    }

    #[test]
    fn emissive_boxes_and_planes_under_whitted_are_named() {
        let glow = Material::Emissive {
            color: Rgb::ONE,
            strength: 2.0,
        };
        let mut s = scene(vec![matte(0.2), glow], vec![point()]);
        s.objects[1].material = 1;
        s.settings.integrator = IntegratorChoice::Whitted;
        assert_eq!(ats(&s), vec![Where::Object(1)]);
        // The path tracer sees its light on paths that hit it.
        s.settings.integrator = IntegratorChoice::Path;
        assert_eq!(ats(&s), vec![]);
        // An emissive sphere is sampled: soft shadows under Whitted.
        s.settings.integrator = IntegratorChoice::Whitted;
        s.objects[1].material = 0;
        s.objects[0].material = 1;
        assert_eq!(ats(&s), vec![]);
    }

    #[test]
    fn depth_zero_with_glass_and_an_unused_filter_are_named() {
        let glass = Material::Dielectric {
            ior: 1.5,
            tint: Rgb::ONE,
        };
        let mut s = scene(vec![matte(0.2), glass], vec![point()]);
        s.settings.max_depth = 0;
        assert_eq!(ats(&s), vec![]);
        s.objects[0].material = 1;
        assert_eq!(ats(&s), vec![Where::Setting("max_depth")]);
        s.settings.max_depth = 1;
        s.settings.filter = Filter::Gaussian {
            radius: 1.5,
            sigma: 0.5,
        };
        assert_eq!(ats(&s), vec![Where::Setting("filter")]);
        s.settings.spp = 4;
        assert_eq!(ats(&s), vec![]);
    }

    #[test]
    fn objects_nothing_lights_are_named_but_emitters_light_them() {
        let glow = Material::Emissive {
            color: Rgb::ONE,
            strength: 2.0,
        };
        let mut s = scene(vec![matte(0.2), glow], vec![]);
        for integrator in [IntegratorChoice::Whitted, IntegratorChoice::Path] {
            s.settings.integrator = integrator;
            s.objects[0].material = 0;
            assert_eq!(ats(&s), vec![Where::Scene]);
            // An emissive sphere lights the scene (the lamp of a Cornell box).
            s.objects[0].material = 1;
            assert_eq!(ats(&s), vec![]);
        }
        // A light, or nothing to light, leaves nothing to say.
        s.objects[0].material = 0;
        s.lights = vec![point()];
        assert_eq!(ats(&s), vec![]);
        s.lights.clear();
        s.objects.clear();
        assert_eq!(ats(&s), vec![]);
    }
}
