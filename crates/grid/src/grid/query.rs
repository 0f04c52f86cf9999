//! The queries' per-cell work: the closest hit and any hit, each walking a
//! crowded cell's nested grid instead of testing its references.

use super::EXIT_MARGIN;
use crate::counters::Counters;
use crate::dda::{CellFn, CellVisit, Dda};
use crate::groups::{Frame, GroupBlock, Groups, RaySlabs};
use crate::nested::{Children, Sub};
use crate::{Hit, Primitive};
use gridrt_bbox::{Ray, Real, SlabRay};
use std::ops::ControlFlow;

/// Where the run `cell` of the grid's references `all` starts among them.
#[inline(always)]
pub(super) fn run_start(all: &[u32], cell: &[u32]) -> u32 {
    ((cell.as_ptr() as usize - all.as_ptr() as usize) / std::mem::size_of::<u32>()) as u32
}

/// The primitive index of slot `r`.
#[inline(always)]
pub(super) fn prim_id(ids: &[u32], r: u32) -> u32 {
    debug_assert!((r as usize) < ids.len());
    // SAFETY: every slot has an id (checked by `check_invariants`).
    unsafe { *ids.get_unchecked(r as usize) }
}

/// The closest-hit query's per-cell work.
pub(super) struct Closest<'q, P: Primitive, C, const MB: bool> {
    /// The grid's primitives in slot order: what the references index.
    pub(super) prims: &'q [P],
    /// What the primitives share.
    pub(super) shared: &'q P::Shared,
    /// The primitive index of each slot.
    pub(super) ids: &'q [u32],
    /// The walked grid's references (a cell's nested grid is found by its
    /// run's start).
    pub(super) refs: &'q [u32],
    /// The walked grid's cells with nested grids.
    pub(super) children: &'q Children,
    /// The walked grid's cells with group boxes (the flat grid's; nested
    /// grids have none).
    pub(super) groups: Option<&'q Groups>,
    /// Every nested grid.
    pub(super) subs: &'q [Sub],
    pub(super) ray: &'q Ray,
    /// `ray` prepared for the slab tests of nested grids' boxes.
    pub(super) slab: SlabRay,
    /// The primitives' [`Primitive::ray_data`] of `ray`.
    pub(super) data: &'q P::RayData,
    pub(super) t_min: Real,
    /// `t_max`, then the best hit's t.
    pub(super) t_lim: Real,
    pub(super) best: Option<Hit>,
    pub(super) stamps: &'q mut [u32],
    pub(super) stamp: u32,
    pub(super) counters: &'q mut C,
}

