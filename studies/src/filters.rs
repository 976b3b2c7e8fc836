//! The filters an option names (`filters`, `check_filter`), each checked to fit the scenario's
//! onboard view, with errors that name the option: `filters = '0' is unknown: must be one of …`,
//! `filters: filter 'ukf-ac' does not fit scenario 'orbiters-3': …`.

use crate::error::{StudyError, StudyResult};
use crate::options::filter_list;
use entrynav::estimation::nav::FilterKind;
use entrynav::estimation::onboard::Onboard;

/// The filters of the comma-separated `list` given to option `option`, each fitting `onboard`.
pub fn fitting_filters(
    option: &str,
    list: &str,
    onboard: &Onboard,
) -> StudyResult<Vec<FilterKind>> {
    let kinds = filter_list(option, list)?;
    for k in &kinds {
        k.check_fits(onboard)
            .map_err(|e| StudyError::Refused(format!("{option}: {e}")))?;
    }
    Ok(kinds)
}
