//! The path tracer (global illumination): unidirectional path tracing with
//! next-event estimation, multiple importance sampling (power heuristic)
//! between light and BSDF sampling, and Russian roulette (pbrt-v4's
//! `PathIntegrator`, Veach's thesis ch. 9).
//!
//! The BSDFs are the physically based readings of the scene's materials:
//! Matte is Lambertian with albedo `kd·color`; Phong adds the normalised
//! Phong lobe `ks·specular·(exp + 2)/(2π)·cosᵉˣᵖα`; Reflective adds a
//! perfect mirror `kr·reflect`; Dielectric is smooth glass (Fresnel-chosen
//! reflection or refraction, Beer's law inside); Emissive emits on its front
//! face and reflects nothing. Opaque surfaces reflect on both sides. Ambient
//! lights are not used (the background is the environment's radiance).

use crate::bsdf::microfacet::Ggx;
use crate::bsdf::Micro;
use crate::emitters::Emitters;
use crate::float::to_f32;
use crate::integrator::{face_forward, Integrator, Li, Shading, ThreadState, Tracer};
use crate::integrator::{point_shadow_t_max, DirectLight};
use crate::optics::{fresnel_dielectric, reflect, refract};
use crate::sampling::maps::{cosine_hemisphere, cosine_power_lobe, cosine_power_lobe_pdf, Frame};
use crate::sampling::SampleStream;
use crate::scene::{Material, Rgb};
use crate::shapes::Surface;
use gridrt_bbox::{Ray, Real, Vec3};
use gridrt_grid::Accelerator;

const FRAC_1_PI: Real = std::f64::consts::FRAC_1_PI as Real;

/// The path tracer.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PathTracer;

/// The power heuristic with β = 2.
#[inline]
fn power_heuristic(a: Real, b: Real) -> Real {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

/// Mean of a colour's channels: how likely a lobe is chosen.
#[inline]
fn mean(c: Rgb) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// The non-delta part of an opaque material at a hit: a Lambertian lobe
/// and a normalised Phong lobe, with the probabilities of choosing each
/// (the mirror, a delta lobe, takes the rest).
#[derive(Clone, Copy, Debug)]
struct Lobes {
    diffuse: Rgb,
    glossy: Rgb,
    exp: Real,
    mirror: Rgb,
    p_diffuse: Real,
    p_glossy: Real,
    p_mirror: Real,
}

impl Lobes {
    fn new(diffuse: Rgb, glossy: Rgb, exp: f32, mirror: Rgb) -> Self {
        let (d, g, m) = (mean(diffuse), mean(glossy), mean(mirror));
        let total = d + g + m;
        let p = |x: f32| {
            if total > 0.0 {
                Real::from(x / total)
            } else {
                0.0
            }
        };
        Self {
            diffuse,
            glossy,
            exp: Real::from(exp),
            mirror,
            p_diffuse: p(d),
            p_glossy: p(g),
            p_mirror: p(m),
        }
    }

    /// Whether a light sample can be reflected (some non-delta lobe).
    fn smooth(&self) -> bool {
        self.p_diffuse + self.p_glossy > 0.0
    }

    /// The non-delta BSDF value and the density of choosing `wi` by
    /// [`Lobes`] sampling (lobe choice included), for unit `wo`, `wi` and
    /// shading normal `ns` on `wo`'s side.
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, ns: Vec3) -> (Rgb, Real) {
        let cos = ns.dot(wi);
        if cos <= 0.0 {
            return (Rgb::ZERO, 0.0);
        }
        let mut f = self.diffuse * to_f32(FRAC_1_PI);
        let mut pdf = self.p_diffuse * cos * FRAC_1_PI;
        if self.p_glossy > 0.0 {
            let ca = reflect(wo, ns).dot(wi);
            if ca > 0.0 {
                let lobe = ca.powf(self.exp);
                f += self.glossy * to_f32((self.exp + 2.0) * 0.5 * FRAC_1_PI * lobe);
                pdf += self.p_glossy * cosine_power_lobe_pdf(ca, self.exp);
            }
        }
        (f, pdf)
    }
}

/// The BSDF of an opaque or rough surface at a hit, in world space.
#[derive(Clone, Copy, Debug)]
enum Bsdf {
    /// Suffern's materials: Lambert, Phong and mirror lobes.
    Lobes(Lobes),
    /// A microfacet BSDF in the frame of the shading normal.
    Micro(Micro, Frame),
}

