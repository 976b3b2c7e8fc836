//! Synthetic test set of truth atmospheres for the density-adaptation filters (issue 15).
//!
//! Seed 001 §V flies USKF-NN through perturbed Mars-GRAM profiles and §I motivates the adaptive
//! density with seasonal and dust-storm variability. We cannot ship Mars-GRAM (SPEC.md), so this
//! generator builds a **synthetic** set spanning that variability around a mean profile ρ̄(h)
//! (the built-in `mars-mean`): case *i* scales the mean by a factor `f_above` above 80 km and
//! `f_below` below 60 km, smoothly in ln ρ in between,
//!
//! ln f(h) = ln f_below + (ln f_above − ln f_below)·s((h − 60 km)/20 km),  s(u) = 3u² − 2u³,
//!
//! and multiplies in one seeded realisation of the scenario perturbation ([`Perturbed`], the
//! SPEC.md envelope times `perturbation_scale`, seed `seed + i`). The default grid crosses
//! `f_above` ∈ {0.1, 0.3, 0.5, 1, 2, 3} with `f_below` ∈ {0.7, 1, 1.3}: cold / polar cases
//! (thin upper atmosphere, dense lower one), dusty seasons (dust-heated, expanded thermosphere
//! over a thinner lower atmosphere) and everything in between. These are **not** Mars-GRAM
//! output; they only bracket the ranges seed 001 and the issue name.
//!
//! [`generate_synthetic_set`] returns the profiles; [`synthetic_set_gram_text`] formats them as
//! a Mars-GRAM Monte Carlo set (a `#` header of `Var_X DENSTOT Radius`, stacked profiles), which
//! `atmosphere::parse_profiles` reads back. The core does no I/O: the CLI writes the text.

use super::error::{AtmosphereError, check_closed, check_open};
use super::model::AtmosphereModel;
use super::perturbed::{PerturbationSpec, Perturbed};
use super::{Atmosphere, Tabulated};

/// Altitude (m) below which a case's `f_below` applies.
pub const SYNTHETIC_BLEND_BOTTOM_M: f64 = 60_000.0;
/// Altitude (m) above which a case's `f_above` applies.
pub const SYNTHETIC_BLEND_TOP_M: f64 = 80_000.0;

/// One atmosphere of the set: density factors relative to the mean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticCase {
    /// ρ/ρ̄ above 80 km (before the perturbation).
    pub factor_above: f64,
    /// ρ/ρ̄ below 60 km (before the perturbation).
    pub factor_below: f64,
}

impl SyntheticCase {
    /// The deterministic factor f(h) of the module documentation.
    pub fn factor(&self, altitude_m: f64) -> f64 {
        let u = ((altitude_m - SYNTHETIC_BLEND_BOTTOM_M)
            / (SYNTHETIC_BLEND_TOP_M - SYNTHETIC_BLEND_BOTTOM_M))
            .clamp(0.0, 1.0);
        let s = u * u * (3.0 - 2.0 * u);
        let (lb, la) = (self.factor_below.ln(), self.factor_above.ln());
        (lb + (la - lb) * s).exp()
    }

    /// A short description: "cold / polar", "dusty season", or "mixed".
    pub fn season(&self) -> &'static str {
        match (self.factor_above, self.factor_below) {
            (a, b) if a < 1.0 && b > 1.0 => "cold / polar",
            (a, b) if a > 1.0 && b < 1.0 => "dusty season",
            (a, b) if a == 1.0 && b == 1.0 => "mean",
            _ => "mixed",
        }
    }
}

/// What to generate.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntheticSetSpec {
    /// The cases, in profile order.
    pub cases: Vec<SyntheticCase>,
    /// Seed of the perturbation of case i: `seed + i`.
    pub seed: u64,
    /// Multiplier of the SPEC.md perturbation envelope (0: the scaled means exactly).
    pub perturbation_scale: f64,
    /// Lowest and highest altitude of every profile (m).
    pub altitude_range_m: (f64, f64),
    /// Spacing of the rows (m).
    pub step_m: f64,
}

