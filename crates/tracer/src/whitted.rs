//! The Whitted integrator (Suffern's ray casting when it neither reflects
//! nor refracts), specialised at compile time on the effects of the plan.

use crate::bsdf::microfacet::Ggx;
use crate::bsdf::Micro;
use crate::float::to_f32;
use crate::occlusion::occluded_ambient;
use crate::optics::{fresnel_dielectric, reflect, refract};
use crate::sampling::maps::Frame;
use crate::sampling::SampleStream;
use crate::scene::{ConductorFresnel, Material, Rgb};
use crate::shapes::{Surface, SurfacePoint};
use gridrt_bbox::{gamma, Ray, Real, Vec3};
use gridrt_grid::Accelerator;
use std::f32::consts::FRAC_1_PI;

use crate::integrator::{DirectLight, Integrator, Li, Shading, ThreadState, Tracer};

/// Suffern's ray casting (`REFLECT = REFRACT = false`) and Whitted tracing.
/// `SHADOWS = false` removes shadow rays from the code, `REFLECT = false`
/// mirror reflection, `REFRACT = false` dielectrics, `AREA = false` the
/// sampling of area lights (soft shadows): the plan instantiates only the
/// combination the scene needs. `GLOSSY = false` removes the sampled
/// reflection (and transmission) rays of rough microfacet surfaces,
/// `AO = false` the occlusion rays of ambient lights with occlusion (the
/// ambient term is then a constant).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Whitted<
    const SHADOWS: bool,
    const REFLECT: bool,
    const REFRACT: bool,
    const AREA: bool,
    const GLOSSY: bool,
    const AO: bool,
>;

