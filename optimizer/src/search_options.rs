//! What the global search ([`crate::search`]) is given, [`SearchOptions`] (starts, swarm,
//! polish, seed), and what it returns, [`SearchResult`] (the best point, its cost and the
//! evaluation counts).

/// Budget and seeding of [`minimize`](crate::search::minimize).
#[derive(Debug, Clone, PartialEq)]
pub struct SearchOptions {
    /// Master seed.
    pub seed: u64,
    /// Independent swarm starts.
    pub starts: usize,
    /// Particles per swarm.
    pub particles: usize,
    /// Swarm iterations per start.
    pub iterations: usize,
    /// Nelder–Mead iterations per polish round (up to [`POLISH_ROUNDS`](crate::search::POLISH_ROUNDS) restarted rounds per
    /// start; 0 disables the polish).
    pub polish_iterations: usize,
    /// Initial simplex edge of the polish as a fraction of each variable's box width.
    pub polish_step: f64,
}

impl Default for SearchOptions {
    fn default() -> Self {
        SearchOptions {
            seed: 2,
            starts: 4,
            particles: 40,
            iterations: 200,
            polish_iterations: 400,
            polish_step: 0.02,
        }
    }
}

impl SearchOptions {
    /// The evaluation budget (the progress total): swarm evaluations plus an estimate of the
    /// polish (Nelder–Mead uses about two evaluations per iteration).
    pub fn budget(&self, dim: usize) -> usize {
        let swarm = self.particles * (self.iterations + 1);
        let polish = 3 * (dim + 1 + 2 * self.polish_iterations);
        self.starts.max(1) * (swarm + polish)
    }
}

/// What [`minimize`](crate::search::minimize) found.
#[derive(Debug, Clone, PartialEq)]
pub struct SearchResult {
    /// Best point.
    pub x: Vec<f64>,
    /// Its cost.
    pub cost: f64,
    /// Cost evaluations in total (all starts, swarm and polish).
    pub evaluations: usize,
    /// Of which in the swarms.
    pub swarm_evaluations: usize,
    /// Best cost of each start after its polish, in start order.
    pub start_costs: Vec<f64>,
    /// Index of the winning start.
    pub best_start: usize,
}
