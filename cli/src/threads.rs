//! `--threads N` for the commands that are not studies of the study layer (`train-density`): the
//! study layer's pool ([`entrynav_studies::threads::with_threads`]) around a closure that returns
//! an `anyhow` result.

use anyhow::Result;

/// Run `f` on a pool of `threads` workers, or on rayon's global pool when `threads` is `None`.
pub fn with_threads<R: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> Result<R> + Send,
) -> Result<R> {
    let mut out = None;
    entrynav_studies::threads::with_threads(threads, || {
        out = Some(f());
        Ok(())
    })?;
    out.expect("the pool ran the closure")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closure_runs_on_the_asked_pool_and_its_error_comes_back() {
        let seen = with_threads(Some(3), || Ok(rayon::current_num_threads())).unwrap();
        assert_eq!(seen, 3);
        let e = with_threads(Some(2), || -> Result<()> { anyhow::bail!("inner") }).unwrap_err();
        assert_eq!(e.to_string(), "inner");
    }
}