impl<
        const SHADOWS: bool,
        const REFLECT: bool,
        const REFRACT: bool,
        const AREA: bool,
        const GLOSSY: bool,
        const AO: bool,
    > Integrator for Whitted<SHADOWS, REFLECT, REFRACT, AREA, GLOSSY, AO>
{
    // Light, lobe and occlusion sampling draw from each pixel sample's
    // stream, which the render loop only hands out per sample.
    const BATCH: bool = !(AREA || GLOSSY || AO);
    const SAMPLED: bool = AREA || GLOSSY || AO;

    #[inline]
    fn li<A>(
        tr: &Tracer<'_, A>,
        ray: &Ray,
        depth: u32,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Li
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        let hit = tr
            .closest(ray, Real::INFINITY, &mut ts.scratch)
            .map(|f| tr.shading(ray, f));
        Self::shade(tr, ray, hit.as_ref(), depth, stream, ts)
    }

    fn shade<A>(
        tr: &Tracer<'_, A>,
        ray: &Ray,
        hit: Option<&Shading>,
        depth: u32,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Li
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        let Some(sh) = hit else {
            return Li {
                color: tr.data.miss(ray.dir),
                t: Real::INFINITY,
                hit: false,
            };
        };
        let t = sh.t;
        let wo = -ray.dir;
        let color = match tr.data.materials[sh.material as usize] {
            Material::Matte { color, ka, kd } => {
                let color = sh.albedo.unwrap_or(color);
                let (ng, ns) = face_forward(sh.sp.n, sh.ns, wo);
                Self::direct(
                    tr,
                    &sh.sp,
                    ng,
                    ns,
                    wo,
                    color * ka,
                    Brdf::Suffern {
                        diffuse: color * (kd * FRAC_1_PI),
                        spec: None,
                    },
                    stream,
                    ts,
                )
            }
            Material::Phong {
                color,
                ka,
                kd,
                ks,
                exp,
                specular,
            } => {
                let color = sh.albedo.unwrap_or(color);
                let (ng, ns) = face_forward(sh.sp.n, sh.ns, wo);
                let spec = Some((specular * ks, exp));
                Self::direct(
                    tr,
                    &sh.sp,
                    ng,
                    ns,
                    wo,
                    color * ka,
                    Brdf::Suffern {
                        diffuse: color * (kd * FRAC_1_PI),
                        spec,
                    },
                    stream,
                    ts,
                )
            }
            Material::Reflective {
                color,
                ka,
                kd,
                ks,
                exp,
                kr,
                reflect: cr,
            } => {
                let color = sh.albedo.unwrap_or(color);
                let (ng, ns) = face_forward(sh.sp.n, sh.ns, wo);
                // Suffern's Reflective extends Phong with a white highlight.
                let spec = (ks != 0.0).then_some((Rgb::splat(ks), exp));
                let mut l = Self::direct(
                    tr,
                    &sh.sp,
                    ng,
                    ns,
                    wo,
                    color * ka,
                    Brdf::Suffern {
                        diffuse: color * (kd * FRAC_1_PI),
                        spec,
                    },
                    stream,
                    ts,
                );
                if REFLECT && depth < tr.data.max_depth && kr != 0.0 {
                    let wr = on_side(reflect(wo, secondary_ns(ng, ns, wo)), ng, ns, true);
                    let origin = tr.data.ray_offset.origin(sh.sp.p, sh.sp.p_err, ng, wr);
                    ts.counts.reflection += 1;
                    l += cr * kr * Self::li(tr, &Ray::new(origin, wr), depth + 1, stream, ts).color;
                }
                l
            }
            Material::Dielectric { ior, tint } => {
                if REFRACT {
                    Self::dielectric(tr, sh, wo, ior, tint, depth, stream, ts)
                } else {
                    // The plan leaves refraction out only when max_depth is 0
                    // (or no dielectric is in use): glass is then black, as at
                    // the end of any ray tree.
                    Rgb::ZERO
                }
            }
            Material::Conductor { fresnel, roughness } => {
                let (ng, ns) = face_forward(sh.sp.n, sh.ns, wo);
                let micro = Micro::Conductor {
                    ggx: Ggx::from_roughness(roughness),
                    fresnel,
                };
                let frame = Frame::new(ns);
                let brdf = Brdf::Micro(micro, frame);
                Self::direct(tr, &sh.sp, ng, ns, wo, Rgb::ZERO, brdf, stream, ts)
                    + Self::micro_ray(tr, sh, &micro, frame, ng, wo, Rgb::ONE, depth, stream, ts)
            }
            Material::MetallicRoughness {
                base,
                metallic,
                roughness,
            } => {
                let (metallic, roughness) = sh.metal_rough.unwrap_or((metallic, roughness));
                let base = sh.albedo.unwrap_or(base);
                let (ng, ns) = face_forward(sh.sp.n, sh.ns, wo);
                let frame = Frame::new(ns);
                let micro = Micro::gltf(base, metallic, roughness, ns.dot(wo));
                let ambient = base * (1.0 - metallic);
                let brdf = Brdf::Micro(micro, frame);
                // Secondary rays follow the specular lobe only (Whitted
                // gathers no diffuse indirect light): a conductor with
                // Schlick's F0.
                let spec = Micro::Conductor {
                    ggx: Ggx::from_roughness(roughness),
                    fresnel: ConductorFresnel::Schlick {
                        f0: Rgb::splat(0.04).lerp(base, metallic),
                    },
                };
                Self::direct(tr, &sh.sp, ng, ns, wo, ambient, brdf, stream, ts)
                    + Self::micro_ray(tr, sh, &spec, frame, ng, wo, Rgb::ONE, depth, stream, ts)
            }
            Material::RoughDielectric {
                ior,
                tint,
                roughness,
            } => {
                let (ng, ns) = face_forward(sh.sp.n, sh.ns, wo);
                let glass = Micro::Glass {
                    ggx: Ggx::from_roughness(roughness),
                    eta: ior as Real,
                };
                // The outward frame: inside is below.
                let frame = Frame::new(sh.ns);
                let brdf = Brdf::Micro(glass, frame);
                let mut l = Self::direct(tr, &sh.sp, ng, ns, wo, Rgb::ZERO, brdf, stream, ts);
                if REFRACT {
                    l += Self::micro_ray(tr, sh, &glass, frame, ng, wo, tint, depth, stream, ts);
                }
                l
            }
            // Emission is one-sided: the front face (where the geometric
            // normal points) glows, the back is black.
            Material::Emissive { color, strength } => {
                if sh.sp.n.dot(wo) > 0.0 {
                    color * strength
                } else {
                    Rgb::ZERO
                }
            }
        };
        Li {
            color: color + sh.emission,
            t,
            hit: true,
        }
    }
}

/// The BRDF that direct lighting evaluates at a hit.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Brdf {
    /// Suffern's: Lambert `diffuse` plus, with `spec = (ks·cs, exp)`, the
    /// glossy `ks·cs·(r·wo)^exp`.
    Suffern {
        diffuse: Rgb,
        spec: Option<(Rgb, f32)>,
    },
    /// A microfacet BSDF in the frame of the shading normal (its
    /// reflection; light is not gathered through transmission).
    Micro(Micro, Frame),
}

