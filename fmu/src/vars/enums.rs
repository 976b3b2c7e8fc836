//! The Enumeration types of the tables (`nav_status`, `truth_stop`, `guidance_status`).

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

/// `guidance_status`: how the guidance FMU stands
/// ([`GuidanceEngine::status`](crate::instance::GuidanceEngine::status)).
pub static GUIDANCE_STATUS: EnumType = EnumType {
    name: "GuidanceStatus",
    description: "Entry guidance state",
    items: &[
        (
            "waiting",
            "No guidance cycle run yet: the bank is the reference bank",
        ),
        ("flying", "Guidance cycles fly the navigation estimate"),
        (
            "deployed",
            "The trigger was reached on the estimate: cycles stopped, the actuator holds the last command",
        ),
    ],
};

/// Every Enumeration type a table may use.
pub static ENUM_TYPES: [&EnumType; 3] = [&NAV_STATUS, &TRUTH_STOP, &GUIDANCE_STATUS];
