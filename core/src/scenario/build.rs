//! From a validated [`ScenarioConfig`] to runtime models, and per-run Monte Carlo draws.

use super::config::*;
use super::error::ScenarioError;
use super::validate::StateForm;
use crate::atmosphere::{AtmosphereModel, ProfileChoice};
use crate::beacons::ephemeris_table::gcd;
use crate::beacons::{Beacon, BeaconState, EphemerisTable};
use crate::dynamics::{DynamicsKind, EntryModel, Vehicle};
use crate::estimation::Onboard;
use crate::files::FileLoader;
use crate::frames::{HeadingConvention, inertial_to_spherical, spherical_to_inertial};
use crate::guidance::{BuiltGuidance, GuidanceAtmosphere, GuidanceError, NavState, build_guidance};
use crate::planet::Planet;
use crate::sensors::{Channel, Fault, MeasurementModel};
pub use crate::sensors::{ChannelSpec, Noise};
use nalgebra::SVector;
use std::borrow::Cow;
use std::sync::Arc;

use super::onboard::{OnboardParts, onboard_view};

/// A built scenario: everything a simulation or filter needs, in SI units and internal conventions.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// The validated configuration it was built from.
    pub config: ScenarioConfig,
    /// Planet constants.
    pub planet: Planet,
    /// Truth dynamics with the nominal vehicle and the *mean* atmosphere (for a truth table of
    /// stacked profiles: the profile run 0 flies).
    pub truth_model: EntryModel<AtmosphereModel>,
    /// The truth table's profiles and the run → profile rule, when the truth atmosphere is a
    /// table file ([`ProfileChoice`]: run k flies profile k mod n, or one selected profile).
    pub truth_profiles: Option<ProfileChoice>,
    /// Nominal truth initial state in the truth model's coordinates.
    pub truth_initial: SVector<f64, 6>,
    /// Truth bank angle \[rad\] (the commanded bank; the onboard view starts with it too).
    pub truth_bank: f64,
    /// What the vehicle knows onboard: the only input of a navigation filter (its dynamics and
    /// atmosphere model, channels with the assumed noise, beacons, timing, tuning, the nominal
    /// initial estimate).
    pub onboard: Arc<Onboard>,
    /// Beacons, in file order.
    pub beacons: Vec<Beacon>,
    /// Beacon names, in file order.
    pub beacon_names: Vec<String>,
    /// The beacons' states at the measurement epochs every run shares (also the onboard view's:
    /// the filter knows the same ephemerides). Built from `beacons`: rebuild the scenario rather
    /// than edit `beacons` in place.
    pub ephemerides: Arc<EphemerisTable>,
    /// Deterministic measurement model.
    pub measurement: MeasurementModel,
    /// All measurement channels with their schedules and noise.
    pub channels: Vec<ChannelSpec>,
    /// The truth's sensor faults (`[[faults]]`), beacons resolved.
    pub faults: Vec<Fault>,
}

/// Convert a state description to the six kinematic states of a model of `kind`.
pub fn state_to_model(
    cfg: &StateConfig,
    field: &str,
    convention: HeadingConvention,
    kind: DynamicsKind,
    planet: &Planet,
) -> Result<SVector<f64, 6>, ScenarioError> {
    let omega = if kind == DynamicsKind::Spherical {
        0.0
    } else {
        planet.rotation_rate
    };
    let x = match cfg.form(field)? {
        StateForm::Spherical => {
            let s = [
                cfg.radius_km.unwrap_or_default() * 1e3,
                cfg.lon_deg.unwrap_or_default().to_radians(),
                cfg.lat_deg.unwrap_or_default().to_radians(),
                cfg.speed_mps.unwrap_or_default(),
                cfg.fpa_deg.unwrap_or_default().to_radians(),
                convention.to_internal(cfg.heading_deg.unwrap_or_default().to_radians()),
            ];
            if kind.is_cartesian() {
                let (p, v) = spherical_to_inertial(&s, 0.0, omega);
                [p[0], p[1], p[2], v[0], v[1], v[2]]
            } else {
                s
            }
        }
        StateForm::Cartesian => {
            let p = cfg.position_km.unwrap_or_default().map(|c| c * 1e3);
            let v = cfg.velocity_mps.unwrap_or_default();
            if kind.is_cartesian() {
                [p[0], p[1], p[2], v[0], v[1], v[2]]
            } else {
                inertial_to_spherical(&p, &v, 0.0, omega)
            }
        }
    };
    Ok(SVector::from(x))
}

