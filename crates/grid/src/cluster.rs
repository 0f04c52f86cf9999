//! How many primitives the top grid of [`crate::GridConfig::auto`] is
//! sized for: the "teapot in a stadium" rule.
//!
//! The lecture's formula sizes a grid for its `n` primitives, as if they
//! were spread evenly over its box. When most of them crowd into a few
//! cells (a detailed object in a large, mostly empty scene), the grid is
//! sized for the crowd, and a ray crossing the empty rest walks through
//! tens of empty cells to meet the few large primitives around it. The
//! crowded cells get nested grids anyway ([`crate::nested`]), which are
//! sized for their own references, so the top grid should be sized for
//! what it holds itself: the primitives outside the crowd, plus one
//! "primitive" per crowded cell (the nested grid in it), as a grid of
//! compound objects is sized for its objects (Suffern) and the top level
//! of a two-level grid for the scene's coarse structure (Kalojanov,
//! Billeter & Slusallek 2011).
//!
//! The crowd is found by counting the primitives' box centres in the cells
//! of the grid the formula gives for all `n` (on an evenly spaced sample
//! of at most [`SAMPLE`] primitives, so the count costs the same on every
//! scene): a cell is crowded when its estimated count reaches
//! [`crate::cost::min_refs`], the fewest references the build plans a
//! nested grid for. The top grid is sized for the smaller count only when
//! that is at most a quarter of `n` ([`MIN_GAIN`]): a scene without a clear
//! crowd keeps the lecture's grid (Suffern's random spheres, whose densest
//! cells hold about a dozen, are not touched).

use crate::geom::{self, gridded, Geom};
use crate::Primitive;
use gridrt_bbox::Aabb;

/// The most primitives whose centres are counted.
pub(crate) const SAMPLE: usize = 1 << 16;

/// The top grid is sized for the smaller count only when it is at most
/// `1 / MIN_GAIN` of all primitives (1.6 times fewer cells along each axis,
/// or fewer still). Measured with `gridrt rays` (one thread, best of three
/// alternated runs): the stadium's top count is 0.2% of its primitives,
/// and its rays trace 1.0–2.1× as fast so; the 1,024,000-triangle mesh's
/// is 16%, 1.2–1.3×; the dragon's, a dense surface whose crowded cells
/// hold most of its triangles, would be 41%, and it traced 0.82–0.87× as
/// fast, so it keeps the lecture's grid.
pub(crate) const MIN_GAIN: usize = 4;

/// When the top count is at most `1 / OBJECTS_GAIN` of the primitives
/// (four times fewer cells along each axis than the lecture's grid, or
/// fewer still), the top grid holds objects rather than primitives: a few
/// nested grids (each a cluster's own grid) and the large primitives
/// around them. Its multiplier is then [`OBJECTS_M`] times the lecture's.
pub(crate) const OBJECTS_GAIN: usize = 64;

/// The top grid's multiplier over the lecture's `m` for a grid of objects
/// ([`OBJECTS_GAIN`]): 5/3, so 1.25 for the default 0.75. A finer top grid
/// cuts the clusters closer: a ray that passes beside a cluster crosses
/// fewer of the cells it crowds, and so walks fewer of their nested
/// grids. Measured with `gridrt rays` (one thread, best of five alternated
/// runs), against the lecture's `m`: the teapot in the stadium (top count
/// 1/2230 of its primitives) 1.22× as fast on close camera rays, 1.14× on
/// their bounces and 1.23× on the prop rays, unchanged on the far views
/// (within ±6%); the 40 teapots (1/958) 1.35× and 1.33× on the close view,
/// 1.07× on the far one. Scales 2 and 2.5 gave less. The 1,024,000-triangle
/// mesh (a top count of 1/6.4) traced 0.84–0.90× as fast with it, so a
/// grid of crowded cells among many primitives keeps the lecture's `m`.
pub(crate) const OBJECTS_M: f64 = 5.0 / 3.0;

/// The multiplier of a top grid sized for `top` of the `n` primitives,
/// with the lecture's `m` ([`OBJECTS_M`]).
pub(crate) fn top_m(n: usize, top: usize, m: f64) -> f64 {
    if top.saturating_mul(OBJECTS_GAIN) <= n {
        m * OBJECTS_M
    } else {
        m
    }
}

