//! The Trowbridge–Reitz (GGX) microfacet distribution with Smith's
//! height-correlated masking-shadowing and sampling of the visible normals
//! (Heitz 2018), as in pbrt-v4's `TrowbridgeReitzDistribution`.
//!
//! Directions are in the local shading frame: `z` is the macro-surface
//! normal.

use gridrt_bbox::{Real, Vec3};

const PI: Real = std::f64::consts::PI as Real;

/// Below this `α` a lobe is a delta (mirror or smooth glass): GGX values
/// overflow long before and a delta lobe is exact in the limit.
pub(crate) const SMOOTH_ALPHA: Real = 1e-3;

/// An isotropic GGX distribution of microfacet normals with width `α`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ggx {
    alpha: Real,
}

impl Ggx {
    /// The distribution of the artists' roughness `r` in `[0, 1]`: `α = r²`
    /// (Burley's and glTF's remapping).
    #[inline]
    pub(crate) fn from_roughness(r: f32) -> Self {
        let r = Real::from(r.clamp(0.0, 1.0));
        Self { alpha: r * r }
    }

    /// The distribution of width `alpha` (≥ 0).
    #[cfg(test)]
    pub(crate) fn new(alpha: Real) -> Self {
        Self { alpha }
    }

    /// Whether the lobe is so narrow that it is treated as a delta.
    #[inline]
    pub(crate) fn smooth(&self) -> bool {
        self.alpha < SMOOTH_ALPHA
    }

    /// The same distribution no narrower than [`SMOOTH_ALPHA`] (for BRDFs
    /// that have no delta form, such as glTF's).
    #[inline]
    pub(crate) fn at_least_smooth_limit(self) -> Self {
        Self {
            alpha: self.alpha.max(SMOOTH_ALPHA),
        }
    }

    /// The density of microfacet normals `D(ωm)` (per unit projected area).
    #[inline]
    pub(crate) fn d(&self, wm: Vec3) -> Real {
        let c2 = wm.z * wm.z;
        if !(wm.z > 0.0) {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t = c2 * (a2 - 1.0) + 1.0;
        a2 / (PI * t * t)
    }

    /// Smith's auxiliary function `Λ(ω)`.
    #[inline]
    pub(crate) fn lambda(&self, w: Vec3) -> Real {
        let c2 = w.z * w.z;
        if c2 == 0.0 {
            // Exactly grazing: pbrt's convention (the lobes vanish there
            // through their cosines anyway).
            return 0.0;
        }
        let tan2 = (1.0 - c2).max(0.0) / c2;
        ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0) * 0.5
    }

    /// Masking of one direction, `G₁(ω)`.
    #[inline]
    pub(crate) fn g1(&self, w: Vec3) -> Real {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing `G(ωo, ωi)`.
    #[inline]
    pub(crate) fn g(&self, wo: Vec3, wi: Vec3) -> Real {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// The density of the normals visible from `w`, `D_ω(ωm)`: what
    /// [`Ggx::sample_wm`] draws.
    #[inline]
    pub(crate) fn pdf_wm(&self, w: Vec3, wm: Vec3) -> Real {
        let c = w.z.abs();
        if c == 0.0 {
            return 0.0;
        }
        self.g1(w) / c * self.d(wm) * w.dot(wm).abs()
    }

    /// A microfacet normal visible from `w` (either hemisphere), by Heitz's
    /// sampling of the visible normals; always in the upper hemisphere.
    #[inline]
    pub(crate) fn sample_wm(&self, w: Vec3, u: (Real, Real)) -> Vec3 {
        // The view direction in the hemisphere configuration.
        let mut wh = Vec3::new(self.alpha * w.x, self.alpha * w.y, w.z).normalize();
        if wh.z < 0.0 {
            wh = -wh;
        }
        let t1 = if wh.z < 0.99999 {
            Vec3::Z.cross(wh).normalize()
        } else {
            Vec3::X
        };
        let t2 = wh.cross(t1);
        // A uniform point of the disk, warped to the visible half.
        let r = u.0.sqrt();
        let phi = 2.0 * PI * u.1;
        let (px, py) = (r * phi.cos(), r * phi.sin());
        let h = (1.0 - px * px).max(0.0).sqrt();
        let s = (1.0 + wh.z) * 0.5;
        let py = (1.0 - s) * h + s * py;
        let pz = (1.0 - px * px - py * py).max(0.0).sqrt();
        let nh = t1 * px + t2 * py + wh * pz;
        Vec3::new(self.alpha * nh.x, self.alpha * nh.y, nh.z.max(1e-6)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::float::to_f64;
    use crate::sampling::maps::uniform_sphere;

    fn grid(n: u32) -> impl Iterator<Item = (Real, Real)> {
        (0..n * n).map(move |i| {
            (
                ((i / n) as Real + 0.5) / n as Real,
                ((i % n) as Real + 0.5) / n as Real,
            )
        })
    }

    #[test]
    fn projected_normal_density_integrates_to_one() {
        for alpha in [0.2 as Real, 0.5, 0.9] {
            let g = Ggx::new(alpha);
            // ∫ D(ωm) cos θm dωm = 1, by sampling ωm with the cosine
            // weight removed: uniform directions.
            let n = 600;
            let total: f64 = grid(n)
                .map(|u| {
                    let wm = uniform_sphere(u);
                    to_f64(g.d(wm) * wm.z.max(0.0))
                })
                .sum::<f64>()
                * 4.0
                * std::f64::consts::PI
                / f64::from(n * n);
            assert!((total - 1.0).abs() < 0.01, "α {alpha}: {total}");
        }
    }

    #[test]
    fn visible_normals_have_the_visible_normal_density() {
        // Mean of ωm.x and ωm.z under sampling against quadrature of
        // D_ω: the sampler draws what `pdf_wm` says.
        let g = Ggx::new(0.4);
        let w = Vec3::new(0.6, 0.0, 0.8);
        let n = 300;
        let mut sampled = Vec3::ZERO;
        for u in grid(n) {
            sampled += g.sample_wm(w, u);
        }
        sampled /= (n * n) as Real;
        let m = 800;
        let mut quad = Vec3::ZERO;
        let mut mass: Real = 0.0;
        for u in grid(m) {
            let wm = uniform_sphere(u);
            // Back-facing microfacets are never sampled (the density
            // takes |ω·ωm| for use at sampled normals only).
            if w.dot(wm) <= 0.0 {
                continue;
            }
            let p = g.pdf_wm(w, wm) * 4.0 * PI / (m * m) as Real;
            quad += wm * p;
            mass += p;
        }
        assert!((mass - 1.0).abs() < 0.01, "{mass}");
        assert!((sampled - quad).length() < 0.01, "{sampled} vs {quad}");
    }

    #[test]
    fn masking_is_one_at_normal_incidence_and_falls_towards_grazing() {
        let g = Ggx::new(0.5);
        assert!((g.g1(Vec3::Z) - 1.0).abs() < 1e-6);
        let grazing = Vec3::new(0.999, 0.0, 0.0447).normalize();
        assert!(g.g1(grazing) < 0.3);
        assert!(g.g(Vec3::Z, grazing) <= g.g1(grazing) + 1e-6);
    }
}
