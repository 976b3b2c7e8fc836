//! Sums over Monte Carlo runs, one type per thing summed: [`Moments`] of one scalar, the sums of
//! one epoch ([`EpochSums`]) and of the final epoch ([`FinalSums`]). Each has `add` (one run's
//! value) and `merge` (another block's sums); runs are added and blocks merged in run order, so a
//! study's statistics do not depend on thread count or sharding. The RMSE, mean error and mean
//! |error| of the reports are these sums divided by their counts.

use super::run_record::EpochRecord;
use serde::{Deserialize, Serialize};

/// Count, Σx, Σ|x| and Σx² of one scalar over runs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Moments {
    /// Values added.
    pub n: u64,
    /// Σx.
    pub sum: f64,
    /// Σ|x|.
    pub sum_abs: f64,
    /// Σx².
    pub sum_sq: f64,
}

impl Moments {
    /// Add one value.
    pub fn add(&mut self, x: f64) {
        self.n += 1;
        self.sum += x;
        self.sum_abs += x.abs();
        self.sum_sq += x * x;
    }

    /// Add another block's sums.
    pub fn merge(&mut self, o: &Moments) {
        self.n += o.n;
        self.sum += o.sum;
        self.sum_abs += o.sum_abs;
        self.sum_sq += o.sum_sq;
    }

    /// Mean, if any value was added.
    pub fn mean(&self) -> Option<f64> {
        (self.n > 0).then(|| self.sum / self.n as f64)
    }

    /// Mean absolute value, if any value was added.
    pub fn mean_abs(&self) -> Option<f64> {
        (self.n > 0).then(|| self.sum_abs / self.n as f64)
    }

    /// Root mean square, if any value was added.
    pub fn rms(&self) -> Option<f64> {
        (self.n > 0).then(|| (self.sum_sq / self.n as f64).sqrt())
    }
}

/// One state's sums at one epoch: its error over the runs where it has a truth value, and the
/// filter's σ over the same runs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct StateSums {
    /// Moments of the estimation error.
    pub err: Moments,
    /// Σσ (the filter's predicted 1σ).
    pub sigma: f64,
}

/// Sums over the runs that reached one epoch.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EpochSums {
    /// Runs that reached the epoch.
    pub runs: u64,
    /// Per state.
    pub states: Vec<StateSums>,
    /// Σ of the squared position error norm \[m²\].
    pub pos_sq: f64,
    /// Σ of the squared velocity error norm \[m²/s²\].
    pub vel_sq: f64,
    /// Σ of the squared downrange, crossrange and up errors \[m²\].
    pub local_sq: [f64; 3],
    /// Relative error of the filter's density profile at the true altitude.
    pub density: Moments,
    /// Relative error of the filter's density at its estimate.
    pub density_at_estimate: Moments,
    /// Σ of the fusion weights / model probabilities.
    pub weights: Vec<f64>,
}

fn add_into(a: &mut Vec<f64>, b: &[f64]) {
    if a.len() < b.len() {
        a.resize(b.len(), 0.0);
    }
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
}

impl EpochSums {
    /// Add one run's record of this epoch.
    pub fn add(&mut self, e: &EpochRecord) {
        if self.states.len() < e.err.len() {
            self.states.resize(e.err.len(), StateSums::default());
        }
        for ((s, err), sigma) in self.states.iter_mut().zip(&e.err).zip(&e.sigma) {
            if err.is_finite() {
                s.err.add(*err);
                s.sigma += sigma;
            }
        }
        self.runs += 1;
        for (s, v) in self.local_sq.iter_mut().zip(e.local_err) {
            *s += v * v;
        }
        self.pos_sq += e.pos_vel_err.0 * e.pos_vel_err.0;
        self.vel_sq += e.pos_vel_err.1 * e.pos_vel_err.1;
        if let Some(d) = e.density_rel_err {
            self.density.add(d);
        }
        if let Some(d) = e.density_at_estimate_rel_err {
            self.density_at_estimate.add(d);
        }
        if let Some(w) = &e.weights {
            add_into(&mut self.weights, w);
        }
    }

