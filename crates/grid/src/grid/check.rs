//! The grid's self-checks, for tests.

use super::fours::pack_fours;
use super::{Cells, Grid};
use crate::dda::BlockMap;
use crate::groups::Run;
use crate::{morton, Primitive};

impl<P: Primitive> Grid<P> {
    /// Checks the grid's internal consistency; `Err` names the first
    /// violation. Meant for tests (it is slow: it re-derives every
    /// primitive's cells).
    ///
    /// Checked: the geometry (planes nondecreasing from the box's min to its
    /// max, cell count within the cap), the CSR layout (offsets or table
    /// runs inside the reference array, no primitive twice in a
    /// cell, keys in Morton order), that every gridded primitive is in
    /// exactly the cells its padded box overlaps (or, with exact insertion,
    /// in every such cell it reports touching and no other), that the
    /// unbounded list holds exactly the primitives with non-finite or
    /// outsized boxes ([`Geom::holds`](crate::geom::Geom::holds)),
    /// that every primitive has exactly one slot, and that the stats match.
    pub fn check_invariants(&self) -> Result<(), String> {
        let g = &self.geom;
        let n = self.prims.len();
        if self.ids.len() != n {
            return Err(format!("{} ids for {n} slots", self.ids.len()));
        }
        // The slots hold every primitive once.
        let mut seen = vec![false; n];
        for (k, &p) in self.ids.iter().enumerate() {
            if p as usize >= n {
                return Err(format!("slot {k}: primitive {p} of {n}"));
            }
            if std::mem::replace(&mut seen[p as usize], true) {
                return Err(format!("primitive {p} has two slots"));
            }
        }
        if g.is_empty() {
            if !self.refs.is_empty() || !matches!(self.cells, Cells::Empty) {
                return Err("empty grid with cells or references".into());
            }
        } else {
            for a in 0..3 {
                let p = &g.planes[a];
                if g.dims[a] == 0 || p.len() != g.dims[a] as usize + 1 {
                    return Err(format!(
                        "axis {a}: {} planes for {} cells",
                        p.len(),
                        g.dims[a]
                    ));
                }
                if p[0] != g.bounds.min[a] || p[p.len() - 1] != g.bounds.max[a] {
                    return Err(format!("axis {a}: planes do not span the grid box"));
                }
                if p.windows(2).any(|w| !(w[0] <= w[1])) {
                    return Err(format!("axis {a}: planes not nondecreasing"));
                }
            }
            if g.cell_count() > self.config.max_cells.max(1) {
                return Err(format!(
                    "{} cells exceed max_cells {}",
                    g.cell_count(),
                    self.config.max_cells
                ));
            }
        }
        let slots = self.prims.len();
        if let Some(&p) = self.refs.iter().find(|&&p| p as usize >= slots) {
            return Err(format!("reference {p} of {slots}"));
        }
        // Every cell's run, by key order.
        let mut runs: Vec<(u64, [u32; 3], u32, u32)> = Vec::new();
        match &self.cells {
            Cells::Empty => {}
            Cells::Dense { offsets } => {
                if offsets.len() as u64 != g.cell_count() + 1 {
                    return Err("dense offsets: wrong length".into());
                }
                if offsets[0] != 0 || offsets[offsets.len() - 1] as usize != self.refs.len() {
                    return Err("dense offsets do not span the references".into());
                }
                let [nx, ny, _] = g.dims;
                for c in 0..offsets.len() - 1 {
                    let (s, e) = (offsets[c], offsets[c + 1]);
                    if s > e {
                        return Err(format!("dense offsets decrease at cell {c}"));
                    }
                    if e > s {
                        let c32 = c as u32;
                        let idx = [c32 % nx, (c32 / nx) % ny, c32 / (nx * ny)];
                        runs.push((c as u64, idx, s, e - s));
                    }
                }
            }
            Cells::Hashed { table } => {
                let mut slots: Vec<_> = table.occupied().copied().collect();
                slots.sort_by_key(|s| s.start);
                let mut next = 0u32;
                let mut prev_key = None;
                for s in &slots {
                    if s.start != next || s.len == 0 {
                        return Err(format!("hashed runs not contiguous at {}", s.start));
                    }
                    next = s.start + s.len;
                    if prev_key.is_some_and(|k| k >= s.key) {
                        return Err("references not in Morton order".into());
                    }
                    prev_key = Some(s.key);
                    let idx = morton::decode3(s.key);
                    if !self.in_grid(idx) {
                        return Err(format!("cell key {} outside the grid", s.key));
                    }
                    if table.get(s.key) != (s.start, s.len) {
                        return Err(format!("cell key {} not found by probing", s.key));
                    }
                    runs.push((s.key, idx, s.start, s.len));
                }
                if next as usize != self.refs.len() {
                    return Err("hashed runs do not span the references".into());
                }
                if table.capacity() < 2 * slots.len() {
                    return Err("hash table over half full".into());
                }
            }
        }
        // The block map and the occupancy bits say which cells hold references.
        if !matches!(self.cells, Cells::Empty) {
            let blocks = BlockMap::new(g.dims, runs.iter().map(|r| r.1));
            if blocks.bits != self.blocks.bits {
                return Err("block map disagrees with the occupied cells".into());
            }
            let bit = |key: u64| {
                self.occ
                    .get((key >> 6) as usize)
                    .map_or(0, |w| w >> (key & 63) & 1)
            };
            let set: u64 = self.occ.iter().map(|w| u64::from(w.count_ones())).sum();
            if set != runs.len() as u64 || runs.iter().any(|r| bit(r.0) == 0) {
                return Err("occupancy bits disagree with the occupied cells".into());
            }
        }
        // The distance map is the occupancy's, cell by cell.
        if !self.far.is_empty() {
            let want = crate::empty_space::far_map(g.dims, |c| super::bit(&self.occ, c as u64));
            if self.far != want {
                return Err("distance map disagrees with the occupied cells".into());
            }
        }
        self.check_nested()?;
        let runs_of: Vec<Run> = runs.iter().map(|r| (r.2, r.3, r.1)).collect();
        self.groups
            .check(&self.prims, &self.shared, &self.refs, &runs_of, g)?;
        if !self.fours.is_empty() && self.fours != pack_fours(&self.prims, &self.shared, &self.refs)
        {
            return Err("the packed fours disagree with the references".into());
        }
        // Expected (cell, primitive) pairs against the stored ones.
        let mut stored: Vec<([u32; 3], u32)> = Vec::with_capacity(self.refs.len());
        for &(_, idx, s, len) in &runs {
            let r = &self.refs[s as usize..(s + len) as usize];
            let mut sorted = r.to_vec();
            sorted.sort_unstable();
            if sorted.windows(2).any(|w| w[0] == w[1]) {
                return Err(format!("cell {idx:?}: a primitive listed twice"));
            }
            stored.extend(r.iter().map(|&p| (idx, self.primitive_of(p))));
        }
        let mut expected = Vec::with_capacity(stored.len());
        let mut unbounded = Vec::new();
        for (slot, prim) in self.prims.iter().enumerate() {
            let p = self.ids[slot] as usize;
            let b = prim.bounds(&self.shared);
            if !g.holds(&b) {
                unbounded.push(slot as u32);
                continue;
            }
            if g.is_empty() {
                return Err(format!("primitive {p} is finite but the grid is empty"));
            }
            if !g.bounds.contains(b.min) || !g.bounds.contains(b.max) {
                return Err(format!("primitive {p} sticks out of the grid box"));
            }
            let (lo, hi) = g.cell_range(&b);
            for k in lo[2]..=hi[2] {
                for j in lo[1]..=hi[1] {
                    for i in lo[0]..=hi[0] {
                        let inside = !self.config.exact_insertion
                            || lo == hi
                            || prim.overlaps_box(&self.shared, &g.padded_cell_box([i, j, k]));
                        if inside {
                            expected.push(([i, j, k], p as u32));
                        }
                    }
                }
            }
        }
        if unbounded[..] != self.unbounded[..] {
            return Err("unbounded list does not match the non-finite boxes".into());
        }
        stored.sort_unstable();
        expected.sort_unstable();
        if stored != expected {
            let missing = expected.iter().find(|x| stored.binary_search(x).is_err());
            let extra = stored.iter().find(|x| expected.binary_search(x).is_err());
            return Err(format!(
                "cell contents differ: missing {missing:?}, extra {extra:?}"
            ));
        }
        let s = &self.stats;
        if s.dims != g.dims
            || s.references != self.refs.len() as u64
            || s.occupied_cells != runs.len() as u64
        {
            return Err("stats do not match the grid".into());
        }
        if s.max_refs_per_cell != runs.iter().map(|r| r.3).max().unwrap_or(0) {
            return Err("stats: wrong max references per cell".into());
        }
        Ok(())
    }

    /// The nested grids: every one reachable, each over what its
    /// references cover of its cell and holding exactly the cell's
    /// references in every nested cell their padded box overlaps, and none
    /// left over; and the index within the memory budget.
    fn check_nested(&self) -> Result<(), String> {
        let all = self.runs(1);
        let reached = self.nested.check(
            &self.prims,
            &self.shared,
            &self.geom,
            &self.nested.root,
            all,
        )?;
        if reached != self.nested.subs.len() {
            return Err(format!(
                "{} nested grids, {reached} reachable",
                self.nested.subs.len()
            ));
        }
        if self.index_bytes() > self.stats.budget {
            return Err(format!(
                "{} bytes over the budget of {}",
                self.index_bytes(),
                self.stats.budget
            ));
        }
        Ok(())
    }
}
