//! Errors of the density-adaptation building blocks: network files, network parameters and the
//! offline training.

use crate::atmosphere::AtmosphereError;
use thiserror::Error;

/// Why a density network, a network file or the training cannot be used.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum NetworkError {
    /// A network without hidden neurons.
    #[error("the hidden layer needs at least one neuron")]
    NoHiddenNeurons,
    /// A parameter vector of the wrong length.
    #[error("{given} parameters given, a 1-{hidden}-1 network has {expected}")]
    ParameterCount {
        /// Parameters given.
        given: usize,
        /// Hidden neurons H.
        hidden: usize,
        /// 3H + 1.
        expected: usize,
    },
    /// A non-finite weight or bias.
    #[error("parameter {0} is not finite")]
    NonFiniteParameter(usize),
    /// A non-finite normalisation constant.
    #[error("{name} = {value} is not finite")]
    NonFiniteNormalisation {
        /// Which constant.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A normalisation standard deviation that is not positive.
    #[error("{name} = {value} must be a positive standard deviation")]
    BadStandardDeviation {
        /// Which constant.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A network record whose layers do not fit together.
    #[error("w_in, b_in and w_out must have the same length (got {w_in}, {b_in}, {w_out})")]
    LayerLengths {
        /// Length of `w_in`.
        w_in: usize,
        /// Length of `b_in`.
        b_in: usize,
        /// Length of `w_out`.
        w_out: usize,
    },
    /// A network file that is not valid TOML or does not match the format.
    #[error("{source_name}: {message}")]
    Parse {
        /// File name.
        source_name: String,
        /// The parser's message.
        message: String,
    },
    /// A network file of another format version.
    #[error("{source_name}: format = '{found}', expected '{expected}'")]
    Format {
        /// File name.
        source_name: String,
        /// Format found.
        found: String,
        /// Format expected.
        expected: &'static str,
    },
    /// A network file without networks.
    #[error("the file holds no network")]
    Empty,
    /// A non-positive planet radius.
    #[error("planet_radius_m = {0} must be positive")]
    PlanetRadius(f64),
    /// An altitude band that is not increasing.
    #[error("networks[{index}].altitude_band_km = [{lo}, {hi}] must be increasing")]
    BandOrder {
        /// Network index.
        index: usize,
        /// Band bottom \[km\].
        lo: f64,
        /// Band top \[km\].
        hi: f64,
    },
    /// Bands that are not contiguous.
    #[error(
        "networks[{index}] starts at {lo} km but networks[{previous}] ends at {previous_top} km: bands must be contiguous"
    )]
    BandGap {
        /// Network index.
        index: usize,
        /// Its band bottom \[km\].
        lo: f64,
        /// The previous network's index.
        previous: usize,
        /// The previous band's top \[km\].
        previous_top: f64,
    },
    /// A problem inside one network of a file.
    #[error("networks[{index}]: {source}")]
    InNetwork {
        /// Network index.
        index: usize,
        /// The problem.
        source: Box<NetworkError>,
    },
    /// A problem inside a named file.
    #[error("{source_name}: {source}")]
    InFile {
        /// File name.
        source_name: String,
        /// The problem.
        source: Box<NetworkError>,
    },
    /// `filter.density.network` names no built-in network file.
    #[error(
        "filter.density.network = '{name}' is not a built-in network file (built-ins: {known})"
    )]
    UnknownNetwork {
        /// Name asked for.
        name: String,
        /// Comma-separated built-in names.
        known: String,
    },
    /// A network trained for another planet radius.
    #[error(
        "network file '{name}' was trained for planet radius {trained} m but the scenario uses {used} m"
    )]
    PlanetMismatch {
        /// Network file name.
        name: String,
        /// Radius it was trained for \[m\].
        trained: f64,
        /// The onboard planet radius \[m\].
        used: f64,
    },
    /// Too few samples to train on.
    #[error("only {0} training samples; need at least 10")]
    TooFewSamples(usize),
    /// The least-squares exponential fit failed.
    #[error(transparent)]
    Fit(#[from] AtmosphereError),
}
