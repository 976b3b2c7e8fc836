//! Running a grid ([`GridStudy`]): cell by cell, a Monte Carlo of the filters that fit (or LinCov
//! of each, `method = lincov`), with the minimum observability degree of the cell's nominal
//! entry, each finished cell's rows and report handed to the caller at once so that an
//! interrupted grid keeps them.

use crate::error::{StudyError, StudyResult};
use crate::grid::expand::{GridCell, expand};
use crate::grid::file::GridFile;
use crate::grid::row::{CellRow, cell_deliveries};
use crate::progress::{Progress, Step};
use crate::trade::options::Method;
use entrynav::estimation::nav::FilterKind;
use entrynav::observability::{
    ChannelSet, Method as DegreeMethod, Scaling, analysis_points, degree_series,
};
use entrynav::scenario::Scenario;
use entrynav::sim::{McOptions, TradeReport, run_trade};
use entrynav_loader as load;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Seconds between the result hand-overs of a LinCov grid (a cell takes milliseconds).
const LINCOV_UPDATE_EVERY_S: f64 = 5.0;

/// The options of a grid beside its file: how every cell is computed.
#[derive(Debug, Clone, Default, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GridOptions {
    /// `mc` (a Monte Carlo of the file's runs per cell) or `lincov`; `both` is refused.
    pub method: Method,
}

impl GridOptions {
    /// Refuse `method = both` (a grid runs one method).
    pub fn validate(&self) -> StudyResult<()> {
        if self.method == Method::Both {
            return Err(StudyError::Refused(
                "--method both with --grid: a grid runs one method: mc or lincov".into(),
            ));
        }
        Ok(())
    }
}

/// A grid file, read, checked and expanded into its cells.
pub struct GridStudy {
    /// The grid file.
    pub file: GridFile,
    /// Its cells, in order.
    pub cells: Vec<GridCell>,
    /// How every cell is computed: `mc` or `lincov`.
    pub method: Method,
}

impl GridStudy {
    /// Read the grid file `path` (its scenario and beacon files relative to its folder) and
    /// expand it.
    pub fn load(path: &Path, options: &GridOptions) -> StudyResult<GridStudy> {
        options.validate()?;
        let text = load::read_text(path).map_err(|e| {
            StudyError::Refused(format!("cannot read grid file {}: {e}", path.display()))
        })?;
        let file = GridFile::from_toml(&text)
            .map_err(|e| e.context(format!("grid file {}", path.display())))?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let cells = expand(&file, dir)?;
        Ok(GridStudy {
            file,
            cells,
            method: options.method,
        })
    }

    /// Whether every cell is computed by LinCov.
    pub fn lincov(&self) -> bool {
        self.method == Method::Lincov
    }
}

/// One finished cell's Monte Carlo report.
#[derive(Debug, Clone)]
pub struct CellReport {
    /// Cell label.
    pub cell: String,
    /// The cell scenario's fingerprint.
    pub scenario_fingerprint: String,
    /// Its statistics.
    pub report: TradeReport,
}

/// Where an interrupted grid stopped.
#[derive(Debug, Clone)]
pub struct GridStop {
    /// Cells finished (and in the results).
    pub cells_done: usize,
    /// The cell cut short, with its runs finished and asked: it is not in the results.
    pub dropped: Option<(String, usize, usize)>,
}

/// A grid's results so far.
#[derive(Debug, Clone, Default)]
pub struct GridResults {
    /// One row per cell and filter.
    pub rows: Vec<CellRow>,
    /// The Monte Carlo report of every finished cell.
    pub reports: Vec<CellReport>,
    /// What went wrong beside the statistics (no delivery in a cell), without `warning: `.
    pub warnings: Vec<String>,
    /// Set when the grid was cancelled.
    pub stopped: Option<GridStop>,
}

impl GridResults {
    /// The error an interrupted grid ends in, naming where its results are (`place`).
    pub fn interruption(&self, cells_total: usize, place: &str) -> Option<StudyError> {
        let s = self.stopped.as_ref()?;
        let dropped = s
            .dropped
            .as_ref()
            .map_or(String::new(), |(cell, done, runs)| {
                format!(" (cell {cell} dropped after {done} of {runs} runs)")
            });
        Some(StudyError::Interrupted(format!(
            "{} of {cells_total} cells in {place}{dropped}",
            s.cells_done
        )))
    }
}

