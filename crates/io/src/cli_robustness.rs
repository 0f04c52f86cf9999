//! The command-line switches that turn robustness off (`--triangle-test`,
//! `--slab`, `--ray-offset`), the grid's optional work (`--mailbox`,
//! `--exact-insertion`) and how it stores triangles (`--triangles`), for
//! `gridrt render` and `gridrt rays`. The defaults are the robust choices;
//! docs/cli.md says what each switch risks.

use crate::error::{Error, Result};
use clap::{Args, ValueEnum};
use gridrt_bbox::{Real, SlabTest};
use gridrt_grid::GridConfig;
use gridrt_tracer::{RayOffset, RenderOptions, TriangleStorage, TriangleTest};

/// How rays meet primitives: shared by `render` and `rays`.
#[derive(Debug, Clone, Copy, Args)]
pub struct IntersectArgs {
    /// The ray–triangle test: `watertight` (default; no ray leaks between
    /// triangles sharing an edge) or `moller-trumbore` (the textbook test
    /// with a fixed epsilon: leaks through shared edges and vertices, and
    /// misses small or thin triangles).
    #[arg(long = "triangle-test", value_enum, default_value_t = TriangleTestArg::Watertight)]
    pub triangle_test: TriangleTestArg,
    /// The ray–box test where rays enter the grid: `robust` (default) or
    /// `textbook` (can cull a ray lying in a face of the grid's box).
    #[arg(long, value_enum, default_value_t = SlabArg::Robust)]
    pub slab: SlabArg,
    /// Skip primitives a ray has already tested in another cell
    /// (mailboxing). Changes no pixel; off by default.
    #[arg(long)]
    pub mailbox: bool,
    /// Insert a primitive only into the cells it really touches (triangle–
    /// box and sphere–box tests) rather than every cell its bounding box
    /// overlaps. Changes no pixel; slower build; off by default.
    #[arg(long = "exact-insertion")]
    pub exact_insertion: bool,
    /// How the grid stores a mesh's triangles: `copies` (each triangle
    /// holds its three vertices, 40 bytes), `indexed` (three indices into
    /// one vertex array: 12 bytes, each vertex once, a slower trace) or
    /// `auto` (the default: indexed from 262,144 triangles on, with the
    /// watertight test). Changes no pixel. Scenes with other shapes than
    /// triangles keep copies.
    #[arg(long, value_enum, default_value_t = TrianglesArg::Auto)]
    pub triangles: TrianglesArg,
}

/// `--triangles` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TrianglesArg {
    /// Indexed for large meshes, copies otherwise.
    Auto,
    /// Each triangle holds its vertices.
    Copies,
    /// Each triangle holds the indices of its vertices.
    Indexed,
}

/// `--triangle-test` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TriangleTestArg {
    /// Woop, Benthin & Wald's watertight test (the default).
    Watertight,
    /// Möller & Trumbore's test with its 10⁻⁶ determinant epsilon.
    MollerTrumbore,
}

/// `--slab` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SlabArg {
    /// No `0·∞`, exit widened by 2·γ(3) (the default).
    Robust,
    /// Reciprocals straight into min/max.
    Textbook,
}

/// How secondary rays leave surfaces: `render` only (`rays` casts no
/// secondary rays).
#[derive(Debug, Clone, Copy, Args)]
pub struct OffsetArgs {
    /// How a shadow, reflection or refraction ray's origin leaves the
    /// surface: `error-bound` (default: by a bound on the hit point's
    /// rounding error) or `fixed:EPS` (along the normal by EPS world
    /// units, such as `fixed:1e-4`: acne where EPS is below the
    /// coordinates' rounding, leaks and lost contact shadows where it is
    /// above the scene's details).
    #[arg(long = "ray-offset", value_name = "error-bound|fixed:EPS", value_parser = parse_ray_offset, default_value = "error-bound")]
    pub ray_offset: RayOffset,
}

