//! Microfacet BSDFs: a GGX conductor (rough metal), a rough dielectric
//! (frosted glass) and glTF's metallic-roughness BRDF, in the local
//! shading frame (`z` is the shading normal), as pbrt-v4's
//! `ConductorBxDF`, `DielectricBxDF` and the glTF 2.0 specification's
//! appendix B define them.
//!
//! Each BSDF evaluates `f(ωo, ωi)` with the density of its own sampling
//! (for multiple importance sampling) and samples `ωi` with `f` and the
//! density. Values are radiance BSDFs: transmission is divided by `η²`.

pub(crate) mod fresnel;
pub(crate) mod microfacet;

use crate::float::to_f32;
use crate::optics::fresnel_dielectric;
use crate::scene::{ConductorFresnel, Rgb};
use fresnel::schlick;
use gridrt_bbox::{Real, Vec3};
use microfacet::Ggx;

const FRAC_1_PI: Real = std::f64::consts::FRAC_1_PI as Real;

/// A microfacet BSDF at one hit.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Micro {
    /// A metal: GGX reflection weighted by the conductor's Fresnel term; a
    /// perfect mirror when the roughness is (nearly) 0.
    Conductor { ggx: Ggx, fresnel: ConductorFresnel },
    /// Rough glass: GGX reflection and transmission, chosen by the
    /// dielectric Fresnel term. `z` is the outward normal; `eta` the index
    /// inside over the index outside.
    Glass { ggx: Ggx, eta: Real },
    /// glTF's metallic-roughness BRDF: `(1 − F)·c_diff/π + F·D·G/(4|cos θo cos θi|)`
    /// with Schlick's `F` from `f0`; the specular lobe is sampled with
    /// probability `p_spec`.
    Gltf {
        ggx: Ggx,
        diffuse: Rgb,
        f0: Rgb,
        p_spec: Real,
    },
}

/// A sampled direction.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sample {
    /// The incident direction, local frame.
    pub wi: Vec3,
    /// `f(ωo, ωi)` (for a delta lobe: the weight `f·|cos θi|/pdf`, with
    /// `pdf` 1).
    pub f: Rgb,
    /// The density of `ωi` (1 for a delta lobe).
    pub pdf: Real,
    /// Whether `ωi` is on the other side of the surface.
    pub transmitted: bool,
    /// Whether it came from a delta lobe (mirror).
    pub delta: bool,
}

#[inline]
fn mean(c: Rgb) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// Reflectance of the dielectric boundary for a microfacet with
/// `cos = ωo·ωm` (negative: `ωo` is inside).
#[inline]
fn fr_dielectric(cos: Real, eta: Real) -> Real {
    if cos < 0.0 {
        fresnel_dielectric(-cos, 1.0 / eta)
    } else {
        fresnel_dielectric(cos, eta)
    }
}

/// Refracts `wi` through the microfacet `n` for `eta` (inside over outside,
/// `n` outward): the direction and the relative index `η'` it crossed
/// into, `None` under total internal reflection (pbrt-v4's `Refract`).
#[inline]
fn refract(wi: Vec3, n: Vec3, eta: Real) -> Option<(Vec3, Real)> {
    let mut cos_i = n.dot(wi);
    let (mut eta, mut n) = (eta, n);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-wi / eta + n * (cos_i / eta - cos_t), eta))
}

impl Micro {
    /// The metallic-roughness BRDF of a base colour, metalness and
    /// roughness, and the probability of sampling its specular lobe for
    /// `cos_o = cos θo`.
    pub(crate) fn gltf(base: Rgb, metallic: f32, roughness: f32, cos_o: Real) -> Self {
        let m = metallic.clamp(0.0, 1.0);
        let diffuse = base * (1.0 - m);
        let f0 = Rgb::splat(0.04).lerp(base, m);
        let s = mean(schlick(f0, to_f32(cos_o)));
        let d = mean(diffuse) * (1.0 - s);
        let p_spec = if s + d > 0.0 { s / (s + d) } else { 1.0 };
        Micro::Gltf {
            ggx: Ggx::from_roughness(roughness).at_least_smooth_limit(),
            diffuse,
            f0,
            p_spec: Real::from(p_spec),
        }
    }

