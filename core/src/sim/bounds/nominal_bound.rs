//! A fast position bound for beacon design: the PCRLB along the *nominal* trajectory, with the
//! parts that do not depend on where the range beacons are computed once.
//!
//! **What it is.** The recursion of [`crate::pcrlb_recursion`] (Tichavský et al. 1998, eq. 21, in
//! the covariance form for a truth without process noise, Ristic et al. 2004 §4.2) on a single
//! truth run, the nominal one (no dispersions), with the prior P0 of the trade's bound
//! ([`super::pcrlb`]). The truth does not depend on the beacons, so the transitions F_k, the
//! information of every non-radio channel, the position map Jₚ and the vehicle position at each
//! epoch are computed once ([`NominalBound::new`]); a candidate set of range beacons then costs
//! only the recursion: per epoch P⁻ = F P Fᵀ, the non-radio information, and for each visible
//! beacon the rank-one update with ∇h = Jₚᵀu (u the unit vector beacon → vehicle, seed 002
//! eq. 36's line of sight), P ← P − P∇h ∇hᵀP / (∇hᵀP∇h + σ²) (Sherman–Morrison: the same
//! (P⁻¹ + ∇h∇hᵀ/σ²)⁻¹ as the information form). The bound on the `pos_m` RMSE is √tr(Jₚ P Jₚᵀ),
//! as in the trade's tables.
//!
//! **How it relates to the trade's bound.** For the scenario's own beacons it equals the trade's
//! recursion run on the nominal truth alone (tested to 1e-6); the trade averages F and I over its
//! dispersed Monte Carlo truths instead, so the two differ by the dispersion's effect on geometry
//! (a few per cent on the built-ins). Range epochs are those of the range sensor; a beacon
//! contributes where it sees the vehicle above its horizon (seed 002 eq. 52) and its elevation
//! mask, the engine's rule.
//! Range beacons are placed on the surface ([`NominalBound::ground_sites`]) or moving, e.g. on
//! orbits ([`NominalBound::moving_sites`], line of sight by eq. 58–60); range-rate channels are
//! refused.

use super::nominal_bound_error::NominalBoundError;
use super::nominal_epochs::{Collect, Epoch};
use crate::beacons::{ground_visibility_margin, orbiter_visibility_margin};
use crate::frames::rotate_z;
use crate::scenario::Scenario;
use crate::sensors::Channel;
use crate::sim::engine::{RecordedRun, simulate_truth};
use crate::state_dim::{DimVisitor, with_state_dim};
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;

/// A range beacon on the planet: planet-fixed position \[m\], range 1σ \[m\] and elevation mask.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RangeSite {
    /// Planet-fixed position \[m\].
    pub position_m: [f64; 3],
    /// Range noise 1σ \[m\].
    pub sigma_m: f64,
    /// Elevation mask \[rad\]: the site measures only above it (0: the horizon, eq. 52).
    pub elevation_mask_rad: f64,
}

/// The position bound per epoch for one set of sites.
#[derive(Debug, Clone, PartialEq)]
pub struct NominalBoundSeries {
    /// Epoch times \[s\].
    pub times_s: Vec<f64>,
    /// Bound on the position error 1σ \[m\] at each epoch.
    pub pos_m: Vec<f64>,
}

impl NominalBoundSeries {
    /// The bound averaged over epochs \[m\] (compare a trade's `rmse_time_avg.pos_m`).
    pub fn time_avg(&self) -> f64 {
        self.pos_m.iter().sum::<f64>() / self.pos_m.len().max(1) as f64
    }

    /// The bound at the last epoch \[m\] (compare `rmse_final.pos_m`).
    pub fn final_value(&self) -> f64 {
        self.pos_m.last().copied().unwrap_or(f64::NAN)
    }
}

/// The beacon-independent part of the nominal-trajectory bound of a scenario.
#[derive(Debug, Clone)]
pub struct NominalBound {
    n: usize,
    p0_diag: Vec<f64>,
    epochs: Vec<Epoch>,
    /// Planet rotation rate of the truth \[rad/s\] (planet-fixed ↔ inertial).
    omega: f64,
    /// Reference radius \[m\] (orbiter line of sight, seed 002 eq. 58–60).
    planet_radius: f64,
}

/// Range sites for the recursion: how many, their noise, and the unit vector site → vehicle
/// (planet-fixed) at an epoch where the site sees the vehicle.
trait Sites {
    fn len(&self) -> usize;
    fn sigma(&self, i: usize) -> f64;
    fn line_of_sight(&self, i: usize, k: usize, e: &Epoch, b: &NominalBound) -> Option<[f64; 3]>;
}

