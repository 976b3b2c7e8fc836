//! The cost of an infeasible set of sites: a base above every feasible cost plus a penalty
//! per radian of elevation below the requirement, finite and graded towards the feasible set.

/// Base cost of an infeasible configuration (above every feasible cost).
pub const INFEASIBLE_COST: f64 = 1e4;

/// Cost per radian of elevation below the required minimum.
pub const PENALTY_PER_RAD: f64 = 1e4;