    /// Whether a light sample can be reflected or transmitted (no pure
    /// delta lobe).
    #[inline]
    pub(crate) fn smooth(&self) -> bool {
        match *self {
            Micro::Conductor { ggx, .. } | Micro::Glass { ggx, .. } => !ggx.smooth(),
            Micro::Gltf { .. } => true,
        }
    }

    /// Whether the BSDF transmits (light samples are then taken on both
    /// sides).
    #[inline]
    pub(crate) fn transmits(&self) -> bool {
        matches!(self, Micro::Glass { .. })
    }

    /// `f(ωo, ωi)` and the density with which [`Micro::sample`] draws `ωi`
    /// (delta lobes contribute nothing).
    pub(crate) fn eval(&self, wo: Vec3, wi: Vec3) -> (Rgb, Real) {
        match *self {
            Micro::Conductor { ggx, fresnel } => {
                let (co, ci) = (wo.z, wi.z);
                if ggx.smooth() || !(co > 0.0 && ci > 0.0) {
                    return (Rgb::ZERO, 0.0);
                }
                let Some(wm) = (wo + wi).try_normalize() else {
                    return (Rgb::ZERO, 0.0);
                };
                let f = fresnel.eval(to_f32(wo.dot(wm).abs()))
                    * to_f32(ggx.d(wm) * ggx.g(wo, wi) / (4.0 * ci * co));
                let pdf = ggx.pdf_wm(wo, wm) / (4.0 * wo.dot(wm).abs());
                (f, pdf)
            }
            Micro::Gltf {
                ggx,
                diffuse,
                f0,
                p_spec,
            } => {
                let (co, ci) = (wo.z, wi.z);
                if !(co > 0.0 && ci > 0.0) {
                    return (Rgb::ZERO, 0.0);
                }
                let Some(wm) = (wo + wi).try_normalize() else {
                    return (Rgb::ZERO, 0.0);
                };
                let vh = wo.dot(wm).abs();
                let fr = schlick(f0, to_f32(vh));
                let spec = fr * to_f32(ggx.d(wm) * ggx.g(wo, wi) / (4.0 * ci * co));
                let diff = (Rgb::ONE - fr) * diffuse * to_f32(FRAC_1_PI);
                let pdf =
                    p_spec * ggx.pdf_wm(wo, wm) / (4.0 * vh) + (1.0 - p_spec) * ci * FRAC_1_PI;
                (spec + diff, pdf)
            }
            Micro::Glass { ggx, eta } => {
                if ggx.smooth() {
                    return (Rgb::ZERO, 0.0);
                }
                glass_eval(ggx, eta, wo, wi)
            }
        }
    }

    /// Samples `ωi` for `ωo` with one number `uc` for the lobe choice and a
    /// pair `u` for the direction.
    pub(crate) fn sample(&self, wo: Vec3, uc: Real, u: (Real, Real)) -> Option<Sample> {
        match *self {
            Micro::Conductor { ggx, fresnel } => {
                if !(wo.z > 0.0) {
                    return None;
                }
                if ggx.smooth() {
                    return Some(Sample {
                        wi: Vec3::new(-wo.x, -wo.y, wo.z),
                        f: fresnel.eval(to_f32(wo.z)),
                        pdf: 1.0,
                        transmitted: false,
                        delta: true,
                    });
                }
                let wm = ggx.sample_wm(wo, u);
                let wi = -wo + wm * (2.0 * wo.dot(wm));
                self.finish(wo, wi, false)
            }
            Micro::Gltf { ggx, p_spec, .. } => {
                if !(wo.z > 0.0) {
                    return None;
                }
                let wi = if uc < p_spec {
                    let wm = ggx.sample_wm(wo, u);
                    -wo + wm * (2.0 * wo.dot(wm))
                } else {
                    crate::sampling::maps::cosine_hemisphere(u)
                };
                self.finish(wo, wi, false)
            }
            Micro::Glass { ggx, eta } => {
                if wo.z == 0.0 {
                    return None;
                }
                if ggx.smooth() {
                    return glass_smooth_sample(eta, wo, uc);
                }
                let wm = ggx.sample_wm(wo, u);
                let r = fr_dielectric(wo.dot(wm), eta);
                if uc < r {
                    let wi = -wo + wm * (2.0 * wo.dot(wm));
                    self.finish(wo, wi, false)
                } else {
                    let (wi, _) = refract(wo, wm, eta)?;
                    self.finish(wo, wi, true)
                }
            }
        }
    }

