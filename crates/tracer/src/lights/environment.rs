//! The environment light: radiance from infinitely far away in every
//! direction, a constant colour or an equirectangular (latitude-longitude)
//! image, importance-sampled by a 2D piecewise-constant distribution over
//! the image (pbrt-v4's `ImageInfiniteLight`, `PiecewiseConstant2D`).
//!
//! Image mapping: column `u ∈ [0, 1)` is the azimuth φ = 2π(u − ½) about
//! +y, with the image centre looking along −z and u growing towards +x;
//! row `v ∈ [0, 1)` is the polar angle θ = πv from +y (the top row is the
//! zenith). The direction of (θ, φ) is `(sin θ sin φ, cos θ, −sin θ cos φ)`.

use crate::scene::{EnvImage, Rgb};
use gridrt_bbox::{Real, Vec3};

const PI: Real = std::f64::consts::PI as Real;

/// A piecewise-constant 1D distribution over `[0, 1)`.
#[derive(Clone, Debug, Default)]
struct Distribution1D {
    /// Values (≥ 0).
    func: Vec<Real>,
    /// Cumulative integral, `func.len() + 1` entries from 0 to 1.
    cdf: Vec<Real>,
    /// Integral of `func` over `[0, 1)`.
    integral: Real,
}

impl Distribution1D {
    fn new(func: Vec<Real>) -> Self {
        let n = func.len();
        let mut cdf = vec![0.0; n + 1];
        for i in 0..n {
            cdf[i + 1] = cdf[i] + func[i] / n as Real;
        }
        let integral = cdf[n];
        if integral > 0.0 {
            for c in &mut cdf[1..] {
                *c /= integral;
            }
        } else {
            // Nothing to prefer: uniform.
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as Real / n as Real;
            }
        }
        Self {
            func,
            cdf,
            integral,
        }
    }

    /// A point in `[0, 1)` for `u`, with its density and its bin.
    #[inline]
    fn sample(&self, u: Real) -> (Real, Real, usize) {
        let n = self.func.len();
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(n - 1);
        let width = self.cdf[i + 1] - self.cdf[i];
        let du = if width > 0.0 {
            (u - self.cdf[i]) / width
        } else {
            0.0
        };
        let pdf = self.pdf(i);
        (
            ((i as Real + du) / n as Real).min(1.0 - Real::EPSILON),
            pdf,
            i,
        )
    }

    /// Density of bin `i`.
    #[inline]
    fn pdf(&self, i: usize) -> Real {
        if self.integral > 0.0 {
            self.func[i] / self.integral
        } else {
            1.0
        }
    }
}

/// The environment as the renderer holds it.
#[derive(Clone, Debug)]
pub(crate) struct Environment {
    /// Constant radiance scale (`color · intensity`).
    scale: Rgb,
    image: Option<std::sync::Arc<EnvImage>>,
    /// One conditional distribution per row, over the columns.
    rows: Vec<Distribution1D>,
    /// The marginal distribution over the rows.
    marginal: Distribution1D,
}

/// A direction sampled on the environment.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EnvSample {
    /// Unit direction towards the environment.
    pub wi: Vec3,
    /// Radiance arriving from it.
    pub radiance: Rgb,
    /// Density per unit solid angle.
    pub pdf: Real,
}

impl Environment {
    /// The environment of radiance `scale` times `image` (or constant).
    pub(crate) fn new(scale: Rgb, image: Option<std::sync::Arc<EnvImage>>) -> Self {
        let mut env = Self {
            scale,
            image: None,
            rows: Vec::new(),
            marginal: Distribution1D::default(),
        };
        let Some(img) = image.filter(|i| i.width > 0 && i.height > 0) else {
            return env;
        };
        let (w, h) = (img.width as usize, img.height as usize);
        let mut marginal = Vec::with_capacity(h);
        for r in 0..h {
            // Rows near the poles cover less solid angle: weight by sin θ.
            let sin = ((r as Real + 0.5) / h as Real * PI).sin();
            let func: Vec<Real> = img.pixels[r * w..(r + 1) * w]
                .iter()
                .map(|p| Real::from(p.x + p.y + p.z) / 3.0 * sin)
                .collect();
            let d = Distribution1D::new(func);
            marginal.push(d.integral);
            env.rows.push(d);
        }
        env.marginal = Distribution1D::new(marginal);
        env.image = Some(img);
        env
    }

    /// Whether it has an image to importance-sample.
    #[inline]
    pub(crate) fn sampled(&self) -> bool {
        self.image.is_some() && self.marginal.integral > 0.0
    }

    /// Radiance arriving along the unit direction `-d` from direction `d`.
    #[inline]
    pub(crate) fn radiance(&self, d: Vec3) -> Rgb {
        match &self.image {
            None => self.scale,
            Some(img) => {
                let (c, r) = pixel(d, img.width, img.height);
                self.scale * img.pixels[r * img.width as usize + c]
            }
        }
    }