/// The minimum scaled observability degree δ of the centralised system along the nominal
/// entry (about 50 ms a cell, by Lie derivatives).
fn min_delta(scenario: &Scenario) -> Option<f64> {
    let pts = analysis_points(scenario, 1.0).ok()?;
    let channels = ChannelSet::centralised(scenario);
    let scaling = Scaling::characteristic(scenario.filter_model());
    let series = degree_series(scenario, &pts, &channels, DegreeMethod::Lie, &scaling).ok()?;
    series.summary(true).map(|s| s.min)
}

/// Run every cell of `study`; `progress` gets a `cells` step as each cell starts (its task
/// says the cell, its scenario and variation, and what runs), `on_results` the results after
/// every finished Monte Carlo cell (every few seconds in a LinCov grid). Stops when `cancel` is
/// set: the results keep the finished cells and say where it stopped ([`GridResults::stopped`]).
pub fn run_grid<E: From<StudyError>>(
    study: &GridStudy,
    cancel: Option<&'static AtomicBool>,
    progress: Progress,
    mut on_results: impl FnMut(&GridResults) -> Result<(), E>,
) -> Result<GridResults, E> {
    let grid = &study.file;
    let total = study.cells.len();
    let mut out = GridResults::default();
    let mut handed = Instant::now();
    for (i, cell) in study.cells.iter().enumerate() {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            out.stopped = Some(GridStop {
                cells_done: i,
                dropped: None,
            });
            return Ok(out);
        }
        let scenario = load::build(cell.config.clone(), &cell.dir).map_err(StudyError::from)?;
        let mut fit = Vec::new();
        for name in &grid.filters {
            let k = FilterKind::parse(name).map_err(|e| StudyError::Refused(e.to_string()))?;
            match k.misfit(&scenario.onboard) {
                None => fit.push(k),
                Some(reason) => out.rows.push(CellRow {
                    refused: Some(reason),
                    ..CellRow::empty(&cell.label, &scenario, &cell.variation, name)
                }),
            }
        }
        // The observability column costs ~50 ms a cell (Lie derivatives by jets), five LinCovs'
        // worth: a LinCov grid leaves it out (`observe` gives it per scenario).
        let min_delta = (!study.lincov()).then(|| min_delta(&scenario)).flatten();
        let what = if study.lincov() {
            "LinCov".to_string()
        } else {
            format!("{} runs", grid.runs)
        };
        let task = format!(
            "{} {} ({}): {} filters × {what}",
            cell.label,
            scenario.config.name,
            cell.variation,
            fit.len()
        );
        progress(Step::of("cells", &task, i as u64, total as u64));
        if fit.is_empty() {
            continue;
        }
        let row = |name: &str| CellRow {
            min_delta_scaled: min_delta,
            ..CellRow::empty(&cell.label, &scenario, &cell.variation, name)
        };
        if study.lincov() {
            for &k in &fit {
                out.rows.push(row(k.name()).lincov(&scenario, k));
            }
            if handed.elapsed().as_secs_f64() > LINCOV_UPDATE_EVERY_S {
                on_results(&out)?;
                handed = Instant::now();
            }
            continue;
        }
        let opts = McOptions {
            cancel,
            ..McOptions::new(grid.runs, grid.seed)
        };
        let report = run_trade(&scenario, &fit, &opts, &|_| {}).map_err(StudyError::from)?;
        if !report.complete {
            // The cell was cut short: the results keep the cells finished before it.
            let dropped = (cell.label.clone(), report.runs_completed, report.runs);
            out.stopped = Some(GridStop {
                cells_done: i,
                dropped: Some(dropped),
            });
            return Ok(out);
        }
        let deliveries = cell_deliveries(&scenario, &fit, grid.runs, grid.seed)
            .map_err(|w| out.warnings.push(w))
            .ok()
            .flatten();
        for f in &report.filters {
            let delivery = deliveries
                .as_ref()
                .and_then(|d| d.iter().find(|(n, _)| *n == f.name))
                .map(|(_, d)| d.clone());
            out.rows.push(row(&f.name).monte_carlo(f, delivery));
        }
        out.reports.push(CellReport {
            cell: cell.label.clone(),
            scenario_fingerprint: entrynav::sim::monte_carlo::shard::scenario_fingerprint(
                &scenario,
            ),
            report,
        });
        // Each finished cell is in the results at once, so an interrupted grid keeps them.
        on_results(&out)?;
    }
    Ok(out)
}
