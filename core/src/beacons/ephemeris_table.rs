//! Beacon ephemerides tabulated once per scenario at the measurement epochs.
//!
//! Every Monte Carlo run measures at the same epochs t_k = k·Δt (k a multiple of the radio
//! channels' common period in truth steps), and the truth, every filter and the PCRLB ask for the
//! beacons' states there; an orbiter's state is a universal-variable Kepler solve
//! ([`super::Orbiter`]). The table holds them, computed by the same
//! [`BeaconMotion::state_at`] at the same `t` (so a looked-up state is the computed one bit for
//! bit); any other time is computed on the spot.

use super::motion::BeaconMotion;
use super::visibility::Beacon;
use std::borrow::Cow;

/// A beacon's inertial (position \[m\], velocity [m/s]).
pub type BeaconState = ([f64; 3], [f64; 3]);

/// The table's size limit (states, all beacons and epochs): about 10 MB. A longer study keeps
/// the first epochs tabulated and computes the rest.
pub const MAX_TABLE_STATES: usize = 200_000;

/// Beacon states at t_j = (j·stride)·Δt, j = 0, 1, …, for every beacon of one list.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EphemerisTable {
    dt: f64,
    stride: usize,
    beacons: usize,
    epochs: usize,
    states: Vec<BeaconState>,
}

impl EphemerisTable {
    /// The states of `beacons` at t_j = (j·`stride`)·`dt` for (j·stride) ≤ `max_steps`, within
    /// [`MAX_TABLE_STATES`]. `dt` is the truth step \[s\]; an empty list, a zero stride or a
    /// non-positive step gives an empty table (every lookup computes).
    pub fn new(beacons: &[Beacon], dt: f64, stride: usize, max_steps: usize) -> Self {
        if beacons.is_empty() || stride == 0 || !(dt.is_finite() && dt > 0.0) {
            return EphemerisTable::default();
        }
        let epochs = (max_steps / stride + 1).min(MAX_TABLE_STATES / beacons.len());
        let mut states = Vec::with_capacity(epochs * beacons.len());
        for j in 0..epochs {
            let t = (j * stride) as f64 * dt;
            states.extend(beacons.iter().map(|b| b.state_at(t)));
        }
        EphemerisTable {
            dt,
            stride,
            beacons: beacons.len(),
            epochs,
            states,
        }
    }

    /// The tabulated states at `t`, if `t` is exactly a tabulated epoch.
    pub fn lookup(&self, t: f64) -> Option<&[BeaconState]> {
        if self.epochs == 0 || t.is_nan() || t < 0.0 {
            return None;
        }
        let j = (t / (self.dt * self.stride as f64)).round();
        if j.is_nan() || j >= self.epochs as f64 {
            return None;
        }
        let j = j as usize;
        // The truth's epoch time is (step index)·Δt: exactly this product.
        ((j * self.stride) as f64 * self.dt == t)
            .then(|| &self.states[j * self.beacons..(j + 1) * self.beacons])
    }

    /// The states of `beacons` (the list the table was built from) at `t`: tabulated or computed.
    pub fn states_at<'a>(&'a self, beacons: &[Beacon], t: f64) -> Cow<'a, [BeaconState]> {
        match self.lookup(t) {
            Some(s) if s.len() == beacons.len() => Cow::Borrowed(s),
            _ => Cow::Owned(beacons.iter().map(|b| b.state_at(t)).collect()),
        }
    }

    /// Number of tabulated epochs.
    pub fn epochs(&self) -> usize {
        self.epochs
    }
}

/// Greatest common divisor (0 with 0 is 0).
pub fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beacons::{Orbiter, SurfaceBeacon};
    use crate::planet::Planet;

    fn beacons() -> Vec<Beacon> {
        let mars = Planet::MARS;
        let orbiter =
            Orbiter::from_state(&mars, [3_796_200.0, 0.0, 0.0], [0.0, 2_000.0, 2_500.0]).unwrap();
        vec![
            Beacon::Orbiter(orbiter),
            Beacon::Surface(SurfaceBeacon::from_lat_lon_alt(-0.2, 0.3, 0.0, &mars).unwrap()),
        ]
    }

    #[test]
    fn a_tabulated_state_is_the_computed_one_bit_for_bit() {
        let b = beacons();
        let table = EphemerisTable::new(&b, 0.1, 10, 3000);
        assert_eq!(table.epochs(), 301);
        for k in [0usize, 10, 20, 1230, 3000] {
            let t = k as f64 * 0.1;
            let looked = table.lookup(t).expect("tabulated");
            let computed: Vec<_> = b.iter().map(|x| x.state_at(t)).collect();
            assert_eq!(looked, &computed[..], "t = {t}");
        }
    }

    #[test]
    fn other_times_are_computed() {
        let b = beacons();
        let table = EphemerisTable::new(&b, 0.1, 10, 3000);
        // Off the grid, between strides, past the end, negative, NaN.
        for t in [0.1, 1.05, 300.1 + 1.0, 1e9, -1.0, f64::NAN] {
            assert!(table.lookup(t).is_none(), "t = {t}");
        }
        // 3·0.1 is not 0.3 in floating point: 0.3 is not the truth's epoch time, so computed.
        let table = EphemerisTable::new(&b, 0.1, 1, 3000);
        assert!(table.lookup(0.3).is_none());
        assert!(table.lookup(3.0 * 0.1).is_some());
        let s = table.states_at(&b, 1.05);
        assert!(matches!(s, Cow::Owned(_)));
        assert_eq!(s[0], b[0].state_at(1.05));
    }

    #[test]
    fn the_table_is_bounded() {
        let b = beacons();
        let table = EphemerisTable::new(&b, 0.1, 1, usize::MAX / 2);
        assert_eq!(table.epochs(), MAX_TABLE_STATES / 2);
        assert!(EphemerisTable::new(&[], 0.1, 1, 100).lookup(0.0).is_none());
        assert!(EphemerisTable::new(&b, 0.0, 1, 100).lookup(0.0).is_none());
        assert_eq!(gcd(10, 4), 2);
        assert_eq!(gcd(0, 7), 7);
    }
}
