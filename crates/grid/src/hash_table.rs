//! A small open-addressing hash table from a cell's Morton code to its run of
//! references: the lecture's "only allocate space for a cell if it is occupied".
//!
//! Linear probing over 16-byte slots (key, start, length), capacity a power of
//! two at least twice the number of occupied cells, so a probe sequence is
//! short and always ends at an empty slot. The hash is Fibonacci hashing
//! (Knuth, TAOCP vol. 3 §6.4): one multiply and a shift, no SipHash.

/// Marks an empty slot. Morton codes use at most 63 bits, so it never
/// collides with a key.
pub(crate) const EMPTY: u64 = u64::MAX;

/// One slot: a cell's Morton code and its references `refs[start..start + len]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C, align(16))]
pub(crate) struct Slot {
    pub key: u64,
    pub start: u32,
    pub len: u32,
}

/// The table. Immutable after the build.
#[derive(Clone, Debug)]
pub(crate) struct CellTable {
    slots: Box<[Slot]>,
    mask: usize,
    shift: u32,
}

impl CellTable {
    /// An empty table sized for `occupied` cells.
    pub(crate) fn with_cells(occupied: usize) -> Self {
        let cap = (occupied.max(1) * 2).next_power_of_two().max(4);
        let empty = Slot {
            key: EMPTY,
            start: 0,
            len: 0,
        };
        Self {
            slots: vec![empty; cap].into_boxed_slice(),
            mask: cap - 1,
            shift: 64 - cap.trailing_zeros(),
        }
    }

    /// The home slot of a key.
    #[inline(always)]
    fn home(&self, key: u64) -> usize {
        (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> self.shift) as usize
    }

    /// Adds a cell. Keys must be distinct and the table must not be full
    /// (guaranteed by [`CellTable::with_cells`] for at most `occupied` inserts).
    pub(crate) fn insert(&mut self, key: u64, start: u32, len: u32) {
        debug_assert!(key != EMPTY);
        let mut i = self.home(key);
        loop {
            let s = &mut self.slots[i];
            if s.key == EMPTY {
                *s = Slot { key, start, len };
                return;
            }
            debug_assert!(s.key != key, "duplicate cell key");
            i = (i + 1) & self.mask;
        }
    }

    /// The run `(start, len)` of an occupied cell, or `(0, 0)` for an empty one.
    #[inline(always)]
    pub(crate) fn get(&self, key: u64) -> (u32, u32) {
        let mut i = self.home(key);
        loop {
            // SAFETY: `i` is masked to the power-of-two capacity.
            let s = unsafe { self.slots.get_unchecked(i) };
            if s.key == key {
                return (s.start, s.len);
            }
            if s.key == EMPTY {
                return (0, 0);
            }
            i = (i + 1) & self.mask;
        }
    }

    /// All occupied slots, in table order.
    pub(crate) fn occupied(&self) -> impl Iterator<Item = &Slot> + '_ {
        self.slots.iter().filter(|s| s.key != EMPTY)
    }

    /// Slots allocated (occupied or not).
    pub(crate) fn capacity(&self) -> usize {
        self.slots.len()
    }

    /// Heap bytes of the table.
    pub(crate) fn bytes(&self) -> usize {
        std::mem::size_of_val(&*self.slots)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_what_was_inserted_and_nothing_else() {
        let mut t = CellTable::with_cells(1000);
        for k in 0..1000u64 {
            t.insert(k * 7, k as u32, 1 + (k % 3) as u32);
        }
        for k in 0..7000u64 {
            let want = if k % 7 == 0 {
                ((k / 7) as u32, 1 + ((k / 7) % 3) as u32)
            } else {
                (0, 0)
            };
            assert_eq!(t.get(k), want);
        }
        assert_eq!(t.occupied().count(), 1000);
        assert!(t.capacity() >= 2000);
    }
}
