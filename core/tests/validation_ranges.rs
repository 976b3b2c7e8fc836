//! Every numeric range of scenario validation, probed at its limits through `--set`-style edits
//! of a built-in scenario. Each case names a field and the message a user reads for it; the test
//! takes the limits from that message ("must be > 0 and <= 7200 s") and checks that a value at an
//! inclusive limit is accepted, a value at an exclusive limit is refused, the next value past
//! either limit is refused, and every refusal names the field, the value and the same words. A
//! second test lists the range checks that validation makes (`ScenarioConfig::range_checks`) on
//! every built-in and every case's scenario, and fails when one has no case here.

use entrynav::scenario::{BUILTIN_NAMES, ScenarioConfig};
use std::collections::BTreeSet;

/// One range: the field (as errors name it, and as `--set` reaches it), the built-in scenario and
/// `--set` edits that make the field present and every probe otherwise valid, and the message.
struct Case {
    field: &'static str,
    base: &'static str,
    sets: &'static [&'static str],
    allowed: &'static str,
}

const fn case(
    field: &'static str,
    base: &'static str,
    sets: &'static [&'static str],
    allowed: &'static str,
) -> Case {
    Case {
        field,
        base,
        sets,
        allowed,
    }
}

const AIR: &str = "msl-airdata";
const FUSION: &str = "four-beacon-fusion";
const PRESSURE: &str = "msl-pressure";
const ORBITERS: &str = "orbiters-3";
const FAULTS: &str = "four-beacon-fusion-faults";

/// A 100 s run with 10 s periods: the truth step's lower limit (at most 1e6 steps) is 1e-4 s,
/// a divisor of every period.
const SLOW: &[&str] = &[
    "timing.duration_s=100.0",
    "timing.filter_step_s=10.0",
    "sensors.imu.rate_hz=0.1",
    "sensors.range.rate_hz=0.1",
];

/// A 5 s run: the truth step's limit is the duration.
const SHORT: &[&str] = &[
    "timing.duration_s=5.0",
    "timing.filter_step_s=5.0",
    "sensors.imu.rate_hz=0.2",
    "sensors.range.rate_hz=0.2",
];

/// `[guidance]` on seed 001's MSL entry, every field that holds an integer written out.
const GUIDED: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=60.0",
    "guidance.trigger.speed_mps=450.0",
    "guidance.fnpeg.iterations=4",
];

/// Load-scaled process noise on a scenario with a density state (ρ0) for `density_sigma` to drive.
const AERO_SCALED: &[&str] = &[
    "filter.process_noise.model=\"aero-scaled\"",
    "filter.process_noise.fraction=[0.01, 0.0, 0.01]",
    "filter.process_noise.correlation_time_s=5.0",
];

/// A filter's own load-scaled process noise on a scenario with a density state (ρ0).
const AERO_SCALED_OWN: &[&str] = &[
    "filter.tuned.uskf-nn.process_noise.model=\"aero-scaled\"",
    "filter.tuned.uskf-nn.process_noise.fraction=[0.01, 0.0, 0.01]",
    "filter.tuned.uskf-nn.process_noise.correlation_time_s=5.0",
];

/// `[guidance]` with its deployment box written out.
const GUIDED_BOX: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=60.0",
    "guidance.trigger.speed_mps=450.0",
    "guidance.deploy_box.speed_min_mps=380.0",
    "guidance.deploy_box.speed_max_mps=540.0",
    "guidance.deploy_box.dynamic_pressure_min_pa=250.0",
    "guidance.deploy_box.dynamic_pressure_max_pa=850.0",
    "guidance.deploy_box.altitude_min_m=5000.0",
];

/// `[guidance]` with the Mars 2020 range trigger.
const GUIDED_RANGE_TRIGGER: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=60.0",
    "guidance.trigger.range.nominal_speed_mps=450.0",
    "guidance.trigger.range.backstop_speed_mps=420.0",
    "guidance.trigger.range.window_margin=0.01",
];

/// `[guidance]` with the altitude safeguard (as msl-guided ships it).
const GUIDED_FLOOR: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=45.0",
    "guidance.trigger.speed_mps=450.0",
    "guidance.min_deploy_altitude_m=7000.0",
];