impl<P: Primitive, C: Counters, const MB: bool> Closest<'_, P, C, MB> {
    /// Tests the primitives in slots `refs` without the mailbox, four at a
    /// time where the primitive can ([`Primitive::closest_hits`]).
    #[inline(always)]
    pub(super) fn test_each(&mut self, refs: &[u32]) {
        self.counters.tests(refs.len());
        let (prims, shared, ids, ray, data, t_min, t_lim) = (
            self.prims,
            self.shared,
            self.ids,
            self.ray,
            self.data,
            self.t_min,
            self.t_lim,
        );
        let best = self.best.as_ref().map_or(crate::NO_SLOT, |b| b.slot);
        P::closest_hits(
            prims,
            shared,
            refs,
            ray,
            data,
            t_min,
            t_lim,
            best,
            &mut |r, h| self.keep(Hit::new(h, prim_id(ids, r), r)),
        );
    }

    /// Tests the primitive in slot `r`, keeping its hit if it is better
    /// ([`Hit::is_better_than`]).
    #[inline(always)]
    pub(super) fn test(&mut self, r: u32) {
        debug_assert!((r as usize) < self.prims.len());
        // SAFETY: every stored reference is a valid index into `prims`
        // (checked by `check_invariants`).
        let prim = unsafe { self.prims.get_unchecked(r as usize) };
        self.counters.test();
        if let Some(h) = prim.closest_hit(self.shared, self.ray, self.data, self.t_min, self.t_lim)
        {
            self.keep(Hit::new(h, prim_id(self.ids, r), r));
        }
    }

    /// Keeps `hit` if it is better ([`Hit::is_better_than`]); gives the
    /// limit for the tests that follow.
    #[inline(always)]
    pub(super) fn keep(&mut self, hit: Hit) -> Real {
        if self.best.as_ref().is_none_or(|b| hit.is_better_than(b)) {
            self.t_lim = hit.t;
            self.best = Some(hit);
        }
        self.t_lim
    }

    /// Walks the nested grid of a crowded cell instead of testing the
    /// cell's references one by one: the same query, one level down. A ray
    /// from beyond the nested grid's reach walks its wide grid, or tests
    /// them one by one if it meets their box ([`Sub::far_refs`]).
    #[inline(never)]
    fn walk_sub(&mut self, sub: &Sub, refs: &[u32]) {
        let Some(sub) = sub.for_ray(self.ray) else {
            return self
                .test_refs(sub.far_refs(refs, self.ray, &self.slab, self.t_min, self.t_lim));
        };
        if !sub.direct.is_empty() {
            self.test_refs(&sub.direct);
        }
        let entered = || sub.prefetch();
        let Some(dda) = Dda::new_then(
            &sub.geom, self.ray, &self.slab, self.t_min, self.t_lim, entered,
        ) else {
            return;
        };
        let lookup = sub.lookup();
        let mut q = Closest::<P, C, MB> {
            prims: self.prims,
            shared: self.shared,
            ids: self.ids,
            refs: &sub.refs,
            children: &sub.children,
            groups: None,
            subs: self.subs,
            ray: self.ray,
            slab: self.slab,
            data: self.data,
            t_min: self.t_min,
            t_lim: self.t_lim,
            best: self.best,
            stamps: &mut *self.stamps,
            stamp: self.stamp,
            counters: &mut *self.counters,
        };
        let _ = dda.walk(&lookup, &mut q);
        (self.t_lim, self.best) = (q.t_lim, q.best);
    }
}

impl<'a, P: Primitive, C: Counters, const MB: bool> CellFn<'a> for Closest<'_, P, C, MB> {
    type Break = ();

    #[inline(always)]
    fn call(&mut self, visit: CellVisit, refs: &'a [u32]) -> ControlFlow<()> {
        self.counters.cell();
        if refs.is_empty() {
            return ControlFlow::Continue(());
        }
        let start = run_start(self.refs, refs);
        if let Some(i) = self.children.find(refs.len(), start) {
            // SAFETY: `Children::find` returns arena indices of `subs`
            // (checked by `check_invariants`).
            let sub = unsafe { self.subs.get_unchecked(i) };
            if !sub.misses(self.ray, &self.slab, self.t_min, self.t_lim) {
                self.walk_sub(sub, refs);
            }
        } else if let Some((frame, blocks)) = self.groups.and_then(|g| g.of(refs.len(), start)) {
            self.test_groups(frame, blocks, refs);
        } else {
            self.test_refs(refs);
        }
        // Stop only when the best hit is certainly inside this cell: a hit on
        // (or within rounding of) the exit plane may tie with a lower-index
        // primitive of the next cell. A hit found here that lies in a later
        // cell stays in `best` and is confirmed there. (Empty cells cannot
        // change the answer, so the test is made after occupied ones only.)
        let t_exit = visit.t_exit;
        if self.best.is_some() && self.t_lim < t_exit - t_exit.abs() * EXIT_MARGIN {
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }
}

