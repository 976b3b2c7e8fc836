//! A scalar measurement linearised at a point ([`LinearizedMeasurement`]) and how far the
//! linearisation is off at another point ([`linearization_error`]), the test of the iterated
//! updates.

use nalgebra::SVector;

/// A linearised scalar measurement: `(h(x_prior), ∂h/∂x, z, r)`.
pub type LinearizedMeasurement<const N: usize> = (f64, SVector<f64, N>, f64, f64);

/// The largest linearisation error, in units of each measurement's σ, of `items` (linearised at
/// `lin`) at the point `x`: max |h(x) − h(lin) − H (x − lin)| / √r, where `at_x` are the same
/// measurements linearised at `x`.
pub fn linearization_error<const N: usize>(
    lin: &SVector<f64, N>,
    items: &[LinearizedMeasurement<N>],
    x: &SVector<f64, N>,
    at_x: &[LinearizedMeasurement<N>],
) -> f64 {
    let values: Vec<f64> = at_x.iter().map(|it| it.0).collect();
    linearization_error_values(lin, items, x, &values)
}

/// [`linearization_error`] from the measurement values `h(x)` alone.
pub fn linearization_error_values<const N: usize>(
    lin: &SVector<f64, N>,
    items: &[LinearizedMeasurement<N>],
    x: &SVector<f64, N>,
    at_x: &[f64],
) -> f64 {
    let dx = x - lin;
    items
        .iter()
        .zip(at_x)
        .map(|((h0, hrow, _, r), h1)| (h1 - h0 - hrow.dot(&dx)).abs() / r.sqrt())
        .fold(0.0, f64::max)
}