/// `[guidance]` with Apollo's heading alignment.
const GUIDED_HA: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=45.0",
    "guidance.trigger.speed_mps=450.0",
    "guidance.apollo.heading_alignment_speed_mps=1100.0",
];

/// `[guidance]` with a dynamic-pressure trigger.
const GUIDED_Q: &[&str] = &[
    "guidance.algorithm=\"fnpeg\"",
    "guidance.reference_bank_deg=60.0",
    "guidance.trigger.dynamic_pressure_pa=700.0",
];

/// `[guidance]` with a 10 ms truth step, so that every rate up to 100 Hz divides it.
const GUIDED_FAST: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=60.0",
    "guidance.trigger.speed_mps=450.0",
    "timing.truth_step_s=0.01",
];

/// `[guidance]` whose banks all sit at 180°, so `bank_min_deg` may reach it.
const GUIDED_HIGH: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=180.0",
    "guidance.fnpeg.final_bank_deg=180.0",
    "guidance.trigger.speed_mps=450.0",
];

/// `[guidance]` whose banks all sit at 0°, so `bank_max_deg` may reach it.
const GUIDED_LOW: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=0.0",
    "guidance.fnpeg.final_bank_deg=0.0",
    "guidance.trigger.speed_mps=450.0",
];

/// `[guidance]` with a target point.
const GUIDED_POINT: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=60.0",
    "guidance.trigger.speed_mps=450.0",
    "guidance.target.lat_deg=-4.0",
    "guidance.target.lon_deg=137.0",
];

/// `[guidance]` with a target downrange.
const GUIDED_RANGE: &[&str] = &[
    "guidance.algorithm=\"apollo\"",
    "guidance.reference_bank_deg=60.0",
    "guidance.trigger.speed_mps=450.0",
    "guidance.target.range_km=600.0",
];

const PLANET: &[&str] = &[
    "planet.radius_km=3396.2",
    "planet.rotation_rate_rad_s=7.088e-5",
];

const TUNED: &[&str] = &[
    "timing.stop_speed_mps=450.0",
    "filter.imu_sigma_mps2=0.01",
    "filter.accel_bias_tau_s=100.0",
    "filter.ukf.kappa=0.0",
    "filter.noise_inflation.range=2.0",
];

/// The EKF's own tuning (`[filter.tuned.ekf]`, four-beacon-fusion's 11 states).
const PER_FILTER: &[&str] = &[
    "filter.tuned.ekf.q_diag=[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]",
    "filter.tuned.ekf.noise_inflation.range=2.0",
];

/// A Cartesian filter start (orbiters-3 has none).
const CARTESIAN_START: &[&str] = &[
    "filter.initial.position_km=[-3.92, -3103.37, -1665.41]",
    "filter.initial.velocity_mps=[5775.31, 1124.27, 1175.48]",
];

