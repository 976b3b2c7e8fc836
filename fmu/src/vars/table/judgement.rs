//! The judgement outputs of the combined models: the truth at the estimate's epoch, the error,
//! the NEES and the true density.

use super::builder::Builder;
use crate::vars::sizes::MAX_STATES;
use crate::vars::slot::Key;
use crate::vars::specific::Specific;
use crate::vars::var::Type;

/// The judgement of the estimate against the truth (the combined model).
pub(super) fn judgement_outputs(b: &mut Builder, specific: Option<&Specific>) {
    use Type::*;
    match specific {
        None => {
            for i in 0..MAX_STATES {
                b.out(
                    format!("truth_x_{}", i + 1),
                    Real,
                    None,
                    format!(
                        "Truth of filter state {} at the estimate's epoch (0 without a truth counterpart)",
                        i + 1
                    ),
                    Key::TruthX(i),
                );
            }
            for i in 0..MAX_STATES {
                b.out(
                    format!("err_{}", i + 1),
                    Real,
                    None,
                    format!(
                        "Estimation error est_x - truth_x of filter state {} (angles wrapped)",
                        i + 1
                    ),
                    Key::Err(i),
                );
            }
        }
        Some(s) => {
            for (i, st) in s.states.iter().enumerate() {
                b.out(
                    format!("truth_x.{}", st.name),
                    Real,
                    Some(st.unit),
                    format!(
                        "True {} at the estimate's epoch (0 without a truth counterpart)",
                        st.description
                    ),
                    Key::TruthX(i),
                );
            }
            for (i, st) in s.states.iter().enumerate() {
                b.out(
                    format!("err.{}", st.name),
                    Real,
                    Some(st.unit),
                    format!(
                        "Estimation error of the {} (angles wrapped)",
                        st.description
                    ),
                    Key::Err(i),
                );
            }
        }
    }
    b.out(
        "nees",
        Real,
        Some("1"),
        "Normalised estimation error squared over the states with a truth value (0 while nees_dof = 0)",
        Key::Nees,
    );
    b.out(
        "nees_dof",
        Integer,
        None,
        "Degrees of freedom of the NEES",
        Key::NeesDof,
    );
    b.out(
        "nav_truth_density",
        Real,
        Some("kg/m3"),
        "True density at the estimate's epoch",
        Key::NavTruthDensity,
    );
}