/// The count the top grid is sized for, of the `n` gridded primitives of
/// `prims` inside `bounds`, with multiplier `m` and at most `max_cells`
/// cells: `n`, or less when most of them crowd into a few cells (see the
/// module documentation).
pub(crate) fn top_count<P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    bounds: &Aabb,
    n: usize,
    m: f64,
    max_cells: u64,
) -> usize {
    let ext = bounds.extent().to_array().map(geom::wide);
    let dims = geom::resolution(ext, n, m, max_cells);
    let g = Geom::new(*bounds, dims);
    let cells = g.cell_count() as usize;
    if cells <= 1 {
        return n;
    }
    let stride = prims.len().div_ceil(SAMPLE).max(1);
    // A cell is crowded once it holds `need` sampled centres.
    let need = (crate::cost::min_refs() as usize).div_ceil(stride).max(1) as u16;
    let [nx, ny, _] = dims.map(|d| d as usize);
    let mut counts = vec![0u16; cells];
    let (mut crowded_cells, mut crowded_samples) = (0usize, 0usize);
    for (i, p) in prims.iter().enumerate().step_by(stride) {
        // The strided reads miss the cache: ask for one some samples ahead.
        if let Some(q) = prims.get(i + 16 * stride) {
            crate::mem::prefetch(q);
        }
        let b = p.bounds(shared);
        if gridded(&b).is_none() {
            continue;
        }
        let [i, j, k] = std::array::from_fn(|a| g.cell_of(a, (b.min[a] + b.max[a]) * 0.5) as usize);
        let count = &mut counts[i + nx * (j + ny * k)];
        *count = count.saturating_add(1);
        if *count == need {
            crowded_cells += 1;
            crowded_samples += need as usize;
        } else if *count > need {
            crowded_samples += 1;
        }
    }
    let crowd = (crowded_samples * stride).min(n);
    let top = n - crowd + crowded_cells;
    if top.saturating_mul(MIN_GAIN) <= n {
        top.max(1)
    } else {
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::tests::Ball;
    use gridrt_bbox::{Real, Vec3};

    fn count(prims: &[Ball]) -> usize {
        let b = prims
            .iter()
            .fold(Aabb::EMPTY, |b, p| b.union(p.bounds(&())));
        top_count(prims, &(), &b, prims.len(), 0.75, 1 << 26)
    }

    /// Points spread by a fixed sequence over `[-1, 1]³`.
    fn spread(n: usize, scale: Real) -> impl Iterator<Item = Vec3> {
        (0..n).map(move |i| {
            let a = i as Real;
            Vec3::new((a * 0.37).sin(), (a * 0.11).cos(), (a * 0.07).sin()) * scale
        })
    }

    #[test]
    fn a_small_crowd_in_a_large_box_sizes_the_top_grid_for_the_rest() {
        // 20,000 small balls in a unit ball, 50 spread over a 1000-wide box.
        let mut prims: Vec<Ball> = spread(20_000, 0.5).map(|c| Ball(c, 0.01)).collect();
        prims.extend(spread(50, 500.0).map(|c| Ball(c, 5.0)));
        let n = count(&prims);
        assert!(n < 200, "{n}");
        assert!(n >= 50, "the primitives outside the crowd count: {n}");
    }

    #[test]
    fn only_a_grid_of_objects_gets_the_finer_multiplier() {
        assert_eq!(top_m(1_000_000, 1_000_000, 0.75), 0.75);
        // A crowd among many (the 1,024,000-triangle mesh's 1/6.4).
        assert_eq!(top_m(1_024_000, 159_058, 0.75), 0.75);
        assert_eq!(top_m(64_000, 1_001, 0.75), 0.75);
        assert_eq!(top_m(64_000, 1_000, 0.75), 0.75 * OBJECTS_M);
        // The stadium's 1/2230.
        assert_eq!(top_m(75_807, 34, 0.75), 0.75 * OBJECTS_M);
    }

    #[test]
    fn a_uniform_scene_or_a_crowd_among_many_keeps_the_lecture_s_count() {
        let mut s = 7u64;
        let mut next = move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
            (s >> 40) as Real / (1u64 << 24) as Real
        };
        let mut prims: Vec<Ball> = (0..100_000)
            .map(|_| Ball(Vec3::new(next(), next(), next()) * 100.0, 0.05))
            .collect();
        assert_eq!(count(&prims), prims.len());
        // A crowd of 16,000, but 6,000 elsewhere: sized for about 6,000,
        // the top grid would have only 1.5 times fewer cells per axis.
        prims.truncate(6000);
        prims.extend(spread(16_000, 0.5).map(|c| Ball(c + Vec3::splat(50.0), 0.01)));
        assert_eq!(count(&prims), prims.len());
        // With 400 elsewhere it has 3.7 times fewer.
        prims.drain(400..6000);
        assert!(count(&prims) < 500, "{}", count(&prims));
    }
}