#[rustfmt::skip]
const CASES: &[Case] = &[
    // planet
    case("planet.mu_m3s2", FUSION, &[], "must be > 1e9 and < 1e17 m³/s²"),
    case("planet.radius_km", FUSION, PLANET, "must be > 100 and < 100000 km"),
    case("planet.rotation_rate_rad_s", FUSION, PLANET, "must be >= -0.001 and <= 0.001 rad/s"),
    // timing
    case("timing.duration_s", FUSION, &[], "must be > 0 and <= 7200 s"),
    case("timing.truth_step_s", FUSION, SLOW, "must be >= timing.duration_s / 1e6 = 1e-4 and <= 10 s (at most 1e6 truth steps per run)"),
    case("timing.truth_step_s", FUSION, SHORT, "must be >= timing.duration_s / 1e6 = 5e-6 and <= timing.duration_s = 5 s (at most 1e6 truth steps per run)"),
    case("timing.filter_step_s", FUSION, &[], "must be > 0 and <= 60 s"),
    case("timing.stop_speed_mps", PRESSURE, &[], "must be > 0 and < 30000 m/s"),
    // truth: spherical and Cartesian states, vehicles by C_D S/m and by ballistic coefficient
    case("truth.initial.radius_km", FUSION, &[], "must be > the surface = 3396.2 and < 10 planet radii = 33962 km"),
    case("truth.initial.lat_deg", FUSION, &[], "must be > -90 and < 90°"),
    case("truth.initial.lon_deg", FUSION, &[], "must be >= -360 and <= 360°"),
    case("truth.initial.speed_mps", FUSION, &[], "must be > 0 and < 30000 m/s"),
    case("truth.initial.fpa_deg", FUSION, &[], "must be > -90 and < 90°"),
    case("truth.initial.heading_deg", FUSION, &[], "must be >= -360 and <= 360°"),
    case("truth.initial.position_km", ORBITERS, &[], "its norm must be > the surface = 3396.2 and < 10 planet radii = 33962 km"),
    case("truth.initial.velocity_mps", ORBITERS, &[], "its norm must be > 0 and < 30000 m/s"),
    case("truth.vehicle.cd_s_over_m_m2kg", FUSION, &[], "must be > 0 and < 1 m²/kg (mass and area positive)"),
    case("truth.vehicle.ballistic_coefficient_kgm2", PRESSURE, &[], "must be > 0 and < 100000 kg/m² (mass and area positive)"),
    case("truth.vehicle.lift_to_drag", FUSION, &[], "must be >= 0 and < 3"),
    case("truth.density_bias", FUSION, &[], "must be > -1 and < 10 (density stays positive)"),
    case("truth.bank_deg", FUSION, &[], "must be >= -180 and <= 180°"),
    // filter: states and vehicles as the truth's
    case("filter.initial.radius_km", FUSION, &[], "must be > the surface = 3396.2 and < 10 planet radii = 33962 km"),
    case("filter.initial.lat_deg", FUSION, &[], "must be > -90 and < 90°"),
    case("filter.initial.lon_deg", FUSION, &[], "must be >= -360 and <= 360°"),
    case("filter.initial.speed_mps", FUSION, &[], "must be > 0 and < 30000 m/s"),
    case("filter.initial.fpa_deg", FUSION, &[], "must be > -90 and < 90°"),
    case("filter.initial.heading_deg", FUSION, &[], "must be >= -360 and <= 360°"),
    case("filter.initial.position_km", ORBITERS, CARTESIAN_START, "its norm must be > the surface = 3396.2 and < 10 planet radii = 33962 km"),
    case("filter.initial.velocity_mps", ORBITERS, CARTESIAN_START, "its norm must be > 0 and < 30000 m/s"),
    case("filter.vehicle.cd_s_over_m_m2kg", FUSION, &[], "must be > 0 and < 1 m²/kg (mass and area positive)"),
    case("filter.vehicle.ballistic_coefficient_kgm2", PRESSURE, &[], "must be > 0 and < 100000 kg/m² (mass and area positive)"),
    case("filter.vehicle.lift_to_drag", FUSION, &[], "must be >= 0 and < 3"),
    // filter: covariances and start values of augmented and consider states
    case("filter.p0_diag[0]", FUSION, &[], "must be > 0 and finite (a variance)"),
    case("filter.q_diag[0]", FUSION, &[], "must be >= 0 and finite (a variance)"),
    case("filter.process_noise.fraction[0]", AIR, AERO_SCALED, "must be >= 0 and <= 10 (1-sigma of the unmodelled specific force over |a_aero|)"),
    case("filter.process_noise.correlation_time_s", AIR, AERO_SCALED, "must be > 0 and <= 1000 s"),
    case("filter.process_noise.density_sigma", FUSION, AERO_SCALED, "must be >= 0 and <= 1 (1-sigma of the relative density error)"),
    case("filter.process_noise.floor_mps2", AIR, AERO_SCALED, "must be >= 0 and <= 10 m/s²"),
    // msl-airdata's USKF-NN has its own load-scaled process noise (issue 49).
    case("filter.tuned.uskf-nn.q_diag[0]", AIR, &[], "must be >= 0 and finite (a variance)"),
    case("filter.tuned.uskf-nn.process_noise.fraction[0]", AIR, &[], "must be >= 0 and <= 10 (1-sigma of the unmodelled specific force over |a_aero|)"),
    case("filter.tuned.uskf-nn.process_noise.correlation_time_s", AIR, &[], "must be > 0 and <= 1000 s"),
    case("filter.tuned.uskf-nn.process_noise.density_sigma", FUSION, AERO_SCALED_OWN, "must be >= 0 and <= 1 (1-sigma of the relative density error)"),
    case("filter.tuned.uskf-nn.process_noise.floor_mps2", AIR, &[], "must be >= 0 and <= 10 m/s²"),
    case("filter.initial_augmented[0]", FUSION, &[], "ρ0 must be > 0 and < 1 kg/m³"),
    case("filter.initial_augmented[1]", FUSION, &[], "L/D must be >= 0 and < 3"),
    case("filter.initial_augmented[2]", FUSION, &[], "an accelerometer bias must be >= -10 and <= 10 m/s²"),
    case("filter.initial_augmented[0]", AIR, &[], "C_D S/m must be > 0 and < 1 m²/kg (mass and area positive)"),
    case("filter.initial_consider[0]", PRESSURE, &[], "Δ must be > -1 and < 10 (density stays positive)"),
    // filter: tuning
    case("filter.update_iterations", FUSION, &[], "must be >= 1 and <= 20 (1 is the standard EKF, more iterate it)"),
    case("filter.imu_sigma_mps2", FUSION, TUNED, "must be > 0 and < 10 m/s²"),
    case("filter.noise_inflation.accel", FUSION, TUNED, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.noise_inflation.dynamic_pressure", FUSION, TUNED, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.noise_inflation.heating", FUSION, TUNED, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.noise_inflation.range", FUSION, TUNED, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.noise_inflation.range_rate", FUSION, TUNED, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.tuned.ekf.q_diag[0]", FUSION, PER_FILTER, "must be >= 0 and finite (a variance)"),
    case("filter.tuned.ekf.noise_inflation.accel", FUSION, PER_FILTER, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.tuned.ekf.noise_inflation.dynamic_pressure", FUSION, PER_FILTER, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.tuned.ekf.noise_inflation.heating", FUSION, PER_FILTER, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.tuned.ekf.noise_inflation.range", FUSION, PER_FILTER, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.tuned.ekf.noise_inflation.range_rate", FUSION, PER_FILTER, "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)"),
    case("filter.accel_bias_tau_s", FUSION, TUNED, "must be > 0 s and finite (the Gauss-Markov time constant)"),
    case("filter.ukf.alpha", AIR, &[], "must be > 0 and <= 1"),
    case("filter.ukf.beta", AIR, &[], "must be >= 0 and < 10"),
    case("filter.ukf.kappa", FUSION, TUNED, "must be >= -100 and <= 100"),
    case("filter.model_bank_density_bias[0]", PRESSURE, &[], "must be > -1 and < 10 (density stays positive)"),
    // filter.density
    case("filter.density.cm_batch", AIR, &[], "must be >= 2 and <= 10000"),
    case("filter.density.ac_p0", AIR, &[], "must be > 0 and < 1"),
    case("filter.density.ac_q", AIR, &[], "must be >= 0 and < 1"),
    case("filter.density.ac_initial", AIR, &["filter.density.ac_initial=1.0"], "must be > 0 and < 100"),
    case("filter.density.consider_tau_s", AIR, &[], "must be > 0 and < 1000000 s"),
    case("filter.density.consider_pss", AIR, &[], "must be >= 0 and < 1"),
    case("filter.density.consider_p0", AIR, &[], "must be > 0 and < 1"),
    case("filter.density.adam_beta1", AIR, &[], "must be >= 0 and < 1"),
    case("filter.density.adam_beta2", AIR, &[], "must be >= 0 and < 1"),
    case("filter.density.adam_epsilon", AIR, &[], "must be > 0 and < 1"),
    case("filter.density.adam_step", AIR, &[], "must be >= 0 and < 10"),
    case("filter.density.patience", AIR, &[], "must be >= 1 and <= 1000"),
    case("filter.density.loss_threshold", AIR, &[], "must be >= 0 and finite"),
    case("filter.density.max_iterations", AIR, &[], "must be >= 1 and <= 100000"),
    case("filter.density.window", AIR, &[], "must be >= 1 and <= 1000"),
    case("filter.density.slope_window", AIR, &[], "must be >= 1 and <= 1000"),
    case("filter.density.slope_sigma_per_km", AIR, &[], "must be > 0 and <= 100 1/km"),
    case("filter.density.slope_log_density_sigma", AIR, &[], "must be > 0 and < 1"),
    case("filter.density.consider_match_epochs", AIR, &["filter.density.consider_match_epochs=10"], "must be >= 1 and <= 1000"),
    case("filter.density.training.trajectories", AIR, &[], "must be >= 1 and <= 1000000"),
    case("filter.density.training.hidden", AIR, &[], "must be >= 1 and <= 10000"),
    case("filter.density.training.epochs", AIR, &[], "must be >= 1 and <= 1000000"),
    case("filter.density.training.batch_size", AIR, &[], "must be >= 1 and <= 1e8"),
    case("filter.density.training.duration_s", AIR, &[], "must be > 0 and <= 7200 s"),
    case("filter.density.training.sample_interval_s", AIR, &[], "must be > 0 and < duration_s = 250 s"),
    case("filter.density.training.lr_max", AIR, &[], "must be > 0 and < 10"),
    case("filter.density.training.lr_min", AIR, &[], "must be > 0 and <= lr_max = 0.01"),
    case("filter.density.training.validation_fraction", AIR, &[], "must be > 0 and < 1"),
    case("filter.density.training.fit_altitude_km[0]", AIR, &[], "must be >= -100 and < 1000 km"),
    case("filter.density.training.fit_altitude_km[1]", AIR, &[], "must be > fit_altitude_km[0] = 0 and <= 1000 km"),
    // dispersions
    case("dispersions.initial.radius_km", AIR, &[], "a 1σ must be >= 0 and < 10000"),
    case("dispersions.initial.lon_deg", AIR, &[], "a 1σ must be >= 0 and < 10000"),
    case("dispersions.initial.lat_deg", AIR, &[], "a 1σ must be >= 0 and < 10000"),
    case("dispersions.initial.speed_mps", AIR, &[], "a 1σ must be >= 0 and < 10000"),
    case("dispersions.initial.fpa_deg", AIR, &[], "a 1σ must be >= 0 and < 10000"),
    case("dispersions.initial.heading_deg", AIR, &[], "a 1σ must be >= 0 and < 10000"),
    case("dispersions.initial.position_km[0]", ORBITERS, &[], "a 1σ must be >= 0 and < 10000"),
    case("dispersions.initial.velocity_mps[0]", ORBITERS, &[], "a 1σ must be >= 0 and < 10000"),
    case("dispersions.cd_s_over_m_m2kg", AIR, &[], "a 1σ must be >= 0 and < 1"),
    case("dispersions.lift_to_drag", AIR, &[], "a 1σ must be >= 0 and < 3"),
    case("dispersions.density_bias", PRESSURE, &[], "a 1σ must be >= 0 and < 1"),
    case("dispersions.density_bias_clip", PRESSURE, &[], "must be >= 0 and < 1 (0 = no clipping)"),
    case("monte_carlo.runs", FUSION, &[], "must be >= 1 and <= 1000000"),
    case("filter.gating.probability", FAULTS, &[], "must be >= 0.9 and < 1 (the χ² gate's probability)"),
    case("filter.gating.exclude_after", FAULTS, &[], "must be >= 1 and <= 1000 epochs"),
    case("filter.gating.readmit_after", FAULTS, &[], "must be >= 1 and <= 100000 epochs"),
    case("faults[0].start_s", FAULTS, &[], "must be >= 0 and <= 1000000 s"),
    case("faults[0].bias_m", FAULTS, &[], "must be >= -1e7 and <= 1e7 m"),
    case("faults[0].drift_mps", FAULTS, &[], "must be >= -10000 and <= 10000 m/s"),
    case("faults[1].probability", FAULTS, &[], "must be >= 0 and <= 1"),
    case("faults[1].size_m", FAULTS, &[], "must be >= 0 and <= 1e7 m"),
    case("guidance.rate_hz", AIR, GUIDED_FAST, "must be > 0 and <= 100 Hz"),
    case("guidance.bank_min_deg", AIR, GUIDED_HIGH, "must be >= 0 and <= 180°"),
    case("guidance.bank_max_deg", AIR, GUIDED_LOW, "must be >= guidance.bank_min_deg = 0 and <= 180°"),
    case("guidance.reference_bank_deg", AIR, GUIDED, "must be >= guidance.bank_min_deg = 0 and <= guidance.bank_max_deg = 180°"),
    case("guidance.bank_rate_limit_deg_s", AIR, GUIDED, "must be > 0 and <= 360 deg/s"),
    case("guidance.bank_accel_limit_deg_s2", AIR, GUIDED, "must be > 0 and <= 360 deg/s²"),
    case("guidance.trigger.speed_mps", AIR, GUIDED, "must be > 0 and < 30000 m/s"),
    case("guidance.min_deploy_altitude_m", AIR, GUIDED_FLOOR, "must be >= 0 and <= 50000 m"),
    case("guidance.apollo.heading_alignment_speed_mps", AIR, GUIDED_HA, "must be > 0 and < 30000 m/s"),
    case("guidance.apollo.heading_alignment_gain", AIR, GUIDED, "must be > 0 and <= 1000"),
    case("guidance.apollo.heading_alignment_max_bank_deg", AIR, GUIDED, "must be > 0 and <= 180°"),
    case("guidance.trigger.dynamic_pressure_pa", AIR, GUIDED_Q, "must be > 0 and <= 1000000 Pa"),
    case("guidance.target.lat_deg", AIR, GUIDED_POINT, "must be >= -90 and <= 90°"),
    case("guidance.target.lon_deg", AIR, GUIDED_POINT, "must be >= -360 and <= 360°"),
    case("guidance.target.range_km", AIR, GUIDED_RANGE, "must be > 0 and < 10000 km"),
    case("guidance.lateral.deadband_high_m", AIR, GUIDED, "must be >= 0 and <= 1000000 m"),
    case("guidance.lateral.deadband_low_m", AIR, GUIDED, "must be >= 0 and <= guidance.lateral.deadband_high_m = 4000 m"),
    case("guidance.lateral.speed_high_mps", AIR, GUIDED, "must be > 0 and < 30000 m/s"),
    case("guidance.lateral.speed_low_mps", AIR, GUIDED, "must be >= 0 and < guidance.lateral.speed_high_mps = 5000 m/s"),
    case("guidance.apollo.overcontrol_gain", AIR, GUIDED, "must be > 0 and <= 100"),
    case("guidance.apollo.start_drag_mps2", AIR, GUIDED, "must be >= 0 and <= 1000 m/s²"),
    case("guidance.apollo.hold_speed_mps", AIR, GUIDED, "must be >= 0 and < 30000 m/s"),
    case("guidance.fnpeg.final_bank_deg", AIR, GUIDED, "must be >= guidance.bank_min_deg = 0 and <= guidance.bank_max_deg = 180°"),
    case("guidance.fnpeg.predictor_step_s", AIR, GUIDED, "must be > 0 and <= 10 s"),
    case("guidance.fnpeg.iterations", AIR, GUIDED, "must be >= 1 and <= 50"),
    case("guidance.fnpeg.density_gain", AIR, GUIDED, "must be >= 0 and <= 1 (0 = trust the onboard atmosphere)"),
    case("guidance.fnpeg.hold_speed_mps", AIR, GUIDED, "must be >= 0 and < 30000 m/s"),
    case("guidance.trigger.range.nominal_speed_mps", AIR, GUIDED_RANGE_TRIGGER, "must be > 0 and < 30000 m/s"),
    case("guidance.trigger.range.backstop_speed_mps", AIR, GUIDED_RANGE_TRIGGER, "must be > 0 and <= guidance.trigger.range.nominal_speed_mps = 450 m/s"),
    case("guidance.trigger.range.window_margin", AIR, GUIDED_RANGE_TRIGGER, "must be >= 0 and <= 0.5"),
    case("guidance.deploy_box.speed_min_mps", AIR, GUIDED_BOX, "must be >= 0 and < 30000 m/s"),
    case("guidance.deploy_box.speed_max_mps", AIR, GUIDED_BOX, "must be > guidance.deploy_box.speed_min_mps = 380 and < 30000 m/s"),
    case("guidance.deploy_box.dynamic_pressure_min_pa", AIR, GUIDED_BOX, "must be >= 0 and < 1000000 Pa"),
    case("guidance.deploy_box.dynamic_pressure_max_pa", AIR, GUIDED_BOX, "must be > guidance.deploy_box.dynamic_pressure_min_pa = 250 and <= 1000000 Pa"),
    case("guidance.deploy_box.altitude_min_m", AIR, GUIDED_BOX, "must be >= -10000 and <= 100000 m"),
];

/// The built-in `base` with `sets` applied, as a TOML table (what `--set` edits).
fn table(base: &str, sets: &[&str]) -> toml::Table {
    let cfg = ScenarioConfig::builtin(base).unwrap();
    let mut doc: toml::Table = toml::from_str(&cfg.to_toml_string()).unwrap();
    for s in sets {
        let (path, value) = s.split_once('=').unwrap();
        let value: toml::Table = toml::from_str(&format!("v = {value}")).unwrap();
        *slot(&mut doc, path) = value["v"].clone();
    }
    doc
}

/// The value at a dotted `path` with `[k]` indices, created (as a table entry) when missing.
fn slot<'a>(doc: &'a mut toml::Table, path: &str) -> &'a mut toml::Value {
    let mut keys = path.split('.').peekable();
    let mut table = doc;
    loop {
        let key = keys.next().unwrap();
        let (name, indices) = match key.split_once('[') {
            Some((name, rest)) => (name, Some(rest)),
            None => (key, None),
        };
        let last = keys.peek().is_none();
        let entry = table.entry(name.to_string()).or_insert_with(|| {
            if last {
                toml::Value::Float(0.0)
            } else {
                toml::Value::Table(toml::Table::new())
            }
        });
        let mut value = entry;
        for index in indices.into_iter().flat_map(|r| r.split('[')) {
            let k: usize = index.trim_end_matches(']').parse().unwrap();
            value = &mut value.as_array_mut().unwrap()[k];
        }
        if last {
            return value;
        }
        table = value.as_table_mut().unwrap();
    }
}