impl Scenario {
    /// Build from a validated configuration. `load(path)` returns the text of a file the scenario
    /// refers to (tabulated atmospheres); the core never touches the file system itself.
    pub fn build(config: ScenarioConfig, load: &FileLoader<'_>) -> Result<Scenario, ScenarioError> {
        config.validate()?;
        let planet = config.planet.resolve();
        let conv = config.heading_convention;

        let entry_lat = entry_latitude(&config, conv, &planet)?;
        let (truth_atm, truth_profiles) =
            config.truth.atmosphere.build_at(&planet, entry_lat, load)?;
        let truth_model = EntryModel {
            kind: config.truth.dynamics,
            planet,
            atmosphere: truth_atm,
            vehicle: Vehicle {
                cd_s_over_m: config.truth.vehicle.cd_s_over_m(),
                lift_to_drag: config.truth.vehicle.lift_to_drag,
            },
            augmented: vec![],
            rho0_model: config.truth.atmosphere.reference_density().unwrap_or(1.0),
            density_factor: 1.0 + config.truth.density_bias,
            bias_tau_s: None,
        };
        let truth_initial = state_to_model(
            &config.truth.initial,
            "truth.initial",
            conv,
            config.truth.dynamics,
            &planet,
        )?;

        let f = &config.filter;
        let filter_model = EntryModel {
            kind: f.dynamics,
            planet,
            atmosphere: f.atmosphere.build_at(&planet, entry_lat, load)?.0,
            vehicle: Vehicle {
                cd_s_over_m: f.vehicle.cd_s_over_m(),
                lift_to_drag: f.vehicle.lift_to_drag,
            },
            augmented: f.state_params(),
            rho0_model: f.atmosphere.reference_density().unwrap_or(1.0),
            density_factor: 1.0,
            bias_tau_s: f.accel_bias_tau_s,
        };
        let start = f.initial.as_ref().unwrap_or(&config.truth.initial);
        let kin = state_to_model(start, "filter.initial", conv, f.dynamics, &planet)?;
        let mut filter_initial: Vec<f64> = kin.iter().copied().collect();
        filter_initial.extend_from_slice(&f.initial_augmented);
        filter_initial.extend_from_slice(&f.initial_consider);

        let (beacons, beacon_names, faults) = beacon_parts(&config, &planet, truth_model.omega())?;
        let climatology = climatology(&config, &filter_model, &planet, entry_lat, load)?;
        let channels = channel_specs(&config, &beacon_names);
        let ephemerides = Arc::new(ephemeris_table(&config, &channels, &beacons));
        let measurement = config.sensors.measurement_model();
        let truth_bank = config.truth.bank_deg.to_radians();
        let onboard = Arc::new(onboard_view(OnboardParts {
            config: &config,
            model: filter_model,
            climatology,
            measurement: measurement.clone(),
            channels: &channels,
            beacons: &beacons,
            beacon_names: &beacon_names,
            ephemerides: Arc::clone(&ephemerides),
            initial_bank: truth_bank,
            initial_estimate: filter_initial,
        }));
        Ok(Scenario {
            measurement,
            config,
            planet,
            truth_model,
            truth_profiles,
            truth_initial,
            truth_bank,
            onboard,
            beacons,
            beacon_names,
            ephemerides,
            channels,
            faults,
        })
    }

    /// The filter's dynamics model (the onboard view's).
    pub fn filter_model(&self) -> &EntryModel<AtmosphereModel> {
        &self.onboard.model
    }

