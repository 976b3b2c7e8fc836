//! [`Guidance`]: the trait every guidance algorithm implements, one bank command per guidance
//! cycle.

use super::error::GuidanceError;
use super::nav_state::NavState;

/// A guidance algorithm: one bank command per guidance cycle.
pub trait Guidance {
    /// The signed bank command \[rad\] (positive: lift to the right, heading increases) for the
    /// navigation solution `nav`.
    fn command(&mut self, nav: &NavState) -> Result<f64, GuidanceError>;

    /// Short name for reports.
    fn name(&self) -> &'static str;
}
