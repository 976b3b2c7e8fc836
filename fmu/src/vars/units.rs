//! The units the variables use, with their SI base-unit exponents and display units.

/// A unit: name, SI base-unit exponents (kg, m, s, rad), and an optional display unit (name, factor).
pub type UnitDef = (&'static str, [i32; 4], Option<(&'static str, f64)>);

/// The units the variables use ("1": dimensionless).
pub const UNITS: [UnitDef; 11] = [
    ("m", [0, 1, 0, 0], None),
    ("rad", [0, 0, 0, 1], Some(("deg", 57.29577951308232))),
    ("m/s", [0, 1, -1, 0], None),
    ("m/s2", [0, 1, -2, 0], None),
    ("s", [0, 0, 1, 0], None),
    ("kg/m3", [1, -3, 0, 0], None),
    ("Pa", [1, -1, -2, 0], None),
    ("W/m2", [1, 0, -3, 0], None),
    ("m2/kg", [-1, 2, 0, 0], None),
    ("1", [0, 0, 0, 0], None),
    ("rad/s", [0, 0, -1, 1], Some(("deg/s", 57.29577951308232))),
];
