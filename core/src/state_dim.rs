//! The one dimension switch: from a filter state dimension known at run time to code generic over
//! the dimension `N` (nalgebra's fixed-size `SVector<f64, N>` / `SMatrix<f64, N, N>`).
//!
//! Filters, observability and the simulation engine are written for a compile-time `N`; a
//! scenario's filter has 6 kinematic states plus its augmented constants and, for some filters,
//! bias states. [`with_state_dim`] is the only place where a run-time dimension becomes a type:
//! it covers [`MIN_STATE_DIM`]`..=`[`MAX_STATE_DIM`] and hands the visitor both `N` and `L = N + 1`
//! (the size of a filter that carries one internal augmented state beside the navigation states,
//! such as UKF-AC's correction factor or USKF-NN's consider parameter; stable Rust cannot write
//! `N + 1` in a generic position).

use thiserror::Error;

/// Smallest supported filter state dimension (the six kinematic states).
pub const MIN_STATE_DIM: usize = 6;
/// Largest supported filter state dimension.
pub const MAX_STATE_DIM: usize = 12;

/// A state dimension outside the supported range.
#[derive(Debug, Error, Clone, Copy, PartialEq, Eq)]
#[error(
    "filter state dimension {0} is not supported (supported: {MIN_STATE_DIM} to {MAX_STATE_DIM})"
)]
pub struct UnsupportedDimension(pub usize);

/// Code generic over the state dimension, run by [`with_state_dim`].
pub trait DimVisitor {
    /// What the visit returns.
    type Output;
    /// Run with state dimension `N`; `L` is always `N + 1`.
    fn visit<const N: usize, const L: usize>(self) -> Self::Output;
}

/// Run `visitor` with the compile-time dimension equal to `n`.
pub fn with_state_dim<V: DimVisitor>(
    n: usize,
    visitor: V,
) -> Result<V::Output, UnsupportedDimension> {
    Ok(match n {
        6 => visitor.visit::<6, 7>(),
        7 => visitor.visit::<7, 8>(),
        8 => visitor.visit::<8, 9>(),
        9 => visitor.visit::<9, 10>(),
        10 => visitor.visit::<10, 11>(),
        11 => visitor.visit::<11, 12>(),
        12 => visitor.visit::<12, 13>(),
        other => return Err(UnsupportedDimension(other)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Report;
    impl DimVisitor for Report {
        type Output = (usize, usize);
        fn visit<const N: usize, const L: usize>(self) -> (usize, usize) {
            (N, L)
        }
    }

    #[test]
    fn every_supported_dimension_reaches_its_type() {
        for n in MIN_STATE_DIM..=MAX_STATE_DIM {
            assert_eq!(with_state_dim(n, Report), Ok((n, n + 1)));
        }
        assert_eq!(with_state_dim(5, Report), Err(UnsupportedDimension(5)));
        assert_eq!(with_state_dim(13, Report), Err(UnsupportedDimension(13)));
    }
}
