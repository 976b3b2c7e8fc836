//! [`SelectionCriterion`]: what a selection maximises, D-optimal (log det) or E-optimal
//! (max-min λ_min).

/// The design criterion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SelectionCriterion {
    /// D-optimal: `log det Σ_{i∈S} A_i` (blocks summed).
    LogDet,
    /// E-optimal: `min_e λ_min(Σ_{i∈S} A_i^e)`.
    MinEig,
}

impl SelectionCriterion {
    /// Name used on the command line and in reports: `logdet` or `min-eig`.
    pub fn name(self) -> &'static str {
        match self {
            SelectionCriterion::LogDet => "logdet",
            SelectionCriterion::MinEig => "min-eig",
        }
    }
}
