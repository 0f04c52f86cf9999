//! The effect plan: which effects a scene calls for, worked out once before
//! rendering, and the ray counts that prove unused effects cost nothing.

use crate::sampling::{Filter, SamplerKind};
use crate::scene::{Geometry, IntegratorChoice, Light, Material, Scene};
use std::fmt;

/// Rays traced, by kind. Counted per tile and summed, so counting costs no
/// contended atomics.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct RayCounts {
    /// Primary rays, one per pixel sample.
    pub camera: u64,
    /// Occlusion rays towards lights.
    pub shadow: u64,
    /// Mirror and Fresnel reflection rays.
    pub reflection: u64,
    /// Rays refracted through dielectrics.
    pub refraction: u64,
    /// Shadow rays towards points sampled on area lights (path tracing).
    pub light_sample: u64,
    /// Rays sampled from a glossy lobe: Phong or microfacet (path tracing),
    /// rough microfacet surfaces (Whitted).
    pub glossy: u64,
    /// Diffuse bounce rays: indirect light (path tracing).
    pub indirect: u64,
    /// Occlusion rays of ambient lights with occlusion (Whitted).
    pub ambient_occlusion: u64,
}

impl RayCounts {
    /// All rays of every kind.
    #[inline]
    #[must_use]
    pub fn total(&self) -> u64 {
        self.camera
            + self.shadow
            + self.reflection
            + self.refraction
            + self.light_sample
            + self.glossy
            + self.indirect
            + self.ambient_occlusion
    }
}

impl std::ops::AddAssign for RayCounts {
    fn add_assign(&mut self, o: Self) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
        self.light_sample += o.light_sample;
        self.glossy += o.glossy;
        self.indirect += o.indirect;
        self.ambient_occlusion += o.ambient_occlusion;
    }
}

impl fmt::Display for RayCounts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} rays: {} camera, {} shadow, {} reflection, {} refraction",
            self.total(),
            self.camera,
            self.shadow,
            self.reflection,
            self.refraction
        )?;
        if self.light_sample + self.glossy + self.indirect > 0 {
            write!(
                f,
                ", {} light sample, {} glossy, {} indirect",
                self.light_sample, self.glossy, self.indirect
            )?;
        }
        if self.ambient_occlusion > 0 {
            write!(f, ", {} ambient occlusion", self.ambient_occlusion)?;
        }
        Ok(())
    }
}

/// The light transport algorithm a plan runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[non_exhaustive]
pub enum IntegratorKind {
    /// Camera rays and direct lighting only (Suffern's ray casting).
    RayCast,
    /// Ray casting plus recursive mirror reflection and refraction
    /// (Suffern's Whitted tracer).
    Whitted,
    /// Unidirectional path tracing with next-event estimation and MIS
    /// (global illumination).
    Path,
}

impl fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            IntegratorKind::RayCast => "ray casting",
            IntegratorKind::Whitted => "Whitted",
            IntegratorKind::Path => "path tracing",
        })
    }
}

