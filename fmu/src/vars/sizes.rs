//! The fixed sizes of the generic tables: filter state, beacon and weight slots.

/// Filter state slots of the generic FMUs: every supported filter dimension.
pub const MAX_STATES: usize = entrynav::state_dim::MAX_STATE_DIM;
/// Beacon slots.
pub const MAX_BEACONS: usize = 6;
/// Fusion-weight / model-probability slots.
pub const MAX_WEIGHTS: usize = 8;
