//! Entry guidance: the onboard layer that turns a navigation estimate into a bank command.
//!
//! Guidance sits beside `estimation`: it sees the onboard model (the filter's [`EntryModel`]:
//! planet, atmosphere, vehicle constants) and a navigation solution ([`NavState`]), never the
//! truth — it may not import `scenario` or `sim` (checked by `core/tests/architecture.rs`). Two
//! algorithms:
//!
//! * [`apollo::ApolloGuidance`]: Apollo final-phase entry guidance as adapted for MSL (Mendeck &
//!   Craig, AIAA 2011-6639), on a reference trajectory with adjoint gains ([`mod@reference`]);
//! * [`fnpeg::Fnpeg`]: the fully numerical predictor–corrector of Lu (J. Guid. Control Dyn.
//!   37(4), 2014), a bank profile linear in energy corrected every cycle.
//!
//! Either may be wrapped in the altitude safeguard ([`safeguard`], `min_deploy_altitude_m`),
//! which caps the bank magnitude when the predicted deployment altitude falls below a floor.
//! Both share the lateral logic ([`lateral`]: crossrange deadband, bank reversals). The bank the
//! vehicle flies is the command through the rate and acceleration limits ([`limits`]).
//!
//! [`EntryModel`]: crate::dynamics::EntryModel

pub mod apollo;
pub mod config;
pub mod error;
pub mod fnpeg;
pub mod lateral;
pub mod limits;
pub mod longitudinal;
pub mod reference;
pub mod safeguard;

pub use config::{
    BuiltGuidance, GuidanceAlgorithm, GuidanceAtmosphere, GuidanceConfig, TargetConfig,
    build_guidance,
};
pub use error::GuidanceError;
pub use limits::{BankActuator, BankLimits};
pub use longitudinal::Trigger;

use crate::frames::inertial_to_spherical;

/// The navigation solution guidance is given each cycle: the onboard estimate, in the planet
/// frame, never the truth type. Build it from a filter's state with [`NavState::from_estimate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavState {
    /// Time \[s\].
    pub t: f64,
    /// Planet-relative spherical state `[r, lon, lat, v, fpa, heading]` (SI, rad, heading
    /// north-clockwise), the state order of the spherical filters.
    pub spherical: [f64; 6],
    /// Drag acceleration sensed by the accelerometers \[m/s²\] (the IMU's along-velocity specific
    /// force; Apollo compares it with the reference drag).
    pub drag_mps2: f64,
}

impl NavState {
    /// From the six kinematic states of a filter estimate (`cartesian`: inertial
    /// `[x, y, z, vx, vy, vz]` on a planet rotating at `omega`; otherwise already spherical and
    /// planet-relative) at time `t`, with the sensed drag.
    pub fn from_estimate(
        x: &[f64],
        cartesian: bool,
        t: f64,
        omega: f64,
        drag_mps2: f64,
    ) -> Result<Self, GuidanceError> {
        if x.len() < 6 || !x[..6].iter().all(|v| v.is_finite()) {
            return Err(GuidanceError::BadNavigation {
                t_s: t,
                what: "fewer than six finite kinematic states",
            });
        }
        let spherical = if cartesian {
            inertial_to_spherical(&[x[0], x[1], x[2]], &[x[3], x[4], x[5]], t, omega)
        } else {
            [x[0], x[1], x[2], x[3], x[4], x[5]]
        };
        Ok(NavState {
            t,
            spherical,
            drag_mps2,
        })
    }

    /// Speed \[m/s\].
    pub fn speed(&self) -> f64 {
        self.spherical[3]
    }

    /// Altitude rate ṙ = v sinγ \[m/s\].
    pub fn rdot(&self) -> f64 {
        self.spherical[3] * self.spherical[4].sin()
    }
}

/// A guidance algorithm: one bank command per guidance cycle.
pub trait Guidance {
    /// The signed bank command \[rad\] (positive: lift to the right, heading increases) for the
    /// navigation solution `nav`.
    fn command(&mut self, nav: &NavState) -> Result<f64, GuidanceError>;

    /// Short name for reports.
    fn name(&self) -> &'static str;
}

/// A surface target (deployment point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// Latitude \[rad\].
    pub lat: f64,
    /// Longitude \[rad\].
    pub lon: f64,
}

/// Great-circle angle between two points \[rad\] (haversine form).
pub fn central_angle(lat1: f64, lon1: f64, lat2: f64, lon2: f64) -> f64 {
    let a = ((lat2 - lat1) / 2.0).sin().powi(2)
        + lat1.cos() * lat2.cos() * ((lon2 - lon1) / 2.0).sin().powi(2);
    2.0 * a.sqrt().min(1.0).asin()
}

/// Initial bearing from point 1 to point 2 \[rad\], north-clockwise.
pub fn bearing(lat1: f64, lon1: f64, lat2: f64, lon2: f64) -> f64 {
    let dl = lon2 - lon1;
    (dl.sin() * lat2.cos()).atan2(lat1.cos() * lat2.sin() - lat1.sin() * lat2.cos() * dl.cos())
}

/// The point reached from (lat, lon) along bearing `psi` (north-clockwise) over central angle `d`.
pub fn destination(lat: f64, lon: f64, psi: f64, d: f64) -> Target {
    let lat2 = (lat.sin() * d.cos() + lat.cos() * d.sin() * psi.cos()).asin();
    let lon2 = lon + (psi.sin() * d.sin() * lat.cos()).atan2(d.cos() - lat.sin() * lat2.sin());
    Target {
        lat: lat2,
        lon: lon2,
    }
}

/// Range-to-go and crossrange of `target` from the vehicle, as central angles \[rad\]: the
/// great-circle angle to the target, and asin(sin d · sin(β − ψ)) for bearing β and heading ψ
/// (positive: the target lies to the right of the velocity's great circle).
pub fn range_crossrange(nav: &NavState, target: &Target) -> (f64, f64) {
    let [_, lon, lat, _, _, psi] = nav.spherical;
    let d = central_angle(lat, lon, target.lat, target.lon);
    let b = bearing(lat, lon, target.lat, target.lon);
    (d, (d.sin() * (b - psi).sin()).asin())
}
