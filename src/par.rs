//! The parallelism of a computation as a value ([`Par`]): how many worker threads its parallel
//! maps use.
//!
//! A computation that maps in parallel takes a `Par` and runs its map through it
//! ([`Par::map`], [`Par::install`]), so the thread count a caller asks for (`--threads`,
//! [`crate::experiment::Settings::threads`], [`crate::sweep::driver::SweepOptions::par`]) is
//! the one applied. [`Par::all`] is rayon's pool as found (the global pool, one thread per
//! core, or the pool the caller already runs on); [`Par::threads`]`(n)` runs on a pool of `n`
//! threads, built once per call unless the calling thread is already a worker of a pool of
//! that size (nested maps then share it, no second pool). Maps keep the input order, so the
//! output is the same for every thread count. Cost of a pool: n thread starts (≈ 0.1 ms
//! each), paid once per outermost map.
//!
//! ```
//! use helixreach::par::Par;
//! let squares = Par::threads(2)?.map(&[1, 2, 3, 4], |x| x * x)?;
//! assert_eq!(squares, vec![1, 4, 9, 16]);
//! assert_eq!(Par::threads(3)?.install(rayon::current_num_threads)?, 3);
//! assert!(Par::threads(0).is_err());
//! # Ok::<(), helixreach::Error>(())
//! ```

use crate::error::{Error, Result};
use rayon::prelude::*;

/// How many worker threads a computation's parallel maps use (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Par {
    /// The thread count; 0: the pool as found ([`Par::all`]).
    threads: usize,
}

impl Par {
    /// The pool as found: the calling pool, else rayon's global pool (one thread per core).
    pub fn all() -> Par {
        Par { threads: 0 }
    }

    /// `n` worker threads, 1 ≤ n ≤ [`crate::limits::MAX_THREADS`].
    pub fn threads(n: usize) -> Result<Par> {
        crate::limits::check_range("threads", n, 1, crate::limits::MAX_THREADS)?;
        Ok(Par { threads: n })
    }

    /// `Some(n)`: [`Par::threads`]`(n)`; `None`: [`Par::all`].
    pub fn from_option(n: Option<usize>) -> Result<Par> {
        n.map_or(Ok(Par::all()), Par::threads)
    }

    /// The number of worker threads the maps run on.
    pub fn count(&self) -> usize {
        if self.threads == 0 {
            rayon::current_num_threads().max(1)
        } else {
            self.threads
        }
    }

    /// Run `f` with this parallelism: every rayon map inside it uses [`Par::count`] threads.
    /// Errors when the worker threads cannot be started.
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> Result<R> {
        let n = self.threads;
        if n == 0 || (rayon::current_thread_index().is_some() && rayon::current_num_threads() == n)
        {
            return Ok(f());
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| {
                Error::invalid(
                    "threads",
                    n,
                    format!("cannot start the worker threads: {e}"),
                )
            })?;
        Ok(pool.install(f))
    }

    /// `f` over `items` in parallel, results in input order.
    pub fn map<T: Sync, U: Send>(
        &self,
        items: &[T],
        f: impl Fn(&T) -> U + Sync + Send,
    ) -> Result<Vec<U>> {
        self.install(|| items.par_iter().map(f).collect())
    }

    /// `f` over `0..n` in parallel, results in index order.
    pub fn map_range<U: Send>(
        &self,
        n: usize,
        f: impl Fn(usize) -> U + Sync + Send,
    ) -> Result<Vec<U>> {
        self.install(|| (0..n).into_par_iter().map(f).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The maps run on exactly the threads asked for (counted by distinct worker indices, a
    /// bound the pool size sets), and keep input order.
    #[test]
    fn threads_are_applied_and_order_kept() {
        for n in [1, 2, 3] {
            let p = Par::threads(n).unwrap();
            let seen = p
                .map_range(200, |i| {
                    std::thread::sleep(std::time::Duration::from_micros(200));
                    (
                        i,
                        rayon::current_num_threads(),
                        rayon::current_thread_index(),
                    )
                })
                .unwrap();
            for (k, (i, pool, idx)) in seen.iter().enumerate() {
                assert_eq!(*i, k);
                assert_eq!(*pool, n);
                assert!(idx.is_some_and(|x| x < n));
            }
        }
        // Nested: a map inside a pool of the same size shares it.
        let p = Par::threads(2).unwrap();
        let inner = p
            .install(|| p.install(rayon::current_num_threads).unwrap())
            .unwrap();
        assert_eq!(inner, 2);
    }
}