/// Parses `--ray-offset`.
fn parse_ray_offset(s: &str) -> std::result::Result<RayOffset, String> {
    if s == "error-bound" {
        return Ok(RayOffset::ErrorBound);
    }
    let Some(eps) = s.strip_prefix("fixed:") else {
        return Err(format!(
            "`{s}` is not a ray offset: use `error-bound` or `fixed:EPS` (such as `fixed:1e-4`)"
        ));
    };
    let e: f64 = eps.parse().map_err(|_| {
        format!("`{eps}` in `{s}` is not a number: use `fixed:EPS` such as `fixed:1e-4`")
    })?;
    let r = e as Real;
    if r.is_finite() && r > 0.0 {
        Ok(RayOffset::Fixed(r))
    } else {
        Err(format!(
            "the fixed offset {eps} must be a positive finite number (in this build's precision)"
        ))
    }
}

impl IntersectArgs {
    /// The grid configuration with these switches applied.
    pub(crate) fn grid(&self, mut g: GridConfig) -> GridConfig {
        g.mailbox = self.mailbox;
        g.exact_insertion = self.exact_insertion;
        g.slab = match self.slab {
            SlabArg::Robust => SlabTest::Robust,
            SlabArg::Textbook => SlabTest::Textbook,
        };
        g
    }

    /// The library's triangle test.
    pub(crate) fn triangle_test(&self) -> TriangleTest {
        match self.triangle_test {
            TriangleTestArg::Watertight => TriangleTest::Watertight,
            TriangleTestArg::MollerTrumbore => TriangleTest::MollerTrumbore,
        }
    }

    /// The library's triangle storage.
    pub(crate) fn triangle_storage(&self) -> TriangleStorage {
        match self.triangles {
            TrianglesArg::Auto => TriangleStorage::Auto,
            TrianglesArg::Copies => TriangleStorage::Copies,
            TrianglesArg::Indexed => TriangleStorage::Indexed,
        }
    }

    /// Refuses switches that do not go together: indexed triangles have
    /// only the watertight test.
    pub(crate) fn check(&self) -> Result<()> {
        if self.triangles == TrianglesArg::Indexed
            && self.triangle_test() != TriangleTest::Watertight
        {
            return Err(Error::arg(
                "--triangles",
                "indexed needs the watertight --triangle-test",
            ));
        }
        Ok(())
    }

    /// The render options with these switches (and `offset`'s) applied.
    pub(crate) fn options(&self, o: RenderOptions, offset: &OffsetArgs) -> RenderOptions {
        RenderOptions {
            grid: self.grid(o.grid),
            triangle_test: self.triangle_test(),
            triangles: self.triangle_storage(),
            ray_offset: offset.ray_offset,
            ..o
        }
    }

    pub(crate) fn label(&self, offset: Option<&OffsetArgs>) -> String {
        let mut s = Vec::new();
        if self.triangle_test == TriangleTestArg::MollerTrumbore {
            s.push("triangle test moller-trumbore".to_string());
        }
        if self.slab == SlabArg::Textbook {
            s.push("slab textbook".to_string());
        }
        if let Some(RayOffset::Fixed(e)) = offset.map(|o| o.ray_offset) {
            s.push(format!("ray offset fixed:{e}"));
        }
        if self.mailbox {
            s.push("mailbox".to_string());
        }
        if self.exact_insertion {
            s.push("exact insertion".to_string());
        }
        if self.triangles == TrianglesArg::Indexed {
            s.push("triangles indexed".to_string());
        }
        s.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_offsets_parse_and_bad_ones_say_why() {
        assert_eq!(parse_ray_offset("error-bound"), Ok(RayOffset::ErrorBound));
        assert_eq!(parse_ray_offset("fixed:1e-4"), Ok(RayOffset::Fixed(1e-4)));
        for bad in [
            "fixed:",
            "fixed:x",
            "fixed:0",
            "fixed:-1",
            "fixed:inf",
            "fixed:nan",
            "eps",
            "",
        ] {
            let e = parse_ray_offset(bad).unwrap_err();
            assert!(e.contains("fixed") || e.contains("offset"), "{bad}: {e}");
        }
    }
}