impl Bsdf {
    /// Whether a light sample can be scattered (some non-delta lobe).
    #[inline]
    fn smooth(&self) -> bool {
        match self {
            Bsdf::Lobes(l) => l.smooth(),
            Bsdf::Micro(m, _) => m.smooth(),
        }
    }

    /// Whether light from below the surface (seen from `wo`) can pass.
    #[inline]
    fn transmits(&self) -> bool {
        matches!(self, Bsdf::Micro(m, _) if m.transmits())
    }

    /// `f·|cos θi|` (cosine to the shading normal) and the density of
    /// choosing `wi` by [`PathTracer::sample_bsdf`], for unit `wo`, `wi`;
    /// `ng` is the geometric normal on `wo`'s side and `ns` the shading
    /// normal there. A direction the shading normal puts on the other side
    /// of the geometric surface than the geometric normal does gives 0
    /// (no light leaks through shading normals).
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, ns: Vec3, ng: Vec3) -> (Rgb, Real) {
        match self {
            Bsdf::Lobes(l) => {
                let (f, pdf) = l.eval(wo, wi, ns);
                (f * to_f32(ns.dot(wi).max(0.0)), pdf)
            }
            Bsdf::Micro(m, frame) => {
                let (lo, li) = (frame.to_local(wo), frame.to_local(wi));
                if (lo.z * li.z > 0.0) != (ng.dot(wi) > 0.0) {
                    return (Rgb::ZERO, 0.0);
                }
                let (f, pdf) = m.eval(lo, li);
                (f * to_f32(li.z.abs()), pdf)
            }
        }
    }
}

/// What the next bounce is.
enum Bounce {
    /// A non-delta direction with the throughput factor `f·cos/pdf` and the
    /// density (for MIS against the emitter it may hit).
    Smooth {
        wi: Vec3,
        weight: Rgb,
        pdf: Real,
        glossy: bool,
    },
    /// A delta direction (mirror, glass) with its throughput factor.
    Delta {
        wi: Vec3,
        weight: Rgb,
        refracted: bool,
    },
}

