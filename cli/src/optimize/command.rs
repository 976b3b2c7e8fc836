//! `entrynav optimize`: each problem to its command.

use super::args::{OptimizeArgs, OptimizeProblem};
use anyhow::Result;

/// Run the command.
pub fn run(args: &OptimizeArgs) -> Result<()> {
    match &args.problem {
        OptimizeProblem::Orbiters(a) => super::orbiters::run(a),
        OptimizeProblem::Ground(a) => super::ground::run(a),
        OptimizeProblem::Select(a) => super::select::run(a),
    }
}