    /// A sample for a sampled `wi` on the side `transmitted` says: its
    /// value and density from [`Micro::eval`] (so sampling and evaluation
    /// agree by construction), or `None` when it is on the wrong side.
    #[inline]
    fn finish(&self, wo: Vec3, wi: Vec3, transmitted: bool) -> Option<Sample> {
        if wi.z == 0.0 || ((wi.z * wo.z) < 0.0) != transmitted {
            return None;
        }
        let (f, pdf) = self.eval(wo, wi);
        if !(pdf > 0.0) || f == Rgb::ZERO || !f.is_finite() {
            return None;
        }
        Some(Sample {
            wi,
            f,
            pdf,
            transmitted,
            delta: false,
        })
    }
}

/// Smooth glass: reflection or refraction chosen by the Fresnel term, as
/// delta lobes whose weights are 1 (reflection) and `1/η'²` (radiance
/// crossing the boundary).
fn glass_smooth_sample(eta: Real, wo: Vec3, uc: Real) -> Option<Sample> {
    let r = fr_dielectric(wo.z, eta);
    if uc < r {
        return Some(Sample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            f: Rgb::ONE,
            pdf: 1.0,
            transmitted: false,
            delta: true,
        });
    }
    let (wi, etap) = refract(wo, Vec3::Z, eta)?;
    Some(Sample {
        wi,
        f: Rgb::splat(to_f32(1.0 / (etap * etap))),
        pdf: 1.0,
        transmitted: true,
        delta: true,
    })
}

/// pbrt-v4's rough dielectric `f` and pdf (the generalised half vector).
fn glass_eval(ggx: Ggx, eta: Real, wo: Vec3, wi: Vec3) -> (Rgb, Real) {
    let (co, ci) = (wo.z, wi.z);
    if co == 0.0 || ci == 0.0 {
        return (Rgb::ZERO, 0.0);
    }
    let reflect = co * ci > 0.0;
    let etap = if reflect {
        1.0
    } else if co > 0.0 {
        eta
    } else {
        1.0 / eta
    };
    let Some(mut wm) = (wi * etap + wo).try_normalize() else {
        return (Rgb::ZERO, 0.0);
    };
    if wm.z < 0.0 {
        wm = -wm;
    }
    // Microfacets seen from behind contribute nothing.
    if wm.dot(wi) * ci < 0.0 || wm.dot(wo) * co < 0.0 {
        return (Rgb::ZERO, 0.0);
    }
    let r = fr_dielectric(wo.dot(wm), eta);
    let t = 1.0 - r;
    if reflect {
        let f = ggx.d(wm) * ggx.g(wo, wi) * r / (4.0 * ci * co).abs();
        let pdf = ggx.pdf_wm(wo, wm) / (4.0 * wo.dot(wm).abs()) * r;
        (Rgb::splat(to_f32(f)), pdf)
    } else {
        let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
        if !(denom > 0.0) {
            return (Rgb::ZERO, 0.0);
        }
        let f = ggx.d(wm) * t * ggx.g(wo, wi) * (wi.dot(wm) * wo.dot(wm) / (ci * co * denom)).abs()
            / (etap * etap);
        let pdf = ggx.pdf_wm(wo, wm) * wi.dot(wm).abs() / denom * t;
        (Rgb::splat(to_f32(f)), pdf)
    }
}

#[cfg(test)]
mod tests;