impl PathTracer {
    /// Next-event estimation at an opaque hit: one sample of the area
    /// lights (weighted by MIS against BSDF sampling) and every point or
    /// directional light (with a shadow ray each when they cast shadows).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn direct<A>(
        tr: &Tracer<'_, A>,
        sh: &Shading,
        ng: Vec3,
        ns: Vec3,
        wo: Vec3,
        bsdf: &Bsdf,
        u1: Real,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Rgb
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        let data = tr.data;
        let p = sh.sp.p;
        let mut l = Rgb::ZERO;
        // An image environment is sampled by its importance, so that the
        // density of a BSDF-sampled direction can be evaluated for MIS.
        if let Some(ls) = data.sample_direct(p, u1, stream, None) {
            if bsdf.transmits() || ng.dot(ls.wi) > 0.0 {
                let (f, pdf_bsdf) = bsdf.eval(wo, ls.wi, ns, ng);
                if f != Rgb::ZERO && tr.sample_visible(&sh.sp, ng, &ls, ts) {
                    let w = power_heuristic(ls.pdf, pdf_bsdf);
                    l += f * ls.radiance * to_f32(w / ls.pdf);
                }
            }
        }
        for light in &data.lights {
            let (wi, radiance, shadow) = match *light {
                DirectLight::Point {
                    position,
                    radiance,
                    inverse_square,
                    shadows,
                }
                | DirectLight::Spot {
                    position,
                    radiance,
                    inverse_square,
                    shadows,
                    ..
                } => {
                    let d = position - p;
                    let d2 = d.length_squared();
                    let Some(wi) = d.try_normalize() else {
                        continue;
                    };
                    let r = if inverse_square {
                        radiance / to_f32(d2)
                    } else {
                        radiance
                    } * light.cone(wi);
                    if r == Rgb::ZERO {
                        continue;
                    }
                    let o = tr.data.ray_offset.origin(p, sh.sp.p_err, ng, wi);
                    (
                        wi,
                        r,
                        shadows.then(|| (Ray::new(o, position - o), point_shadow_t_max())),
                    )
                }
                DirectLight::Directional {
                    dir,
                    radiance,
                    shadows,
                } => {
                    let o = tr.data.ray_offset.origin(p, sh.sp.p_err, ng, dir);
                    (
                        dir,
                        radiance,
                        shadows.then(|| (Ray::new(o, dir), Real::INFINITY)),
                    )
                }
            };
            if !bsdf.transmits() && ng.dot(wi) <= 0.0 {
                continue;
            }
            let (f, _) = bsdf.eval(wo, wi, ns, ng);
            if f == Rgb::ZERO {
                continue;
            }
            if let Some((ray, t_max)) = shadow {
                ts.counts.shadow += 1;
                if tr.occluded(&ray, t_max, &mut ts.scratch) {
                    continue;
                }
            }
            l += f * radiance;
        }
        l
    }

    /// Chooses the next direction at an opaque hit.
    #[inline]
    fn sample_opaque(
        lobes: &Lobes,
        wo: Vec3,
        ns: Vec3,
        ng: Vec3,
        u: Real,
        stream: &mut SampleStream,
    ) -> Option<Bounce> {
        let u2 = stream.next_2d();
        if u < lobes.p_mirror {
            let wi = reflect(wo, ns);
            if ng.dot(wi) <= 0.0 {
                return None;
            }
            return Some(Bounce::Delta {
                wi,
                weight: lobes.mirror / to_f32(lobes.p_mirror),
                refracted: false,
            });
        }
        let glossy = u >= lobes.p_mirror + lobes.p_diffuse;
        let wi = if glossy {
            Frame::new(reflect(wo, ns)).to_world(cosine_power_lobe(u2, lobes.exp))
        } else {
            Frame::new(ns).to_world(cosine_hemisphere(u2))
        };
        if ng.dot(wi) <= 0.0 {
            return None;
        }
        let (f, pdf) = lobes.eval(wo, wi, ns);
        if !(pdf > 0.0) || f == Rgb::ZERO {
            return None;
        }
        Some(Bounce::Smooth {
            wi,
            weight: f * to_f32(ns.dot(wi) / pdf),
            pdf,
            glossy,
        })
    }

    /// Next-event estimation and the next direction at a microfacet
    /// surface: adds the direct light (times `beta`) to `l`.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn scatter<A>(
        tr: &Tracer<'_, A>,
        sh: &Shading,
        bsdf: &Bsdf,
        ng: Vec3,
        wo: Vec3,
        l: &mut Rgb,
        beta: Rgb,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Option<Bounce>
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        let (u_light, u_lobe) = stream.next_2d();
        if bsdf.smooth() {
            *l += beta * Self::direct(tr, sh, ng, sh.ns, wo, bsdf, u_light, stream, ts);
        }
        let Bsdf::Micro(m, frame) = bsdf else {
            return None;
        };
        let s = m.sample(frame.to_local(wo), u_lobe, stream.next_2d())?;
        let wi = frame.to_world(s.wi);
        // The geometric surface decides the side (no leaks through
        // shading normals).
        if (ng.dot(wi) < 0.0) != s.transmitted {
            return None;
        }
        Some(if s.delta {
            Bounce::Delta {
                wi,
                weight: s.f,
                refracted: s.transmitted,
            }
        } else {
            Bounce::Smooth {
                wi,
                weight: s.f * to_f32(s.wi.z.abs() / s.pdf),
                pdf: s.pdf,
                glossy: true,
            }
        })
    }

    /// Chooses reflection or refraction at a smooth dielectric by its
    /// Fresnel reflectance.
    #[inline]
    fn sample_glass(sh: &Shading, wo: Vec3, ior: f32, u: Real) -> (Bounce, Vec3) {
        let ior = Real::from(ior);
        let entering = sh.ns.dot(wo) > 0.0;
        let (ns, ng, eta) = if entering {
            (sh.ns, sh.sp.n, ior)
        } else {
            (-sh.ns, -sh.sp.n, 1.0 / ior)
        };
        let fr = fresnel_dielectric(ns.dot(wo), eta);
        if u >= fr {
            if let Some(wt) = refract(wo, ns, eta) {
                // Radiance is scaled by 1/η² crossing the boundary.
                let weight = Rgb::splat(to_f32(1.0 / (eta * eta)));
                return (
                    Bounce::Delta {
                        wi: wt,
                        weight,
                        refracted: true,
                    },
                    -ng,
                );
            }
        }
        (
            Bounce::Delta {
                wi: reflect(wo, ns),
                weight: Rgb::ONE,
                refracted: false,
            },
            ng,
        )
    }
}

impl Integrator for PathTracer {
    const BATCH: bool = false;
    const SAMPLED: bool = true;

