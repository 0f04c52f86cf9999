//! The accelerator a renderer runs, over the compact primitive type its
//! scene allows, and how the options build it.

use crate::render::{AccelKind, RenderOptions};
use crate::robustness::TriangleTest;
use crate::shapes::{MeshTriangle, Shape, Sphere, Triangle};
use gridrt_grid::{CellStorage, Exhaustive, Grid, GridConfig, GridStats, Primitive};

/// How a renderer's accelerator stores the triangles of a scene made of
/// meshes alone (other scenes hold [`Shape`]s). The images are the same.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TriangleStorage {
    /// [`Self::Indexed`] for scenes of at least [`INDEXED_FROM`] triangles
    /// traced with the watertight test, [`Self::Copies`] otherwise: large
    /// meshes take about half the memory, small ones trace at full speed.
    #[default]
    Auto,
    /// Each triangle holds its three vertices ([`Triangle`], 40 bytes in
    /// `f32`): the fastest to trace.
    Copies,
    /// Each triangle holds the indices of its vertices in one array of
    /// the scene's vertices ([`MeshTriangle`], 12 bytes, and 16 bytes a
    /// vertex): less memory for large meshes, a slower trace (about 1.05×
    /// on the dragon's render). Scenes of more than
    /// [`MeshTriangle::MAX_VERTICES`] vertices, and the Möller–Trumbore
    /// test, keep copies.
    Indexed,
}

/// [`TriangleStorage::Auto`] stores a scene's triangles indexed from this
/// many on. Below it the copies' extra memory (about 20 bytes a triangle,
/// 5 MiB here) is small beside what the process needs anyway, and the
/// copies trace faster; above it the memory they save grows with the
/// mesh (17 MiB on the 871,414-triangle dragon).
pub const INDEXED_FROM: usize = 1 << 18;

impl TriangleStorage {
    /// What the storage is for a scene of `triangles` mesh triangles:
    /// [`Self::Auto`] decided, the others as they are.
    #[must_use]
    pub fn resolve(self, triangles: usize) -> Self {
        match self {
            Self::Auto if triangles >= INDEXED_FROM => Self::Indexed,
            Self::Auto => Self::Copies,
            s => s,
        }
    }

    /// The storage for triangles traced with `test`: indexed triangles
    /// have the watertight test alone (Möller–Trumbore would copy them
    /// back), so [`Self::Auto`] keeps copies for the other test.
    #[must_use]
    pub fn for_test(self, test: TriangleTest) -> Self {
        match (self, test) {
            (Self::Auto, TriangleTest::MollerTrumbore) => Self::Copies,
            (s, _) => s,
        }
    }
}

/// An accelerator over one primitive type.
#[derive(Debug)]
#[allow(clippy::large_enum_variant)] // one per renderer
pub(crate) enum AccelOf<P: Primitive> {
    Grid(Grid<P>),
    Exhaustive(Exhaustive<P>),
}

/// Runs `$body` with `$a` bound to the concrete accelerator (one
/// monomorphised copy of the body per accelerator type).
macro_rules! with_accel {
    ($accel:expr, |$a:ident| $body:expr) => {
        match $accel {
            Accel::Spheres(AccelOf::Grid($a)) => $body,
            Accel::Spheres(AccelOf::Exhaustive($a)) => $body,
            Accel::Triangles(AccelOf::Grid($a)) => $body,
            Accel::Triangles(AccelOf::Exhaustive($a)) => $body,
            Accel::Mesh(AccelOf::Grid($a)) => $body,
            Accel::Mesh(AccelOf::Exhaustive($a)) => $body,
            Accel::Shapes(AccelOf::Grid($a)) => $body,
            Accel::Shapes(AccelOf::Exhaustive($a)) => $body,
        }
    };
}
pub(crate) use with_accel;

/// The accelerator of a prepared scene: spheres only get the compact
/// [`Sphere`] primitive, mesh triangles only the [`Triangle`] (40 bytes a
/// primitive, no tag to match) or, with [`TriangleStorage::Indexed`], the
/// [`MeshTriangle`] (12 bytes, over one shared vertex array), other scenes
/// the [`Shape`] enum (48).
#[derive(Debug)]
#[allow(clippy::large_enum_variant)] // one per renderer
pub(crate) enum Accel {
    Spheres(AccelOf<Sphere>),
    Triangles(AccelOf<Triangle>),
    Mesh(AccelOf<MeshTriangle>),
    Shapes(AccelOf<Shape>),
}

impl Accel {
    /// What it is, for `Debug`.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            Accel::Spheres(AccelOf::Grid(_)) => "grid of spheres",
            Accel::Spheres(AccelOf::Exhaustive(_)) => "exhaustive over spheres",
            Accel::Triangles(AccelOf::Grid(_)) => "grid of triangles",
            Accel::Triangles(AccelOf::Exhaustive(_)) => "exhaustive over triangles",
            Accel::Mesh(AccelOf::Grid(_)) => "grid of indexed triangles",
            Accel::Mesh(AccelOf::Exhaustive(_)) => "exhaustive over indexed triangles",
            Accel::Shapes(AccelOf::Grid(_)) => "grid of shapes",
            Accel::Shapes(AccelOf::Exhaustive(_)) => "exhaustive over shapes",
        }
    }
}

/// The grid configuration the options ask for (`None`: exhaustive).
pub(crate) fn grid_config(options: &RenderOptions, parallel: bool) -> Option<GridConfig> {
    let mut config = options.grid;
    if !parallel {
        config.parallel_build = false;
    }
    match options.accel {
        AccelKind::Grid => Some(config),
        AccelKind::DenseGrid => {
            config.storage = CellStorage::Dense;
            Some(config)
        }
        AccelKind::Exhaustive => None,
    }
}

/// The accelerator the options ask for (a grid stores the primitives in
/// cell order).
pub(crate) fn build_accel<P: Primitive + Send>(
    prims: Vec<P>,
    shared: P::Shared,
    options: &RenderOptions,
    parallel: bool,
) -> (AccelOf<P>, Option<GridStats>) {
    match grid_config(options, parallel) {
        Some(config) => {
            let grid = Grid::build_shared(prims, shared, &config);
            let stats = grid.stats().clone();
            (AccelOf::Grid(grid), Some(stats))
        }
        None => (
            AccelOf::Exhaustive(Exhaustive::with_shared(prims, shared)),
            None,
        ),
    }
}