impl Brdf {
    /// Whether it reflects nothing.
    #[inline]
    fn is_black(&self) -> bool {
        matches!(*self, Brdf::Suffern { diffuse, spec: None } if diffuse == Rgb::ZERO)
    }

    /// `f(ωo, ωi)` for unit vectors and the shading normal `ns` (on
    /// `wo`'s side).
    #[inline]
    fn f(&self, wo: Vec3, wi: Vec3, ns: Vec3) -> Rgb {
        match *self {
            Brdf::Suffern { diffuse, spec } => {
                let mut f = diffuse;
                if let Some((ks, exp)) = spec {
                    let r = reflect(wi, ns);
                    let rdotwo = r.dot(wo);
                    if rdotwo > 0.0 {
                        f += ks * to_f32(rdotwo).powf(exp);
                    }
                }
                f
            }
            Brdf::Micro(m, frame) => m.eval(frame.to_local(wo), frame.to_local(wi)).0,
        }
    }
}

/// Turns the geometric normal to the side of `wo` and the shading normal
/// with it (opaque surfaces are two-sided).
#[inline]
pub(crate) fn face_forward(ng: Vec3, ns: Vec3, wo: Vec3) -> (Vec3, Vec3) {
    if ng.dot(wo) < 0.0 {
        (-ng, -ns)
    } else {
        (ng, ns)
    }
}

/// The shading normal for a secondary ray: `ns`, or `ng` when `wo` lies
/// below `ns` (a smooth normal tilted away from a grazing view), so that
/// the mirror direction is well defined. Both are on `wo`'s side of the
/// geometric surface.
#[inline]
fn secondary_ns(ng: Vec3, ns: Vec3, wo: Vec3) -> Vec3 {
    if ns.dot(wo) > 0.0 {
        ns
    } else {
        ng
    }
}

/// `w` on the given side of the geometric surface (`above`: the side `ng`
/// points to): unchanged when it is, else mirrored across the surface's
/// plane. A direction that a shading normal `ns` bends through the surface
/// would leak light from the other side; mirroring keeps it on the side
/// the reflection or refraction belongs to. Where `ns` is `ng` (flat
/// surfaces, spheres) the direction is on its side by construction, up to
/// rounding at grazing angles, and is left as it is.
#[inline]
pub(crate) fn on_side(w: Vec3, ng: Vec3, ns: Vec3, above: bool) -> Vec3 {
    if ns == ng {
        return w;
    }
    let c = w.dot(ng);
    if (c > 0.0) == above && c != 0.0 {
        return w;
    }
    let m = w - ng * (2.0 * c);
    // Grazing (c = 0): nudge off the plane to the wanted side.
    let m = if m.dot(ng) == 0.0 {
        m + if above { ng } else { -ng } * 1e-3
    } else {
        m
    };
    m.normalize()
}

/// The parameter end of a shadow ray towards a point sampled on an area
/// light at `t = 1`: short of it by a relative margin, so that the light's
/// own surface (whose sampled point carries rounding error) does not
/// occlude it.
pub(crate) const LIGHT_T_MAX: Real = 1.0 - 1e-4;

/// The parameter end of a shadow ray towards a point light at `t = 1`:
/// just short of it by a bound on the rounding of the ray (no fixed epsilon).
#[inline]
pub(crate) fn point_shadow_t_max() -> Real {
    1.0 - gamma(16)
}