/// What the renderer simulates for a scene: only the effects the scene
/// calls for ([`EffectPlan::for_scene`]). The renderer picks a specialised
/// (monomorphised) render loop from it once per render, so a disabled
/// effect has no per-ray cost, not even a branch.
///
/// New effects (area lights, depth of field, glossy reflection, path
/// tracing) become new fields here and new type parameters of the render
/// loop; the struct is `#[non_exhaustive]` so adding them breaks no user.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[non_exhaustive]
pub struct EffectPlan {
    /// The integrator.
    pub integrator: IntegratorKind,
    /// Samples per pixel.
    pub spp: u32,
    /// Whether samples are spread over the pixel (by `sampler`, weighted by
    /// `filter`); off at 1 spp, where the sample goes through the pixel
    /// centre and no filter weight is computed.
    pub jitter: bool,
    /// The sampler that places the samples.
    pub sampler: SamplerKind,
    /// The reconstruction filter (`Box` whenever `jitter` is off).
    pub filter: Filter,
    /// Whether some ambient light reaches a material with `ka > 0`.
    pub ambient: bool,
    /// Whether ambient occlusion rays are traced: the Whitted tracer, an
    /// ambient light with `occlusion` and non-zero radiance, and a material
    /// in use with an ambient term. Off: the ambient term is a constant
    /// and no occlusion code runs.
    pub ambient_occlusion: bool,
    /// Point and directional lights evaluated at each shading point (0 when
    /// no material reacts to direct light).
    pub direct_lights: u32,
    /// Of those, the lights that cast shadow rays: `shadows: true`, and the
    /// scene has geometry that can shadow (more than one object, or a mesh:
    /// a single convex shape never shadows itself).
    pub shadow_lights: u32,
    /// Whether any shadow ray is cast (`shadow_lights > 0`).
    pub shadows: bool,
    /// Whether some material in use reflects (a mirror with `kr > 0`, or a
    /// dielectric) and `max_depth > 0`.
    pub reflection: bool,
    /// Whether some material in use transmits (a dielectric) and
    /// `max_depth > 0`.
    pub refraction: bool,
    /// Longest chain of secondary rays: 0 without reflection and refraction,
    /// else the scene's `max_depth` (the path tracer's `path_max_depth`).
    pub max_depth: u32,
    /// Area lights sampled: emitting primitives (triangles of emissive
    /// meshes, emissive spheres) and rectangle and disk lights.
    pub area_lights: u32,
    /// Whether area lights are sampled: next-event estimation with MIS when
    /// path tracing, soft shadows (one light sample per shading point) in
    /// the Whitted tracer.
    pub light_sampling: bool,
    /// Whether some material in use has a glossy lobe whose directions are
    /// sampled: a Phong lobe or a rough microfacet lobe in the path tracer;
    /// a rough conductor, rough dielectric or glTF metallic-roughness
    /// material in the Whitted tracer (one glossy ray per hit).
    pub glossy: bool,
    /// Whether diffuse surfaces scatter indirect light (path tracing).
    pub indirect: bool,
    /// Whether an environment light (of non-zero radiance) replaces the
    /// background.
    pub environment: bool,
    /// Whether the environment's image is importance-sampled for light
    /// (path tracing with an image environment).
    pub env_sampling: bool,
    /// Whether camera rays start on a thin lens (a lens radius > 0): depth
    /// of field. Off: pinhole rays, and no lens sample is drawn.
    pub depth_of_field: bool,
}

