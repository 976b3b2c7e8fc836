//! [`EntryCoSim`]: truth, sensors and navigation filter together, the filter run at every
//! measurement epoch of the truth and judged against it.

use super::error::EngineError;
use super::filter::Judgement;
use super::navigator::{NavStatus, Navigator};
use super::run_seed::run_seed;
use super::step_check::check_step;
use super::truth_sensors::StepReport;
use super::truth_sensors::TruthSensors;
use crate::estimation::nav::FilterKind;
use crate::scenario::Scenario;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

/// Truth, sensors and a navigation filter in one co-simulation slave.
#[derive(Debug)]
pub struct EntryCoSim {
    truth: TruthSensors,
    nav: Navigator,
    judgement: Judgement,
}

impl EntryCoSim {
    /// Filter `kind` on `scenario` with the truth realisation of `seed` (dispersed or nominal).
    pub fn new(
        scenario: Arc<Scenario>,
        kind: FilterKind,
        seed: u64,
        dispersed: bool,
    ) -> Result<EntryCoSim, EngineError> {
        let truth = TruthSensors::new(Arc::clone(&scenario), seed, dispersed);
        let nav =
            Navigator::for_truth(&scenario, kind, seed, truth.draw(), &truth.outputs().sample)?;
        let judgement = nav.judge(&scenario, truth.draw(), &truth.outputs().sample);
        Ok(EntryCoSim {
            truth,
            nav,
            judgement,
        })
    }

    /// Filter `kind` on `scenario` with the truth realisation of Monte Carlo run `run` of a study
    /// with master seed `seed`: everything from `run_seed(seed, run)` as a trade's run draws it
    /// ([`Scenario::draw_truth_run`], so a truth profile set is cycled by run index), the
    /// measurement noise after the draw, and the filter start from that seed's stream 1 (as
    /// [`EntryCoSim::new`]). Without a cycled profile set this is
    /// `EntryCoSim::new(scenario, kind, run_seed(seed, run), true)`.
    pub fn for_run(
        scenario: Arc<Scenario>,
        kind: FilterKind,
        seed: u64,
        run: usize,
    ) -> Result<EntryCoSim, EngineError> {
        let s = run_seed(seed, run as u64);
        let mut rng = ChaCha8Rng::seed_from_u64(s);
        let draw = scenario.draw_truth_run(run, &mut rng);
        let truth = TruthSensors::with_draw(Arc::clone(&scenario), draw, rng);
        let nav = Navigator::for_truth(&scenario, kind, s, truth.draw(), &truth.outputs().sample)?;
        let judgement = nav.judge(&scenario, truth.draw(), &truth.outputs().sample);
        Ok(EntryCoSim {
            truth,
            nav,
            judgement,
        })
    }

    /// Advance from `t` by `h` with bank angle `bank` \[rad\] and beacon availability flags; the
    /// filter processes every measurement epoch of the step with its onboard models at `bank`.
    pub fn do_step(
        &mut self,
        t: f64,
        h: f64,
        bank: f64,
        beacon_available: &[bool],
    ) -> Result<StepReport, EngineError> {
        check_step(self.nav.time(), t, h)?;
        let mut epochs = Vec::new();
        let mut report =
            self.truth
                .do_step_with(t, h, bank, beacon_available, |epoch, sample| {
                    epochs.push((epoch.clone(), sample.clone()));
                })?;
        report.epochs = 0;
        self.nav.command_bank(t, bank);
        let scenario = self.truth.scenario();
        for (epoch, sample) in &epochs {
            if self.nav.process(epoch) {
                report.epochs += 1;
                if *self.nav.status() == NavStatus::Running {
                    self.judgement = self.nav.judge(scenario, self.truth.draw(), sample);
                }
            }
        }
        self.nav.set_time(t + h);
        Ok(report)
    }

    /// The truth and sensors.
    pub fn truth(&self) -> &TruthSensors {
        &self.truth
    }

    /// The filter.
    pub fn nav(&self) -> &Navigator {
        &self.nav
    }

    /// The latest estimate judged against the truth at its epoch.
    pub fn judgement(&self) -> &Judgement {
        &self.judgement
    }

    /// Current communication point \[s\].
    pub fn time(&self) -> f64 {
        self.nav.time()
    }
}
