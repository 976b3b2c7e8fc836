//! Monte Carlo realisations of a scenario's truth world: the nominal one and run k's draw
//! (initial state, vehicle, density bias, atmosphere profile and perturbation).

use super::build::Scenario;
use super::config::StateConfig;
use super::validate::StateForm;
use crate::atmosphere::{AtmosphereModel, Perturbed};
use crate::dynamics::EntryModel;
use crate::frames::{inertial_to_spherical, spherical_to_inertial};
use nalgebra::SVector;
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

/// One Monte Carlo realisation of the truth world.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthDraw {
    /// Initial state in the truth model's coordinates.
    pub initial: SVector<f64, 6>,
    /// Truth model with dispersed vehicle, density bias and (if configured) perturbed atmosphere.
    pub model: EntryModel<AtmosphereModel>,
}

impl Scenario {
    /// The nominal truth realisation: the scenario's truth initial state and mean truth model,
    /// without dispersions.
    pub fn nominal_truth(&self) -> TruthDraw {
        TruthDraw {
            initial: self.truth_initial,
            model: self.truth_model.clone(),
        }
    }

    /// [`Scenario::draw_truth_run`] for run 0 (callers that know no run index: `simulate`, the
    /// FMUs; they fly profile 0 of a truth profile set, or its selected profile).
    pub fn draw_truth(&self, rng: &mut impl Rng) -> TruthDraw {
        self.draw_truth_run(0, rng)
    }

    /// Draw the truth realisation of Monte Carlo run `run` from `rng`: initial state, vehicle,
    /// density bias, atmosphere.
    ///
    /// The draws happen in a fixed order (initial state, C_D S/m, L/D, Δ, atmosphere) so that a
    /// seed reproduces a run exactly. With a truth table of stacked profiles the run's mean
    /// atmosphere is profile [`ProfileChoice::profile_for_run`](crate::atmosphere::ProfileChoice::profile_for_run) (k mod n: it depends only on the
    /// run index, so shards and threads agree); a configured perturbation is applied on it.
    pub fn draw_truth_run(&self, run: usize, rng: &mut impl Rng) -> TruthDraw {
        let mut draw = self.disperse_with(|| StandardNormal.sample(&mut *rng));
        if let Some(choice) = self.truth_profiles.as_ref().filter(|c| c.is_cycling()) {
            draw.model.atmosphere = choice.model_for_run(run);
        }
        if let Some(p) = &self.config.truth.perturbation {
            let spec = p.to_spec();
            draw.model.atmosphere = AtmosphereModel::Perturbed(Box::new(Perturbed::sample(
                draw.model.atmosphere,
                &spec,
                rng,
            )));
        }
        draw
    }

    /// How many standard normals [`Scenario::disperse_with`] takes: six for the initial state
    /// when `dispersions.initial` is given, then C_D S/m, L/D and Δ.
    pub fn dispersion_normals(&self) -> usize {
        let initial = self.config.dispersions.initial.as_ref();
        3 + if initial.is_some_and(|s| s.form("dispersions.initial").is_ok()) {
            6
        } else {
            0
        }
    }

    /// The truth realisation with the standard normals `z` (called
    /// [`Scenario::dispersion_normals`] times, in the order of [`Scenario::draw_truth_run`])
    /// applied to the initial state, C_D S/m, L/D and the density bias Δ, in the scenario's mean
    /// truth atmosphere (no profile cycling, no perturbation). LinCov differentiates the truth
    /// through it.
    pub fn disperse_with(&self, mut z: impl FnMut() -> f64) -> TruthDraw {
        let d = &self.config.dispersions;
        let mut initial = self.truth_initial;
        if let Some(sig) = &d.initial {
            initial = self.disperse_initial(sig, &mut z);
        }
        let mut model = self.truth_model.clone();
        model.vehicle.cd_s_over_m = (model.vehicle.cd_s_over_m + d.cd_s_over_m_m2kg * z())
            .max(1e-3 * model.vehicle.cd_s_over_m);
        model.vehicle.lift_to_drag = (model.vehicle.lift_to_drag + d.lift_to_drag * z()).max(0.0);
        let mut delta = self.config.truth.density_bias + d.density_bias * z();
        if d.density_bias_clip > 0.0 {
            delta = delta.clamp(-d.density_bias_clip, d.density_bias_clip);
        }
        model.density_factor = 1.0 + delta;
        TruthDraw { initial, model }
    }

    fn disperse_initial(&self, sig: &StateConfig, z: &mut impl FnMut() -> f64) -> SVector<f64, 6> {
        let kind = self.truth_model.kind;
        let omega = self.truth_model.omega();
        let nominal = self.truth_initial;
        let as_array = |v: &SVector<f64, 6>| -> [f64; 6] { [v[0], v[1], v[2], v[3], v[4], v[5]] };
        match sig.form("dispersions.initial") {
            Ok(StateForm::Spherical) => {
                let mut s = if kind.is_cartesian() {
                    inertial_to_spherical(
                        &[nominal[0], nominal[1], nominal[2]],
                        &[nominal[3], nominal[4], nominal[5]],
                        0.0,
                        omega,
                    )
                } else {
                    as_array(&nominal)
                };
                let sd = [
                    sig.radius_km.unwrap_or_default() * 1e3,
                    sig.lon_deg.unwrap_or_default().to_radians(),
                    sig.lat_deg.unwrap_or_default().to_radians(),
                    sig.speed_mps.unwrap_or_default(),
                    sig.fpa_deg.unwrap_or_default().to_radians(),
                    sig.heading_deg.unwrap_or_default().to_radians(),
                ];
                for k in 0..6 {
                    s[k] += sd[k] * z();
                }
                if kind.is_cartesian() {
                    let (p, v) = spherical_to_inertial(&s, 0.0, omega);
                    SVector::from([p[0], p[1], p[2], v[0], v[1], v[2]])
                } else {
                    SVector::from(s)
                }
            }
            Ok(StateForm::Cartesian) => {
                let (mut p, mut v) = if kind.is_cartesian() {
                    (
                        [nominal[0], nominal[1], nominal[2]],
                        [nominal[3], nominal[4], nominal[5]],
                    )
                } else {
                    spherical_to_inertial(&as_array(&nominal), 0.0, omega)
                };
                let sp = sig.position_km.unwrap_or_default();
                let sv = sig.velocity_mps.unwrap_or_default();
                for k in 0..3 {
                    p[k] += sp[k] * 1e3 * z();
                }
                for k in 0..3 {
                    v[k] += sv[k] * z();
                }
                if kind.is_cartesian() {
                    SVector::from([p[0], p[1], p[2], v[0], v[1], v[2]])
                } else {
                    SVector::from(inertial_to_spherical(&p, &v, 0.0, omega))
                }
            }
            Err(_) => nominal,
        }
    }
}
