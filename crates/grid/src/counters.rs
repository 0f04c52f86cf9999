//! Optional per-query counters. The queries are generic over [`Counters`];
//! the plain `Accelerator` methods pass [`NoCounters`], whose methods are
//! empty and inline away, so counting costs nothing unless asked for.

/// Receives one event per cell visited, primitive tested and mailbox skip.
pub trait Counters {
    /// A cell of the grid was visited (for [`crate::Exhaustive`]: never).
    fn cell(&mut self);
    /// A primitive's intersection routine was called.
    fn test(&mut self);
    /// `n` primitives were handed to [`crate::Primitive::closest_hits`]
    /// (each counts as a test).
    #[inline(always)]
    fn tests(&mut self, n: usize) {
        for _ in 0..n {
            self.test();
        }
    }
    /// A primitive was skipped because the mailbox showed it was already tested.
    fn mailbox_skip(&mut self);
    /// A query started.
    fn ray(&mut self);
}

/// Counts nothing; every method is a no-op.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NoCounters;

impl Counters for NoCounters {
    #[inline(always)]
    fn cell(&mut self) {}
    #[inline(always)]
    fn test(&mut self) {}
    #[inline(always)]
    fn mailbox_skip(&mut self) {}
    #[inline(always)]
    fn ray(&mut self) {}
}

/// Totals over any number of queries; add several with [`QueryCounters::merge`].
///
/// ```
/// use gridrt_grid::QueryCounters;
/// let mut a = QueryCounters { rays: 2, cells: 10, tests: 6, mailbox_skips: 1 };
/// a.merge(&QueryCounters { rays: 2, cells: 0, tests: 2, mailbox_skips: 0 });
/// assert_eq!(a.tests_per_ray(), 2.0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryCounters {
    /// Queries made.
    pub rays: u64,
    /// Grid cells visited.
    pub cells: u64,
    /// Primitive intersection tests.
    pub tests: u64,
    /// Tests avoided by mailboxing.
    pub mailbox_skips: u64,
}

impl QueryCounters {
    /// Adds another set of counts (for example one per thread).
    pub fn merge(&mut self, other: &Self) {
        self.rays += other.rays;
        self.cells += other.cells;
        self.tests += other.tests;
        self.mailbox_skips += other.mailbox_skips;
    }

    /// Primitive tests per query (0 without queries).
    #[must_use]
    pub fn tests_per_ray(&self) -> f64 {
        ratio(self.tests, self.rays)
    }

    /// Cells visited per query (0 without queries).
    #[must_use]
    pub fn cells_per_ray(&self) -> f64 {
        ratio(self.cells, self.rays)
    }
}

fn ratio(a: u64, b: u64) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

impl Counters for QueryCounters {
    #[inline(always)]
    fn cell(&mut self) {
        self.cells += 1;
    }
    #[inline(always)]
    fn test(&mut self) {
        self.tests += 1;
    }
    #[inline(always)]
    fn tests(&mut self, n: usize) {
        self.tests += n as u64;
    }
    #[inline(always)]
    fn mailbox_skip(&mut self) {
        self.mailbox_skips += 1;
    }
    #[inline(always)]
    fn ray(&mut self) {
        self.rays += 1;
    }
}
