//! Fresnel reflectance of conductors: Schlick's approximation from an
//! artist's colour at normal incidence, and the exact equations for a
//! complex index of refraction `η + i·k` (pbrt-v4's `FrComplex`).

use crate::scene::{ConductorFresnel, Rgb};

/// Schlick's approximation `F₀ + (1 − F₀)(1 − cos θ)⁵`.
#[inline]
pub(crate) fn schlick(f0: Rgb, cos: f32) -> Rgb {
    let m = (1.0 - cos.clamp(0.0, 1.0)).powi(5);
    f0 + (Rgb::ONE - f0) * m
}

/// A complex number, just enough for the Fresnel equations.
#[derive(Clone, Copy, Debug)]
struct C {
    re: f64,
    im: f64,
}

impl C {
    fn mul(self, o: C) -> C {
        C {
            re: self.re * o.re - self.im * o.im,
            im: self.re * o.im + self.im * o.re,
        }
    }
    fn div(self, o: C) -> C {
        let d = o.re * o.re + o.im * o.im;
        C {
            re: (self.re * o.re + self.im * o.im) / d,
            im: (self.im * o.re - self.re * o.im) / d,
        }
    }
    fn add(self, o: C) -> C {
        C {
            re: self.re + o.re,
            im: self.im + o.im,
        }
    }
    fn sub(self, o: C) -> C {
        C {
            re: self.re - o.re,
            im: self.im - o.im,
        }
    }
    fn norm(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
    fn sqrt(self) -> C {
        let n = self.norm().sqrt();
        if n == 0.0 {
            return C { re: 0.0, im: 0.0 };
        }
        let t1 = (0.5 * (n + self.re.abs())).sqrt();
        let t2 = 0.5 * self.im / t1;
        if self.re >= 0.0 {
            C { re: t1, im: t2 }
        } else {
            C {
                re: t2.abs(),
                im: t1.copysign(self.im),
            }
        }
    }
}

/// Reflectance of a conductor of complex index `eta + i·k` (relative to
/// the outside) for unpolarised light at incident cosine `cos_i`.
pub(crate) fn fr_complex(cos_i: f32, eta: f32, k: f32) -> f32 {
    let ci = f64::from(cos_i.clamp(0.0, 1.0));
    let e = C {
        re: f64::from(eta),
        im: f64::from(k),
    };
    let sin2_i = 1.0 - ci * ci;
    let sin2_t = C {
        re: sin2_i,
        im: 0.0,
    }
    .div(e.mul(e));
    let cos_t = C { re: 1.0, im: 0.0 }.sub(sin2_t).sqrt();
    let ci = C { re: ci, im: 0.0 };
    let r_parl = e.mul(ci).sub(cos_t).div(e.mul(ci).add(cos_t));
    let r_perp = ci.sub(e.mul(cos_t)).div(ci.add(e.mul(cos_t)));
    let r = 0.5 * (r_parl.norm() + r_perp.norm());
    if r.is_finite() {
        r as f32
    } else {
        1.0
    }
}

impl ConductorFresnel {
    /// Reflectance at incident cosine `cos`.
    #[inline]
    pub(crate) fn eval(&self, cos: f32) -> Rgb {
        match *self {
            ConductorFresnel::Schlick { f0 } => schlick(f0, cos),
            ConductorFresnel::Complex { eta, k } => Rgb::new(
                fr_complex(cos, eta.x, k.x),
                fr_complex(cos, eta.y, k.y),
                fr_complex(cos, eta.z, k.z),
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn complex_fresnel_matches_the_normal_incidence_closed_form() {
        // Gold-like values at 600 nm.
        let (n, k) = (0.2f32, 3.0f32);
        let expected = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        assert!((fr_complex(1.0, n, k) - expected).abs() < 1e-5);
        // Without absorption it is the dielectric's reflectance.
        let d = crate::optics::fresnel_dielectric(0.5, 1.5);
        assert!((f64::from(fr_complex(0.5, 1.5, 0.0)) - crate::float::to_f64(d)).abs() < 1e-5);
        // Grazing: everything reflects.
        assert!((fr_complex(0.0, n, k) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn schlick_goes_from_f0_to_one() {
        let f0 = Rgb::new(0.9, 0.6, 0.2);
        assert!((schlick(f0, 1.0) - f0).length() < 1e-6);
        assert!((schlick(f0, 0.0) - Rgb::ONE).length() < 1e-6);
    }
}