fn unit(d: [f64; 3]) -> Option<[f64; 3]> {
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    (len > 0.0).then(|| [d[0] / len, d[1] / len, d[2] / len])
}

impl Sites for [RangeSite] {
    fn len(&self) -> usize {
        <[RangeSite]>::len(self)
    }

    fn sigma(&self, i: usize) -> f64 {
        self[i].sigma_m
    }

    fn line_of_sight(&self, i: usize, _: usize, e: &Epoch, _: &NominalBound) -> Option<[f64; 3]> {
        let s = &self[i];
        let margin = ground_visibility_margin(&s.position_m, &e.vehicle_fixed);
        if margin - s.elevation_mask_rad <= 0.0 {
            return None;
        }
        unit([
            e.vehicle_fixed[0] - s.position_m[0],
            e.vehicle_fixed[1] - s.position_m[1],
            e.vehicle_fixed[2] - s.position_m[2],
        ])
    }
}

/// Moving sites (orbiters): inertial positions per site and epoch, with one range noise each.
struct Moving<'a> {
    sigma_m: &'a [f64],
    /// `positions[i][k]`: inertial position of site i at epoch k \[m\].
    positions: &'a [Vec<[f64; 3]>],
}

impl Sites for Moving<'_> {
    fn len(&self) -> usize {
        self.sigma_m.len()
    }

    fn sigma(&self, i: usize) -> f64 {
        self.sigma_m[i]
    }

    fn line_of_sight(&self, i: usize, k: usize, e: &Epoch, b: &NominalBound) -> Option<[f64; 3]> {
        let site = self.positions[i][k];
        let vehicle = rotate_z(&e.vehicle_fixed, b.omega * e.t);
        if orbiter_visibility_margin(&site, &vehicle, b.planet_radius) <= 0.0 {
            return None;
        }
        let d = [
            vehicle[0] - site[0],
            vehicle[1] - site[1],
            vehicle[2] - site[2],
        ];
        unit(rotate_z(&d, -b.omega * e.t))
    }
}

impl NominalBound {
    /// Fly the nominal truth of `scenario` (its beacons visible throughout, to find every range
    /// epoch) and store what the bound needs at each epoch.
    pub fn new(scenario: &Scenario) -> Result<NominalBound, NominalBoundError> {
        let name = || scenario.config.name.clone();
        let radio: Vec<Channel> = scenario.channels.iter().map(|c| c.channel).collect();
        if radio.iter().any(|c| matches!(c, Channel::RangeRate(_))) {
            return Err(NominalBoundError::RangeRate(name()));
        }
        if !radio.iter().any(|c| matches!(c, Channel::Range(_))) {
            return Err(NominalBoundError::NoRange(name()));
        }
        let mut every_epoch = scenario.clone();
        every_epoch.config.ignore_visibility = true;
        let draw = every_epoch.nominal_truth();
        // Noise values do not enter the bound (only which channels measure); any seed will do.
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0);
        let truth = simulate_truth(&every_epoch, &draw, &mut rng)?;
        let rec = RecordedRun {
            run: 0,
            draw,
            truth,
            x0: Vec::new(),
        };
        let n = scenario.onboard.state_dim();
        let epochs = with_state_dim(
            n,
            Collect {
                scenario,
                rec: &rec,
            },
        )??;
        let p0 = &scenario.onboard.tuning.p0_diag;
        let truth = &rec.draw.model;
        Ok(NominalBound {
            n,
            p0_diag: (0..n).map(|i| p0.get(i).copied().unwrap_or(1.0)).collect(),
            epochs,
            omega: truth.omega(),
            planet_radius: truth.planet.radius,
        })
    }

    /// The epoch times \[s\] (where [`Self::moving_sites`] wants the sites' positions).
    pub fn epoch_times(&self) -> Vec<f64> {
        self.epochs.iter().map(|e| e.t).collect()
    }

    /// The position bound with moving range beacons (orbiters): `positions[i][k]` is beacon i's
    /// inertial position \[m\] at epoch k of [`Self::epoch_times`], `sigma_m[i]` its range 1σ; a
    /// beacon contributes where the line to the vehicle clears the reference sphere (seed 002
    /// eq. 58–60, the engine's rule for orbiters).
    pub fn moving_sites(
        &self,
        sigma_m: &[f64],
        positions: &[Vec<[f64; 3]>],
    ) -> Result<NominalBoundSeries, NominalBoundError> {
        if sigma_m.len() != positions.len() {
            return Err(NominalBoundError::BadSite {
                index: sigma_m.len().min(positions.len()),
                position: [f64::NAN; 3],
                sigma: f64::NAN,
            });
        }
        for (index, (s, p)) in sigma_m.iter().zip(positions).enumerate() {
            let finite = p.iter().all(|x| x.iter().all(|v| v.is_finite()));
            if !(s.is_finite() && *s > 0.0 && finite && p.len() == self.epochs.len()) {
                return Err(NominalBoundError::BadSite {
                    index,
                    position: p.first().copied().unwrap_or([f64::NAN; 3]),
                    sigma: *s,
                });
            }
        }
        let sites = Moving { sigma_m, positions };
        with_state_dim(
            self.n,
            Evaluate {
                bound: self,
                sites: &sites,
            },
        )?
    }

    /// Number of epochs.
    pub fn epochs(&self) -> usize {
        self.epochs.len()
    }

    /// The position bound with range beacons at `sites` (planet-fixed, each seen above its
    /// horizon).
    pub fn ground_sites(
        &self,
        sites: &[RangeSite],
    ) -> Result<NominalBoundSeries, NominalBoundError> {
        for (index, s) in sites.iter().enumerate() {
            if !(s.position_m.iter().all(|v| v.is_finite())
                && s.sigma_m.is_finite()
                && s.sigma_m > 0.0
                && (0.0..std::f64::consts::FRAC_PI_2).contains(&s.elevation_mask_rad))
            {
                return Err(NominalBoundError::BadSite {
                    index,
                    position: s.position_m,
                    sigma: s.sigma_m,
                });
            }
        }
        with_state_dim(self.n, Evaluate { bound: self, sites })?
    }
}