impl<P: Primitive, C: Counters, const MB: bool> Closest<'_, P, C, MB> {
    /// Tests the groups of a cell's `refs` whose boxes `blocks` the ray
    /// meets before the best hit so far.
    #[inline(always)]
    fn test_groups(&mut self, frame: &Frame, blocks: &[GroupBlock], refs: &[u32]) {
        let slabs = RaySlabs::new(self.ray);
        let (t_min, t_lim) = (self.t_min, self.t_lim);
        let _ = for_met_groups(frame, blocks, refs, &slabs, t_min, t_lim, |group| {
            self.test_refs(group);
            ControlFlow::<(), Real>::Continue(self.t_lim)
        });
    }

    /// Tests the references of one cell.
    #[inline(always)]
    fn test_refs(&mut self, refs: &[u32]) {
        if !MB {
            return self.test_each(refs);
        }
        // With the mailbox, one at a time: each reference's stamp decides.
        for &p in refs {
            debug_assert!((p as usize) < self.stamps.len());
            // SAFETY: `GridScratch::begin` sized the stamps to the primitive count.
            let s = unsafe { self.stamps.get_unchecked_mut(p as usize) };
            if *s == self.stamp {
                self.counters.mailbox_skip();
                continue;
            }
            *s = self.stamp;
            self.test(p);
        }
    }
}

/// The any-hit query's per-cell work.
pub(super) struct AnyHit<'q, P: Primitive, C, const MB: bool> {
    /// The grid's primitives in slot order: what the references index.
    pub(super) prims: &'q [P],
    /// What the primitives share.
    pub(super) shared: &'q P::Shared,
    /// The walked grid's references (a cell's nested grid is found by its
    /// run's start).
    pub(super) refs: &'q [u32],
    /// The walked grid's cells with nested grids.
    pub(super) children: &'q Children,
    /// The walked grid's cells with group boxes (the flat grid's; nested
    /// grids have none).
    pub(super) groups: Option<&'q Groups>,
    /// Every nested grid.
    pub(super) subs: &'q [Sub],
    pub(super) ray: &'q Ray,
    /// `ray` prepared for the slab tests of nested grids' boxes.
    pub(super) slab: SlabRay,
    /// The primitives' [`Primitive::ray_data`] of `ray`.
    pub(super) data: &'q P::RayData,
    pub(super) t_min: Real,
    pub(super) t_max: Real,
    pub(super) stamps: &'q mut [u32],
    pub(super) stamp: u32,
    pub(super) counters: &'q mut C,
}

impl<'a, P: Primitive, C: Counters, const MB: bool> CellFn<'a> for AnyHit<'_, P, C, MB> {
    type Break = ();

    #[inline(always)]
    fn call(&mut self, _: CellVisit, refs: &'a [u32]) -> ControlFlow<()> {
        self.counters.cell();
        if refs.is_empty() {
            return ControlFlow::Continue(());
        }
        let start = run_start(self.refs, refs);
        if let Some(i) = self.children.find(refs.len(), start) {
            // SAFETY: as in the closest-hit query.
            let sub = unsafe { self.subs.get_unchecked(i) };
            if sub.misses(self.ray, &self.slab, self.t_min, self.t_max) {
                return ControlFlow::Continue(());
            }
            return self.walk_sub(sub, refs);
        }
        if let Some((frame, blocks)) = self.groups.and_then(|g| g.of(refs.len(), start)) {
            return self.test_groups(frame, blocks, refs);
        }
        self.test_refs(refs)
    }
}

