//! What a render reports: the plan, timings, rays by kind, the grid.

use crate::plan::{EffectPlan, RayCounts};
use gridrt_grid::GridStats;
use std::fmt;
use std::time::Duration;

/// What a render did and how long it took.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct RenderStats {
    /// The effects simulated.
    pub plan: EffectPlan,
    /// Building the accelerator (and preparing the scene).
    #[cfg_attr(
        feature = "serde",
        serde(serialize_with = "crate::serde_support::duration_secs")
    )]
    pub build_time: Duration,
    /// Rendering the pixels.
    #[cfg_attr(
        feature = "serde",
        serde(serialize_with = "crate::serde_support::duration_secs")
    )]
    pub render_time: Duration,
    /// Rays traced, by kind.
    pub rays: RayCounts,
    /// Pixels where at least one camera ray hit something.
    pub pixels_hit: u64,
    /// The grid's statistics (`None` for the exhaustive accelerator).
    #[cfg_attr(
        feature = "serde",
        serde(serialize_with = "crate::serde_support::grid_stats")
    )]
    pub grid: Option<GridStats>,
}

impl RenderStats {
    /// Millions of rays (all kinds) per second of render time.
    #[must_use]
    pub fn mrays_per_sec(&self) -> f64 {
        let s = self.render_time.as_secs_f64();
        if s > 0.0 {
            self.rays.total() as f64 / s * 1e-6
        } else {
            0.0
        }
    }
}

impl fmt::Display for RenderStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.plan)?;
        writeln!(f, "rays        {}", self.rays)?;
        writeln!(f, "pixels hit  {}", self.pixels_hit)?;
        if let Some(g) = &self.grid {
            writeln!(
                f,
                "grid        {}×{}×{} cells, {} occupied, {} references ({:.2} per occupied cell, max {}), {:.1} MiB",
                g.dims[0],
                g.dims[1],
                g.dims[2],
                g.occupied_cells,
                g.references,
                g.mean_refs_per_occupied,
                g.max_refs_per_cell,
                g.bytes as f64 / (1024.0 * 1024.0)
            )?;
        }
        write!(
            f,
            "time        build {:.3} s, render {:.3} s ({:.2} Mrays/s)",
            self.build_time.as_secs_f64(),
            self.render_time.as_secs_f64(),
            self.mrays_per_sec()
        )
    }
}
