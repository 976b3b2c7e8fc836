//! The errors of the libraries a design study calls (the optimizer, the filter names) as the
//! study's own: the text the command line printed for them (the message and each of its sources,
//! joined by `: `) and the kind its exit code said — a truth simulation that failed somewhere in
//! the chain is a failure, anything else was refused.

use crate::error::StudyError;
use entrynav::sim::{SimError, TradeError};
use std::error::Error;

/// `e` as a [`StudyError`], its sources kept in the text.
pub fn study_error(e: impl Error + 'static) -> StudyError {
    let mut text = e.to_string();
    let mut failed = false;
    let mut link: Option<&(dyn Error + 'static)> = Some(&e);
    while let Some(c) = link {
        failed |= c.is::<SimError>() || matches!(c.downcast_ref(), Some(TradeError::Truth(_)));
        link = c.source();
        if let Some(s) = link {
            text.push_str(&format!(": {s}"));
        }
    }
    if failed {
        StudyError::Failed(text)
    } else {
        StudyError::Refused(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ErrorKind;
    use entrynav_optimizer::OptimizerError;

    #[test]
    fn the_text_carries_every_source_and_a_request_is_refused() {
        let e = study_error(OptimizerError::InvalidInput("k = 0".into()));
        assert_eq!(e.to_string(), "invalid input: k = 0");
        assert_eq!(e.kind(), ErrorKind::Refused);
    }
}
