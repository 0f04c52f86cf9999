//! Render passes (arbitrary output variables): what the camera ray through
//! each pixel's centre sees first — albedo, shading normal, depth,
//! position, primitive and material ids — and how much work the
//! acceleration structure did for it (cells visited, primitives tested),
//! for compositing, denoisers and for seeing the grid at work.

use crate::camera::CameraModel;
use crate::float::to_f32;
use crate::framebuffer::PixelRect;
use crate::integrator::{Found, SceneData, Tracer};
use crate::pool::Pool;
use crate::render::Renderer;
use crate::shapes::Surface;
use gridrt_bbox::{Ray, Real};
use gridrt_grid::{Accelerator, Exhaustive, Grid, Hit, Primitive, QueryCounters};

/// One render pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    /// The first hit's diffuse albedo (1 for glass, the emitted colour for
    /// emitters; 0 where the ray escapes), as a denoiser expects it.
    Albedo,
    /// The first hit's shading normal in world space, turned to face the
    /// camera (0 where the ray escapes).
    Normal,
    /// Distance from the camera to the first hit along the ray (infinity
    /// where it escapes).
    Depth,
    /// World-space position of the first hit (0 where the ray escapes).
    Position,
    /// Index of the primitive hit first; planes follow the primitives,
    /// then rectangle and disk lights;
    /// −1 where the ray escapes.
    PrimId,
    /// Index of the first hit's material in the scene; −1 where the ray
    /// escapes.
    MaterialId,
    /// Grid cells the camera ray visited (0 for the exhaustive baseline).
    CellsVisited,
    /// Primitives the camera ray was tested against.
    Tests,
}

impl Aov {
    /// Every pass, in the order of the `--aov` documentation.
    pub const ALL: [Aov; 8] = [
        Aov::Albedo,
        Aov::Normal,
        Aov::Depth,
        Aov::Position,
        Aov::PrimId,
        Aov::MaterialId,
        Aov::CellsVisited,
        Aov::Tests,
    ];

    /// The pass's name on the command line and in files
    /// (`albedo`, `cells-visited`, …).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Position => "position",
            Aov::PrimId => "prim-id",
            Aov::MaterialId => "material-id",
            Aov::CellsVisited => "cells-visited",
            Aov::Tests => "tests",
        }
    }

    /// The pass of a name, if there is one.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Aov> {
        Aov::ALL.into_iter().find(|a| a.name() == name)
    }

    /// Values per pixel: 3 for colours and vectors, 1 otherwise.
    #[must_use]
    pub fn channels(self) -> usize {
        match self {
            Aov::Albedo | Aov::Normal | Aov::Position => 3,
            _ => 1,
        }
    }
}

/// The values of one pass over a window: `channels` values per pixel,
/// row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct AovImage {
    /// Which pass.
    pub aov: Aov,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `aov.channels()` values per pixel.
    pub values: Vec<f32>,
}

/// Closest-hit queries that also count the work done.
pub(crate) trait CountedQuery: Accelerator {
    /// The closest hit in `[t_min, t_max]`, counting into `c`.
    fn closest_counted(
        &self,
        ray: &Ray,
        t_max: Real,
        scratch: &mut Self::Scratch,
        c: &mut QueryCounters,
    ) -> Option<Hit>;
}

impl<P: Primitive> CountedQuery for Grid<P> {
    fn closest_counted(
        &self,
        ray: &Ray,
        t_max: Real,
        scratch: &mut Self::Scratch,
        c: &mut QueryCounters,
    ) -> Option<Hit> {
        self.closest_hit_counted(ray, 0.0, t_max, scratch, c)
    }
}

impl<P: Primitive> CountedQuery for Exhaustive<P> {
    fn closest_counted(
        &self,
        ray: &Ray,
        t_max: Real,
        _: &mut Self::Scratch,
        c: &mut QueryCounters,
    ) -> Option<Hit> {
        self.closest_hit_counted(ray, 0.0, t_max, c)
    }
}

