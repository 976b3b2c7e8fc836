//! The engine of `MarsEntryNavGuided`: truth, sensors, navigation filter and guidance in one
//! loop, the in-process guided flight ([`GuidedLoop`], issue 28) behind the FMI step.
//!
//! **Time.** The loop moves on the grid k·Δt of the scenario's `timing.truth_step_s`, one truth
//! step per [`GuidedLoop::step`]: a guidance cycle at the start of every grid step that is a
//! multiple of the guidance period, the actuator over the step, then the truth, the sensors and
//! the filter. A communication step from t to t + h runs the grid steps that end at or before
//! t + h (as the truth and guidance FMUs), so any step size works and the flight is the same on
//! any communication grid: with `dispersed = true` it is run `run` of `entrynav guidance deliver
//! --seed seed`, bit for bit. Beacon availability is read at the start of each communication
//! step and holds over its grid steps.
//!
//! **The end.** The flight ends at deployment (the trigger reached on the truth, interpolated
//! between the two truth samples around it: the delivery outputs), or without one: the truth
//! stopped first (ground, stop speed, duration), the filter failed at a guidance cycle (the
//! vehicle would fly blind), or guidance failed. After the end the outputs hold and a step only
//! advances time. An engine failure inside a step is an error of the step.
//!
//! Guidance sees only the filter's estimate and the accelerometer triad (the in-process loop's
//! guarantee, tested in the core); the truth is there for the truth outputs and the judgement.

use entrynav::scenario::Scenario;
use entrynav::sim::engine::EntryCoSim;
use entrynav::sim::guided::{Delivery, GuidedLoop, GuidedRunError};
use std::sync::Arc;

/// How the guided flight stands (`guided_status`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GuidedStatus {
    /// Still flying.
    Flying = 0,
    /// Deployed: the delivery is set.
    Deployed = 1,
    /// Ended without deployment.
    Ended = 2,
}

/// What one communication step of the guided engine did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GuidedReport {
    /// Truth steps flown.
    pub steps: usize,
    /// Guidance cycles run.
    pub cycles: usize,
    /// The flight ended in this step: how (a message for the log), and whether it deployed.
    pub ended: Option<(bool, String)>,
}

/// The guided flight of one instance and its communication time.
#[derive(Debug)]
pub struct GuidedEngine {
    flight: GuidedLoop,
    time: f64,
}

impl GuidedEngine {
    /// The guided flight of `cosim` on `scenario` (refused without `[guidance]` or accelerometers).
    pub fn new(scenario: &Arc<Scenario>, cosim: EntryCoSim) -> Result<Self, GuidedRunError> {
        let time = cosim.time();
        Ok(GuidedEngine {
            flight: GuidedLoop::with_cosim(scenario, cosim)?,
            time,
        })
    }

    /// The flight.
    pub fn flight(&self) -> &GuidedLoop {
        &self.flight
    }

    /// Communication time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// How the flight stands.
    pub fn status(&self) -> GuidedStatus {
        match self.flight.outcome() {
            None => GuidedStatus::Flying,
            Some(Ok(_)) => GuidedStatus::Deployed,
            Some(Err(_)) => GuidedStatus::Ended,
        }
    }

    /// The delivery, once deployed.
    pub fn delivery(&self) -> Option<&Delivery> {
        self.flight.delivery()
    }

    /// The grid step that ends last at or before `t + h`.
    fn end_step(&self, t: f64, h: f64) -> usize {
        let k = ((t + h) / self.flight.dt() + 1e-7).floor().max(0.0);
        // Beyond usize the flight has ended long before (the truth stops at its duration).
        if k >= usize::MAX as f64 {
            usize::MAX
        } else {
            k as usize
        }
    }

    /// Advance from `t` by `h` with beacon availability `avail` (module documentation). An
    /// engine failure is an error; every other end of the flight is reported, not an error.
    pub fn do_step(
        &mut self,
        t: f64,
        h: f64,
        avail: &[bool],
    ) -> Result<GuidedReport, GuidedRunError> {
        let end = self.end_step(t, h);
        let cycles_before = self.flight.cycles();
        let mut report = GuidedReport::default();
        while self.flight.outcome().is_none() && self.flight.steps() < end {
            // A failure at a cycle is also recorded as the outcome, read below.
            let _ = self.flight.step(avail);
            report.steps += 1;
        }
        report.cycles = self.flight.cycles() - cycles_before;
        if report.steps > 0 {
            match self.flight.outcome() {
                Some(Err(GuidedRunError::Engine(e))) => {
                    return Err(GuidedRunError::Engine(e.clone()));
                }
                Some(Ok(d)) => {
                    report.ended = Some((
                        true,
                        format!(
                            "deployed at t = {:.3} s, altitude {:.1} m: miss {:.1} m (downrange {:.1} m, crossrange {:.1} m)",
                            d.t_deploy_s, d.altitude_m, d.miss_m, d.downrange_m, d.crossrange_m
                        ),
                    ));
                }
                Some(Err(e)) => {
                    report.ended = Some((
                        false,
                        format!("the guided flight ended without deployment: {e}"),
                    ))
                }
                None => {}
            }
        }
        self.time = t + h;
        Ok(report)
    }
}