    fn li<A>(
        tr: &Tracer<'_, A>,
        ray: &Ray,
        _depth: u32,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Li
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        let data = tr.data;
        let mut l = Rgb::ZERO;
        let mut beta = Rgb::ONE;
        let mut ray = *ray;
        // Emission seen by the camera or after a delta bounce is counted in
        // full; after a smooth bounce it is weighted against light sampling
        // with the density of that bounce.
        let mut specular = true;
        let mut bsdf_pdf: Real = 0.0;
        let mut first = Li {
            color: Rgb::ZERO,
            t: Real::INFINITY,
            hit: false,
        };
        let mut depth = 0u32;
        loop {
            let Some(found) = tr.closest(&ray, Real::INFINITY, &mut ts.scratch) else {
                let mut w = 1.0;
                if !specular && data.env_pick > 0.0 {
                    if let Some(env) = &data.env {
                        let pl = data.env_pick * env.pdf(ray.dir.normalize());
                        w = power_heuristic(bsdf_pdf, pl);
                    }
                }
                l += beta * data.miss(ray.dir) * to_f32(w);
                break;
            };
            let sh = tr.shading(&ray, found);
            if depth == 0 {
                first.t = sh.t;
                first.hit = true;
            }
            let wo = -ray.dir;
            // Emission maps are not sampled as lights: what paths hit counts
            // in full.
            l += beta * sh.emission;
            let (bounce, ng_side) = match data.materials[sh.material as usize] {
                Material::Emissive { color, strength } => {
                    if sh.sp.n.dot(wo) > 0.0 {
                        let mut w = 1.0;
                        if !specular {
                            if let Some(e) = data.sampled_emitter(found) {
                                let pl = (1.0 - data.env_pick)
                                    * Emitters::pdf(e, ray.dir, sh.t, sh.sp.n);
                                w = power_heuristic(bsdf_pdf, pl);
                            }
                        }
                        l += beta * color * strength * to_f32(w);
                    }
                    break;
                }
                Material::Dielectric { ior, tint } => {
                    if tint != Rgb::ONE && sh.ns.dot(wo) <= 0.0 {
                        // Beer's law over the segment just travelled inside.
                        beta *= tint.powf(to_f32(sh.t));
                    }
                    if depth >= data.path_depth {
                        break;
                    }
                    let u = stream.next_2d().0;
                    Self::sample_glass(&sh, wo, ior, u)
                }
                Material::RoughDielectric {
                    ior,
                    tint,
                    roughness,
                } => {
                    if tint != Rgb::ONE && sh.ns.dot(wo) <= 0.0 {
                        beta *= tint.powf(to_f32(sh.t));
                    }
                    if depth >= data.path_depth {
                        break;
                    }
                    let micro = Micro::Glass {
                        ggx: Ggx::from_roughness(roughness),
                        eta: Real::from(ior),
                    };
                    // The frame keeps the outward normal (inside is below).
                    let (ng, _) = face_forward(sh.sp.n, sh.ns, wo);
                    let bsdf = Bsdf::Micro(micro, Frame::new(sh.ns));
                    match Self::scatter(tr, &sh, &bsdf, ng, wo, &mut l, beta, stream, ts) {
                        Some(b) => (b, ng),
                        None => break,
                    }
                }
                Material::Conductor { fresnel, roughness } => {
                    if depth >= data.path_depth {
                        break;
                    }
                    let micro = Micro::Conductor {
                        ggx: Ggx::from_roughness(roughness),
                        fresnel,
                    };
                    let (ng, ns) = face_forward(sh.sp.n, sh.ns, wo);
                    let bsdf = Bsdf::Micro(micro, Frame::new(ns));
                    match Self::scatter(tr, &sh, &bsdf, ng, wo, &mut l, beta, stream, ts) {
                        Some(b) => (b, ng),
                        None => break,
                    }
                }
                Material::MetallicRoughness {
                    base,
                    metallic,
                    roughness,
                } => {
                    if depth >= data.path_depth {
                        break;
                    }
                    let (metallic, roughness) = sh.metal_rough.unwrap_or((metallic, roughness));
                    let (ng, ns) = face_forward(sh.sp.n, sh.ns, wo);
                    let base = sh.albedo.unwrap_or(base);
                    let micro = Micro::gltf(base, metallic, roughness, ns.dot(wo));
                    let bsdf = Bsdf::Micro(micro, Frame::new(ns));
                    match Self::scatter(tr, &sh, &bsdf, ng, wo, &mut l, beta, stream, ts) {
                        Some(b) => (b, ng),
                        None => break,
                    }
                }
                ref m => {
                    let (diffuse, glossy, exp, mirror) = match *m {
                        Material::Matte { color, kd, .. } => {
                            (sh.albedo.unwrap_or(color) * kd, Rgb::ZERO, 1.0, Rgb::ZERO)
                        }
                        Material::Phong {
                            color,
                            kd,
                            ks,
                            exp,
                            specular,
                            ..
                        } => (
                            sh.albedo.unwrap_or(color) * kd,
                            specular * ks,
                            exp,
                            Rgb::ZERO,
                        ),
                        Material::Reflective {
                            color,
                            kd,
                            ks,
                            exp,
                            kr,
                            reflect,
                            ..
                        } => (
                            sh.albedo.unwrap_or(color) * kd,
                            Rgb::splat(ks),
                            exp,
                            reflect * kr,
                        ),
                        Material::Dielectric { .. }
                        | Material::RoughDielectric { .. }
                        | Material::Conductor { .. }
                        | Material::MetallicRoughness { .. }
                        | Material::Emissive { .. } => {
                            unreachable!("matched above")
                        }
                    };
                    if depth >= data.path_depth {
                        break;
                    }
                    let lobes = Lobes::new(diffuse, glossy, exp, mirror);
                    let (ng, ns) = face_forward(sh.sp.n, sh.ns, wo);
                    // One pair chooses the light and the lobe.
                    let (u_light, u_lobe) = stream.next_2d();
                    if lobes.smooth() {
                        let bsdf = Bsdf::Lobes(lobes);
                        l += beta * Self::direct(tr, &sh, ng, ns, wo, &bsdf, u_light, stream, ts);
                    }
                    match Self::sample_opaque(&lobes, wo, ns, ng, u_lobe, stream) {
                        Some(b) => (b, ng),
                        None => break,
                    }
                }
            };
            let wi = match bounce {
                Bounce::Smooth {
                    wi,
                    weight,
                    pdf,
                    glossy,
                } => {
                    if glossy {
                        ts.counts.glossy += 1;
                    } else {
                        ts.counts.indirect += 1;
                    }
                    beta *= weight;
                    bsdf_pdf = pdf;
                    specular = false;
                    wi
                }
                Bounce::Delta {
                    wi,
                    weight,
                    refracted,
                } => {
                    if refracted {
                        ts.counts.refraction += 1;
                    } else {
                        ts.counts.reflection += 1;
                    }
                    beta *= weight;
                    specular = true;
                    wi
                }
            };
            depth += 1;
            // Russian roulette once the path has two bounces: survive with
            // the throughput's largest channel (at most 1).
            if depth > 1 {
                let m = beta.max_element();
                if m < 1.0 {
                    let q = (1.0 - m).max(0.0);
                    if to_f32(stream.next_2d().0) < q {
                        break;
                    }
                    beta /= 1.0 - q;
                }
            }
            if beta == Rgb::ZERO || !beta.is_finite() {
                break;
            }
            let origin = tr.data.ray_offset.origin(sh.sp.p, sh.sp.p_err, ng_side, wi);
            ray = Ray::new(origin, wi);
        }
        first.color = l;
        first
    }

