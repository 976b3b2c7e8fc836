//! Measurement channels and the measurement function h(x, t) shared by truth and filters.

use super::airdata::{dynamic_pressure, sutton_graves_heating};
use super::imu::ImuFrame;
use super::radio::{range, range_rate};
use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use crate::dynamics::aero::{drag_lift, specific_force_wind};
use crate::frames::spherical_to_inertial;
use crate::math::{Dual, Real, V3, cross, lift_dual, norm, seed_duals, sub};
use nalgebra::SVector;

/// One scalar measurement channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// Accelerometer specific force along axis 0, 1 or 2 of the IMU frame [m/s²].
    Accel(u8),
    /// Dynamic pressure \[Pa\].
    DynamicPressure,
    /// Convective heating rate [W/m²].
    Heating,
    /// Two-way range to beacon `i` \[m\].
    Range(usize),
    /// Range-rate to beacon `i` [m/s].
    RangeRate(usize),
}

impl Channel {
    /// Column name with SI unit suffix, e.g. `accel_x_mps2`, `range_orbiter-1_m`.
    pub fn name(&self, beacon_names: &[String]) -> String {
        let b = |i: usize| {
            beacon_names
                .get(i)
                .cloned()
                .unwrap_or_else(|| format!("beacon{i}"))
        };
        match *self {
            Channel::Accel(k) => format!("accel_{}_mps2", ["x", "y", "z"][(k as usize).min(2)]),
            Channel::DynamicPressure => "dynamic_pressure_meas_pa".into(),
            Channel::Heating => "heating_meas_wm2".into(),
            Channel::Range(i) => format!("range_{}_m", b(i)),
            Channel::RangeRate(i) => format!("range_rate_{}_mps", b(i)),
        }
    }

    /// The beacon a radio channel refers to.
    pub fn beacon(&self) -> Option<usize> {
        match *self {
            Channel::Range(i) | Channel::RangeRate(i) => Some(i),
            _ => None,
        }
    }
}

/// Sutton–Graves constants of a heating sensor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatingModel {
    /// k [kg^½/m] (seed 001: 1.9027e-4 for Mars).
    pub k: f64,
    /// Nose radius R_n \[m\].
    pub nose_radius: f64,
}

/// The deterministic part of every sensor: what a noiseless instrument would read.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasurementModel {
    /// Accelerometer frame.
    pub imu_frame: ImuFrame,
    /// Heating sensor constants (required for [`Channel::Heating`]).
    pub heating: HeatingModel,
}

/// Vehicle kinematics derived from a state: inertial position/velocity, airspeed, density.
#[derive(Debug, Clone, Copy)]
pub struct Kinematics<T> {
    /// Inertial position \[m\].
    pub pos: V3<T>,
    /// Inertial velocity [m/s].
    pub vel: V3<T>,
    /// Speed relative to the atmosphere [m/s].
    pub airspeed: T,
    /// Density (model × augmented scale) [kg/m³].
    pub density: T,
}

/// Kinematics of state `x` at time `t` under `model`.
pub fn kinematics<T: Real, A: Atmosphere, const N: usize>(
    model: &EntryModel<A>,
    x: &SVector<T, N>,
    t: f64,
) -> Kinematics<T> {
    let omega = model.omega();
    let k: [T; 6] = [x[0], x[1], x[2], x[3], x[4], x[5]];
    let (pos, vel, airspeed) = if model.kind.is_cartesian() {
        let pos = [k[0], k[1], k[2]];
        let vel = [k[3], k[4], k[5]];
        let w = [T::from(0.0), T::from(0.0), T::from(omega)];
        let vrel = sub(&vel, &cross(&w, &pos));
        (pos, vel, norm(&vrel))
    } else {
        let (p, v) = spherical_to_inertial(&k, t, omega);
        (p, v, k[3])
    };
    kinematics_from_motion(model, x, pos, vel, airspeed)
}

/// [`kinematics`] on the dual numbers `xd` = [`seed_duals`]`(x)` of an EKF's linearisation, with
/// the spherical motion differentiated with respect to the six kinematic states only (on which
/// alone it depends) and lifted to all `N`: each gradient component is the same sum of the same
/// terms as with `N` variables, so the kinematics are `kinematics(model, xd, t)`'s to the bit
/// (but for the sign of their zero gradient entries), for about half of the dual arithmetic on
/// an 11-state filter.
pub fn kinematics_ad<A: Atmosphere, const N: usize>(
    model: &EntryModel<A>,
    x: &SVector<f64, N>,
    xd: &SVector<Dual<N>, N>,
    t: f64,
) -> Kinematics<Dual<N>> {
    if model.kind.is_cartesian() || N < 6 {
        return kinematics(model, xd, t);
    }
    let d6 = seed_duals(&SVector::<f64, 6>::from_fn(|i, _| x[i]));
    let (p, v) = spherical_to_inertial(
        &[d6[0], d6[1], d6[2], d6[3], d6[4], d6[5]],
        t,
        model.omega(),
    );
    let lift = |w: &[Dual<6>; 3]| w.map(|d| lift_dual::<6, N>(&d));
    kinematics_from_motion(model, xd, lift(&p), lift(&v), xd[3])
}

