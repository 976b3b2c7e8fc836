//! How a study tells its caller how far it is: a callback of [`Step`]s. The study never prints;
//! the command line draws bars or lines from the steps, Python calls the user's function. The
//! callback is called from worker threads (hence `Sync`) and must be cheap.

/// One step of progress.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step<'a> {
    /// What is counted: `runs`, `evaluations`, `cells`, `iterations`, …
    pub unit: &'a str,
    /// What is being done (a filter's name, a cell's label, a stage); empty when there is only one.
    pub task: &'a str,
    /// Finished so far.
    pub done: u64,
    /// To do in all (0: unknown).
    pub total: u64,
    /// The best objective value so far, for a search.
    pub best: Option<f64>,
}

impl<'a> Step<'a> {
    /// `done` of `total` `unit` of `task`.
    pub fn of(unit: &'a str, task: &'a str, done: u64, total: u64) -> Step<'a> {
        Step {
            unit,
            task,
            done,
            total,
            best: None,
        }
    }
}

/// The callback a study reports to.
pub type Progress<'a> = &'a (dyn Fn(Step<'_>) + Sync);

/// A callback that ignores every step.
pub fn silent(_: Step<'_>) {}
