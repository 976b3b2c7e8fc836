//! The optimizer's progress (evaluations done of a budget) as the study layer's [`Step`]s.

use crate::progress::{Progress, Step};

/// The optimizer's `(done, budget)` callback reporting `task`'s evaluations to `progress`.
pub fn evaluations<'a>(progress: Progress<'a>, task: &'a str) -> impl Fn(usize, usize) + Sync + 'a {
    move |done, total| progress(Step::of("evaluations", task, done as u64, total as u64))
}