impl<P: Primitive, C: Counters, const MB: bool> AnyHit<'_, P, C, MB> {
    /// Tests the groups of a cell's `refs` whose boxes `blocks` the ray
    /// meets within the range, until one is hit.
    #[inline(always)]
    fn test_groups(
        &mut self,
        frame: &Frame,
        blocks: &[GroupBlock],
        refs: &[u32],
    ) -> ControlFlow<()> {
        let slabs = RaySlabs::new(self.ray);
        let (t_min, t_max) = (self.t_min, self.t_max);
        for_met_groups(frame, blocks, refs, &slabs, t_min, t_max, |group| {
            self.test_refs(group)?;
            ControlFlow::Continue(t_max)
        })
    }

    /// Tests references until one is hit.
    #[inline(always)]
    fn test_refs(&mut self, refs: &[u32]) -> ControlFlow<()> {
        if !MB {
            self.counters.tests(refs.len());
            return if P::any_hits(
                self.prims,
                self.shared,
                refs,
                self.ray,
                self.data,
                self.t_min,
                self.t_max,
            ) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            };
        }
        // With the mailbox, one at a time: each reference's stamp decides.
        for &p in refs {
            // SAFETY: `GridScratch::begin` sized the stamps to the primitive count.
            let s = unsafe { self.stamps.get_unchecked_mut(p as usize) };
            if *s == self.stamp {
                self.counters.mailbox_skip();
                continue;
            }
            *s = self.stamp;
            self.counters.test();
            // SAFETY: every stored reference is a valid index into `prims`.
            let prim = unsafe { self.prims.get_unchecked(p as usize) };
            if prim.any_hit(self.shared, self.ray, self.data, self.t_min, self.t_max) {
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    }
}

impl<P: Primitive, C: Counters, const MB: bool> AnyHit<'_, P, C, MB> {
    /// Walks the nested grid of a crowded cell: only the references in the
    /// nested cells along the ray are tested. An occluder whose hit lies
    /// outside this cell is found in the cell that holds the hit. A ray
    /// from beyond the nested grid's reach walks its wide grid, or tests
    /// the cell's `refs` if it meets their box ([`Sub::far_refs`]).
    #[inline(never)]
    fn walk_sub(&mut self, sub: &Sub, refs: &[u32]) -> ControlFlow<()> {
        let Some(sub) = sub.for_ray(self.ray) else {
            return self
                .test_refs(sub.far_refs(refs, self.ray, &self.slab, self.t_min, self.t_max));
        };
        if !sub.direct.is_empty() {
            self.test_refs(&sub.direct)?;
        }
        let entered = || sub.prefetch();
        let Some(dda) = Dda::new_then(
            &sub.geom, self.ray, &self.slab, self.t_min, self.t_max, entered,
        ) else {
            return ControlFlow::Continue(());
        };
        let lookup = sub.lookup();
        let mut q = AnyHit::<P, C, MB> {
            prims: self.prims,
            shared: self.shared,
            refs: &sub.refs,
            children: &sub.children,
            groups: None,
            subs: self.subs,
            ray: self.ray,
            slab: self.slab,
            data: self.data,
            t_min: self.t_min,
            t_max: self.t_max,
            stamps: &mut *self.stamps,
            stamp: self.stamp,
            counters: &mut *self.counters,
        };
        dda.walk(&lookup, &mut q)
    }
}

/// Calls `f` with each group of four of a cell's `refs` (the last may be
/// shorter) whose box in `blocks` (on `frame`) the ray of `slabs` meets within
/// `[t_min, t_max]`, in order, until `f` breaks; `f` gives the range's new
/// end, so a closer hit culls the blocks after it.
#[inline(always)]
fn for_met_groups<B>(
    frame: &Frame,
    blocks: &[GroupBlock],
    refs: &[u32],
    slabs: &RaySlabs,
    t_min: Real,
    mut t_max: Real,
    mut f: impl FnMut(&[u32]) -> ControlFlow<B, Real>,
) -> ControlFlow<B> {
    let groups = refs.len().div_ceil(4);
    let frame = frame.lanes();
    for (b, block) in blocks.iter().enumerate() {
        let left = groups - 4 * b;
        let valid = if left >= 4 { 0xf } else { (1u32 << left) - 1 };
        let mut met = block.hit_mask(&frame, slabs, t_min, t_max) & valid;
        while met != 0 {
            let g = 4 * b + met.trailing_zeros() as usize;
            met &= met - 1;
            t_max = f(&refs[4 * g..(4 * g + 4).min(refs.len())])?;
        }
    }
    ControlFlow::Continue(())
}