impl Default for SyntheticSetSpec {
    /// 18 cases: `f_above` ∈ {0.1, 0.3, 0.5, 1, 2, 3} × `f_below` ∈ {0.7, 1, 1.3}, seed 1, half the
    /// SPEC.md perturbation, 0–150 km every 1 km.
    fn default() -> Self {
        let mut cases = Vec::new();
        for factor_above in [0.1, 0.3, 0.5, 1.0, 2.0, 3.0] {
            for factor_below in [0.7, 1.0, 1.3] {
                cases.push(SyntheticCase {
                    factor_above,
                    factor_below,
                });
            }
        }
        SyntheticSetSpec {
            cases,
            seed: 1,
            perturbation_scale: 0.5,
            altitude_range_m: (0.0, 150_000.0),
            step_m: 1_000.0,
        }
    }
}

impl SyntheticSetSpec {
    /// Check the spec: 1 to 10 000 cases with factors in [0.01, 100], scale in [0, 10], a range of
    /// at least three rows.
    pub fn validate(&self) -> Result<(), AtmosphereError> {
        if self.cases.is_empty() || self.cases.len() > super::MAX_PROFILES {
            return Err(AtmosphereError::InvalidField {
                field: "cases".to_string(),
                problem: format!(
                    "{} cases; between 1 and {} are allowed",
                    self.cases.len(),
                    super::MAX_PROFILES
                ),
            });
        }
        for (i, c) in self.cases.iter().enumerate() {
            check_closed(
                &format!("cases[{i}].factor_above"),
                c.factor_above,
                0.01,
                100.0,
            )?;
            check_closed(
                &format!("cases[{i}].factor_below"),
                c.factor_below,
                0.01,
                100.0,
            )?;
        }
        check_closed("perturbation_scale", self.perturbation_scale, 0.0, 10.0)?;
        let (lo, hi) = self.altitude_range_m;
        check_open("altitude_range_m.0", lo, -1e5, 1e6)?;
        check_open("altitude_range_m.1", hi, lo, 1e6)?;
        check_open(
            "step_m",
            self.step_m,
            (hi - lo) / 1e5,
            (hi - lo) / 2.0 + 1e-9,
        )?;
        Ok(())
    }
}

/// One generated profile: its case, altitudes (m) and densities (kg/m³).
#[derive(Debug, Clone, PartialEq)]
pub struct SyntheticProfile {
    /// The case it realises.
    pub case: SyntheticCase,
    /// Altitudes above the reference sphere, increasing (m).
    pub altitude_m: Vec<f64>,
    /// Densities (kg/m³).
    pub density: Vec<f64>,
}

/// The set of `spec` around `mean` (deterministic: the same spec gives the same numbers).
pub fn generate_synthetic_set(
    mean: &Tabulated,
    spec: &SyntheticSetSpec,
) -> Result<Vec<SyntheticProfile>, AtmosphereError> {
    spec.validate()?;
    let (lo, hi) = spec.altitude_range_m;
    let rows = ((hi - lo) / spec.step_m + 1e-9).floor() as usize + 1;
    let pert = PerturbationSpec {
        grid_bottom_m: lo.min(0.0),
        grid_top_m: hi.max(150_000.0),
        scale: spec.perturbation_scale,
        ..PerturbationSpec::default()
    };
    let mut out = Vec::with_capacity(spec.cases.len());
    for (i, case) in spec.cases.iter().enumerate() {
        let seed = spec.seed.wrapping_add(i as u64);
        let p = Perturbed::from_seed(AtmosphereModel::Tabulated(mean.clone()), &pert, seed)?;
        let altitude_m: Vec<f64> = (0..rows).map(|k| lo + k as f64 * spec.step_m).collect();
        let density = altitude_m
            .iter()
            .map(|&h| case.factor(h) * p.density(h))
            .collect();
        out.push(SyntheticProfile {
            case: *case,
            altitude_m,
            density,
        });
    }
    Ok(out)
}

