//! How the observability matrix is computed ([`Method`]: exact Lie derivatives, their quadratic
//! approximation, or the linearised system) and the matrix by that method
//! ([`observability_matrix`]).

use super::approx::{linear_matrix, quadratic_matrix};
use super::error::ObservabilityError;
use super::lie::lie_matrix;
use super::system::ObservedSystem;
use nalgebra::{DMatrix, SVector};

/// How the observability matrix is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// Exact Lie derivatives up to order n − 1 (seed 002 eq. 12).
    Lie,
    /// Quadratic approximation of the Lie derivatives (seed 002 eq. 13–17).
    Quadratic,
    /// Linearised system (seed 002 eq. 19).
    Linear,
}

impl Method {
    /// Name used on the command line and in reports: `lie`, `quadratic`, `linear`.
    pub fn name(self) -> &'static str {
        match self {
            Method::Lie => "lie",
            Method::Quadratic => "quadratic",
            Method::Linear => "linear",
        }
    }

    /// Parse [`Method::name`].
    /// All methods, in listing order.
    pub const ALL: [Method; 3] = [Method::Lie, Method::Quadratic, Method::Linear];

    /// The method named `name` (the one parser of method names; [`FromStr`](std::str::FromStr)
    /// calls it).
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name.trim())
    }
}

impl std::str::FromStr for Method {
    type Err = ObservabilityError;

    fn from_str(name: &str) -> Result<Method, ObservabilityError> {
        Method::from_name(name).ok_or_else(|| {
            ObservabilityError::InvalidInput(format!(
                "unknown observability method '{name}'; valid methods are: {}",
                Method::ALL.map(Method::name).join(", ")
            ))
        })
    }
}

/// The observability matrix of `sys` at `x0` by `method`: `(n·m) × n`, rows grouped by Lie
/// order (`k·m + j` is order k of output j).
pub fn observability_matrix<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
    method: Method,
) -> DMatrix<f64> {
    match method {
        Method::Lie => lie_matrix(sys, x0),
        Method::Quadratic => quadratic_matrix(sys, x0),
        Method::Linear => linear_matrix(sys, x0),
    }
}
