//! The nested grids' self-checks, for [`crate::Grid::check_invariants`].

use super::{
    boxes_of, cover, cull_box, pad_of, span_of, split, wide_chain, CellRuns, Children, Nested, Sub,
};
use crate::geom::{Geom, Reach};
use crate::Primitive;

impl Nested {
    /// Checks every nested grid reachable from `children` of a grid with
    /// geometry `g` and references `refs` (cells given as `(index, start,
    /// references)`): each over what its references cover of the cell,
    /// with the pad and reach of [`pad_of`], exactly the cell's references
    /// in every nested cell their padded box overlaps, and its own
    /// children in turn. Returns how many nested grids it reached.
    pub(crate) fn check<P: Primitive>(
        &self,
        prims: &[P],
        shared: &P::Shared,
        g: &Geom,
        children: &Children,
        cells: CellRuns<'_>,
    ) -> Result<usize, String> {
        let mut reached = 0;
        for (idx, start, refs) in cells {
            let Some(i) = children.find(refs.len(), start) else {
                continue;
            };
            let sub = self
                .subs
                .get(i)
                .ok_or_else(|| format!("cell {idx:?}: nested grid {i} missing"))?;
            if sub.start != start {
                return Err(format!("cell {idx:?}: nested grid {i} of another cell"));
            }
            let sg = &sub.geom;
            let (direct, inner, boxes) =
                split(&g.padded_cell_box(idx), refs, boxes_of(prims, shared, refs));
            if direct[..] != sub.direct[..] {
                return Err(format!("cell {idx:?}: wrong references tested directly"));
            }
            if sg.bounds != cover(g, idx, boxes.iter().copied()) {
                return Err(format!("cell {idx:?}: nested grid not over the cell"));
            }
            let span = span_of(sg.bounds, &boxes);
            let pad = pad_of(g.pad, refs.len(), &sg.bounds, sg.dims, &span);
            if sg.pad != pad || sub.reach != Reach::new(&span, pad, g.pad) {
                return Err(format!("cell {idx:?}: nested pad or reach wrong"));
            }
            if sub.outer != g.widen(&sg.bounds) {
                return Err(format!("cell {idx:?}: box for rays beyond reach wrong"));
            }
            for s in std::iter::once(sub).chain(sub.wide_grids()) {
                if s.cull != cull_box(&sub.outer, &s.geom, s.wide.as_deref()) {
                    return Err(format!("cell {idx:?}: box that culls the cell wrong"));
                }
            }
            let own = check_cells(prims, shared, idx, sub, &inner)?;
            // The wide grids: a chain of those `wide_chain` plans, in order
            // (a link whose references did not separate is left out).
            let mut want = wide_chain(g, refs.len(), sg, &span).into_iter();
            for wg in sub.wide_grids() {
                let same = |(geom, reach): &(Geom, Reach)| {
                    (geom.bounds, geom.dims, geom.pad, *reach)
                        == (wg.geom.bounds, wg.geom.dims, wg.geom.pad, wg.reach)
                };
                if !want.any(|link| same(&link)) {
                    return Err(format!(
                        "cell {idx:?}: wide grid's box, cells, pad or reach wrong"
                    ));
                }
                if wg.direct != sub.direct || !wg.children.is_empty() {
                    return Err(format!("cell {idx:?}: wide grid not like its nested grid"));
                }
                check_cells(prims, shared, idx, wg, &inner)?;
            }
            reached += 1 + self.check(prims, shared, sg, &sub.children, own)?;
        }
        Ok(reached)
    }
}

/// Checks that nested grid `sub` of cell `idx` holds exactly the
/// references `inner` in every cell their box overlaps, with its offsets
/// and occupancy bits in order; returns its occupied cells as `(index,
/// start, references)`.
fn check_cells<'s, P: Primitive>(
    prims: &[P],
    shared: &P::Shared,
    idx: [u32; 3],
    sub: &'s Sub,
    inner: &[u32],
) -> Result<CellRuns<'s>, String> {
    let sg = &sub.geom;
    let count = sg.cell_count() as usize;
    let o = &sub.offsets;
    if o.len() != count + 1
        || o[0] != 0
        || o[count] as usize != sub.refs.len()
        || o.windows(2).any(|w| w[0] > w[1])
    {
        return Err(format!("cell {idx:?}: nested offsets malformed"));
    }
    let mut want = Vec::new();
    for &p in inner {
        let range = sg.cell_range(&prims[p as usize].bounds(shared));
        sg.for_each_cell(range, |c| want.push((c, p)));
    }
    let mut got = Vec::new();
    let mut own = Vec::new();
    for c in 0..count {
        let run = &sub.refs[o[c] as usize..o[c + 1] as usize];
        got.extend(run.iter().map(|&p| (c, p)));
        let occupied = sub.occ[c >> 6] >> (c & 63) & 1 != 0;
        if occupied == run.is_empty() {
            return Err(format!("cell {idx:?}: nested occupancy bit {c} wrong"));
        }
        if !run.is_empty() {
            own.push((sg.index_of(c), o[c], run));
        }
    }
    want.sort_unstable();
    got.sort_unstable();
    if want != got {
        return Err(format!("cell {idx:?}: nested references differ"));
    }
    Ok(own)
}