    fn shade<A>(
        tr: &Tracer<'_, A>,
        ray: &Ray,
        _hit: Option<&Shading>,
        depth: u32,
        stream: &mut SampleStream,
        ts: &mut ThreadState<A::Scratch>,
    ) -> Li
    where
        A: Accelerator,
        A::Prim: Surface,
    {
        // Not a batching integrator: the render loop calls `li`; this
        // traces again rather than reusing the hit.
        Self::li(tr, ray, depth, stream, ts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_power_heuristic_sums_to_one() {
        for (a, b) in [(1.0 as Real, 1.0 as Real), (0.2, 5.0), (3.0, 0.0)] {
            assert!((power_heuristic(a, b) + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    }

    #[test]
    fn lobes_are_chosen_by_their_weight_and_pdfs_match() {
        let lobes = Lobes::new(Rgb::splat(0.5), Rgb::splat(0.25), 20.0, Rgb::splat(0.25));
        assert!((lobes.p_diffuse - 0.5).abs() < 1e-6 && (lobes.p_mirror - 0.25).abs() < 1e-6);
        // The density of the non-delta lobes integrates to their share.
        let ns = Vec3::Z;
        let wo = Vec3::new(0.3, 0.0, 1.0).normalize();
        let n = 400;
        let mut total = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = ((i as Real + 0.5) / n as Real, (j as Real + 0.5) / n as Real);
                let wi = crate::sampling::maps::uniform_sphere(u);
                let (_, pdf) = lobes.eval(wo, wi, ns);
                total += crate::float::to_f64(pdf) * 4.0 * std::f64::consts::PI / f64::from(n * n);
            }
        }
        // The glossy lobe's part below the horizon is cut off.
        assert!(total > 0.7 && total <= 0.75 + 1e-3, "{total}");
    }
}
