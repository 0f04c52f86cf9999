//! The `Settings(...)` block of a scene file: image size, samples, sampler,
//! reconstruction filter, depth and background, with their defaults.

use crate::schema::{check_pixels, Color, Depth, Positive, Side, Spp};
use gridrt_tracer::{Filter, IntegratorChoice, SamplerKind};
use serde::Deserialize;

/// `Settings(width: 160, height: 120, spp: 1, max_depth: 5, background: (r, g, b),
/// sampler: MultiJittered, filter: Box)`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(try_from = "RawSettings")]
pub(crate) struct SettingsDesc {
    pub width: Side,
    pub height: Side,
    pub spp: Spp,
    pub max_depth: Depth,
    pub background: Color,
    pub sampler: SamplerDesc,
    pub filter: FilterDesc,
    pub integrator: IntegratorDesc,
    /// `None`: the integrator's default (5 for Whitted, 64 for paths).
    pub max_depth_given: Option<Depth>,
}

/// [`SettingsDesc`] before the cross-field check (total pixel count).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, rename = "Settings")]
struct RawSettings {
    #[serde(default = "default_side_w")]
    width: Side,
    #[serde(default = "default_side_h")]
    height: Side,
    #[serde(default = "default_spp")]
    spp: Spp,
    #[serde(default)]
    max_depth: Option<Depth>,
    #[serde(default = "default_background")]
    background: Color,
    #[serde(default)]
    sampler: SamplerDesc,
    #[serde(default)]
    filter: FilterDesc,
    #[serde(default)]
    integrator: IntegratorDesc,
}

fn default_side_w() -> Side {
    Side(gridrt_tracer::Settings::default().width)
}
fn default_side_h() -> Side {
    Side(gridrt_tracer::Settings::default().height)
}
fn default_spp() -> Spp {
    Spp(gridrt_tracer::Settings::default().spp)
}
fn default_depth() -> Depth {
    Depth(gridrt_tracer::Settings::default().max_depth)
}
fn default_background() -> Color {
    let b = gridrt_tracer::Settings::default().background;
    Color([f64::from(b.x), f64::from(b.y), f64::from(b.z)])
}

impl TryFrom<RawSettings> for SettingsDesc {
    type Error = String;
    fn try_from(r: RawSettings) -> Result<Self, String> {
        check_pixels(r.width.0, r.height.0)?;
        Ok(Self {
            width: r.width,
            height: r.height,
            spp: r.spp,
            max_depth: r.max_depth.unwrap_or_else(default_depth),
            background: r.background,
            sampler: r.sampler,
            filter: r.filter,
            integrator: r.integrator,
            max_depth_given: r.max_depth,
        })
    }
}

impl Default for SettingsDesc {
    fn default() -> Self {
        Self {
            width: default_side_w(),
            height: default_side_h(),
            spp: default_spp(),
            max_depth: default_depth(),
            background: default_background(),
            sampler: SamplerDesc::default(),
            filter: FilterDesc::default(),
            integrator: IntegratorDesc::default(),
            max_depth_given: None,
        }
    }
}

/// `sampler: Random | Regular | Jittered | MultiJittered | Hammersley | Sobol`.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename = "Sampler")]
pub(crate) enum SamplerDesc {
    Random,
    Regular,
    Jittered,
    #[default]
    MultiJittered,
    Hammersley,
    Sobol,
}

impl SamplerDesc {
    /// The tracer's sampler.
    pub(crate) fn kind(self) -> SamplerKind {
        match self {
            SamplerDesc::Random => SamplerKind::Random,
            SamplerDesc::Regular => SamplerKind::Regular,
            SamplerDesc::Jittered => SamplerKind::Jittered,
            SamplerDesc::MultiJittered => SamplerKind::MultiJittered,
            SamplerDesc::Hammersley => SamplerKind::Hammersley,
            SamplerDesc::Sobol => SamplerKind::Sobol,
        }
    }
}

/// `integrator: Auto | Whitted | Path`.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename = "Integrator")]
pub(crate) enum IntegratorDesc {
    #[default]
    Auto,
    Whitted,
    Path,
}

impl IntegratorDesc {
    /// The tracer's choice.
    pub(crate) fn choice(self) -> IntegratorChoice {
        match self {
            IntegratorDesc::Auto => IntegratorChoice::Auto,
            IntegratorDesc::Whitted => IntegratorChoice::Whitted,
            IntegratorDesc::Path => IntegratorChoice::Path,
        }
    }
}

/// `filter: Box` or `filter: Gaussian(radius: 1.5, sigma: 0.5)`.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, rename = "Filter")]
pub(crate) enum FilterDesc {
    #[default]
    Box,
    Gaussian {
        #[serde(default = "default_radius")]
        radius: FilterRadius,
        #[serde(default = "default_sigma")]
        sigma: Positive,
    },
}

fn default_radius() -> FilterRadius {
    FilterRadius(1.5)
}
fn default_sigma() -> Positive {
    Positive(0.5)
}

/// A filter radius in pixels, in (0, 16].
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(try_from = "f64")]
pub(crate) struct FilterRadius(pub f64);

impl TryFrom<f64> for FilterRadius {
    type Error = String;
    fn try_from(x: f64) -> Result<Self, String> {
        if x.is_finite() && x > 0.0 && x <= 16.0 {
            Ok(Self(x))
        } else {
            Err(format!(
                "filter radius {x} is out of range: use (0, 16] pixels (1.5 is usual)"
            ))
        }
    }
}

impl FilterDesc {
    /// The tracer's filter.
    #[allow(clippy::cast_possible_truncation)] // radius ≤ 16, sigma checked finite
    pub(crate) fn filter(self) -> Filter {
        match self {
            FilterDesc::Box => Filter::Box,
            FilterDesc::Gaussian { radius, sigma } => Filter::Gaussian {
                radius: radius.0 as f32,
                sigma: (sigma.0 as f32).max(f32::MIN_POSITIVE),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schema::ron_options;

    fn parse(text: &str) -> Result<SettingsDesc, ron::error::SpannedError> {
        ron_options().from_str(text)
    }

    #[test]
    fn sampler_and_filter_parse_with_defaults() {
        let s = parse("(spp: 4)").unwrap();
        assert_eq!(s.sampler.kind(), SamplerKind::MultiJittered);
        assert_eq!(s.filter.filter(), Filter::Box);
        let s = parse("(sampler: Sobol, filter: Gaussian(radius: 2))").unwrap();
        assert_eq!(s.sampler.kind(), SamplerKind::Sobol);
        assert_eq!(
            s.filter.filter(),
            Filter::Gaussian {
                radius: 2.0,
                sigma: 0.5
            }
        );
        assert!(parse("(filter: Gaussian(radius: 0))").is_err());
        assert!(parse("(filter: Gaussian(radius: 1, sigma: -1))").is_err());
        assert!(parse("(sampler: Halton)").is_err());
        let s = parse("(integrator: Path)").unwrap();
        assert_eq!(s.integrator.choice(), IntegratorChoice::Path);
        assert_eq!((s.max_depth.0, s.max_depth_given), (5, None));
        let s = parse("(max_depth: 7)").unwrap();
        assert_eq!(s.max_depth_given.map(|d| d.0), Some(7));
        assert!(parse("(integrator: Bidirectional)").is_err());
    }
}
