//! Synthetic test set of truth atmospheres for the density-adaptation filters (issue 15).
//!
//! Seed 001 §V flies USKF-NN through perturbed Mars-GRAM profiles and §I motivates the adaptive
//! density with seasonal and dust-storm variability. We cannot ship Mars-GRAM (docs/references.md), so this
//! generator builds a **synthetic** set spanning that variability around a mean profile ρ̄(h)
//! (the built-in `mars-mean`): case *i* scales the mean by a factor `f_above` above 80 km and
//! `f_below` below 60 km, smoothly in ln ρ in between,
//!
//! ln f(h) = ln f_below + (ln f_above − ln f_below)·s((h − 60 km)/20 km),  s(u) = 3u² − 2u³,
//!
//! and multiplies in one seeded realisation of the scenario perturbation ([`Perturbed`], the
//! perturbation envelope (docs/density.md) times `perturbation_scale`, seed `seed + i`). The default grid crosses
//! `f_above` ∈ {0.1, 0.3, 0.5, 1, 2, 3} with `f_below` ∈ {0.7, 1, 1.3}: cold / polar cases
//! (thin upper atmosphere, dense lower one), dusty seasons (dust-heated, expanded thermosphere
//! over a thinner lower atmosphere) and everything in between. These are **not** Mars-GRAM
//! output; they only bracket the ranges seed 001 and the issue name.
//!
//! **High-latitude cases** ([`SyntheticSetSpec::high_latitude`], issue 30). Seed 001 §V reports
//! its largest density errors at 80°N; polar winter atmospheres are cold (a smaller scale height:
//! density falls off faster with height), vary more, and have an upper atmosphere that differs from
//! the mean by a factor of a few either way. A case's `scale_height_factor` s < 1 steepens the
//! lower atmosphere about an anchor altitude h_a = 40 km (the band of peak deceleration of the MSL
//! entry): below 60 km the factor gains
//!
//! k(h) = (ρ̄(h)/ρ̄(h_a))^(1/s − 1),
//!
//! which turns every local scale height H(h) of the mean into s·H(h) (for an exponential mean,
//! exactly an exponential of scale height s·H), held at its 60 km value above that, blended out
//! with f_below over 60–80 km, so `f_above` stays the ratio to the mean above 80 km. Its
//! `perturbation_factor` multiplies the set's perturbation scale (2: the full envelope of docs/density.md for
//! the default scale 0.5). The high-latitude grid crosses s ∈ {0.75, 0.9} with
//! `f_above` ∈ {0.3, 1, 3} and `f_below` ∈ {1, 1.3}, perturbation ×2; [`SyntheticSetSpec::extended`]
//! is the standard 18 cases followed by these 12.
//!
//! [`generate_synthetic_set`] returns the profiles; [`synthetic_set_gram_text`] formats them as
//! a Mars-GRAM Monte Carlo set (a `#` header of `Var_X DENSTOT Radius`, stacked profiles), which
//! `atmosphere::parse_profiles` reads back. The core does no I/O: the CLI writes the text.

use super::density_model::Atmosphere;
use super::error::{AtmosphereError, check_closed, check_open};
use super::model::{AtmosphereModel, Perturbed};
use super::perturbation_spec::PerturbationSpec;
use super::profiles::MAX_PROFILES;
use super::synthetic_case::SyntheticCase;
use super::tabulated::Tabulated;

/// What to generate.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntheticSetSpec {
    /// The cases, in profile order.
    pub cases: Vec<SyntheticCase>,
    /// Seed of the perturbation of case i: `seed + i`.
    pub seed: u64,
    /// Multiplier of the perturbation envelope (docs/density.md) (0: the scaled means exactly).
    pub perturbation_scale: f64,
    /// Lowest and highest altitude of every profile (m).
    pub altitude_range_m: (f64, f64),
    /// Spacing of the rows (m).
    pub step_m: f64,
}