    /// The onboard model `[guidance]` predicts with: the filter's model with the atmosphere
    /// `guidance.atmosphere` names (the climatology by default); `None` without `[guidance]`.
    pub fn guidance_model(&self) -> Option<EntryModel<AtmosphereModel>> {
        let g = self.config.guidance.as_ref()?;
        let mut m = self.onboard.model.clone();
        if g.atmosphere == GuidanceAtmosphere::Climatology {
            m.atmosphere = self.onboard.climatology.clone();
        }
        Some(m)
    }

    /// The guidance of `[guidance]`, built on [`Scenario::guidance_model`] from the onboard
    /// nominal entry (the filter's initial estimate, as a planet-relative spherical state); `None`
    /// without `[guidance]`.
    pub fn build_guidance(&self) -> Option<Result<BuiltGuidance, GuidanceError>> {
        let g = self.config.guidance.as_ref()?;
        let model = self.guidance_model()?;
        let e = &self.onboard.initial_estimate;
        let entry = NavState::from_estimate(e, model.kind.is_cartesian(), 0.0, model.omega(), 0.0)
            .map(|n| n.spherical);
        Some(entry.and_then(|entry| build_guidance(g, &model, &entry)))
    }

    /// Inertial (position, velocity) of every beacon at time `t` (tabulated at the measurement
    /// epochs, [`EphemerisTable`]).
    pub fn beacon_states(&self, t: f64) -> Cow<'_, [BeaconState]> {
        self.ephemerides.states_at(&self.beacons, t)
    }
}

/// Built beacons, their names and the resolved faults.
pub(super) type BeaconParts = (Vec<Beacon>, Vec<String>, Vec<Fault>);

/// The beacons of `config` built on `planet` (surface beacons turn with it only if the truth
/// planet rotates, `truth_omega`), their names, and the faults resolved against those names
/// (validation checked every fault's beacon name, so none is dropped).
pub(super) fn beacon_parts(
    config: &ScenarioConfig,
    planet: &Planet,
    truth_omega: f64,
) -> Result<BeaconParts, ScenarioError> {
    let mut beacon_planet = *planet;
    beacon_planet.rotation_rate = truth_omega;
    let beacons = config
        .beacons
        .iter()
        .map(|b| b.build(&beacon_planet))
        .collect::<Result<Vec<_>, _>>()?;
    let names: Vec<String> = config
        .beacons
        .iter()
        .map(|b| b.name().to_string())
        .collect();
    let faults = config
        .faults
        .iter()
        .filter_map(|f| Fault::resolve(f, &names))
        .collect();
    Ok((beacons, names, faults))
}

/// The onboard climatology (`filter.density.climatology`, default the filter's own atmosphere):
/// a filter-side setting, never the truth's atmosphere. A table of several profiles must name
/// the one to carry (`profile = k`); an averaged file holds one.
fn climatology(
    config: &ScenarioConfig,
    filter_model: &EntryModel<AtmosphereModel>,
    planet: &Planet,
    entry_lat: f64,
    load: &FileLoader<'_>,
) -> Result<AtmosphereModel, ScenarioError> {
    let field = "filter.density.climatology";
    let Some(cfg) = config
        .filter
        .density
        .as_ref()
        .and_then(|d| d.climatology.as_ref())
    else {
        return Ok(filter_model.atmosphere.clone());
    };
    cfg.validate(field)?;
    let (model, profiles) = cfg.build_at(planet, entry_lat, load)?;
    if let Some(choice) = profiles.filter(|c| c.selected.is_none() && c.set.profiles.len() > 1) {
        return Err(ScenarioError::invalid(
            field,
            format!(
                "{} holds {} profiles; a climatology is one mean profile: select one with `profile = k` or give an averaged file",
                choice.set.source_name,
                choice.set.profiles.len()
            ),
        ));
    }
    Ok(model)
}