    /// Samples a direction by `u` in proportion to radiance × sin θ.
    #[inline]
    pub(crate) fn sample(&self, u: (Real, Real)) -> Option<EnvSample> {
        let img = self.image.as_ref()?;
        let (v, pdf_v, r) = self.marginal.sample(u.0);
        let (uu, pdf_u, c) = self.rows[r].sample(u.1);
        let (theta, phi) = (v * PI, (uu - 0.5) * 2.0 * PI);
        let sin = theta.sin();
        if !(sin > 0.0) {
            return None;
        }
        let wi = Vec3::new(sin * phi.sin(), theta.cos(), -sin * phi.cos());
        let pdf = pdf_v * pdf_u / (2.0 * PI * PI * sin);
        let radiance = self.scale * img.pixels[r * img.width as usize + c];
        (pdf > 0.0).then_some(EnvSample { wi, radiance, pdf })
    }

    /// A direction of light arriving at a surface of (unit) normal `n`:
    /// by the image when it has one ([`Environment::sample`]), else
    /// cosine-weighted about `n` (Suffern's environment light), which
    /// makes the estimate of a constant environment on a diffuse surface
    /// noise-free where nothing occludes it.
    #[inline]
    pub(crate) fn sample_at(&self, n: Vec3, u: (Real, Real)) -> Option<EnvSample> {
        if self.sampled() {
            return self.sample(u);
        }
        let local = crate::sampling::maps::cosine_hemisphere(u);
        let pdf = crate::sampling::maps::cosine_hemisphere_pdf(local.z);
        let wi = crate::sampling::maps::Frame::new(n).to_world(local);
        (pdf > 0.0).then_some(EnvSample {
            wi,
            radiance: self.scale,
            pdf,
        })
    }

    /// Density per unit solid angle with which [`Environment::sample`]
    /// picks the unit direction `d`.
    #[inline]
    pub(crate) fn pdf(&self, d: Vec3) -> Real {
        let Some(img) = &self.image else {
            return 0.0;
        };
        let (c, r) = pixel(d, img.width, img.height);
        let sin = (1.0 - d.y * d.y).max(0.0).sqrt();
        if !(sin > 0.0) {
            return 0.0;
        }
        self.marginal.pdf(r) * self.rows[r].pdf(c) / (2.0 * PI * PI * sin)
    }
}

/// The pixel (column, row) of the unit direction `d`.
#[inline]
fn pixel(d: Vec3, w: u32, h: u32) -> (usize, usize) {
    let u = 0.5 + d.x.atan2(-d.z) / (2.0 * PI);
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    let c = ((u * w as Real) as usize).min(w as usize - 1);
    let r = ((v * h as Real) as usize).min(h as usize - 1);
    (c, r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> Rgb) -> Arc<EnvImage> {
        let mut pixels = Vec::new();
        for r in 0..h {
            for c in 0..w {
                pixels.push(f(c, r));
            }
        }
        Arc::new(EnvImage {
            width: w,
            height: h,
            pixels,
        })
    }

    #[test]
    fn directions_map_to_the_documented_pixels() {
        let img = image(8, 4, |c, r| Rgb::new(c as f32, r as f32, 0.0));
        let env = Environment::new(Rgb::ONE, Some(img));
        // −z at the horizon is the image centre; +y the top row.
        let l = env.radiance(Vec3::new(0.0, -0.01, -1.0).normalize());
        assert_eq!((l.x, l.y), (4.0, 2.0));
        assert_eq!(env.radiance(Vec3::Y).y, 0.0);
        assert_eq!(env.radiance(Vec3::NEG_Y).y, 3.0);
        // +x is three quarters across.
        assert_eq!(env.radiance(Vec3::new(1.0, 0.01, 0.0).normalize()).x, 6.0);
    }

    #[test]
    fn sampling_follows_the_image_and_pdfs_agree() {
        // A bright patch: most samples land in it.
        let img = image(32, 16, |c, r| {
            if (10..14).contains(&c) && (5..8).contains(&r) {
                Rgb::splat(50.0)
            } else {
                Rgb::splat(0.5)
            }
        });
        let env = Environment::new(Rgb::ONE, Some(img));
        let n = 64;
        let mut bright = 0;
        for i in 0..n {
            for j in 0..n {
                let u = ((i as Real + 0.5) / n as Real, (j as Real + 0.5) / n as Real);
                let s = env.sample(u).unwrap();
                assert!((s.wi.length() - 1.0).abs() < 1e-4);
                let p = env.pdf(s.wi);
                assert!((p - s.pdf).abs() < 1e-3 * s.pdf, "{p} vs {}", s.pdf);
                assert_eq!(env.radiance(s.wi), s.radiance);
                bright += usize::from(s.radiance.x > 1.0);
            }
        }
        assert!(bright > n * n * 3 / 4, "{bright}");
    }

    #[test]
    fn the_density_integrates_to_one() {
        let img = image(16, 8, |c, r| Rgb::splat(1.0 + (c * r) as f32));
        let env = Environment::new(Rgb::ONE, Some(img));
        let n = 300;
        let mut total = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = ((i as Real + 0.5) / n as Real, (j as Real + 0.5) / n as Real);
                let d = crate::sampling::maps::uniform_sphere(u);
                total += crate::float::to_f64(env.pdf(d)) * 4.0 * std::f64::consts::PI;
            }
        }
        total /= f64::from(n * n);
        assert!((total - 1.0).abs() < 0.01, "{total}");
    }

    #[test]
    fn a_constant_environment_is_not_sampled() {
        let env = Environment::new(Rgb::splat(2.0), None);
        assert!(!env.sampled());
        assert!(env.sample((0.3, 0.4)).is_none());
        assert_eq!(env.radiance(Vec3::X), Rgb::splat(2.0));
    }
}