impl EffectPlan {
    /// Works out the plan for a scene. Only materials some object uses
    /// count; lights of zero radiance count as absent. Material indices out
    /// of range are ignored here ([`crate::Renderer::new`] rejects them).
    #[must_use]
    pub fn for_scene(scene: &Scene) -> Self {
        let used = used_materials(scene);
        let in_use = || {
            scene
                .materials
                .iter()
                .zip(&used)
                .filter(|(_, &u)| u)
                .map(|(m, _)| m)
        };
        let lit = in_use().any(|m| match *m {
            Material::Matte { kd, .. } => kd != 0.0,
            Material::Phong { kd, ks, .. } | Material::Reflective { kd, ks, .. } => {
                kd != 0.0 || ks != 0.0
            }
            Material::Conductor { .. }
            | Material::RoughDielectric { .. }
            | Material::MetallicRoughness { .. } => true,
            Material::Dielectric { .. } | Material::Emissive { .. } => false,
        });
        let ambient_material = in_use().any(|m| match *m {
            Material::Matte { ka, color, .. }
            | Material::Phong { ka, color, .. }
            | Material::Reflective { ka, color, .. } => ka != 0.0 && color != crate::Rgb::ZERO,
            // glTF's material takes the ambient light on its diffuse part.
            Material::MetallicRoughness { base, metallic, .. } => {
                metallic < 1.0 && base != crate::Rgb::ZERO
            }
            Material::Dielectric { .. }
            | Material::RoughDielectric { .. }
            | Material::Conductor { .. }
            | Material::Emissive { .. } => false,
        });
        let reflects = in_use().any(reflects);
        let transmits = in_use().any(|m| {
            matches!(
                m,
                Material::Dielectric { .. } | Material::RoughDielectric { .. }
            )
        });
        // Microfacet lobes with a width (sampled directions, not mirrors).
        let microfacet = in_use().any(|m| match *m {
            Material::Conductor { roughness, .. } => {
                !crate::bsdf::microfacet::Ggx::from_roughness(roughness).smooth()
            }
            Material::RoughDielectric { .. } | Material::MetallicRoughness { .. } => true,
            _ => false,
        });
        // Rectangle and disk lights of non-zero radiance: surfaces that emit.
        let area_surfaces = scene
            .lights
            .iter()
            .filter(|l| match **l {
                Light::Rect {
                    color, intensity, ..
                }
                | Light::Disk {
                    color, intensity, ..
                } => color * intensity != crate::Rgb::ZERO,
                _ => false,
            })
            .count();
        let shapes: usize = scene
            .objects
            .iter()
            .map(|o| match &o.geometry {
                Geometry::Spheres(s) => s.spheres.len(),
                _ => 1,
            })
            .sum();
        let can_shadow = shapes + area_surfaces > 1
            || scene
                .objects
                .iter()
                .any(|o| matches!(o.geometry, Geometry::Mesh(_)));

        let mut ambient = false;
        let mut occluded_ambient = false;
        let mut direct_lights = 0;
        let mut shadow_lights = 0;
        for l in &scene.lights {
            match *l {
                Light::Ambient {
                    color,
                    intensity,
                    occlusion,
                } => {
                    let on = ambient_material && color * intensity != crate::Rgb::ZERO;
                    ambient |= on;
                    occluded_ambient |= on && occlusion.is_some();
                }
                Light::Point {
                    color,
                    intensity,
                    shadows,
                    ..
                }
                | Light::Directional {
                    color,
                    intensity,
                    shadows,
                    ..
                }
                | Light::Spot {
                    color,
                    intensity,
                    shadows,
                    ..
                } => {
                    if lit && color * intensity != crate::Rgb::ZERO {
                        direct_lights += 1;
                        if shadows && can_shadow {
                            shadow_lights += 1;
                        }
                    }
                }
                Light::Rect { .. } | Light::Disk { .. } | Light::Environment { .. } => {}
            }
        }
        let emits = |m: &Material| matches!(*m, Material::Emissive { color, strength } if color * strength != crate::Rgb::ZERO);
        // Emitting geometry that can be sampled (planes are unbounded).
        let emitting_geometry = scene.objects.iter().filter(|o| shows(o)).any(|o| {
            !matches!(o.geometry, Geometry::Plane { .. })
                && scene.materials.get(o.material as usize).is_some_and(emits)
        }) || area_surfaces > 0;
        let environment = scene.lights.iter().any(|l| {
            matches!(*l, Light::Environment { color, intensity, .. } if color * intensity != crate::Rgb::ZERO)
        });
        let path = match scene.settings.integrator {
            IntegratorChoice::Path => true,
            IntegratorChoice::Whitted => false,
            IntegratorChoice::Auto => emitting_geometry || environment,
        };
        if path {
            let glossy = in_use().any(|m| match *m {
                Material::Phong { ks, specular, .. } => ks != 0.0 && specular != crate::Rgb::ZERO,
                Material::Reflective { ks, .. } => ks != 0.0,
                _ => false,
            }) || microfacet;
            let indirect = in_use().any(|m| match *m {
                Material::Matte { color, kd, .. }
                | Material::Phong { color, kd, .. }
                | Material::Reflective { color, kd, .. } => kd != 0.0 && color != crate::Rgb::ZERO,
                Material::MetallicRoughness { base, metallic, .. } => {
                    metallic < 1.0 && base != crate::Rgb::ZERO
                }
                _ => false,
            });
            let mut plan = Self::path(
                scene,
                [emitting_geometry, reflects, transmits, glossy, indirect],
                direct_lights,
                shadow_lights,
            );
            plan.environment = environment;
            return plan;
        }
        let depth = scene.settings.max_depth;
        let reflection = reflects && depth > 0;
        let refraction = transmits && depth > 0;
        let secondary = reflection || refraction;
        Self {
            integrator: if secondary {
                IntegratorKind::Whitted
            } else {
                IntegratorKind::RayCast
            },
            spp: scene.settings.spp,
            jitter: scene.settings.spp > 1,
            sampler: scene.settings.sampler,
            filter: if scene.settings.spp > 1 {
                scene.settings.filter
            } else {
                Filter::Box
            },
            ambient,
            ambient_occlusion: occluded_ambient,
            direct_lights,
            shadow_lights,
            shadows: shadow_lights > 0,
            reflection,
            refraction,
            max_depth: if secondary { depth } else { 0 },
            area_lights: 0,
            // Soft shadows: area lights and the environment sampled at
            // every lit shading point.
            light_sampling: lit && (emitting_geometry || environment),
            // One sampled ray per hit on a rough microfacet surface.
            glossy: microfacet && reflection,
            indirect: false,
            environment,
            env_sampling: false,
            depth_of_field: scene.camera.lens.is_some_and(|l| l.radius > 0.0),
        }
    }

