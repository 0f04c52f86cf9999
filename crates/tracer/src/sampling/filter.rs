//! Pixel reconstruction filters, applied by filter importance sampling
//! (pbrt-v4 §8.8): each camera sample's offset from the pixel centre is
//! drawn from the filter's shape, and the pixel is the weighted mean
//! `Σ w·L / Σ w` of its own samples. A pixel depends only on its own samples,
//! so tiles stay independent and images bit-identical at any thread count.

use gridrt_bbox::Real;
use std::fmt;

/// A reconstruction filter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Filter {
    /// The pixel's own square, uniformly weighted (the default).
    #[default]
    Box,
    /// A Gaussian of standard deviation `sigma` pixels, truncated at
    /// `radius` pixels from the centre (and shifted to reach 0 there, as in
    /// pbrt). pbrt's defaults are radius 1.5, sigma 0.5.
    Gaussian {
        /// Support radius in pixels, > 0.
        radius: f32,
        /// Standard deviation in pixels, > 0.
        sigma: f32,
    },
}

impl Filter {
    /// A short description for the render summary.
    #[must_use]
    pub fn describe(&self) -> String {
        match *self {
            Filter::Box => "box".to_string(),
            Filter::Gaussian { radius, sigma } => {
                format!("gaussian (radius {radius} px, sigma {sigma} px)")
            }
        }
    }

    /// Whether the parameters are usable (finite and positive).
    #[must_use]
    pub fn is_valid(&self) -> bool {
        match *self {
            Filter::Box => true,
            Filter::Gaussian { radius, sigma } => {
                radius.is_finite()
                    && radius > 0.0
                    && radius <= 16.0
                    && sigma.is_finite()
                    && sigma > 0.0
            }
        }
    }
}

impl fmt::Display for Filter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.describe())
    }
}

/// Bins of the tabulated 1D filter profile.
const BINS: usize = 64;

/// A filter ready for sampling: for separable filters, the 1D profile on
/// `[0, radius]` tabulated as a piecewise-constant density.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FilterTable {
    radius: Real,
    /// `None` for the box filter.
    gauss: Option<Gauss>,
}

#[derive(Clone, Debug, PartialEq)]
struct Gauss {
    sigma: Real,
    /// The profile's value at the radius, subtracted so it ends at 0.
    floor: Real,
    /// Bin values of the profile (at the bin centres).
    values: [Real; BINS],
    /// Cumulative sums of `values`, normalised: `cdf[BINS] = 1`.
    cdf: [Real; BINS + 1],
    /// `Σ values · bin width`: the integral of the profile on `[0, radius]`.
    integral: Real,
}

impl Gauss {
    #[inline]
    fn profile(&self, x: Real) -> Real {
        ((-x * x / (2.0 * self.sigma * self.sigma)).exp() - self.floor).max(0.0)
    }
}

impl FilterTable {
    pub(crate) fn new(filter: Filter) -> Self {
        match filter {
            Filter::Box => Self {
                radius: 0.5,
                gauss: None,
            },
            Filter::Gaussian { radius, sigma } => {
                let radius = radius as Real;
                let sigma = sigma as Real;
                let mut g = Gauss {
                    sigma,
                    floor: 0.0,
                    values: [0.0; BINS],
                    cdf: [0.0; BINS + 1],
                    integral: 0.0,
                };
                g.floor = (-radius * radius / (2.0 * sigma * sigma)).exp();
                let dx = radius / BINS as Real;
                for i in 0..BINS {
                    g.values[i] = g.profile((i as Real + 0.5) * dx);
                    g.cdf[i + 1] = g.cdf[i] + g.values[i];
                }
                let total = g.cdf[BINS];
                g.integral = total * dx;
                for c in &mut g.cdf {
                    *c /= total;
                }
                Self {
                    radius,
                    gauss: Some(g),
                }
            }
        }
    }

    /// One axis: an offset from the pixel centre in pixels and its weight
    /// `f(x)/p(x)` (up to a constant that cancels in `Σ w·L / Σ w`).
    #[inline]
    fn axis(&self, u: Real) -> (Real, Real) {
        let Some(g) = &self.gauss else {
            return (u - 0.5, 1.0);
        };
        // The sign from the first half of u, |x| from the rest.
        let (sign, u) = if u < 0.5 {
            (-1.0, 2.0 * u)
        } else {
            (1.0, 2.0 * u - 1.0)
        };
        let i = g.cdf[1..].partition_point(|&c| c <= u).min(BINS - 1);
        let lo = g.cdf[i];
        let width = g.cdf[i + 1] - lo;
        let frac = if width > 0.0 { (u - lo) / width } else { 0.5 };
        let dx = self.radius / BINS as Real;
        let x = (i as Real + frac.clamp(0.0, 1.0)) * dx;
        // Density of |x| is values[i] / integral on [0, r].
        let pdf = g.values[i] / g.integral;
        let w = if pdf > 0.0 { g.profile(x) / pdf } else { 0.0 };
        (sign * x, w)
    }

    /// A sample position inside the pixel grid's cell coordinates
    /// (`0.5, 0.5` is the centre) and its weight.
    #[inline]
    pub(crate) fn sample(&self, u: (Real, Real)) -> (Real, Real, f32) {
        if self.gauss.is_none() {
            // The box: the sample as drawn (bit for bit), weight 1.
            return (u.0, u.1, 1.0);
        }
        let (x, wx) = self.axis(u.0);
        let (y, wy) = self.axis(u.1);
        (0.5 + x, 0.5 + y, crate::float::to_f32(wx * wy))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_filter_is_the_pixel() {
        let t = FilterTable::new(Filter::Box);
        assert_eq!(t.sample((0.25, 0.75)), (0.25, 0.75, 1.0));
    }

    #[test]
    fn gaussian_offsets_follow_the_filter() {
        let filter = Filter::Gaussian {
            radius: 1.5,
            sigma: 0.5,
        };
        let t = FilterTable::new(filter);
        // The weighted second moment Σ w·x² / Σ w of stratified samples is
        // the filter's own, ∫ x² f / ∫ f (by the midpoint rule).
        let n = 20_000;
        let (mut sw, mut sx2) = (0.0f64, 0.0f64);
        for i in 0..n {
            let (x, w) = t.axis((i as Real + 0.5) / n as Real);
            assert!(x.abs() <= 1.5 && w >= 0.0);
            sw += crate::float::to_f64(w);
            sx2 += crate::float::to_f64(w) * crate::float::to_f64(x * x);
        }
        let f = |x: f64| ((-2.0 * x * x).exp() - (-4.5f64).exp()).max(0.0);
        let (mut a, mut b) = (0.0, 0.0);
        for i in 0..n {
            let x = -1.5 + 3.0 * (f64::from(i) + 0.5) / f64::from(n);
            a += x * x * f(x);
            b += f(x);
        }
        let (got, want) = (sx2 / sw, a / b);
        assert!(
            (got - want).abs() < 0.002 * want.max(1.0),
            "{got} vs {want}"
        );
        // Offsets near the centre are more likely than near the edge.
        let near = (0..n)
            .filter(|&i| t.axis((i as Real + 0.5) / n as Real).0.abs() < 0.5)
            .count();
        assert!(near as f64 > 0.6 * f64::from(n), "{near}");
    }

    #[test]
    fn bad_parameters_are_rejected() {
        assert!(!Filter::Gaussian {
            radius: 0.0,
            sigma: 0.5
        }
        .is_valid());
        assert!(!Filter::Gaussian {
            radius: 1.0,
            sigma: f32::NAN
        }
        .is_valid());
        assert!(Filter::Box.is_valid());
    }
}
