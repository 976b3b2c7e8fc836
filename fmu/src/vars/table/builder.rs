//! [`Builder`]: the variable list being declared, each variable with its value reference (its
//! index), and the variability its causality and key give it.

use crate::vars::enums::EnumType;
use crate::vars::slot::Key;
use crate::vars::var::{Causality, Type, Value, Var, Variability};

/// The six spherical states: name, unit, meaning.
pub(crate) const SPH: [(&str, &str, &str); 6] = [
    ("r", "m", "radius"),
    ("lon", "rad", "longitude"),
    ("lat", "rad", "latitude"),
    ("v", "m/s", "planet-relative speed"),
    ("fpa", "rad", "flight-path angle"),
    ("heading", "rad", "heading (north-clockwise)"),
];

/// The variables declared so far, in value-reference order.
pub(crate) struct Builder {
    pub(crate) vars: Vec<Var>,
}

/// Reals of the sampled-data part (measurements, the estimate and its judgement) change only at
/// measurement epochs; the truth and the bank command are continuous.
fn real_variability(key: Key) -> Variability {
    match key {
        Key::Bank
        | Key::TruthSph(_)
        | Key::TruthAltitude
        | Key::TruthDensity
        | Key::TruthDynamicPressure
        | Key::TruthHeating
        | Key::TruthAeroAccel
        | Key::TruthSensedAccel(_)
        | Key::BeaconRange(_) => Variability::Continuous,
        _ => Variability::Discrete,
    }
}

impl Builder {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn add(
        &mut self,
        name: impl Into<String>,
        ty: Type,
        causality: Causality,
        unit: Option<&'static str>,
        start: Option<Value>,
        description: impl Into<String>,
        key: Key,
    ) {
        let variability = match (causality, ty) {
            (Causality::Parameter, _) => Variability::Fixed,
            (_, Type::Real) => real_variability(key),
            _ => Variability::Discrete,
        };
        self.vars.push(Var {
            vr: self.vars.len() as u32,
            name: name.into(),
            ty,
            declared: None,
            causality,
            variability,
            unit,
            start,
            description: description.into(),
            key,
        });
    }

    pub(crate) fn out(
        &mut self,
        name: impl Into<String>,
        ty: Type,
        unit: Option<&'static str>,
        description: impl Into<String>,
        key: Key,
    ) {
        self.add(name, ty, Causality::Output, unit, None, description, key);
    }

    /// An Integer output declared as the Enumeration `e`.
    pub(crate) fn enumeration(
        &mut self,
        name: &str,
        e: &'static EnumType,
        description: &str,
        key: Key,
    ) {
        self.out(name, Type::Integer, None, description, key);
        if let Some(v) = self.vars.last_mut() {
            v.declared = Some(e);
        }
    }
}
