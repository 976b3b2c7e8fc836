//! `msl-guided` as it was before issue 50 changed its defaults: seed 001's Table 1 dispersions
//! (C_D S/m 22.5 %, L/D 21 %, 1σ) with the matching filter P0, the 60° reference bank, the
//! 450 m/s speed trigger, no altitude safeguard and no heading alignment. On these dispersions some runs reach the
//! ground before the trigger (docs/guidance.md), which the tests of failure handling need.

use entrynav::guidance::Trigger;
use entrynav::scenario::ScenarioConfig;

/// The built-in `msl-guided` with its pre-issue-50 settings (module documentation).
pub fn seed001_guided_config() -> ScenarioConfig {
    let mut cfg = ScenarioConfig::builtin("msl-guided").unwrap();
    cfg.dispersions.cd_s_over_m_m2kg = 1.6e-3;
    cfg.dispersions.lift_to_drag = 5.0593e-2;
    cfg.filter.p0_diag[6] = 2.56e-6;
    cfg.filter.p0_diag[7] = 2.5597e-3;
    cfg.truth.bank_deg = 60.0;
    let g = cfg.guidance.as_mut().unwrap();
    g.reference_bank_deg = 60.0;
    g.trigger = Trigger::SpeedMps(450.0);
    g.min_deploy_altitude_m = None;
    g.apollo.heading_alignment_speed_mps = None;
    cfg
}
