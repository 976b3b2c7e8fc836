//! The inputs of the tables: the bank-angle command, the beacons' availability, and the
//! measurements (inputs of the filter FMU, outputs of the truth FMU).

use super::builder::Builder;
use crate::vars::model::Model;
use crate::vars::slot::{Key, Slot};
use crate::vars::var::{Causality, Type, Value};

/// `bank_angle`: every model but the guided one (whose guidance commands the bank); the truth
/// flies the command, the filter's onboard models use it (known onboard).
pub(super) fn bank_input(b: &mut Builder, model: Model) {
    use Causality::*;
    use Type::*;
    // Every model but the guided one (whose guidance commands the bank): the truth flies the
    // command, the filter's onboard models use it (known onboard).
    if model != Model::Guided {
        b.add(
        "bank_angle",
        Real,
        Input,
        Some("rad"),
        Some(Value::Real(0.0)),
        match model {
            Model::Combined => {
                "Bank-angle command, held over each communication step: flown by the truth and used by the filter's onboard dynamics and measurement models"
            }
            Model::Filter => {
                "Bank-angle command the vehicle flies, held over each communication step: used by the filter's onboard dynamics and measurement models"
            }
            Model::Truth | Model::Guidance | Model::Guided => {
                "Bank-angle command, held over each communication step"
            }
        },
        Key::Bank,
    );
    }
}

/// `beacon_available_i` (`n_beacons` of them) of a model with a truth.
pub(super) fn beacon_inputs(b: &mut Builder, model: Model, n_beacons: usize) {
    use Causality::*;
    use Type::*;
    if model.has_truth() {
        for i in 0..n_beacons {
            b.add(
                format!("beacon_available_{}", i + 1),
                Boolean,
                Input,
                None,
                Some(Value::Boolean(true)),
                format!(
                    "Beacon {} transmits (false: an outage commanded by the master)",
                    i + 1
                ),
                Key::BeaconAvailable(i),
            );
        }
    }
}

/// The measurement variables of an open model: inputs of the filter FMU, outputs of the truth FMU.
pub(super) fn measurements(b: &mut Builder, model: Model) {
    use Causality::*;
    use Type::*;
    // Measurements: inputs of the filter FMU, outputs of the truth FMU.
    if !model.is_closed() {
        let c = if model == Model::Filter {
            Input
        } else {
            Output
        };
        let start = |v: Value| (c == Input).then_some(v);
        b.add(
            "meas_epoch",
            Boolean,
            c,
            None,
            start(Value::Boolean(false)),
            "A measurement epoch: the meas_* values were taken at meas_time",
            Key::MeasEpoch,
        );
        b.add(
            "meas_time",
            Real,
            c,
            Some("s"),
            start(Value::Real(0.0)),
            "Time the measurements were taken",
            Key::MeasTime,
        );
        for s in Slot::all() {
            b.add(
                s.name(),
                Real,
                c,
                Some(s.unit()),
                start(Value::Real(0.0)),
                format!("Measured {} (0 when not valid)", s.what()),
                Key::Meas(s),
            );
            b.add(
                format!("{}_valid", s.name()),
                Boolean,
                c,
                None,
                start(Value::Boolean(false)),
                format!("The measured {} is valid at this epoch", s.what()),
                Key::MeasValid(s),
            );
        }
    }
}