/// One limit read from a message: the number, whether it is a lower limit, whether included.
#[derive(Debug, Clone, Copy)]
struct Limit {
    value: f64,
    lower: bool,
    inclusive: bool,
}

/// The limits a message promises: the clauses after "must be", each `op [name =] number [unit]`.
fn limits(allowed: &str) -> Vec<Limit> {
    let words = allowed.split_once("must be ").unwrap().1;
    let words = words.split(" (").next().unwrap();
    let mut out = Vec::new();
    for clause in words.split(" and ").filter(|c| *c != "finite") {
        let (op, rest) = clause.split_once(' ').unwrap();
        let number = rest.rsplit(" = ").next().unwrap();
        let number = number.split(' ').next().unwrap().trim_end_matches('°');
        let (lower, inclusive) = match op {
            ">" => (true, false),
            ">=" => (true, true),
            "<" => (false, false),
            "<=" => (false, true),
            _ => panic!("no limit in '{clause}' of '{allowed}'"),
        };
        let value = number.parse().unwrap_or_else(|e| panic!("'{number}': {e}"));
        out.push(Limit {
            value,
            lower,
            inclusive,
        });
    }
    out
}

/// The next f64 past `v`, downwards or upwards.
fn next(v: f64, up: bool) -> f64 {
    if v == 0.0 {
        let tiny = f64::from_bits(1);
        return if up { tiny } else { -tiny };
    }
    let away = (v > 0.0) == up;
    f64::from_bits(if away {
        v.to_bits() + 1
    } else {
        v.to_bits() - 1
    })
}