/// The profiles as a Mars-GRAM Monte Carlo set file: comment lines, the `#` header
/// `Var_X DENSTOT Radius` (height km, density kg/m³, planet-centred radius km for a sphere of
/// `sphere_radius_m`, so the height datum is exact) and the profiles stacked in case order.
pub fn synthetic_set_gram_text(
    profiles: &[SyntheticProfile],
    spec: &SyntheticSetSpec,
    sphere_radius_m: f64,
) -> String {
    let mut s = String::new();
    s.push_str(
        "# Synthetic Monte Carlo set of Mars density profiles (NOT Mars-GRAM output), written by\n",
    );
    s.push_str("# `entrynav atmosphere generate` (core/src/atmosphere/synthetic_set.rs): built-in mars-mean\n");
    s.push_str(&format!(
        "# x f(h) (f_below below 60 km, f_above above 80 km, smooth in ln rho between) x a seeded\n# perturbation (SPEC.md envelope x {}, seed {} + profile index). Profiles, in order:\n",
        spec.perturbation_scale, spec.seed
    ));
    for (i, p) in profiles.iter().enumerate() {
        s.push_str(&format!(
            "#   profile {i:>3}: f_above {:>4} f_below {:>4} ({})\n",
            p.case.factor_above,
            p.case.factor_below,
            p.case.season()
        ));
    }
    s.push_str("#      Var_X      DENSTOT       Radius\n");
    for p in profiles {
        for (&h, &rho) in p.altitude_m.iter().zip(&p.density) {
            s.push_str(&format!(
                "  {:>9.3}  {:>11.5E}  {:>11.4}\n",
                h / 1e3,
                rho,
                (sphere_radius_m + h) / 1e3
            ));
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atmosphere::mars_mean_profile;

    #[test]
    fn factor_is_f_below_low_f_above_high_and_monotone_between() {
        let c = SyntheticCase {
            factor_above: 3.0,
            factor_below: 0.7,
        };
        assert!((c.factor(0.0) - 0.7).abs() < 1e-15);
        assert!((c.factor(59_999.0) - 0.7).abs() < 1e-15);
        assert!((c.factor(80_000.0) - 3.0).abs() < 1e-12);
        assert!((c.factor(140_000.0) - 3.0).abs() < 1e-12);
        let mid = c.factor(70_000.0);
        assert!((mid - (0.7_f64 * 3.0).sqrt()).abs() < 1e-12, "{mid}");
        assert_eq!(c.season(), "dusty season");
    }

    #[test]
    fn set_is_deterministic_and_unperturbed_cases_are_exact_scalings() {
        let mean = mars_mean_profile();
        let spec = SyntheticSetSpec::default();
        let a = generate_synthetic_set(&mean, &spec).unwrap();
        assert_eq!(a, generate_synthetic_set(&mean, &spec).unwrap());
        assert_eq!(a.len(), 18);
        assert_eq!(a[0].altitude_m.len(), 151);
        let exact = SyntheticSetSpec {
            perturbation_scale: 0.0,
            ..spec.clone()
        };
        let b = generate_synthetic_set(&mean, &exact).unwrap();
        for p in &b {
            for (&h, &rho) in p.altitude_m.iter().zip(&p.density) {
                let want = p.case.factor(h) * mean.density(h);
                assert!((rho / want - 1.0).abs() < 1e-12);
            }
        }
        let bad = SyntheticSetSpec {
            cases: vec![SyntheticCase {
                factor_above: 0.0,
                factor_below: 1.0,
            }],
            ..spec
        };
        let e = generate_synthetic_set(&mean, &bad).unwrap_err().to_string();
        assert!(e.contains("cases[0].factor_above"), "{e}");
    }
}
