//! The budget of the global search (seeded multi-start particle swarm and Nelder–Mead polish,
//! `entrynav_optimizer::search`) as a user gives it — each count optional, the problem's default
//! otherwise — with its bounds, and the `search` block of a design's JSON.
//!
//! The bounds follow from what one machine does in reasonable time and memory. An evaluation of
//! the navigation objectives costs 0.1–0.3 ms on one core (the default ground search is about
//! 15 000 evaluations, 1.5 s; the orbiter search 100 000, 33 s), so a budget of
//! [`MAX_EVALUATIONS`] is hours to a few days on one core: beyond it a search does not end in
//! any useful time. Each count is also bounded alone so that no count sizes an allocation
//! (a swarm holds its particles, a start runs on one thread).

use crate::options::{OptionError, check_count};
use entrynav_optimizer::{SearchOptions, SearchResult};
use serde_json::{Value, json};

/// Most independent starts.
pub const MAX_STARTS: usize = 1000;
/// Most particles per swarm (the swarm needs at least 2).
pub const MAX_PARTICLES: usize = 10_000;
/// Most swarm iterations per start.
pub const MAX_ITERATIONS: usize = 1_000_000;
/// Most Nelder–Mead iterations per polish round (at most 8 rounds per start).
pub const MAX_POLISH_ITERATIONS: usize = 100_000;
/// Most evaluations of the whole search (the optimizer's estimate of swarm and polish).
pub const MAX_EVALUATIONS: usize = 100_000_000;

/// The search's seed and counts as given (`None`: the problem's default).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchCounts {
    /// Master seed (the same seed gives the same answer on any thread count).
    pub seed: u64,
    /// Independent particle-swarm starts.
    pub starts: Option<usize>,
    /// Particles per swarm.
    pub particles: Option<usize>,
    /// Swarm iterations per start.
    pub iterations: Option<usize>,
    /// Nelder–Mead iterations per polish round.
    pub polish_iterations: Option<usize>,
}

impl SearchCounts {
    /// The search with the problem's `defaults` where a count is not given.
    pub fn resolve(&self, defaults: SearchOptions) -> SearchOptions {
        SearchOptions {
            seed: self.seed,
            starts: self.starts.unwrap_or(defaults.starts),
            particles: self.particles.unwrap_or(defaults.particles),
            iterations: self.iterations.unwrap_or(defaults.iterations),
            polish_iterations: self.polish_iterations.unwrap_or(defaults.polish_iterations),
            polish_step: defaults.polish_step,
        }
    }

    /// Refuse a count outside its range, and a search of more than [`MAX_EVALUATIONS`]
    /// evaluations with the problem's `defaults` filled in.
    pub fn validate(&self, defaults: SearchOptions) -> Result<(), OptionError> {
        let o = self.resolve(defaults);
        check_count("starts", o.starts, 1, MAX_STARTS)?;
        check_count("particles", o.particles, 2, MAX_PARTICLES)?;
        check_count("iterations", o.iterations, 0, MAX_ITERATIONS)?;
        check_count(
            "polish_iterations",
            o.polish_iterations,
            0,
            MAX_POLISH_ITERATIONS,
        )?;
        let budget = o.budget(1);
        if budget > MAX_EVALUATIONS {
            return Err(OptionError::new(
                "search budget (starts, particles, iterations, polish_iterations)",
                budget,
                format!("at most {MAX_EVALUATIONS} evaluations"),
            ));
        }
        Ok(())
    }
}

/// The `search` block of the JSON of `optimize orbiters` and `optimize ground`.
pub fn search_json(s: &SearchResult, opts: &SearchOptions) -> Value {
    json!({
        "seed": opts.seed,
        "starts": opts.starts,
        "particles": opts.particles,
        "iterations": opts.iterations,
        "polish_iterations": opts.polish_iterations,
        "swarm_evaluations": s.swarm_evaluations,
        "start_costs": s.start_costs,
        "best_start": s.best_start,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(starts: usize, particles: usize, iterations: usize) -> SearchCounts {
        SearchCounts {
            seed: 2,
            starts: Some(starts),
            particles: Some(particles),
            iterations: Some(iterations),
            polish_iterations: None,
        }
    }

    #[test]
    fn each_count_and_the_whole_budget_are_bounded() {
        let d = entrynav_optimizer::ground::default_search(2);
        assert!(counts(4, 24, 60).validate(d.clone()).is_ok());
        let e = counts(10_000_000_000_000, 24, 60).validate(d.clone());
        assert_eq!(
            e.unwrap_err().to_string(),
            "starts = 10000000000000 is out of range: must be from 1 to 1000"
        );
        let e = counts(4, 1, 60).validate(d.clone()).unwrap_err();
        assert!(
            e.to_string().starts_with("particles = 1 is out of range"),
            "{e}"
        );
        let e = counts(1000, 10_000, 1000).validate(d).unwrap_err();
        assert!(e.to_string().starts_with("search budget"), "{e}");
    }
}
