//! The worker threads of a renderer: a rayon pool of its own, or the
//! caller's thread when one thread is asked for or no pool can be built.

use std::fmt;

/// The worker threads of a renderer.
pub(crate) struct Pool {
    #[cfg(feature = "rayon")]
    pool: Option<rayon::ThreadPool>,
}

impl fmt::Debug for Pool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Pool")
    }
}

impl Pool {
    /// `None` threads = all cores; 1 thread = no pool (run on the caller).
    pub(crate) fn new(threads: Option<usize>) -> Self {
        #[cfg(feature = "rayon")]
        {
            let pool = match threads {
                Some(1) => None,
                n => rayon::ThreadPoolBuilder::new()
                    .num_threads(n.unwrap_or(0))
                    .thread_name(|i| format!("gridrt-{i}"))
                    .build()
                    .ok(),
            };
            Self { pool }
        }
        #[cfg(not(feature = "rayon"))]
        {
            let _ = threads;
            Self {}
        }
    }

    /// True when the renderer has worker threads. Without them (one thread
    /// asked for, or none could be started, as in a container whose process
    /// limit is reached) everything runs on the caller's thread and nothing
    /// touches rayon's global pool, which would panic when it cannot start.
    pub(crate) fn is_parallel(&self) -> bool {
        #[cfg(feature = "rayon")]
        {
            self.pool.is_some()
        }
        #[cfg(not(feature = "rayon"))]
        {
            false
        }
    }

    /// Runs `f` inside the pool (so rayon calls in it use the pool's threads).
    pub(crate) fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        #[cfg(feature = "rayon")]
        if let Some(p) = &self.pool {
            return p.install(f);
        }
        f()
    }

    /// `f` over `items` with one `init()` state per worker (per rayon
    /// split), in parallel when the pool has threads; results in item order.
    pub(crate) fn map_init<T, S, R>(
        &self,
        items: &[T],
        init: impl Fn() -> S + Sync + Send,
        f: impl Fn(&mut S, &T) -> R + Sync + Send,
    ) -> Vec<R>
    where
        T: Sync,
        R: Send,
    {
        #[cfg(feature = "rayon")]
        if let Some(p) = &self.pool {
            use rayon::prelude::*;
            return p.install(|| items.par_iter().map_init(&init, &f).collect());
        }
        let mut state = init();
        items.iter().map(|t| f(&mut state, t)).collect()
    }
}
