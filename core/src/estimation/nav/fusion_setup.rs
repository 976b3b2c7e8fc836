//! How a CI fusion is laid out: the channels of each local filter ([`local_masks`]), the CI
//! weighting with or without feedback ([`weighting`]) and the scale of the locals' start
//! ([`local_start_scale`]). LinCov's fusion recursion uses the same.

use crate::estimation::ci::CiWeighting;
use crate::estimation::onboard::Onboard;

/// The channel slots of each local filter: the non-radio channels (the IMU) plus the radio
/// channels of one beacon, one local per beacon with radio channels (seed 000 §3.4).
pub fn local_masks(onboard: &Onboard) -> Vec<Vec<usize>> {
    let of_beacon = |b: Option<usize>| -> Vec<usize> {
        (0..onboard.channels.len())
            .filter(|&i| onboard.channels[i].channel.beacon() == b)
            .collect()
    };
    let common = of_beacon(None);
    onboard
        .radio_beacons()
        .into_iter()
        .map(|b| [common.clone(), of_beacon(Some(b))].concat())
        .collect()
}

/// The CI weights of the fusion: determinant-optimal without feedback (`ci`), the fast ∞-norm
/// rule of seed 000 eq. 21 with it (`dcifaif`).
pub fn weighting(with_feedback: bool) -> CiWeighting {
    if with_feedback {
        CiWeighting::FastInfNorm
    } else {
        CiWeighting::OptimalDet
    }
}

/// The factor on P0 of every local filter's start: `n_locals` for the paper's feedback (the
/// equal-weight feedback of (x̂0, P0), eq. 22), 1 otherwise.
pub fn local_start_scale(n_locals: usize, with_feedback: bool, exact: bool) -> f64 {
    if with_feedback && !exact {
        n_locals as f64
    } else {
        1.0
    }
}