impl Default for SyntheticSetSpec {
    /// 18 cases: `f_above` ∈ {0.1, 0.3, 0.5, 1, 2, 3} × `f_below` ∈ {0.7, 1, 1.3}, seed 1, half the
    /// the docs/density.md perturbation, 0–150 km every 1 km.
    fn default() -> Self {
        let mut cases = Vec::new();
        for factor_above in [0.1, 0.3, 0.5, 1.0, 2.0, 3.0] {
            for factor_below in [0.7, 1.0, 1.3] {
                cases.push(SyntheticCase::scaled(factor_above, factor_below));
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

/// The 12 high-latitude cases of the module documentation: s ∈ {0.75, 0.9} × `f_above` ∈
/// {0.3, 1, 3} × `f_below` ∈ {1, 1.3}, perturbation ×2.
pub fn high_latitude_cases() -> Vec<SyntheticCase> {
    let mut cases = Vec::new();
    for scale_height_factor in [0.75, 0.9] {
        for factor_above in [0.3, 1.0, 3.0] {
            for factor_below in [1.0, 1.3] {
                cases.push(SyntheticCase {
                    factor_above,
                    factor_below,
                    scale_height_factor,
                    perturbation_factor: 2.0,
                });
            }
        }
    }
    cases
}

impl SyntheticSetSpec {
    /// The high-latitude set alone (12 cases, seed 1, scale 0.5 × each case's factor 2).
    pub fn high_latitude() -> Self {
        SyntheticSetSpec {
            cases: high_latitude_cases(),
            ..SyntheticSetSpec::default()
        }
    }

    /// The extended set: the standard 18 cases, then the 12 high-latitude ones (30 profiles;
    /// profile i keeps seed + i, so the first 18 equal the standard set's).
    pub fn extended() -> Self {
        let mut spec = SyntheticSetSpec::default();
        spec.cases.extend(high_latitude_cases());
        spec
    }

    /// Check the spec: 1 to 10 000 cases with factors in [0.01, 100], scale height factors in
    /// [0.5, 2], perturbation factors in [0, 10], scale in [0, 10] (and scale × factor ≤ 10), a
    /// range of at least three rows.
    pub fn validate(&self) -> Result<(), AtmosphereError> {
        if self.cases.is_empty() || self.cases.len() > MAX_PROFILES {
            return Err(AtmosphereError::InvalidField {
                field: "cases".to_string(),
                problem: format!(
                    "{} cases; between 1 and {} are allowed",
                    self.cases.len(),
                    MAX_PROFILES
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
            check_closed(
                &format!("cases[{i}].scale_height_factor"),
                c.scale_height_factor,
                0.5,
                2.0,
            )?;
            check_closed(
                &format!("cases[{i}].perturbation_factor"),
                c.perturbation_factor,
                0.0,
                10.0,
            )?;
            check_closed(
                &format!("cases[{i}].perturbation_factor x perturbation_scale"),
                c.perturbation_factor * self.perturbation_scale,
                0.0,
                10.0,
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
    let mut out = Vec::with_capacity(spec.cases.len());
    for (i, case) in spec.cases.iter().enumerate() {
        let seed = spec.seed.wrapping_add(i as u64);
        let pert = PerturbationSpec {
            grid_bottom_m: lo.min(0.0),
            grid_top_m: hi.max(150_000.0),
            scale: spec.perturbation_scale * case.perturbation_factor,
            ..PerturbationSpec::default()
        };
        let p = Perturbed::from_seed(AtmosphereModel::Tabulated(mean.clone()), &pert, seed)?;
        let altitude_m: Vec<f64> = (0..rows).map(|k| lo + k as f64 * spec.step_m).collect();
        let density = altitude_m
            .iter()
            .map(|&h| case.factor(mean, h) * p.density(h))
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
        "# x f(h) (f_below below 60 km, f_above above 80 km, smooth in ln rho between) x a seeded\n# perturbation (docs/density.md envelope x {}, seed {} + profile index). Profiles, in order:\n",
        spec.perturbation_scale, spec.seed
    ));
    if profiles.iter().any(|p| p.case.season() == "high latitude") {
        s.push_str(
            "# High-latitude cases: scale heights below 60 km x s about 40 km (blended out over\n# 60-80 km) and the perturbation scale x the case's factor.\n",
        );
    }
    for (i, p) in profiles.iter().enumerate() {
        s.push_str(&format!("#   profile {i:>3}: {}\n", p.case.describe()));
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
        let c = SyntheticCase::scaled(3.0, 0.7);
        let mean = mars_mean_profile();
        assert!((c.factor(&mean, 0.0) - 0.7).abs() < 1e-15);
        assert!((c.factor(&mean, 59_999.0) - 0.7).abs() < 1e-15);
        assert!((c.factor(&mean, 80_000.0) - 3.0).abs() < 1e-12);
        assert!((c.factor(&mean, 140_000.0) - 3.0).abs() < 1e-12);
        let mid = c.factor(&mean, 70_000.0);
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
                let want = p.case.factor(&mean, h) * mean.density(h);
                assert!((rho / want - 1.0).abs() < 1e-12);
            }
        }
        let bad = SyntheticSetSpec {
            cases: vec![SyntheticCase::scaled(0.0, 1.0)],
            ..spec.clone()
        };
        let e = generate_synthetic_set(&mean, &bad).unwrap_err().to_string();
        assert!(e.contains("cases[0].factor_above"), "{e}");
        let steep = SyntheticCase {
            scale_height_factor: 0.3,
            ..SyntheticCase::scaled(1.0, 1.0)
        };
        let bad = SyntheticSetSpec {
            cases: vec![steep],
            ..spec
        };
        let e = generate_synthetic_set(&mean, &bad).unwrap_err().to_string();
        assert!(e.contains("cases[0].scale_height_factor"), "{e}");
        assert!(e.contains("0.3"), "{e}");
    }

    /// A high-latitude case has s times the mean's scale heights below 60 km (ln ρ differences
    /// scaled by 1/s), equals the mean at the 40 km anchor and f_above above 80 km; the extended
    /// set starts with the standard set, profile for profile.
    #[test]
    fn high_latitude_cases_steepen_the_lower_atmosphere_and_extend_the_set() {
        let mean = mars_mean_profile();
        let spec = SyntheticSetSpec {
            perturbation_scale: 0.0,
            ..SyntheticSetSpec::high_latitude()
        };
        let set = generate_synthetic_set(&mean, &spec).unwrap();
        assert_eq!(set.len(), 12);
        for p in &set {
            let (s, c) = (p.case.scale_height_factor, p.case);
            assert!(s < 1.0 && c.perturbation_factor == 2.0);
            assert_eq!(c.season(), "high latitude");
            let rho = |h: f64| p.density[(h / 1000.0) as usize];
            assert!((rho(40_000.0) / mean.density(40_000.0) / c.factor_below - 1.0).abs() < 1e-12);
            for (a, b) in [(0.0, 20_000.0), (25_000.0, 55_000.0), (10_000.0, 60_000.0)] {
                let steep = (rho(a) / rho(b)).ln();
                let base = (mean.density(a) / mean.density(b)).ln();
                assert!((steep * s / base - 1.0).abs() < 1e-9, "{c:?} {a} {b}");
            }
            for h in [80_000.0, 120_000.0] {
                assert!((rho(h) / mean.density(h) / c.factor_above - 1.0).abs() < 1e-12);
            }
        }
        let std = generate_synthetic_set(&mean, &SyntheticSetSpec::default()).unwrap();
        let ext = generate_synthetic_set(&mean, &SyntheticSetSpec::extended()).unwrap();
        assert_eq!(ext.len(), 30);
        assert_eq!(&ext[..18], &std[..]);
        // Twice the perturbation: the spread of ln(ρ/deterministic) at 100 km over the 12 cases
        // is larger than over the standard set's 18.
        let spread = |ps: &[SyntheticProfile]| {
            let v: Vec<f64> = ps
                .iter()
                .map(|p| {
                    (p.density[100] / (p.case.factor(&mean, 100e3) * mean.density(100e3))).ln()
                })
                .collect();
            (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt()
        };
        assert!(
            spread(&ext[18..]) > 1.4 * spread(&std),
            "{} {}",
            spread(&ext[18..]),
            spread(&std)
        );
    }
}
