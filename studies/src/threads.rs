//! The one place a study's worker pool is chosen. Results never depend on the pool (runs are
//! folded in run order), only the wall time does.

use crate::error::{StudyError, StudyResult};
use crate::options::check_threads;

/// Run `f` on a pool of `threads` workers (checked: 1 to `MAX_THREADS`), or on rayon's global
/// pool (all cores, or `RAYON_NUM_THREADS`) when `threads` is `None`.
pub fn with_threads<R: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> StudyResult<R> + Send,
) -> StudyResult<R> {
    check_threads(threads)?;
    match threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| {
                StudyError::Failed(format!(
                    "--threads {n}: cannot start the worker threads: {e}"
                ))
            })?
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
        let e = with_threads(Some(2), || -> StudyResult<()> {
            Err(StudyError::Failed("inner".into()))
        })
        .unwrap_err();
        assert_eq!(e.to_string(), "inner");
        let e = with_threads(Some(1_000_000), || Ok(())).unwrap_err();
        assert_eq!(
            e.to_string(),
            "threads = 1000000 is out of range: must be from 1 to 1024"
        );
    }
}
