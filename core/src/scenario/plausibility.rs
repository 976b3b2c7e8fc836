//! Values that pass validation but no Mars entry has: most are a unit slip (a speed in km/s, a
//! flight-path angle in radians, a radius in metres). They are not errors — a study may mean them —
//! so they are reported as warnings, naming the field, the value, the plausible range and the
//! likely slip. Envelopes from the entries of the four papers and flown missions: entry interface
//! 80–250 km above the surface, inertial or relative speed 3–8 km/s, flight-path angle −30° to −5°.

use super::config::{ScenarioConfig, StateConfig};
use crate::planet::Planet;

/// A value outside what a Mars entry plausibly has.
#[derive(Debug, Clone, PartialEq)]
pub struct Implausible {
    /// The field (as `--set` names it).
    pub field: String,
    /// Its value.
    pub value: f64,
    /// The plausible range and, where one is likely, the slip.
    pub note: String,
}

impl std::fmt::Display for Implausible {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} = {} is outside what a Mars entry plausibly has: {}",
            self.field, self.value, self.note
        )
    }
}

/// Plausible entry-interface altitude \[km\].
pub const ALTITUDE_KM: (f64, f64) = (80.0, 250.0);
/// Plausible entry speed \[m/s\].
pub const SPEED_MPS: (f64, f64) = (3000.0, 8000.0);
/// Plausible entry flight-path angle \[°\].
pub const FPA_DEG: (f64, f64) = (-30.0, -5.0);

fn outside(v: f64, (lo, hi): (f64, f64)) -> bool {
    !(lo..=hi).contains(&v)
}

impl ScenarioConfig {
    /// Every implausible value of the vehicle's initial states (`truth.initial`,
    /// `filter.initial`); empty for a plausible scenario (every built-in).
    pub fn implausible(&self) -> Vec<Implausible> {
        let planet = self.planet.resolve();
        let mut out = Vec::new();
        state(&mut out, "truth.initial", &self.truth.initial, &planet);
        if let Some(s) = &self.filter.initial {
            state(&mut out, "filter.initial", s, &planet);
        }
        out
    }
}

fn state(out: &mut Vec<Implausible>, prefix: &str, s: &StateConfig, planet: &Planet) {
    let r_km = planet.radius / 1e3;
    let mut push = |name: &str, value: f64, note: String| {
        out.push(Implausible {
            field: format!("{prefix}.{name}"),
            value,
            note,
        })
    };
    let (radius_km, speed, fpa, names) = match (s.position_km, s.velocity_mps) {
        (Some(p), Some(v)) => {
            let norm = |x: [f64; 3]| (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            let (pn, vn) = (norm(p), norm(v));
            let dot = p[0] * v[0] + p[1] * v[1] + p[2] * v[2];
            let fpa = (dot / (pn * vn).max(f64::MIN_POSITIVE))
                .clamp(-1.0, 1.0)
                .asin()
                .to_degrees();
            (
                pn,
                vn,
                fpa,
                [
                    "position_km (norm)",
                    "velocity_mps (norm)",
                    "velocity_mps (flight-path angle)",
                ],
            )
        }
        _ => match (s.radius_km, s.speed_mps, s.fpa_deg) {
            (Some(r), Some(v), Some(g)) => (r, v, g, ["radius_km", "speed_mps", "fpa_deg"]),
            _ => return,
        },
    };
    let altitude = radius_km - r_km;
    if outside(altitude, ALTITUDE_KM) {
        let slip = if radius_km > 1e3 * r_km {
            format!(" (a radius in metres? {:.1} km)", radius_km / 1e3)
        } else if altitude < ALTITUDE_KM.0 && radius_km < r_km + 1.0 {
            " (an altitude given as a radius?)".to_string()
        } else {
            String::new()
        };
        push(
            names[0],
            radius_km,
            format!(
                "{altitude:.1} km above the surface, plausible {}–{} km{slip}",
                ALTITUDE_KM.0, ALTITUDE_KM.1
            ),
        );
    }
    if outside(speed, SPEED_MPS) {
        let slip = if speed > 0.0 && outside(speed, (1.0, 100.0)) {
            String::new()
        } else {
            format!(" (km/s? {} km/s = {:.0} m/s)", speed, 1e3 * speed)
        };
        push(
            names[1],
            speed,
            format!(
                "{speed} m/s, plausible {}–{} m/s{slip}",
                SPEED_MPS.0, SPEED_MPS.1
            ),
        );
    }
    if outside(fpa, FPA_DEG) {
        let slip = if fpa < 0.0 && fpa > -0.6 {
            format!(" (radians? {fpa} rad = {:.1}°)", fpa.to_degrees())
        } else if fpa > 0.0 {
            " (positive: the vehicle climbs; entry angles are negative)".to_string()
        } else {
            String::new()
        };
        push(
            names[2],
            fpa,
            format!(
                "{fpa:.3}°, plausible {}° to {}°{slip}",
                FPA_DEG.0, FPA_DEG.1
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::BUILTIN_NAMES;

    #[test]
    fn builtins_are_plausible_and_slips_are_named() {
        for name in BUILTIN_NAMES {
            let cfg = ScenarioConfig::builtin(name).unwrap();
            assert_eq!(cfg.implausible(), vec![], "{name}");
        }
        let mut cfg = ScenarioConfig::builtin("four-beacon-fusion").unwrap();
        cfg.truth.initial.speed_mps = Some(5.6);
        cfg.truth.initial.fpa_deg = Some(-0.21);
        let w: Vec<String> = cfg.implausible().iter().map(|w| w.to_string()).collect();
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].starts_with("truth.initial.speed_mps = 5.6")
                && w[0].contains("km/s? 5.6 km/s = 5600 m/s"),
            "{w:?}"
        );
        assert!(
            w[1].starts_with("truth.initial.fpa_deg = -0.21")
                && w[1].contains("radians? -0.21 rad = -12.0°"),
            "{w:?}"
        );
    }

    #[test]
    fn validation_refuses_an_implausible_value_unless_allowed() {
        let mut cfg = ScenarioConfig::builtin("four-beacon-fusion").unwrap();
        cfg.truth.initial.speed_mps = Some(5.515);
        let e = cfg.validate().unwrap_err().to_string();
        assert!(
            e.starts_with("truth.initial.speed_mps = 5.515 is outside what a Mars entry")
                && e.contains("km/s? 5.515 km/s = 5515 m/s")
                && e.contains("allow_implausible = true"),
            "{e}"
        );
        cfg.allow_implausible = true;
        cfg.validate().unwrap();
        // The allowance does not lift a range check: a negative speed stays refused.
        cfg.truth.initial.speed_mps = Some(-1.0);
        assert!(cfg.validate().is_err());
    }
}