/// [`kinematics`] from the state's inertial position `pos`, velocity `vel` and `airspeed`,
/// already computed (e.g. with derivatives with respect to the kinematic states only): adds the
/// density at `pos` with the state's density scale.
pub fn kinematics_from_motion<T: Real, A: Atmosphere, const N: usize>(
    model: &EntryModel<A>,
    x: &SVector<T, N>,
    pos: V3<T>,
    vel: V3<T>,
    airspeed: T,
) -> Kinematics<T> {
    let scale = model.aero_params(x, 0.0).density_scale;
    let density = model.atmosphere.density(norm(&pos) - model.planet.radius) * scale;
    Kinematics {
        pos,
        vel,
        airspeed,
        density,
    }
}

impl MeasurementModel {
    /// The noiseless accelerometer triad (IMU frame, without biases) at state `x`: what
    /// [`Channel::Accel`] reads on each axis before its bias. Compute it once per epoch and pass
    /// it to [`MeasurementModel::accel_axis`] to read several axes.
    pub fn accel_triad<T: Real, A: Atmosphere, const N: usize>(
        &self,
        model: &EntryModel<A>,
        x: &SVector<T, N>,
        kin: &Kinematics<T>,
        bank: f64,
    ) -> V3<T> {
        let p = model.aero_params(x, bank);
        let (d, l) = drag_lift(kin.density, kin.airspeed, &p);
        self.imu_frame.express(&specific_force_wind(d, l, p.bank))
    }

    /// [`Channel::Accel`]`(axis)`: the triad's `axis` (clamped to 2) plus the state's bias on it;
    /// `triad` is [`MeasurementModel::accel_triad`] at the same state, computed here when `None`.
    pub fn accel_axis<T: Real, A: Atmosphere, const N: usize>(
        &self,
        model: &EntryModel<A>,
        x: &SVector<T, N>,
        kin: &Kinematics<T>,
        bank: f64,
        axis: u8,
        triad: Option<&V3<T>>,
    ) -> T {
        let axis = axis.min(2);
        let a = match triad {
            Some(a) => a[axis as usize],
            None => self.accel_triad(model, x, kin, bank)[axis as usize],
        };
        match model.accel_bias(x, axis) {
            Some(b) => a + b,
            None => a,
        }
    }

    /// Noiseless value of `channel` at state `x`, time `t`, bank `bank`; `beacons[i]` is the
    /// inertial (position, velocity) of beacon `i` at `t`. A radio channel whose beacon index is
    /// out of range evaluates to NaN — callers build channels from the same beacon list.
    pub fn evaluate<T: Real, A: Atmosphere, const N: usize>(
        &self,
        model: &EntryModel<A>,
        x: &SVector<T, N>,
        t: f64,
        bank: f64,
        beacons: &[(V3<f64>, V3<f64>)],
        channel: Channel,
    ) -> T {
        let kin = kinematics(model, x, t);
        self.evaluate_with(model, x, &kin, bank, beacons, channel)
    }

    /// [`MeasurementModel::evaluate_with`] for one of several channels of the same state: the
    /// accelerometer triad is computed at the first [`Channel::Accel`] and kept in `triad` for
    /// the others ([`MeasurementModel::evaluate_with`] is this with a triad of its own).
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate_sharing_triad<T: Real, A: Atmosphere, const N: usize>(
        &self,
        model: &EntryModel<A>,
        x: &SVector<T, N>,
        kin: &Kinematics<T>,
        bank: f64,
        beacons: &[(V3<f64>, V3<f64>)],
        channel: Channel,
        triad: &mut Option<V3<T>>,
    ) -> T {
        match channel {
            Channel::Accel(axis) => {
                let a = triad.get_or_insert_with(|| self.accel_triad(model, x, kin, bank));
                self.accel_axis(model, x, kin, bank, axis, Some(a))
            }
            Channel::DynamicPressure => dynamic_pressure(kin.density, kin.airspeed),
            Channel::Heating => sutton_graves_heating(
                kin.density,
                kin.airspeed,
                self.heating.k,
                self.heating.nose_radius,
            ),
            Channel::Range(i) => match beacons.get(i) {
                Some((rb, _)) => range(&kin.pos, rb),
                None => T::from(f64::NAN),
            },
            Channel::RangeRate(i) => match beacons.get(i) {
                Some((rb, vb)) => range_rate(&kin.pos, &kin.vel, rb, vb),
                None => T::from(f64::NAN),
            },
        }
    }

    /// As [`MeasurementModel::evaluate`] with precomputed kinematics (saves work for many channels).
    pub fn evaluate_with<T: Real, A: Atmosphere, const N: usize>(
        &self,
        model: &EntryModel<A>,
        x: &SVector<T, N>,
        kin: &Kinematics<T>,
        bank: f64,
        beacons: &[(V3<f64>, V3<f64>)],
        channel: Channel,
    ) -> T {
        self.evaluate_sharing_triad(model, x, kin, bank, beacons, channel, &mut None)
    }
}
