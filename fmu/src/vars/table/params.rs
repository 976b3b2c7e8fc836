//! The parameters of the tables: the scenario, the filter, the seed, dispersed or nominal, the
//! guided FMU's Monte Carlo run, and whether files outside the resources folder may be read.

use super::builder::Builder;
use crate::vars::defaults::{DEFAULT_FILTER, DEFAULT_SCENARIO, DEFAULT_SEED, GUIDED_FILTER};
use crate::vars::model::Model;
use crate::vars::slot::Key;
use crate::vars::specific::Specific;
use crate::vars::var::{Causality, Type, Value};

/// The `scenario` parameter of a generic FMU other than the guidance and guided ones.
pub(super) fn scenario_param(b: &mut Builder) {
    use Causality::*;
    use Type::*;
    b.add(
        "scenario",
        String,
        Parameter,
        None,
        Some(Value::String(DEFAULT_SCENARIO.into())),
        format!(
            "Scenario: a built-in name ({}) or a TOML file in the FMU's resources folder (a file elsewhere only with allow_external_files = true)",
            entrynav::scenario::BUILTIN_NAMES.join(", ")
        ),
        Key::Scenario,
    );
}

/// The `filter` parameter of a model with a filter: its default is the specific FMU's filter, the
/// guided FMU's [`GUIDED_FILTER`] or [`DEFAULT_FILTER`].
pub(super) fn filter_param(b: &mut Builder, model: Model, specific: Option<&Specific>) {
    use Causality::*;
    use Type::*;
    // The guided FMU's default scenario (msl-guided) has no radio beacons: the EKF, as in the
    // guided SSP's filter.
    let default_filter = match (specific, model) {
        (Some(s), _) => s.filter.name(),
        (None, Model::Guided) => GUIDED_FILTER,
        (None, _) => DEFAULT_FILTER,
    };
    if model.has_filter() {
        b.add(
            "filter",
            String,
            Parameter,
            None,
            Some(Value::String(default_filter.into())),
            format!(
                "Navigation filter, as entrynav trade: {}",
                entrynav::estimation::nav::FilterKind::ALL
                    .map(|k| k.name())
                    .join(", ")
            ),
            Key::Filter,
        );
    }
}

/// `seed`, `dispersed` and (the guided FMU) `run`.
pub(super) fn draw_params(b: &mut Builder, model: Model) {
    use Causality::*;
    use Type::*;
    b.add(
        "seed",
        Integer,
        Parameter,
        None,
        Some(Value::Integer(DEFAULT_SEED)),
        "Seed (>= 0) of the dispersions, measurement noise and filter start, as entrynav simulate --seed",
        Key::Seed,
    );
    b.add(
        "dispersed",
        Boolean,
        Parameter,
        None,
        Some(Value::Boolean(false)),
        "Draw the truth from the scenario's dispersions (true) or use the nominal truth (false)",
        Key::Dispersed,
    );
    if model == Model::Guided {
        b.add(
            "run",
            Integer,
            Parameter,
            None,
            Some(Value::Integer(0)),
            "With dispersed = true: the Monte Carlo run (0 to 999999999) whose truth, noise and filter start are flown, as run `run` of entrynav guidance deliver --seed seed (the same delivery, bit for bit); not used when dispersed = false",
            Key::Run,
        );
    }
}

/// `allow_external_files` (every generic FMU).
pub(super) fn allow_external_files(b: &mut Builder) {
    use Causality::*;
    use Type::*;
    b.add(
        "allow_external_files",
        Boolean,
        Parameter,
        None,
        Some(Value::Boolean(false)),
        "Let scenario name a file outside the FMU's resources folder (an absolute path or one with ..); off by default, so a parameter cannot make the FMU read host files",
        Key::AllowExternalFiles,
    );
}
