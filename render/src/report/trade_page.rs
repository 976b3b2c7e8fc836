//! The HTML report of one trade study (`trade --report FILE.html`): summary and consistency
//! verdicts, RMSE beside the PCRLB, per-state errors with ±3σ, NEES/NIS with χ² bands, fusion
//! weights and model probabilities, the deployment dispersion, the delivery at deployment with
//! guidance in the loop (a scenario with `[guidance]`), LinCov beside the Monte Carlo
//! (`--method both`), provenance; a table of contents first.

use super::html::{self, Cell, escape, figures, note, section};
use super::summary;
use crate::figure::{Figure, Kind};
use entrynav::sim::TradeReport;
use entrynav_studies::provenance::{Provenance, Timing};
use entrynav_studies::trade::expected::bad_runs_line;
use entrynav_studies::trade::lincov_comparison::{LinCovComparison, figures as compared};

/// What a trade report shows besides the statistics.
pub struct TradePage<'a> {
    /// The statistics.
    pub report: &'a TradeReport,
    /// The figures of `report` (`plots::trade_figures`).
    pub figures: &'a [Figure],
    /// Where it came from.
    pub provenance: &'a Provenance,
    /// Wall time of the study (s).
    pub wall_s: f64,
    /// LinCov beside the Monte Carlo (`trade --method both`).
    pub lincov: Option<&'a LinCovComparison>,
    /// Delivery at deployment with guidance in the loop (a scenario with `[guidance]`).
    pub delivery: Option<&'a entrynav::sim::guided::delivery::DeliveryReport>,
}

fn svgs(figs: &[Figure], keep: impl Fn(&Kind) -> bool) -> Vec<&str> {
    figs.iter()
        .filter(|f| keep(&f.kind))
        .map(|f| f.svg.as_str())
        .collect()
}

