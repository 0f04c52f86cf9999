//! The effect plan: which effects a scene calls for, worked out once before
//! rendering, and the ray counts that prove unused effects cost nothing.

use crate::sampling::{Filter, SamplerKind};
use crate::scene::{Geometry, Light, Material, Scene};
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
}

impl RayCounts {
    /// All rays of every kind.
    #[inline]
    #[must_use]
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.reflection + self.refraction
    }
}

impl std::ops::AddAssign for RayCounts {
    fn add_assign(&mut self, o: Self) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
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
        )
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
}

impl fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            IntegratorKind::RayCast => "ray casting",
            IntegratorKind::Whitted => "Whitted",
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
    /// else the scene's `max_depth`.
    pub max_depth: u32,
}

impl EffectPlan {
    /// Works out the plan for a scene. Only materials some object uses
    /// count; lights of zero radiance count as absent. Material indices out
    /// of range are ignored here ([`crate::Renderer::new`] rejects them).
    #[must_use]
    pub fn for_scene(scene: &Scene) -> Self {
        Self::derive(scene, None)
    }

    /// The plan for a scene plus `extra = (count, material)` spheres that are
    /// not in `scene.objects` (a [`crate::SphereSet`]).
    pub(crate) fn derive(scene: &Scene, extra: Option<(usize, u32)>) -> Self {
        let mut used = vec![false; scene.materials.len()];
        let extra = extra.filter(|e| e.0 > 0);
        for m in scene
            .objects
            .iter()
            .map(|o| o.material)
            .chain(extra.map(|e| e.1))
        {
            if let Some(u) = used.get_mut(m as usize) {
                *u = true;
            }
        }
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
            Material::Dielectric { .. } | Material::Emissive { .. } => false,
        });
        let ambient_material = in_use().any(|m| match *m {
            Material::Matte { ka, color, .. }
            | Material::Phong { ka, color, .. }
            | Material::Reflective { ka, color, .. } => ka != 0.0 && color != crate::Rgb::ZERO,
            Material::Dielectric { .. } | Material::Emissive { .. } => false,
        });
        let reflects = in_use().any(|m| match *m {
            Material::Reflective { kr, reflect, .. } => kr != 0.0 && reflect != crate::Rgb::ZERO,
            Material::Dielectric { .. } => true,
            _ => false,
        });
        let transmits = in_use().any(|m| matches!(m, Material::Dielectric { .. }));
        let can_shadow = scene.objects.len() + extra.map_or(0, |e| e.0) > 1
            || scene
                .objects
                .iter()
                .any(|o| matches!(o.geometry, Geometry::Mesh(_)));

        let mut ambient = false;
        let mut direct_lights = 0;
        let mut shadow_lights = 0;
        for l in &scene.lights {
            match *l {
                Light::Ambient { color, intensity } => {
                    ambient |= ambient_material && color * intensity != crate::Rgb::ZERO;
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
                } => {
                    if lit && color * intensity != crate::Rgb::ZERO {
                        direct_lights += 1;
                        if shadows && can_shadow {
                            shadow_lights += 1;
                        }
                    }
                }
            }
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
            direct_lights,
            shadow_lights,
            shadows: shadow_lights > 0,
            reflection,
            refraction,
            max_depth: if secondary { depth } else { 0 },
        }
    }
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
            "lights      ambient {}, {} direct",
            on_off(self.ambient),
            self.direct_lights
        )?;
        writeln!(
            f,
            "shadows     {} ({} of {} lights cast shadow rays)",
            on_off(self.shadows),
            self.shadow_lights,
            self.direct_lights
        )?;
        writeln!(f, "reflection  {}", on_off(self.reflection))?;
        write!(f, "refraction  {}", on_off(self.refraction))
    }
}