/// Geocentric latitude (rad) of the truth entry interface (the areoid datum of table files).
fn entry_latitude(
    config: &ScenarioConfig,
    conv: HeadingConvention,
    planet: &Planet,
) -> Result<f64, ScenarioError> {
    let s = state_to_model(
        &config.truth.initial,
        "truth.initial",
        conv,
        DynamicsKind::Spherical,
        planet,
    )?;
    Ok(s[2])
}

/// The beacons' states at every measurement epoch of the truth: steps that are multiples of the
/// channels' common period (in truth steps, as the truth schedules them), up to the duration.
pub(super) fn ephemeris_table(
    config: &ScenarioConfig,
    channels: &[ChannelSpec],
    beacons: &[Beacon],
) -> EphemerisTable {
    let dt = config.timing.truth_step_s;
    let max_steps = (config.timing.duration_s / dt).round().max(1.0) as usize;
    let stride = channels
        .iter()
        .map(|c| (c.period_s / dt).round().max(1.0) as usize)
        .fold(0, gcd);
    EphemerisTable::new(beacons, dt, stride, max_steps)
}

pub(super) fn channel_specs(config: &ScenarioConfig, beacon_names: &[String]) -> Vec<ChannelSpec> {
    let mut out = channel_specs_as_sensed(config, beacon_names);
    if let Some(inflation) = &config.filter.noise_inflation {
        for spec in &mut out {
            spec.filter_noise = spec.filter_noise.scaled(inflation.factor(spec.channel));
        }
    }
    out
}

/// The channels with the filter noise before `filter.noise_inflation`.
fn channel_specs_as_sensed(config: &ScenarioConfig, beacon_names: &[String]) -> Vec<ChannelSpec> {
    let mut out = Vec::new();
    let s = &config.sensors;
    if let Some(imu) = &s.imu {
        for k in 0..3u8 {
            let channel = Channel::Accel(k);
            out.push(ChannelSpec {
                channel,
                name: channel.name(beacon_names),
                period_s: 1.0 / imu.rate_hz,
                noise: Noise::Absolute(imu.noise_sigma_mps2),
                filter_noise: Noise::Absolute(
                    config.filter.imu_sigma_mps2.unwrap_or(imu.noise_sigma_mps2),
                ),
                bias: imu.bias_mps2[k as usize],
            });
        }
    }
    if let Some(q) = &s.dynamic_pressure {
        let channel = Channel::DynamicPressure;
        out.push(ChannelSpec {
            channel,
            name: channel.name(beacon_names),
            period_s: 1.0 / q.rate_hz,
            noise: Noise::Relative(q.noise_fraction),
            filter_noise: Noise::Relative(q.noise_fraction),
            bias: 0.0,
        });
    }
    if let Some(h) = &s.heating {
        let channel = Channel::Heating;
        out.push(ChannelSpec {
            channel,
            name: channel.name(beacon_names),
            period_s: 1.0 / h.rate_hz,
            noise: Noise::Relative(h.noise_fraction),
            filter_noise: Noise::Relative(h.noise_fraction),
            bias: 0.0,
        });
    }
    for (i, b) in config.beacons.iter().enumerate() {
        if let (Some(r), Some(sig)) = (&s.range, b.range_sigma_m()) {
            let channel = Channel::Range(i);
            out.push(ChannelSpec {
                channel,
                name: channel.name(beacon_names),
                period_s: 1.0 / r.rate_hz,
                noise: Noise::Absolute(sig),
                filter_noise: Noise::Absolute(sig),
                bias: 0.0,
            });
        }
        if let (Some(r), Some(sig)) = (&s.range_rate, b.range_rate_sigma_mps()) {
            let channel = Channel::RangeRate(i);
            out.push(ChannelSpec {
                channel,
                name: channel.name(beacon_names),
                period_s: 1.0 / r.rate_hz,
                noise: Noise::Absolute(sig),
                filter_noise: Noise::Absolute(sig),
                bias: 0.0,
            });
        }
    }
    out
}