    /// Add another block's sums of the same epoch.
    pub fn merge(&mut self, o: &EpochSums) {
        self.runs += o.runs;
        if self.states.len() < o.states.len() {
            self.states.resize(o.states.len(), StateSums::default());
        }
        for (s, t) in self.states.iter_mut().zip(&o.states) {
            s.err.merge(&t.err);
            s.sigma += t.sigma;
        }
        self.pos_sq += o.pos_sq;
        self.vel_sq += o.vel_sq;
        for (a, b) in self.local_sq.iter_mut().zip(o.local_sq) {
            *a += b;
        }
        self.density.merge(&o.density);
        self.density_at_estimate.merge(&o.density_at_estimate);
        add_into(&mut self.weights, &o.weights);
    }

    /// Root mean square over runs of a Σ of squares of this epoch.
    pub fn rms_of(&self, sum_sq: f64) -> Option<f64> {
        (self.runs > 0).then(|| (sum_sq / self.runs as f64).sqrt())
    }
}

/// Sums over the runs that reached their final epoch (parachute deployment) without failing.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct FinalSums {
    /// Runs.
    pub runs: u64,
    /// Moments of each state's final error (over the runs where it has a truth value).
    pub states: Vec<Moments>,
    /// Σ of the squared final position error norm \[m²\].
    pub pos_sq: f64,
    /// Σ of the squared final velocity error norm \[m²/s²\].
    pub vel_sq: f64,
    /// Σ of the squared final up error \[m²\].
    pub up_sq: f64,
    /// Σd, Σc, Σd², Σc², Σdc of the downrange d and crossrange c errors \[m\] (the deployment
    /// ellipse).
    pub dr_cr: [f64; 5],
}

impl FinalSums {
    /// Add a run's last epoch `last` with its deployment-point errors `(d, c)`.
    pub fn add(&mut self, last: &EpochRecord, (d, c): (f64, f64)) {
        self.runs += 1;
        if self.states.len() < last.err.len() {
            self.states.resize(last.err.len(), Moments::default());
        }
        for (s, e) in self.states.iter_mut().zip(&last.err) {
            if e.is_finite() {
                s.add(*e);
            }
        }
        self.pos_sq += last.pos_vel_err.0 * last.pos_vel_err.0;
        self.vel_sq += last.pos_vel_err.1 * last.pos_vel_err.1;
        self.up_sq += last.local_err[2] * last.local_err[2];
        for (s, v) in self.dr_cr.iter_mut().zip([d, c, d * d, c * c, d * c]) {
            *s += v;
        }
    }

    /// Add another block's sums.
    pub fn merge(&mut self, o: &FinalSums) {
        self.runs += o.runs;
        if self.states.len() < o.states.len() {
            self.states.resize(o.states.len(), Moments::default());
        }
        for (s, t) in self.states.iter_mut().zip(&o.states) {
            s.merge(t);
        }
        self.pos_sq += o.pos_sq;
        self.vel_sq += o.vel_sq;
        self.up_sq += o.up_sq;
        for (a, b) in self.dr_cr.iter_mut().zip(o.dr_cr) {
            *a += b;
        }
    }

    /// Root mean square over runs of a Σ of squares.
    pub fn rms_of(&self, sum_sq: f64) -> Option<f64> {
        (self.runs > 0).then(|| (sum_sq / self.runs as f64).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merging_blocks_equals_adding_in_order() {
        let xs = [1.5, -2.0, 0.25, 3.0, -0.5];
        let mut all = Moments::default();
        xs.iter().for_each(|&x| all.add(x));
        let (mut a, mut b) = (Moments::default(), Moments::default());
        xs[..2].iter().for_each(|&x| a.add(x));
        xs[2..].iter().for_each(|&x| b.add(x));
        a.merge(&b);
        assert_eq!(a.n, 5);
        assert!((a.sum - all.sum).abs() < 1e-15 && (a.sum_sq - all.sum_sq).abs() < 1e-12);
        assert_eq!(all.mean(), Some(2.25 / 5.0));
        assert_eq!(all.mean_abs(), Some(7.25 / 5.0));
        assert_eq!(Moments::default().rms(), None);
    }
}
