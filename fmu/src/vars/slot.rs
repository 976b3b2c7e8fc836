//! What a variable is bound to ([`Key`]) and the measurement slots ([`Slot`]) the truth FMU
//! outputs and the filter FMU reads.

use super::sizes::MAX_BEACONS;
use entrynav::sensors::Channel;

/// A measurement slot (one scalar sensor reading).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Slot {
    /// Accelerometer axis 0..3 of the IMU frame.
    Accel(u8),
    /// Dynamic pressure.
    DynamicPressure,
    /// Heating rate.
    Heating,
    /// Range to beacon slot i.
    Range(usize),
    /// Range-rate to beacon slot i.
    RangeRate(usize),
}

impl Slot {
    /// Every slot, in table order.
    pub fn all() -> Vec<Slot> {
        let mut v = vec![
            Slot::Accel(0),
            Slot::Accel(1),
            Slot::Accel(2),
            Slot::DynamicPressure,
            Slot::Heating,
        ];
        v.extend((0..MAX_BEACONS).map(Slot::Range));
        v.extend((0..MAX_BEACONS).map(Slot::RangeRate));
        v
    }

    /// The slot of a scenario channel (None for beacons past the slots).
    pub fn of(channel: Channel) -> Option<Slot> {
        let s = match channel {
            Channel::Accel(k) => Slot::Accel(k.min(2)),
            Channel::DynamicPressure => Slot::DynamicPressure,
            Channel::Heating => Slot::Heating,
            Channel::Range(i) => Slot::Range(i),
            Channel::RangeRate(i) => Slot::RangeRate(i),
        };
        match s {
            Slot::Range(i) | Slot::RangeRate(i) if i >= MAX_BEACONS => None,
            s => Some(s),
        }
    }

    pub(super) fn name(self) -> String {
        match self {
            Slot::Accel(k) => format!("meas_accel_{}", ["x", "y", "z"][k as usize]),
            Slot::DynamicPressure => "meas_dynamic_pressure".into(),
            Slot::Heating => "meas_heating".into(),
            Slot::Range(i) => format!("meas_range_{}", i + 1),
            Slot::RangeRate(i) => format!("meas_range_rate_{}", i + 1),
        }
    }

    pub(super) fn unit(self) -> &'static str {
        match self {
            Slot::Accel(_) => "m/s2",
            Slot::DynamicPressure => "Pa",
            Slot::Heating => "W/m2",
            Slot::Range(_) => "m",
            Slot::RangeRate(_) => "m/s",
        }
    }

    pub(super) fn what(self) -> String {
        match self {
            Slot::Accel(k) => format!(
                "accelerometer specific force along IMU axis {}",
                ["x", "y", "z"][k as usize]
            ),
            Slot::DynamicPressure => "dynamic pressure (air data)".into(),
            Slot::Heating => "convective heating rate (air data)".into(),
            Slot::Range(i) => format!("two-way range to beacon {}", i + 1),
            Slot::RangeRate(i) => format!("range-rate to beacon {}", i + 1),
        }
    }
}

/// What a variable is bound to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Key {
    /// Scenario: built-in name or file in the FMU's resources.
    Scenario,
    /// Filter name.
    Filter,
    /// Generator seed.
    Seed,
    /// Draw the truth from the scenario's dispersions.
    Dispersed,
    /// Let `scenario` name files outside the FMU's resources folder.
    AllowExternalFiles,
    /// Bank-angle command \[rad\].
    Bank,
    /// Beacon slot commanded available.
    BeaconAvailable(usize),
    /// A measurement epoch is present (filter input / truth output).
    MeasEpoch,
    /// Time the measurements were taken.
    MeasTime,
    /// Measurement value.
    Meas(Slot),
    /// Measurement validity flag.
    MeasValid(Slot),
    /// Planet-relative spherical truth component k = r, lon, lat, v, fpa, heading.
    TruthSph(usize),
    /// Truth altitude.
    TruthAltitude,
    /// True density.
    TruthDensity,
    /// True dynamic pressure.
    TruthDynamicPressure,
    /// True heating rate.
    TruthHeating,
    /// Magnitude of the aerodynamic acceleration.
    TruthAeroAccel,
    /// Noiseless accelerometer reading, IMU axis k.
    TruthSensedAccel(usize),
    /// Geometric range to beacon slot i.
    BeaconRange(usize),
    /// Beacon slot i above the horizon.
    BeaconVisible(usize),
    /// Why the truth stopped.
    TruthStop,
    /// The bank angle the truth flew over its last step (0 before the first step).
    TruthBankFlown,
    /// [`Key::TruthStop`] as a plain Integer.
    TruthStopCode,
    /// Number of beacons.
    NBeacons,
    /// Epoch of the estimate.
    NavTime,
    /// Filter status.
    NavStatus,
    /// [`Key::NavStatus`] as a plain Integer.
    NavStatusCode,
    /// Filter state dimension.
    NStates,
    /// Estimate, state slot i.
    EstX(usize),
    /// 1σ, state slot i.
    EstSigma(usize),
    /// Estimate as planet-relative spherical component k.
    EstSph(usize),
    /// Estimated density.
    EstDensity,
    /// Normalised innovation squared of the last update.
    Nis,
    /// Scalar measurements used in the last update.
    NMeas,
    /// Fusion weight / model probability i.
    Weight(usize),
    /// Number of weights.
    NWeights,
    /// Truth in filter coordinates at the estimate's epoch, slot i.
    TruthX(usize),
    /// Estimation error, slot i.
    Err(usize),
    /// NEES.
    Nees,
    /// NEES degrees of freedom.
    NeesDof,
    /// True density at the estimate's epoch.
    NavTruthDensity,
    /// Guidance: the actuator's bank (the bank to fly).
    GuidanceBank,
    /// Guidance: the actuator's bank rate.
    GuidanceBankRate,
    /// Guidance: the latest command, before the limits.
    GuidanceCommand,
    /// Guidance: time of the latest cycle.
    GuidanceTime,
    /// Guidance: cycles run.
    GuidanceCycles,
    /// Guidance: sensed drag of the latest cycle.
    SensedDrag,
    /// Guidance: range to go to the target.
    RangeToGo,
    /// Guidance: crossrange of the target.
    Crossrange,
    /// Guidance: deployment trigger function on the estimate.
    DeployTrigger,
    /// Guidance: the trigger was reached.
    Deployed,
    /// Guidance FMU: waiting, flying or deployed (the Enumeration `GuidanceStatus`).
    GuidanceStatus,
    /// Guidance FMU: `GuidanceStatus` as an Integer.
    GuidanceStatusCode,
    /// Guided FMU: the Monte Carlo run index whose dispersed truth it flies.
    Run,
    /// Guided FMU: how the guided flight stands (flying, deployed, ended without deployment).
    GuidedStatus,
    /// Guided FMU: deployment time (on the truth).
    DeployTime,
    /// Guided FMU: surface miss distance at deployment.
    MissDistance,
    /// Guided FMU: along-track part of the miss.
    MissDownrange,
    /// Guided FMU: cross-track part of the miss.
    MissCrossrange,
    /// Guided FMU: deployment altitude.
    DeployAltitude,
}
