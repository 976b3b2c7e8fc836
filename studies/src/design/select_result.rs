//! What the site selection returns: the candidates, the answer — certified by the relaxation
//! (and with `exact` proved by branch and bound), the branch and bound alone when the heuristic
//! failed, or a local search on the nominal bound — the answer as a scenario and its check.

use crate::design::check::{DesignCheck, verdict};
use crate::design::choices::SelectObjectiveName;
use crate::design::select_candidates::Candidates;
use crate::design::select_options::SelectOptions;
use crate::design::sites::chosen;
use crate::error::StudyResult;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::ground::{BoundSelection, LinCovSelection};
use entrynav_optimizer::{
    BranchBoundReport, LinCovFigures, Selection, SelectionCriterion, SelectionProblem,
    SelectionReport, Site,
};

/// The certified selection: the relaxation's bound, rounded, greedy and swap-improved
/// selections, the enumeration and (with `exact`) the branch and bound's proof.
#[derive(Debug, Clone)]
pub struct Certified {
    /// The selection problem (blocks, k, criterion, side constraints).
    pub problem: SelectionProblem,
    /// Candidate pairs closer than the minimum separation.
    pub close_pairs: usize,
    /// The relaxation and the heuristics.
    pub report: SelectionReport,
    /// The exact optimum by enumeration, when there are few enough k-subsets.
    pub brute: Option<Selection>,
    /// `exact`: the branch and bound.
    pub exact: Option<BranchBoundReport>,
    /// Each answer to certify, labelled.
    pub certified: Vec<(String, Selection)>,
}

impl Certified {
    /// The best bound known: the proof's, else the relaxation's. Gaps are measured from it.
    pub fn bound(&self) -> f64 {
        self.exact
            .as_ref()
            .map_or(self.report.relaxation.bound, |e| e.bound)
    }

    /// What the criterion's value is, in words (`eig_epochs`: the option).
    pub fn criterion_definition(&self, eig_epochs: Option<f64>) -> String {
        match (self.problem.criterion(), eig_epochs) {
            (SelectionCriterion::LogDet, _) => "ln det of the time-averaged unit-sigma range FIM \
                sum_i A_i, A_i = (1/T) integral n_i n_i^T dt (planet-fixed frame)"
                .to_string(),
            (SelectionCriterion::MinEig, None) => {
                "lambda_min of the time-averaged unit-sigma range FIM".to_string()
            }
            (SelectionCriterion::MinEig, Some(s)) => format!(
                "min over epochs every {s} s of lambda_min of the instantaneous unit-sigma FIM \
                 sum n n^T"
            ),
        }
    }

    /// The answer: the proof's, else the swap-improved heuristic.
    pub fn answer(&self) -> &Selection {
        self.exact
            .as_ref()
            .map_or(&self.report.improved, |e| &e.best)
    }
}

/// `exact` after the heuristic failed: the branch and bound alone.
#[derive(Debug, Clone)]
pub struct ExactOnly {
    /// The selection problem.
    pub problem: SelectionProblem,
    /// The exact optimum by enumeration, when there are few enough k-subsets.
    pub brute: Option<Selection>,
    /// The branch and bound.
    pub exact: BranchBoundReport,
}

/// `objective`: k sites chosen on the nominal position bound (greedy + exchanges, no
/// certificate), for lincov-* then exchanges on the filter's LinCov.
#[derive(Debug, Clone)]
pub struct OnBound {
    /// The objective.
    pub objective: SelectObjectiveName,
    /// The selection (indices and value: after the LinCov exchanges, if any).
    pub selection: BoundSelection,
    /// lincov-*: the filter, the input design's figures and the exchanges.
    pub lincov: Option<(FilterKind, Option<LinCovFigures>, LinCovSelection)>,
    /// Nominal position bound (time-averaged, final) \[m\] of the answer and of the input.
    pub bounds: [(f64, f64); 2],
}

impl OnBound {
    /// What the objective's value is: its units and meaning.
    pub fn units(&self) -> String {
        match &self.lincov {
            Some((f, _, _)) => self
                .objective
                .lincov()
                .map_or_else(String::new, |l| l.units(*f)),
            None => self.objective.ground().units(),
        }
    }
}

/// How the selection was answered.
#[derive(Debug, Clone)]
pub enum SelectionAnswer {
    /// Certified by the relaxation (and proved with `exact`).
    Certified(Box<Certified>),
    /// The branch and bound alone (`exact`, the heuristic failed).
    ExactOnly(ExactOnly),
    /// A local search on the nominal bound (`objective`).
    OnBound(OnBound),
}

/// A site selection.
#[derive(Debug, Clone)]
pub struct SiteSelection {
    /// The options it ran with.
    pub options: SelectOptions,
    /// The scenario's name.
    pub scenario: String,
    /// What the command line printed as `note: …` before its tables.
    pub notes: Vec<String>,
    /// The candidates.
    pub candidates: Candidates,
    /// The answer.
    pub answer: SelectionAnswer,
    /// The answer as a scenario configuration.
    pub design: ScenarioConfig,
    /// Its file text (what `--write-scenario` writes).
    pub design_toml: String,
    /// The check against the input design (`None`: skipped, or not run for
    /// [`SelectionAnswer::ExactOnly`]).
    pub check: Option<DesignCheck>,
    /// The worker threads it ran on.
    pub threads: usize,
    /// Wall time of the study \[s\].
    pub wall_s: f64,
}

impl SiteSelection {
    /// The indices of the chosen candidates.
    pub fn indices(&self) -> &[usize] {
        match &self.answer {
            SelectionAnswer::Certified(c) => &c.answer().indices,
            SelectionAnswer::ExactOnly(e) => &e.exact.best.indices,
            SelectionAnswer::OnBound(b) => &b.selection.indices,
        }
    }

    /// The chosen sites.
    pub fn sites(&self) -> Vec<Site> {
        chosen(&self.candidates.sites, self.indices())
    }

    /// The error to end with when the check found the answer worse than the input.
    pub fn verdict(&self) -> StudyResult<()> {
        verdict(self.check.as_ref())
    }
}