impl<
        const SHADOWS: bool,
        const REFLECT: bool,
        const REFRACT: bool,
        const AREA: bool,
        const GLOSSY: bool,
        const AO: bool,
    > Whitted<SHADOWS, REFLECT, REFRACT, AREA, GLOSSY, AO>
{
    /// The secondary ray of a microfacet surface: the mirror of a smooth
    /// conductor (with `REFLECT`), or one direction sampled from a rough
    /// lobe (with `GLOSSY`), weighted by `f·|cos|/pdf`. `tint` is the
    /// absorption inside a dielectric (Beer's law over the traced segment).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn micro_ray<A>(
        tr: &Tracer<'_, A>,
        sh: &Shading,
        micro: &Micro,
        frame: Frame,
        ng: Vec3,
        wo: Vec3,
        tint: Rgb,
        depth: u32,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Rgb
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        if !REFLECT || depth >= tr.data.max_depth {
            return Rgb::ZERO;
        }
        // `smooth()`: some lobe has a width; else the BSDF is a delta.
        let delta = !micro.smooth() && !micro.transmits();
        let (uc, u) = if delta {
            // A delta mirror needs no random numbers.
            (0.0, (0.5, 0.5))
        } else if GLOSSY {
            (stream.next_2d().0, stream.next_2d())
        } else {
            return Rgb::ZERO;
        };
        let Some(s) = micro.sample(frame.to_local(wo), uc, u) else {
            return Rgb::ZERO;
        };
        let wi = frame.to_world(s.wi);
        if (ng.dot(wi) < 0.0) != s.transmitted {
            return Rgb::ZERO;
        }
        let weight = if s.delta {
            if s.transmitted {
                ts.counts.refraction += 1;
            } else {
                ts.counts.reflection += 1;
            }
            s.f
        } else {
            ts.counts.glossy += 1;
            s.f * to_f32(s.wi.z.abs() / s.pdf)
        };
        let origin = tr.data.ray_offset.origin(sh.sp.p, sh.sp.p_err, ng, wi);
        let ray = Ray::new(origin, wi);
        let li = if AREA && !s.delta {
            Self::li_unlit(tr, &ray, depth + 1, stream, ts)
        } else {
            Self::li(tr, &ray, depth + 1, stream, ts)
        };
        let inside = sh.sp.n.dot(wi) < 0.0;
        if inside && tint != Rgb::ONE {
            weight * li.color * tint.powf(to_f32(li.t))
        } else {
            weight * li.color
        }
    }

    /// [`Integrator::li`] for a ray sampled from a rough lobe while lights
    /// are sampled (`AREA`): the light that sampling gathers at the
    /// surface the ray left (sampled emitters, and the environment when
    /// it is sampled) is not counted again where the ray finds it, so
    /// that direct light is counted once; the ray brings the rest.
    fn li_unlit<A>(
        tr: &Tracer<'_, A>,
        ray: &Ray,
        depth: u32,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Li
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        let data = tr.data;
        let Some(found) = tr.closest(ray, Real::INFINITY, &mut ts.scratch) else {
            let color = if data.env_pick > 0.0 {
                Rgb::ZERO
            } else {
                data.miss(ray.dir)
            };
            return Li {
                color,
                t: Real::INFINITY,
                hit: false,
            };
        };
        let sh = tr.shading(ray, found);
        if matches!(
            data.materials[sh.material as usize],
            Material::Emissive { .. }
        ) && data.sampled_emitter(found).is_some()
        {
            return Li {
                color: sh.emission,
                t: sh.t,
                hit: true,
            };
        }
        Self::shade(tr, ray, Some(&sh), depth, stream, ts)
    }

    /// Ambient plus direct lighting with Suffern's BRDFs: Lambert `kd·cd/π`
    /// and, with `spec = (ks·cs, exp)`, the glossy `ks·cs·(r·wo)^exp`; each
    /// light contributes `f · L · cos θ`. With `AO`, the ambient lights
    /// with occlusion add what of them reaches the point (only where
    /// `ambient` is not black).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn direct<A>(
        tr: &Tracer<'_, A>,
        sp: &SurfacePoint,
        ng: Vec3,
        ns: Vec3,
        wo: Vec3,
        ambient: Rgb,
        brdf: Brdf,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Rgb
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        let mut l = if AO && ambient != Rgb::ZERO {
            ambient * (tr.data.ambient + occluded_ambient(tr, sp, ng, ns, stream, ts))
        } else {
            ambient * tr.data.ambient
        };
        if brdf.is_black() {
            return l;
        }
        let brdf = |wi: Vec3| brdf.f(wo, wi, ns);
        if AREA {
            // One sample of the area lights or the environment, chosen by
            // `env_pick` and then by power (Suffern ch. 18 samples each
            // light; choosing one keeps the cost per shading point constant
            // with many emitting triangles).
            let u1 = stream.next_2d().0;
            if let Some(ls) = tr.data.sample_direct(sp.p, u1, stream, Some(ns)) {
                let cos = ns.dot(ls.wi);
                if cos > 0.0 && ng.dot(ls.wi) > 0.0 && tr.sample_visible(sp, ng, &ls, ts) {
                    l += brdf(ls.wi) * ls.radiance * to_f32(cos / ls.pdf);
                }
            }
        }
        for light in &tr.data.lights {
            let (wi, radiance) = match *light {
                DirectLight::Point {
                    position,
                    radiance,
                    inverse_square,
                    ..
                }
                | DirectLight::Spot {
                    position,
                    radiance,
                    inverse_square,
                    ..
                } => {
                    let to = position - sp.p;
                    let d2 = to.dot(to);
                    let wi = to / d2.sqrt();
                    let radiance = if inverse_square {
                        radiance / to_f32(d2)
                    } else {
                        radiance
                    };
                    (wi, radiance * light.cone(wi))
                }
                DirectLight::Directional { dir, radiance, .. } => (dir, radiance),
            };
            if radiance == Rgb::ZERO {
                continue;
            }
            let cos = ns.dot(wi);
            // The geometric normal decides the side (pbrt's rule): a light
            // below the surface lights nothing, whatever the shading normal.
            if !(cos > 0.0) || !(ng.dot(wi) > 0.0) {
                continue;
            }
            if SHADOWS {
                let (casts, shadow) = match *light {
                    DirectLight::Point {
                        position, shadows, ..
                    }
                    | DirectLight::Spot {
                        position, shadows, ..
                    } => {
                        let o = tr.data.ray_offset.origin(sp.p, sp.p_err, ng, wi);
                        (shadows, (Ray::new(o, position - o), point_shadow_t_max()))
                    }
                    DirectLight::Directional { shadows, .. } => {
                        let o = tr.data.ray_offset.origin(sp.p, sp.p_err, ng, wi);
                        (shadows, (Ray::new(o, wi), Real::INFINITY))
                    }
                };
                if casts {
                    ts.counts.shadow += 1;
                    if tr.occluded(&shadow.0, shadow.1, &mut ts.scratch) {
                        continue;
                    }
                }
            }
            l += brdf(wi) * radiance * to_f32(cos);
        }
        l
    }

    /// A smooth dielectric: Fresnel-weighted reflection and refraction,
    /// total internal reflection, radiance scaled by `1/η²` on refraction
    /// (Suffern's `FresnelTransmitter`) and Beer's law inside.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn dielectric<A>(
        tr: &Tracer<'_, A>,
        sh: &Shading,
        wo: Vec3,
        ior: f32,
        tint: Rgb,
        depth: u32,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Rgb
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        if depth >= tr.data.max_depth {
            return Rgb::ZERO;
        }
        let ior = ior as Real;
        // The geometric normal decides inside and outside.
        let entering = sh.sp.n.dot(wo) > 0.0;
        // Normals on the side of wo; eta = η_far / η_near.
        let (ns, ng, eta) = if entering {
            (sh.ns, sh.sp.n, ior)
        } else {
            (-sh.ns, -sh.sp.n, 1.0 / ior)
        };
        let ns = secondary_ns(ng, ns, wo);
        let cos_i = ns.dot(wo);
        let fr = to_f32(fresnel_dielectric(cos_i, eta));
        // Beer's law for the part of a ray that runs inside.
        let absorb = |li: Li| -> Rgb {
            if tint == Rgb::ONE {
                li.color
            } else {
                li.color * tint.powf(to_f32(li.t))
            }
        };
        let mut l = Rgb::ZERO;
        if REFLECT && fr > 0.0 {
            let wr = on_side(reflect(wo, ns), ng, ns, true);
            let origin = tr.data.ray_offset.origin(sh.sp.p, sh.sp.p_err, ng, wr);
            ts.counts.reflection += 1;
            let li = Self::li(tr, &Ray::new(origin, wr), depth + 1, stream, ts);
            // A reflection from the inside stays inside.
            l += fr * if entering { li.color } else { absorb(li) };
        }
        if fr < 1.0 {
            if let Some(wt) = refract(wo, ns, eta) {
                let wt = on_side(wt, ng, ns, false);
                let origin = tr.data.ray_offset.origin(sh.sp.p, sh.sp.p_err, ng, wt);
                ts.counts.refraction += 1;
                let li = Self::li(tr, &Ray::new(origin, wt), depth + 1, stream, ts);
                let scale = (1.0 - fr) / to_f32(eta * eta);
                l += scale * if entering { absorb(li) } else { li.color };
            }
        }
        l
    }
}
