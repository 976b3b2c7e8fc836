//! Why a figure or a page could not be drawn.

/// A drawing failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The plotting library refused a chart (`plot: …`).
    #[error("plot: {0}")]
    Plot(String),
    /// A drawing operation failed (the plotting library's own message).
    #[error("{0}")]
    Draw(String),
}

impl<E: std::error::Error + Send + Sync> From<plotters::drawing::DrawingAreaErrorKind<E>>
    for RenderError
{
    fn from(e: plotters::drawing::DrawingAreaErrorKind<E>) -> Self {
        RenderError::Draw(e.to_string())
    }
}

/// A drawing's result.
pub type Result<T> = std::result::Result<T, RenderError>;
