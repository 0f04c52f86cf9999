//! Command-line overrides of how light is simulated: the sampler and the
//! reconstruction filter (`gridrt render --sampler … --filter …`).

use clap::{Args, ValueEnum};
use gridrt_tracer::{Filter, SamplerKind, Settings};

/// Sampling options of `gridrt render`.
#[derive(Debug, Clone, Default, Args)]
pub struct EffectArgs {
    /// How samples are placed in each pixel (overrides the scene).
    #[arg(long, value_name = "KIND")]
    pub sampler: Option<SamplerArg>,
    /// Reconstruction filter (overrides the scene): `box`, or
    /// `gaussian[:RADIUS[:SIGMA]]` in pixels (default 1.5 and 0.5).
    #[arg(long, value_name = "FILTER", value_parser = parse_filter)]
    pub filter: Option<Filter>,
}

/// The samplers, as the command line names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SamplerArg {
    /// Independent random numbers (hashed: reproducible).
    Random,
    /// Centres of a regular grid of strata.
    Regular,
    /// One random point per stratum.
    Jittered,
    /// Correlated multi-jittered (the default).
    MultiJittered,
    /// The Hammersley set, scrambled per pixel.
    Hammersley,
    /// Owen-scrambled Sobol points.
    Sobol,
}

impl SamplerArg {
    fn kind(self) -> SamplerKind {
        match self {
            Self::Random => SamplerKind::Random,
            Self::Regular => SamplerKind::Regular,
            Self::Jittered => SamplerKind::Jittered,
            Self::MultiJittered => SamplerKind::MultiJittered,
            Self::Hammersley => SamplerKind::Hammersley,
            Self::Sobol => SamplerKind::Sobol,
        }
    }
}

/// Parses `box` or `gaussian[:RADIUS[:SIGMA]]`.
fn parse_filter(s: &str) -> Result<Filter, String> {
    let mut parts = s.split(':');
    let name = parts.next().unwrap_or_default();
    let mut number = |what: &str, default: f32| -> Result<f32, String> {
        match parts.next() {
            None => Ok(default),
            Some(t) => t
                .parse::<f32>()
                .map_err(|_| format!("the {what} `{t}` is not a number")),
        }
    };
    let f = match name {
        "box" => Filter::Box,
        "gaussian" => Filter::Gaussian {
            radius: number("radius", 1.5)?,
            sigma: number("sigma", 0.5)?,
        },
        _ => {
            return Err(format!(
                "unknown filter `{name}`: use `box` or `gaussian[:RADIUS[:SIGMA]]`"
            ))
        }
    };
    if parts.next().is_some() {
        return Err(format!(
            "`{s}` has too many parts: use `gaussian:RADIUS:SIGMA`"
        ));
    }
    if !f.is_valid() {
        return Err(format!(
            "`{s}`: the radius must be in (0, 16] pixels and sigma > 0"
        ));
    }
    Ok(f)
}

impl EffectArgs {
    /// Applies the overrides to the scene's settings.
    pub(crate) fn apply(&self, settings: &mut Settings) {
        if let Some(s) = self.sampler {
            settings.sampler = s.kind();
        }
        if let Some(f) = self.filter {
            settings.filter = f;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_parse_and_bad_ones_say_why() {
        assert_eq!(parse_filter("box"), Ok(Filter::Box));
        assert_eq!(
            parse_filter("gaussian"),
            Ok(Filter::Gaussian {
                radius: 1.5,
                sigma: 0.5
            })
        );
        assert_eq!(
            parse_filter("gaussian:2:0.7"),
            Ok(Filter::Gaussian {
                radius: 2.0,
                sigma: 0.7
            })
        );
        assert!(parse_filter("mitchell")
            .unwrap_err()
            .contains("unknown filter"));
        assert!(parse_filter("gaussian:x")
            .unwrap_err()
            .contains("not a number"));
        assert!(parse_filter("gaussian:0").unwrap_err().contains("radius"));
        assert!(parse_filter("gaussian:1:1:1").is_err());
    }
}
