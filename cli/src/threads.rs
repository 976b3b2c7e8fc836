//! `--threads N`: the one place a command's worker pool is chosen. Results never depend on the
//! pool (runs are folded in run order), only the wall time does.

use anyhow::{Context, Result};

/// Run `f` on a pool of `threads` workers (`--threads N`, at least 1), or on rayon's global pool
/// (all cores, or `RAYON_NUM_THREADS`) when `threads` is `None`.
pub fn with_threads<R: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> Result<R> + Send,
) -> Result<R> {
    match threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .with_context(|| format!("--threads {n}: cannot start the worker threads"))?
            .install(f),
        None => f(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closure_runs_on_a_pool_of_the_asked_size_or_on_the_global_pool() {
        for n in [1, 3] {
            let seen = with_threads(Some(n), || Ok(rayon::current_num_threads())).unwrap();
            assert_eq!(seen, n);
        }
        let global = with_threads(None, || Ok(rayon::current_num_threads())).unwrap();
        assert_eq!(global, rayon::current_num_threads());
        let e = with_threads(Some(2), || -> Result<()> { anyhow::bail!("inner") }).unwrap_err();
        assert_eq!(e.to_string(), "inner");
    }
}