/// The passes of one pixel.
fn pixel<A>(
    tr: &Tracer<'_, A>,
    data: &SceneData,
    ray: &Ray,
    aovs: &[Aov],
    scratch: &mut A::Scratch,
    out: &mut [Vec<f32>],
) where
    A: CountedQuery,
    A::Prim: Surface,
{
    let mut counters = QueryCounters::default();
    // The counted walk gives the same hit as the plain one; the planes
    // (outside the grid) are added by `closest`.
    let counted = aovs
        .iter()
        .any(|a| matches!(a, Aov::CellsVisited | Aov::Tests));
    if counted {
        tr.accel
            .closest_counted(ray, Real::INFINITY, scratch, &mut counters);
    }
    let found = tr.closest(ray, Real::INFINITY, scratch);
    let shading = found.map(|f| tr.shading(ray, f));
    let len = to_f32(ray.dir.length());
    for (a, v) in aovs.iter().zip(out.iter_mut()) {
        match (a, &shading) {
            (Aov::Albedo, Some(s)) => v.extend(s.albedo(data).to_array()),
            (Aov::Normal, Some(s)) => {
                let n = s.normal();
                let n = if n.dot(ray.dir) > 0.0 { -n } else { n };
                v.extend([to_f32(n.x), to_f32(n.y), to_f32(n.z)]);
            }
            (Aov::Position, Some(s)) => {
                let p = ray.at(s.t());
                v.extend([to_f32(p.x), to_f32(p.y), to_f32(p.z)]);
            }
            (Aov::Albedo | Aov::Normal | Aov::Position, None) => v.extend([0.0; 3]),
            (Aov::Depth, s) => v.push(s.map_or(f32::INFINITY, |s| to_f32(s.t()) * len)),
            (Aov::PrimId, _) => v.push(match found {
                Some(Found::Prim(h)) => h.prim as f32,
                Some(Found::Plane { index, .. }) => {
                    (tr.accel.primitives().len() + index as usize) as f32
                }
                Some(Found::Area { index, .. }) => {
                    let planes = tr.data.planes.len();
                    (tr.accel.primitives().len() + planes + index as usize) as f32
                }
                None => -1.0,
            }),
            (Aov::MaterialId, s) => v.push(s.map_or(-1.0, |s| s.material() as f32)),
            (Aov::CellsVisited, _) => v.push(counters.cells as f32),
            (Aov::Tests, _) => v.push(counters.tests as f32),
        }
    }
}

/// The passes of the rows `window.y0..window.y1` of an image `height` rows
/// high: for each row, one vector of values per pass.
pub(crate) fn rows<A>(
    accel: &A,
    data: &SceneData,
    camera: &CameraModel,
    pool: &Pool,
    height: u32,
    aovs: &[Aov],
    window: PixelRect,
) -> Vec<Vec<Vec<f32>>>
where
    A: CountedQuery,
    A::Prim: Surface,
{
    let tr = Tracer { accel, data };
    let rows: Vec<u32> = (window.y0..window.y1).collect();
    pool.map_init(
        &rows,
        || accel.scratch(),
        |scratch, &y| {
            let mut out: Vec<Vec<f32>> = aovs
                .iter()
                .map(|a| Vec::with_capacity(a.channels() * window.width() as usize))
                .collect();
            for x in window.x0..window.x1 {
                let ray = camera.ray(x, height - 1 - y, 0.5, 0.5);
                pixel(&tr, data, &ray, aovs, scratch, &mut out);
            }
            out
        },
    )
}

impl Renderer {
    /// Renders the passes `aovs` over `window` from one camera ray through
    /// each pixel's centre (so they stay sharp where the image is
    /// antialiased). Independent of the thread count, like the image.
    ///
    /// ```
    /// use gridrt_tracer::{suffern, Aov, PixelRect, RenderOptions, Renderer};
    /// let r = suffern::renderer(1000, suffern::DEFAULT_SEED, &RenderOptions::default()).unwrap();
    /// let all = PixelRect { x0: 0, y0: 0, x1: 400, y1: 400 };
    /// let passes = r.render_aovs(&[Aov::PrimId, Aov::Tests], all);
    /// let (ids, tests) = (&passes[0].values, &passes[1].values);
    /// // The corner pixel's ray misses every sphere; some ray hits one.
    /// assert_eq!(ids[0], -1.0);
    /// assert!(ids.iter().any(|&i| i >= 0.0));
    /// // A ray that hits was tested against at least the sphere it hit.
    /// assert!(ids.iter().zip(tests).all(|(&i, &t)| i < 0.0 || t >= 1.0));
    /// ```
    ///
    /// # Panics
    /// When the window is empty or reaches outside the image.
    #[must_use]
    pub fn render_aovs(&self, aovs: &[Aov], window: PixelRect) -> Vec<AovImage> {
        let (w, h) = self.size();
        assert!(
            window.x0 < window.x1 && window.y0 < window.y1 && window.x1 <= w && window.y1 <= h,
            "window {window:?} is empty or outside a {w} x {h} image"
        );
        let row_values = self.aov_rows(aovs, window);
        aovs.iter()
            .enumerate()
            .map(|(k, &aov)| AovImage {
                aov,
                width: window.width(),
                height: window.height(),
                values: row_values
                    .iter()
                    .flat_map(|r| r[k].iter().copied())
                    .collect(),
            })
            .collect()
    }
}