/// Validate `case` with its field set to `v` (a count when the field holds an integer); the
/// error message if refused.
fn probe(case: &Case, v: f64) -> Result<(), String> {
    let mut doc = table(case.base, case.sets);
    let field = slot(&mut doc, case.field);
    let vector = |x: f64| toml::Value::Array(vec![x.into(), 0.0.into(), 0.0.into()]);
    *field = match field {
        toml::Value::Integer(_) => toml::Value::Integer(v as i64),
        toml::Value::Array(_) => vector(v),
        _ => toml::Value::Float(v),
    };
    let text = toml::to_string(&doc).unwrap();
    ScenarioConfig::from_toml_str(&text, "probe")
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// How a case's field is probed.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// A real number: the next value past a limit is the next f64.
    Real,
    /// A count: the next value past a limit is one more or one less.
    Count,
    /// A vector checked by its norm: probed as `[v, 0, 0]`; no norm is below 0.
    Norm,
}

fn kind(case: &Case) -> Kind {
    let mut doc = table(case.base, case.sets);
    match slot(&mut doc, case.field) {
        toml::Value::Integer(_) => Kind::Count,
        toml::Value::Array(_) => Kind::Norm,
        _ => Kind::Real,
    }
}

#[test]
fn every_range_holds_at_its_limits() {
    let mut failures = Vec::new();
    for case in CASES {
        let lims = limits(case.allowed);
        assert!(
            !lims.is_empty(),
            "{}: no limit in '{}'",
            case.field,
            case.allowed
        );
        let kind = kind(case);
        for lim in lims {
            let outward = !lim.lower;
            let past = match kind {
                Kind::Count => lim.value + if outward { 1.0 } else { -1.0 },
                _ => next(lim.value, outward),
            };
            let shown = |v: f64| match kind {
                Kind::Count => (v as i64).to_string(),
                _ => v.to_string(),
            };
            let refusal = |v: f64| {
                format!(
                    "{} = {} is out of range: {}",
                    case.field,
                    shown(v),
                    case.allowed
                )
            };
            let at = probe(case, lim.value);
            match (&at, lim.inclusive) {
                (Ok(()), true) => {}
                (Err(e), false) if *e == refusal(lim.value) => {}
                _ => failures.push(format!(
                    "{} = {} ({}): {at:?}",
                    case.field,
                    lim.value,
                    if lim.inclusive {
                        "included"
                    } else {
                        "excluded"
                    }
                )),
            }
            if kind == Kind::Norm && past < 0.0 {
                continue;
            }
            match probe(case, past) {
                Err(e) if e == refusal(past) => {}
                other => failures.push(format!(
                    "{} = {past} (past the limit {}): {other:?}",
                    case.field, lim.value
                )),
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} problems:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// A field path with its indices left out: `filter.p0_diag[3]` is `filter.p0_diag[]`.
fn family(field: &str) -> String {
    let mut out = String::new();
    let mut inside = false;
    for ch in field.chars() {
        match ch {
            '[' => {
                inside = true;
                out.push_str("[]");
            }
            ']' => inside = false,
            _ if !inside => out.push(ch),
            _ => {}
        }
    }
    out
}

#[test]
fn every_range_check_has_a_case() {
    let cased: BTreeSet<String> = CASES.iter().map(|c| family(c.field)).collect();
    let mut checked = BTreeSet::new();
    let scenarios = BUILTIN_NAMES
        .iter()
        .map(|name| table(name, &[]))
        .chain(CASES.iter().map(|c| table(c.base, c.sets)));
    for doc in scenarios {
        let cfg = ScenarioConfig::from_toml_str(&toml::to_string(&doc).unwrap(), "case").unwrap();
        for check in cfg.range_checks().unwrap() {
            // The listed check says what it checked: its message is the range's own words.
            assert!(check.range.contains(check.value.parse().unwrap()));
            checked.insert(family(&check.field));
        }
    }
    let missing: Vec<_> = checked.difference(&cased).collect();
    assert!(
        missing.is_empty(),
        "range checks without a case here: {missing:?}"
    );
    let unused: Vec<_> = cased.difference(&checked).collect();
    assert!(
        unused.is_empty(),
        "cases no validation check reaches: {unused:?}"
    );
}

/// A field that only means something with another is refused by name when that one is absent:
/// `consider_match_epochs` matches the level-and-slope correction's prediction error, so it needs
/// `slope_window` (msl-guided has none).
#[test]
fn consider_matching_without_the_correction_is_refused_by_name() {
    let set = ["filter.density.consider_match_epochs=10"];
    let mut doc = table("msl-guided", &set);
    let text = toml::to_string(&doc).unwrap();
    let err = ScenarioConfig::from_toml_str(&text, "probe")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("filter.density.consider_match_epochs")
            && err.contains("needs filter.density.slope_window"),
        "{err}"
    );
    *slot(&mut doc, "filter.density.slope_window") = toml::Value::Integer(2);
    assert!(ScenarioConfig::from_toml_str(&toml::to_string(&doc).unwrap(), "probe").is_ok());
}
