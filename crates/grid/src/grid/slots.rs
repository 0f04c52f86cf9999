//! The grid's one array of primitives: which primitive each slot holds,
//! and moving the primitives into slot order once.

/// The primitive of each slot: the gridded primitives in the order of
/// `gridded` (their first reference), then the unbounded ones, then any
/// primitive that no cell references (none in practice: every gridded
/// primitive touches a cell); and the slots of the unbounded ones.
pub(super) fn slot_order(
    gridded: Box<[u32]>,
    unbounded: &[u32],
    n: usize,
) -> (Box<[u32]>, Box<[u32]>) {
    let mut ids = gridded.into_vec();
    let first = ids.len() as u32;
    ids.extend_from_slice(unbounded);
    let slots = (first..ids.len() as u32).collect();
    if ids.len() < n {
        let mut seen = vec![false; n];
        for &p in &ids {
            seen[p as usize] = true;
        }
        ids.extend((0..n as u32).filter(|&p| !seen[p as usize]));
    }
    debug_assert_eq!(ids.len(), n);
    (ids.into_boxed_slice(), slots)
}

/// `prims` in slot order: slot `s` holds `prims[ids[s]]`. Each primitive
/// is moved once, in parallel when asked; `ids` must be a permutation of
/// `0..prims.len()` (as [`slot_order`] makes it).
pub(super) fn reorder<P: Send>(mut prims: Vec<P>, ids: &[u32], parallel: bool) -> Vec<P> {
    assert_eq!(ids.len(), prims.len(), "one slot per primitive");
    if ids.iter().enumerate().all(|(s, &p)| s == p as usize) {
        return prims;
    }
    let src = crate::par::SharedMut(prims.as_mut_ptr());
    let out = crate::par::map_range(ids.len(), parallel, |s| {
        // The reads jump around: ask for a primitive some slots ahead.
        if let Some(&p) = ids.get(s + 32) {
            src.prefetch(p as usize);
        }
        // SAFETY: `ids` is a permutation of the indices of `prims`, so each
        // primitive is read exactly once; `set_len(0)` below makes sure
        // none is dropped twice.
        unsafe { src.read(ids[s] as usize) }
    });
    // SAFETY: every element has been moved out above.
    unsafe { prims.set_len(0) };
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_hold_every_primitive_once() {
        // Primitives 4 and 1 gridded (in that order), 2 unbounded, 0 and 3
        // in no cell.
        let (ids, unbounded) = slot_order(Box::new([4, 1]), &[2], 5);
        assert_eq!(&*ids, &[4, 1, 2, 0, 3]);
        assert_eq!(&*unbounded, &[2]);
    }

    #[test]
    fn reorder_moves_each_primitive_into_its_slot() {
        let prims: Vec<String> = (0..100).map(|i| format!("p{i}")).collect();
        let ids: Vec<u32> = (0..100).map(|s| (s * 37 + 11) % 100).collect();
        for parallel in [false, true] {
            let out = reorder(prims.clone(), &ids, parallel);
            for (s, &p) in ids.iter().enumerate() {
                assert_eq!(out[s], prims[p as usize]);
            }
        }
        // The identity keeps the vector as it is.
        let same: Vec<u32> = (0..100).collect();
        assert_eq!(reorder(prims.clone(), &same, true), prims);
    }
}
