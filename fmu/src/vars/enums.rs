//! The Enumeration types of the tables (`nav_status`, `truth_stop`).

/// An FMI Enumeration type (`TypeDefinitions/SimpleType`): item `k` has the value `k`.
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct EnumType {
    /// Type name (`declaredType`).
    pub name: &'static str,
    /// Description.
    pub description: &'static str,
    /// Items (name, description), valued 0, 1, ….
    pub items: &'static [(&'static str, &'static str)],
}

/// `nav_status`: [`entrynav::sim::engine::NavStatus::code`].
pub static NAV_STATUS: EnumType = EnumType {
    name: "NavStatus",
    description: "Navigation filter health",
    items: &[
        (
            "initial",
            "No measurement epoch processed yet: the estimate is the filter start",
        ),
        ("running", "Processing measurement epochs"),
        (
            "failed",
            "Stopped on a numerical failure (reason logged); the estimate is frozen",
        ),
    ],
};

/// `truth_stop`: why the truth stopped.
pub static TRUTH_STOP: EnumType = EnumType {
    name: "TruthStop",
    description: "Why the truth trajectory stopped",
    items: &[
        ("running", "The truth is still being integrated"),
        ("duration", "The scenario duration was reached"),
        ("stop_speed", "The airspeed fell below the stop speed"),
        ("ground", "The altitude reached zero"),
    ],
};

/// Every Enumeration type a table may use.
pub static ENUM_TYPES: [&EnumType; 2] = [&NAV_STATUS, &TRUTH_STOP];
