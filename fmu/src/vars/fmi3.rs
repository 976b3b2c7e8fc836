//! The variables an FMI 3.0 description adds to the scalar table ([`super::variables`]).
//!
//! An FMI 3.0 FMU of a model has every scalar variable of its FMI 2.0 FMU, with the same name and
//! value reference (Real → `Float64`, Integer → `Int32`, an Enumeration → `Enumeration`, accessed
//! through `fmi3GetInt64`/`fmi3SetInt64` as FMI 3.0 requires, Boolean → `Boolean`, String →
//! `String`), so an output reads the same bits through either interface. After them come the
//! variables only FMI 3.0 can express ([`Extra`]):
//! - `time`, the independent variable FMI 3.0 requires (the instance's current time);
//! - `n_state_slots`, a `UInt64` structural parameter: the number of filter-state slots (the
//!   generic models' [`super::MAX_STATES`], or the embedded scenario's state dimension), fixed by
//!   the model (this FMU has no configuration mode, so only its own value may be set);
//! - `est_x`, `est_sigma` (`[n_state_slots]`) and `est_covariance` (`[n_state_slots,
//!   n_state_slots]`, row-major): the estimate, its 1σ and its covariance as `Float64` arrays whose
//!   dimensions refer to `n_state_slots`. `est_x[i]` and `est_sigma[i]` are bit for bit the scalar
//!   outputs of slot i; slots past the filter's dimension read 0, as the scalars do.
//!
//! Models without a filter (`MarsEntryTruth`, `MarsEntryGuidance`) have only `time`.

use super::{Key, ModelSpec};

/// What an FMI 3.0-only variable is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Extra {
    /// The independent variable (`causality="independent"`).
    Time,
    /// The structural parameter sizing the arrays.
    Slots,
    /// The estimate, one element per slot.
    Estimate,
    /// 1σ per slot.
    Sigma,
    /// The covariance, slots × slots, row-major.
    Covariance,
}

/// An FMI 3.0-only variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Var3 {
    /// Value reference (after every scalar variable's).
    pub vr: u32,
    /// Name.
    pub name: &'static str,
    /// What it is.
    pub extra: Extra,
    /// Description.
    pub description: &'static str,
}

impl Var3 {
    /// The number of values it holds: 1, `slots` or `slots²`.
    pub fn len(&self, slots: usize) -> usize {
        match self.extra {
            Extra::Time | Extra::Slots => 1,
            Extra::Estimate | Extra::Sigma => slots,
            Extra::Covariance => slots * slots,
        }
    }

    /// Whether it is an array (its length comes from the structural parameter).
    pub fn is_array(&self) -> bool {
        matches!(
            self.extra,
            Extra::Estimate | Extra::Sigma | Extra::Covariance
        )
    }
}

/// The number of filter-state slots of `spec` (0 for a model without a filter; the guidance
/// FMU's `est_x_*` are inputs, not a filter's state).
pub fn state_slots(spec: &ModelSpec) -> usize {
    if !spec.model().has_filter() {
        return 0;
    }
    spec.vars()
        .iter()
        .filter(|v| matches!(v.key, Key::EstX(_)))
        .count()
}

/// The FMI 3.0-only variables of `spec`, value references following the scalar table's.
pub fn extras(spec: &ModelSpec) -> Vec<Var3> {
    let mut vr = spec.vars().len() as u32;
    let mut next = || {
        vr += 1;
        vr - 1
    };
    let mut v = vec![Var3 {
        vr: next(),
        name: "time",
        extra: Extra::Time,
        description: "Simulation time [s] (the independent variable)",
    }];
    if state_slots(spec) > 0 {
        v.push(Var3 {
            vr: next(),
            name: "n_state_slots",
            extra: Extra::Slots,
            description: "Number of filter-state slots: the length of est_x and est_sigma and each dimension of est_covariance (fixed by the model)",
        });
        v.push(Var3 {
            vr: next(),
            name: "est_x",
            extra: Extra::Estimate,
            description: "Estimate per filter-state slot (filter-model coordinates; slots past the filter's dimension read 0)",
        });
        v.push(Var3 {
            vr: next(),
            name: "est_sigma",
            extra: Extra::Sigma,
            description: "1-sigma per filter-state slot (square root of the covariance diagonal)",
        });
        v.push(Var3 {
            vr: next(),
            name: "est_covariance",
            extra: Extra::Covariance,
            description: "Estimate covariance, slots x slots, row-major (entries outside the filter's dimension read 0)",
        });
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vars::{MAX_STATES, Model};

    #[test]
    fn extras_follow_the_scalar_table_and_only_filters_have_arrays() {
        for m in Model::ALL {
            let spec = ModelSpec::generic(m);
            let x = extras(&spec);
            let n = spec.vars().len() as u32;
            for (k, v) in x.iter().enumerate() {
                assert_eq!(v.vr, n + k as u32);
                assert!(spec.vars().iter().all(|s| s.name != v.name), "{}", v.name);
            }
            let slots = state_slots(&spec);
            assert_eq!(slots, if m.has_filter() { MAX_STATES } else { 0 });
            assert_eq!(x.len(), if m.has_filter() { 5 } else { 1 });
        }
    }
}