    /// The plan of the path tracer. Ambient light (with or without
    /// occlusion) is not used: the background is the environment's
    /// radiance.
    fn path(scene: &Scene, has: [bool; 5], direct_lights: u32, shadow_lights: u32) -> Self {
        let [emitting_geometry, reflects, transmits, glossy, indirect] = has;
        let depth = scene.settings.path_max_depth;
        Self {
            integrator: IntegratorKind::Path,
            spp: scene.settings.spp,
            jitter: scene.settings.spp > 1,
            sampler: scene.settings.sampler,
            filter: if scene.settings.spp > 1 {
                scene.settings.filter
            } else {
                Filter::Box
            },
            ambient: false,
            ambient_occlusion: false,
            direct_lights,
            shadow_lights,
            shadows: shadow_lights > 0,
            reflection: reflects && depth > 0,
            refraction: transmits && depth > 0,
            max_depth: depth,
            area_lights: 0,
            light_sampling: emitting_geometry && depth > 0,
            glossy: glossy && depth > 0,
            indirect: indirect && depth > 0,
            environment: false,
            env_sampling: false,
            depth_of_field: scene.camera.lens.is_some_and(|l| l.radius > 0.0),
        }
    }
}

/// Whether an object shows its material (an empty sphere set shows
/// nothing).
fn shows(o: &crate::Object) -> bool {
    !matches!(&o.geometry, Geometry::Spheres(s) if s.spheres.is_empty())
}

/// Which of the scene's materials some object shows.
fn used_materials(scene: &Scene) -> Vec<bool> {
    let mut used = vec![false; scene.materials.len()];
    for m in scene
        .objects
        .iter()
        .filter(|o| shows(o))
        .map(|o| o.material)
    {
        if let Some(u) = used.get_mut(m as usize) {
            *u = true;
        }
    }
    used
}

/// Whether a material sends secondary rays: mirror reflection, Fresnel
/// reflection and refraction, microfacet lobes.
fn reflects(m: &Material) -> bool {
    match *m {
        Material::Reflective { kr, reflect, .. } => kr != 0.0 && reflect != crate::Rgb::ZERO,
        Material::Dielectric { .. }
        | Material::RoughDielectric { .. }
        | Material::Conductor { .. }
        | Material::MetallicRoughness { .. } => true,
        _ => false,
    }
}

/// Whether some material in use would send secondary rays (reflection or
/// refraction) given a `max_depth` above 0.
pub(crate) fn uses_secondary_rays(scene: &Scene) -> bool {
    scene
        .materials
        .iter()
        .zip(used_materials(scene))
        .any(|(m, u)| u && reflects(m))
}

fn on_off(b: bool) -> &'static str {
    if b {
        "on"
    } else {
        "off"
    }
}

impl fmt::Display for EffectPlan {
    /// One effect per line, for the render summary.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "integrator  {} (max depth {})",
            self.integrator, self.max_depth
        )?;
        if self.jitter {
            writeln!(
                f,
                "samples     {} per pixel, {} sampler, {} filter",
                self.spp, self.sampler, self.filter
            )?;
        } else {
            writeln!(
                f,
                "samples     {} per pixel, pixel centre (no jitter)",
                self.spp
            )?;
        }
        writeln!(
            f,
            "lights      ambient {}{}, {} direct",
            on_off(self.ambient),
            if self.ambient_occlusion {
                " (occlusion rays)"
            } else {
                ""
            },
            self.direct_lights
        )?;
        writeln!(
            f,
            "shadows     {} ({} of {} lights cast shadow rays)",
            on_off(self.shadows),
            self.shadow_lights,
            self.direct_lights
        )?;
        if self.integrator == IntegratorKind::Path {
            writeln!(
                f,
                "area lights {} sampled ({})",
                self.area_lights,
                if self.light_sampling {
                    "next-event estimation, MIS"
                } else {
                    "off"
                }
            )?;
            writeln!(f, "indirect    {}", on_off(self.indirect))?;
            if self.environment {
                writeln!(
                    f,
                    "environment on ({})",
                    if self.env_sampling {
                        "image, importance-sampled"
                    } else {
                        "constant, reached by BSDF sampling"
                    }
                )?;
            }
            writeln!(f, "glossy      {}", on_off(self.glossy))?;
        }
        if self.integrator != IntegratorKind::Path && self.glossy {
            writeln!(f, "glossy      on (one sampled ray per rough hit)")?;
        }
        if self.integrator != IntegratorKind::Path && self.light_sampling {
            writeln!(f, "area lights {} sampled (soft shadows)", self.area_lights)?;
        }
        if self.integrator != IntegratorKind::Path && self.environment {
            writeln!(
                f,
                "environment {}",
                if self.env_sampling {
                    "on (sampled for light and shadows)"
                } else {
                    "background only (no surface takes light)"
                }
            )?;
        }
        if self.depth_of_field {
            writeln!(f, "lens        thin lens (depth of field)")?;
        }
        writeln!(f, "reflection  {}", on_off(self.reflection))?;
        write!(f, "refraction  {}", on_off(self.refraction))
    }
}