impl TradePage<'_> {
    fn summary(&self) -> String {
        let r = self.report;
        let status = if r.complete {
            format!("{} runs", r.runs_completed)
        } else {
            format!(
                "INTERRUPTED: {} of {} runs completed (partial results)",
                r.runs_completed, r.runs
            )
        };
        let filters: Vec<&str> = r.filters.iter().map(|f| f.name.as_str()).collect();
        let mut s = format!(
            "<p class=\"recommendation\"><b>Recommendation:</b> {}</p>\n",
            escape(&summary::recommendation(r))
        );
        s += &format!(
            "<p>Scenario <b>{}</b>, filters <b>{}</b>, {}, seed {}, {:.2} s wall.</p>\n",
            escape(&r.scenario),
            escape(&filters.join(", ")),
            escape(&status),
            r.seed,
            self.wall_s
        );
        s += &note(
            "Verdicts compare each filter's average NEES (and NIS) over epochs with the two-sided \
             95 % χ² band of a per-epoch mean over the runs: above the band the filter is \
             optimistic (its σ is too small for its errors), below it pessimistic.",
        );
        s += &summary::consistency_table(r);
        for f in &r.filters {
            let problems = entrynav_studies::diagnosis::diagnose(f, &r.states);
            if !problems.is_empty() && !entrynav_studies::trade::expected::mostly_bad(f) {
                s += &format!(
                    "<p class=\"warn\">{}: {}</p>\n",
                    escape(&f.name),
                    escape(&problems.join("; "))
                );
            }
            if let Some(line) = bad_runs_line(f) {
                let class = if line.starts_with("WARNING") {
                    "bad"
                } else {
                    "note"
                };
                s += &format!(
                    "<p class=\"{class}\">{}: {}</p>\n",
                    escape(&f.name),
                    escape(&line)
                );
            }
        }
        s
    }

    /// LinCov's prediction beside the Monte Carlo, per filter and figure, with the Monte
    /// Carlo's 95 % interval and, where LinCov falls outside it, the reason (the CLI's table).
    fn lincov(&self, c: &LinCovComparison) -> String {
        let mut s = note(
            "Per filter: LinCov's first-order prediction along the nominal trajectory beside the \
             Monte Carlo, their ratio and the Monte Carlo's 95 % sampling interval; ! marks a \
             figure outside it. LinCov's RMSE curves are drawn dashed in the RMSE charts, in \
             their filter's colour.",
        );
        for a in &c.analysed {
            let Some(f) = self
                .report
                .filters
                .iter()
                .find(|f| f.name == a.lincov.filter)
            else {
                continue;
            };
            s += &format!(
                "<h3 id=\"lincov-{}\">{} ({} runs; LinCov {:.3} s)</h3>\n",
                escape(&f.name),
                escape(&f.name),
                f.runs,
                a.seconds
            );
            for n in &a.lincov.notes {
                s += &note(n);
            }
            let rows = compared(a, f);
            let cells: Vec<Vec<Cell>> = rows
                .iter()
                .map(|r| {
                    let flag = if r.disagrees() {
                        Cell {
                            text: "!".into(),
                            class: "warn",
                        }
                    } else {
                        Cell::text("")
                    };
                    vec![
                        Cell::text(r.figure.clone()),
                        Cell::num(html::num(Some(r.lincov))),
                        Cell::num(html::num(Some(r.mc))),
                        Cell::num(format!("{:.3}", r.ratio())),
                        Cell::num(format!(
                            "{} .. {}",
                            html::num(Some(r.mc - r.half)),
                            html::num(Some(r.mc + r.half))
                        )),
                        flag,
                    ]
                })
                .collect();
            s += &html::table(
                &[
                    "figure",
                    "LinCov",
                    "Monte Carlo",
                    "ratio",
                    "MC 95 % interval",
                    "",
                ],
                &cells,
            );
            if let Some(why) = entrynav_studies::trade::expected::lincov_disagreement(f, &rows) {
                s += &format!("<p class=\"warn\">Warning: {}</p>\n", escape(&why));
            }
        }
        s
    }

    fn rmse(&self) -> String {
        let mut s = match &self.report.pcrlb {
            Some(b) if b.available => note(&format!(
                "The PCRLB is the posterior Cramér–Rao lower bound of any estimator's RMSE on this \
                 scenario (dashed in the plots); prior: {}.",
                b.prior
            )),
            Some(b) => note(&format!(
                "PCRLB not available: {}",
                b.reason.as_deref().unwrap_or("unknown reason")
            )),
            None => note("No PCRLB in this study."),
        };
        s += &summary::rmse_table(self.report);
        s += &figures(svgs(self.figures, |k| *k == Kind::Rmse));
        s
    }

    fn errors(&self) -> String {
        let mut s = note(
            "Per filter and state: RMSE and mean error over runs against the mean predicted \
             ±3σ envelope.",
        );
        for f in &self.report.filters {
            s += &format!(
                "<h3 id=\"errors-{}\">{}</h3>\n",
                escape(&f.name),
                escape(&f.name)
            );
            s += &summary::state_table(self.report, f);
            s += &figures(svgs(
                self.figures,
                |k| matches!(k, Kind::ErrorSigma(n) if *n == f.name),
            ));
        }
        s
    }

    fn weights(&self) -> String {
        let figs = svgs(self.figures, |k| matches!(k, Kind::Weights(_)));
        if figs.is_empty() {
            return note("No filter of this study fuses local filters or runs a model bank.");
        }
        let mut s = note(
            "Mean over runs of the CI fusion weight of each beacon's local filter (ci, dcifaif) \
             and of the model probabilities (mmae, mmae-moe).",
        );
        s += &figures(figs);
        s
    }

    /// The innovation gate, for studies whose filters run behind one (`[filter.gating]`).
    fn gating(&self) -> Option<String> {
        let gated: Vec<_> = self
            .report
            .filters
            .iter()
            .filter_map(|f| f.gating.as_ref().map(|g| (f, g)))
            .collect();
        if gated.is_empty() {
            return None;
        }
        let pct = |v: f64| format!("{:.3} %", 100.0 * v);
        let opt = |v: Option<f64>, unit: &str| {
            v.map(|v| format!("{v:.3}{unit}"))
                .unwrap_or_else(|| "-".into())
        };
        let mut s = note(
            "Every filter ran behind a χ² innovation gate: a measurement whose ν²/S at the \
             filter's prior exceeds the gate is rejected, a beacon outside the gate at several \
             consecutive epochs is excluded until it is back inside. A consistent filter without \
             faults rejects 1 − p of its measurements and excludes nobody. The same study with \
             --set filter.gating.enabled=false shows the filters without the gate.",
        );
        let rows: Vec<Vec<Cell>> = gated
            .iter()
            .map(|(f, g)| {
                vec![
                    Cell::text(f.name.clone()),
                    Cell::num(pct(g.rejected_frac)),
                    Cell::num(opt(g.anis_before_gating_per_dof, "")),
                    Cell::num(opt(f.consistency.anis_per_dof, "")),
                    Cell::num(pct(g.false_exclusion_run_frac)),
                ]
            })
            .collect();
        s += &html::table(
            &[
                "filter",
                "rejected",
                "ANIS/dof before the gate",
                "ANIS/dof after",
                "runs with a false exclusion",
            ],
            &rows,
        );
        let beacons: Vec<Vec<Cell>> = gated
            .iter()
            .flat_map(|(f, g)| {
                g.per_beacon.iter().map(move |(b, e)| {
                    vec![
                        Cell::text(format!("{} / {b}", f.name)),
                        Cell::num(format!("{} of {}", e.detected_runs, g.runs)),
                        Cell::num(
                            e.detected_within_10s_frac
                                .map(|v| format!("{:.1} %", 100.0 * v))
                                .unwrap_or_else(|| "-".into()),
                        ),
                        Cell::num(opt(e.detection_mean_s, " s")),
                        Cell::num(opt(e.detection_max_s, " s")),
                        Cell::num(e.false_exclusion_runs.to_string()),
                    ]
                })
            })
            .collect();
        if !beacons.is_empty() {
            s += &html::table(
                &[
                    "filter / beacon",
                    "excluded after its fault",
                    "within 10 s",
                    "mean delay",
                    "longest",
                    "false exclusions (runs)",
                ],
                &beacons,
            );
        }
        Some(s)
    }

    fn dispersion(&self) -> String {
        let mut s = note(
            "Every run's final position error resolved along (downrange) and across \
             (crossrange) the true heading, with each filter's 3σ ellipse.",
        );
        s += &summary::ellipse_table(self.report);
        s += &figures(svgs(self.figures, |k| *k == Kind::Dispersion));
        s
    }

    fn provenance(&self) -> String {
        let v = serde_json::json!({
            "provenance": self.provenance,
            "timing": Timing::of(self.report, self.wall_s),
            "atmosphere": self.report.atmosphere,
        });
        html::json_block(&v)
    }

    /// The page: a table of contents, then the sections.
    pub fn html(&self) -> String {
        let r = self.report;
        // (anchor, heading, content), in page order.
        let mut parts: Vec<(&str, &str, String)> = vec![
            ("summary", "Summary and consistency", self.summary()),
            ("rmse", "RMSE and the PCRLB", self.rmse()),
        ];
        if let Some(c) = self.lincov {
            parts.push(("lincov", "LinCov beside the Monte Carlo", self.lincov(c)));
        }
        parts.push(("errors", "Errors and ±3σ per state", self.errors()));
        parts.push((
            "nees-nis",
            "NEES and NIS with χ² bands, NIS per channel",
            figures(svgs(self.figures, |k| {
                matches!(k, Kind::Nees | Kind::Nis | Kind::ChannelNis(_))
            })),
        ));
        let dens = svgs(self.figures, |k| *k == Kind::Density);
        if !dens.is_empty() {
            parts.push(("density", "Density error", figures(dens)));
        }
        parts.push((
            "weights",
            "Fusion weights and model probabilities",
            self.weights(),
        ));
        if let Some(g) = self.gating() {
            parts.push(("gating", "Innovation gate and beacon exclusion", g));
        }
        parts.push(("dispersion", "Deployment dispersion", self.dispersion()));
        if let Some(d) = self.delivery {
            parts.push((
                "delivery",
                "Delivery at deployment (guidance in the loop)",
                crate::delivery_figures::delivery_section(d, self.figures),
            ));
        }
        parts.push(("provenance", "Provenance", self.provenance()));
        let entries: Vec<(String, String)> = parts
            .iter()
            .map(|(id, heading, _)| (id.to_string(), heading.to_string()))
            .collect();
        let filters: Vec<(String, String)> = r
            .filters
            .iter()
            .map(|f| (format!("errors-{}", f.name), f.name.clone()))
            .collect();
        let mut body = html::toc(&entries, "errors", &filters);
        for (id, heading, content) in &parts {
            body += &section(id, heading, content);
        }
        html::page(&format!("entrynav trade report: {}", r.scenario), &body)
    }
}
