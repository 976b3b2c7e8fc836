//! `trade --grid FILE.toml`: scenarios × variations × filters in one study. The grid file
//! ([`mod@file`]), its cells ([`expand`]), running them ([`run`]) into rows ([`row`]) and the
//! documents of the results ([`documents`]: Markdown, CSV, JSON).

pub mod documents;
pub mod expand;
pub mod file;
pub mod row;
pub mod run;

pub use expand::GridCell;
pub use file::{GridFile, Variations};
pub use row::{CellDelivery, CellRow};
pub use run::{CellReport, GridOptions, GridResults, GridStop, GridStudy, run_grid};
