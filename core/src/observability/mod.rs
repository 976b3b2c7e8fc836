//! Observability of the entry navigation system and Fisher information of radio beacons.
//!
//! * [`lie`] — the nonlinear observability matrix O_Σ of seed 002 eq. 12 (seed 000 eq. 11) from
//!   the **exact** Lie derivatives up to order n − 1, by Taylor-mode forward AD over [`Jet`]s
//!   (no symbolic algebra, no finite differences);
//! * [`approx`] — the **quadratic** approximation (seed 002 eq. 13–17) and the **linearised**
//!   matrix (eq. 18–19);
//! * [`degree()`] — δ = σ_min/σ_max by SVD (seed 000 eq. 14, seed 002 eq. 21), its numerical rank,
//!   and the unit scaling: every δ is reported **raw (SI)** and **scaled** (see [`Scaling`]);
//! * [`system`] / [`trajectory`] — the scenario's filter model and channels as an
//!   [`ObservedSystem`], the analysis points on the nominal truth trajectory, and δ(t) for the
//!   centralised system and the IMU + one-beacon subsystems of seed 000 §2.3.3;
//! * [`fisher`] / [`geometry`] — range and range-rate FIM (seed 002 eq. 25, 36, 42–45), det/trace
//!   bounds (eq. 27–28, 37–41), geometry index I (eq. 54), the best N-beacon geometry (Table 1)
//!   and the range FIM along a trajectory;
//!
//! An unobservable configuration (one beacon, rank-deficient O) gives δ = 0 with its rank —
//! never NaN; non-finite inputs are errors ([`ObservabilityError`]).

pub mod approx;
pub mod degree;
pub mod error;
pub mod fisher;
pub mod geometry;
pub mod jet;
mod jet_math;
pub mod lie;
pub mod method;
pub mod system;
pub mod trajectory;

pub use approx::{linear_matrix, quadratic_matrix};
pub use degree::{Degree, Scaling, degree};
pub use error::ObservabilityError;
pub use fisher::{FimSummary, geometry_index, max_det_bound};
pub use geometry::{FimEpoch, MaxDet, max_det_directions, range_fim_series};
pub use jet::Jet;
pub use lie::{LieDerivatives, lie_derivatives, lie_matrix};
pub use method::{Method, observability_matrix};
pub use system::{AnalysisPoint, ObservedSystem, ScenarioSystem, analysis_points};
pub use trajectory::{ChannelSet, DegreeSample, DegreeSeries, DeltaSummary, degree_series};