/// Runs the recursion for one set of sites (dimension N).
struct Evaluate<'a, S: Sites + ?Sized> {
    bound: &'a NominalBound,
    sites: &'a S,
}

impl<S: Sites + ?Sized> DimVisitor for Evaluate<'_, S> {
    type Output = Result<NominalBoundSeries, NominalBoundError>;

    fn visit<const N: usize, const L: usize>(self) -> Self::Output {
        let b = self.bound;
        let mut p = SMatrix::<f64, N, N>::from_diagonal(&SVector::from_column_slice(&b.p0_diag));
        let mut series = NominalBoundSeries {
            times_s: Vec::with_capacity(b.epochs.len()),
            pos_m: Vec::with_capacity(b.epochs.len()),
        };
        for (k, e) in b.epochs.iter().enumerate() {
            let phi = SMatrix::<f64, N, N>::from_column_slice(&e.phi);
            p = phi * p * phi.transpose();
            if let Some(info) = &e.base {
                let info = SMatrix::<f64, N, N>::from_column_slice(info);
                p = posterior(&p, &info).ok_or(NominalBoundError::NonFinite(e.t))?;
            }
            let jp = SMatrix::<f64, 3, N>::from_column_slice(&e.jp);
            if e.ranged {
                for i in 0..self.sites.len() {
                    let Some(u) = self.sites.line_of_sight(i, k, e, b) else {
                        continue;
                    };
                    let u = rotate_z(&u, e.angle);
                    let u = nalgebra::Vector3::new(u[0], u[1], u[2]);
                    let g: SVector<f64, N> = jp.transpose() * u;
                    let pg = p * g;
                    let sigma = self.sites.sigma(i);
                    let s2 = g.dot(&pg) + sigma * sigma;
                    p -= pg * pg.transpose() / s2;
                }
            }
            p = (p + p.transpose()) * 0.5;
            let var = (jp * p * jp.transpose()).trace();
            if !var.is_finite() {
                return Err(NominalBoundError::NonFinite(e.t));
            }
            series.times_s.push(e.t);
            series.pos_m.push(var.max(0.0).sqrt());
        }
        Ok(series)
    }
}

/// (P⁻¹ + I)⁻¹ on the correlation scale of P (as [`crate::pcrlb_recursion`] does).
fn posterior<const N: usize>(
    prior: &SMatrix<f64, N, N>,
    info: &SMatrix<f64, N, N>,
) -> Option<SMatrix<f64, N, N>> {
    let d = SVector::<f64, N>::from_fn(|i, _| prior[(i, i)].sqrt());
    if d.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return None;
    }
    let corr = SMatrix::<f64, N, N>::from_fn(|i, j| prior[(i, j)] / (d[i] * d[j]));
    let info_scaled = SMatrix::<f64, N, N>::from_fn(|i, j| info[(i, j)] * d[i] * d[j]);
    let corr_inv = corr.cholesky()?.inverse();
    let inv = (corr_inv + info_scaled).cholesky()?.inverse();
    let p = SMatrix::<f64, N, N>::from_fn(|i, j| inv[(i, j)] * d[i] * d[j]);
    p.iter().all(|v| v.is_finite()).then_some(p)
}
