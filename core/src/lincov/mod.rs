//! Linear covariance analysis (LinCov) of the *actual* filter: the statistics of a filter's
//! estimation error, model mismatch included, in one pass instead of a Monte Carlo.
//!
//! A Kalman-type filter is linear in the truth, the noise and its own start given its gains, and
//! its gains come from its own onboard covariance alone. So the joint covariance of the truth
//! state x and the filter's estimate x̂ can be propagated exactly along the filter's schedule
//! (Maybeck, *Stochastic Models, Estimation and Control* vol. 1, Academic Press 1979, ch. 6
//! "design and performance analysis of Kalman filters"; Geller, "Linear covariance techniques for
//! orbital rendezvous analysis and autonomous onboard mission planning", J. Spacecraft Rockets
//! 43(6), 2006). The error e = x̂ − x then has the mean-square matrix a Monte Carlo of the same
//! filter would estimate, and the filter's own P says what it believes.
//!
//! [`linear`] is the exact form for linear truth and filter models (the reference a nonlinear
//! LinCov along a nominal trajectory is checked against).

pub mod linear;

pub use linear::{LinCovEpoch, LinearFilterModel, LinearLinCov, LinearTruthModel};
