//! `entrynav simulate` as a study: one truth run of a scenario (nominal or dispersed) with its
//! measurement record and peak loads, and the run as a table ([`truth_table`]: what the command
//! writes as CSV and the Python package's `simulate` returns).

use crate::error::StudyResult;
use entrynav::scenario::{Scenario, TruthDraw};
use entrynav::sim::{Peaks, TruthRun, simulate_truth_with_peaks};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Which truth to fly.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimulateOptions {
    /// Seed of the measurement noise (and of the dispersions with `dispersed`).
    pub seed: u64,
    /// Draw the truth from the scenario's dispersions (initial state, vehicle, density bias,
    /// atmosphere perturbation) instead of using the nominal truth.
    pub dispersed: bool,
}

impl Default for SimulateOptions {
    fn default() -> Self {
        SimulateOptions {
            seed: 1,
            dispersed: false,
        }
    }
}

impl SimulateOptions {
    /// Every value of these options is in range (a seed is any `u64`).
    pub fn validate(&self) -> StudyResult<()> {
        Ok(())
    }
}

/// One truth run.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The run: truth samples and measurement epochs.
    pub run: TruthRun,
    /// Its peak loads over every truth integration step (`timing.truth_step_s`), not only the
    /// sampled rows.
    pub peaks: Peaks,
}

impl Simulation {
    /// The run as a table ([`truth_table`]).
    pub fn truth_table(&self, scenario: &Scenario) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
        truth_table(scenario, &self.run)
    }
}

/// Fly `scenario`'s truth once.
pub fn run_simulate(scenario: &Scenario, options: &SimulateOptions) -> StudyResult<Simulation> {
    options.validate()?;
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let draw = if options.dispersed {
        scenario.draw_truth(&mut rng)
    } else {
        TruthDraw {
            initial: scenario.truth_initial,
            model: scenario.truth_model.clone(),
        }
    };
    let (run, peaks) = simulate_truth_with_peaks(scenario, &draw, &mut rng)?;
    Ok(Simulation { run, peaks })
}

/// The truth run as a table: the column names and one row per truth sample (t = 0, every
/// measurement epoch, the final time); a measurement is `None` where the channel was not sampled
/// or not available, a visibility 0 or 1. What `--out FILE` writes and the Python package's
/// `simulate` returns.
pub fn truth_table(scenario: &Scenario, run: &TruthRun) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
    let cartesian = scenario.truth_model.kind.is_cartesian();
    let mut header: Vec<String> = [
        "t_s",
        "r_m",
        "lon_rad",
        "lat_rad",
        "v_mps",
        "fpa_rad",
        "heading_rad",
        "altitude_m",
        "density_kgm3",
        "dynamic_pressure_pa",
        "heating_wm2",
        "aero_accel_mps2",
    ]
    .map(String::from)
    .to_vec();
    if cartesian {
        header.extend(["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"].map(String::from));
    }
    header.extend(scenario.beacon_names.iter().map(|b| format!("visible_{b}")));
    header.extend(scenario.channels.iter().map(|c| c.name.clone()));
    let mut epochs = run.epochs.iter().peekable();
    let mut rows = Vec::with_capacity(run.samples.len());
    for s in &run.samples {
        let mut row: Vec<Option<f64>> = vec![Some(s.t)];
        row.extend(s.spherical.iter().map(|v| Some(*v)));
        row.extend(
            [
                s.altitude,
                s.density,
                s.dynamic_pressure,
                s.heating,
                s.aero_accel,
            ]
            .map(Some),
        );
        if cartesian {
            row.extend(s.state.iter().map(|v| Some(*v)));
        }
        row.extend(s.visible.iter().map(|v| Some(f64::from(u8::from(*v)))));
        match epochs.peek() {
            Some(e) if (e.t - s.t).abs() < 1e-9 => {
                row.extend(e.values.iter().copied());
                epochs.next();
            }
            _ => row.extend(std::iter::repeat_n(None, scenario.channels.len())),
        }
        rows.push(row);
    }
    (header, rows)
}
