//! One rendered figure and what it shows (the report groups figures by it).

/// What a figure shows (the report groups figures by it).
#[derive(Debug, Clone, PartialEq)]
pub enum Kind {
    /// RMSE of one state (or position/velocity) for every filter, with the PCRLB.
    Rmse,
    /// One filter's error of one state with its ±3σ envelope.
    ErrorSigma(String),
    /// Mean NEES with its χ² band.
    Nees,
    /// Mean NIS with its χ² band.
    Nis,
    /// One filter's NIS per measurement channel over time.
    ChannelNis(String),
    /// Density errors.
    Density,
    /// One filter's fusion weights or model probabilities.
    Weights(String),
    /// Final downrange/crossrange errors per run with the 3σ ellipse.
    Dispersion,
    /// Deployment misses per run with the 99 % ellipse (guidance in the loop).
    Delivery,
}

/// One rendered figure.
pub struct Figure {
    /// File name in `--plots DIR`.
    pub file: String,
    /// What it shows.
    pub kind: Kind,
    /// The SVG document.
    pub svg: String,
}
