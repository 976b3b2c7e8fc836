//! The site selection with `objective = nav | pcrlb-avg | pcrlb-final | lincov-*`: k of the
//! candidate sites chosen on the nominal position bound (greedy + exchanges, no certificate: the
//! bound is not concave in the selection), for lincov-* then exchanges on the filter's LinCov;
//! checked against the input design like every optimum.

use crate::design::check::check_configs;
use crate::design::choices::{Choice, SelectObjectiveName};
use crate::design::failure::study_error;
use crate::design::select_candidates::load_candidates;
use crate::design::select_options::SelectOptions;
use crate::design::select_result::{OnBound, SelectionAnswer, SiteSelection};
use crate::design::sites::{chosen, scenario_mask_deg, scenario_sites};
use crate::error::StudyResult;
use crate::scenario::ScenarioInput;
use entrynav::estimation::nav::FilterKind;
use entrynav_optimizer::output::{self, template_noise};
use entrynav_optimizer::{GroundProblem, LinCovScore};

/// Choose on the nominal bound of `objective` (then on LinCov for lincov-*), write the answer as
/// a scenario and check it.
pub fn select_on_bound(
    input: &ScenarioInput,
    o: &SelectOptions,
    objective: SelectObjectiveName,
) -> StudyResult<SiteSelection> {
    let cfg = &input.config;
    let own = scenario_sites(cfg);
    let own_mask = scenario_mask_deg(cfg).to_radians();
    let load = entrynav_loader::file_loader(&input.dir);
    let ground = GroundProblem::new(
        cfg,
        &load,
        o.k.max(1),
        objective.ground(),
        o.step,
        o.min_elevation_deg.to_radians(),
    )
    .and_then(|g| g.with_min_separation(o.min_separation_deg.to_radians()))
    .and_then(|g| g.with_reference(&own, own_mask))
    .map_err(study_error)?;
    let mut notes = Vec::new();
    let candidates = load_candidates(o, cfg, &ground, &mut notes)?;
    let mut selection = ground
        .select_on_bound(&candidates.sites)
        .map_err(study_error)?;
    let lincov = match objective.lincov() {
        Some(figure) => {
            let filter = FilterKind::parse(&o.lincov_filter).map_err(study_error)?;
            let score = LinCovScore::new(ground.scenario(), filter, figure)
                .and_then(|s| s.with_reference(ground.beacons_masked(&own, own_mask)))
                .map_err(study_error)?;
            let l = ground
                .exchange_on_lincov(&candidates.sites, &selection.indices, &score)
                .map_err(study_error)?;
            selection.indices = l.indices.clone();
            selection.value = l.value;
            Some((filter, score.reference(), l))
        }
        None => None,
    };
    let sites = chosen(&candidates.sites, &selection.indices);
    let noise = template_noise(cfg, false).map_err(study_error)?;
    let (design, design_toml) = output::with_beacons(
        cfg,
        output::surface_beacons(&sites, &noise),
        o.scenario_name.as_deref().unwrap_or("selected"),
        &format!(
            "Sites chosen by `entrynav optimize select --objective {}` (k = {}, grid {} deg, at \
             least {} deg apart; greedy + exchanges, no certificate): value {:.6}.",
            objective.name(),
            o.k,
            o.grid_deg,
            o.min_separation_deg,
            selection.value
        ),
    )
    .map_err(study_error)?;
    let check = check_configs(cfg, &design, &input.dir, objective.name(), o.check())?;
    let series = ground.bound_series(&sites).map_err(study_error)?;
    let input_series = ground
        .bound_series_masked(&own, own_mask)
        .map_err(study_error)?;
    let bounds = [
        (series.time_avg(), series.final_value()),
        (input_series.time_avg(), input_series.final_value()),
    ];
    Ok(SiteSelection {
        options: o.clone(),
        scenario: cfg.name.clone(),
        notes,
        candidates,
        answer: SelectionAnswer::OnBound(OnBound {
            objective,
            selection,
            lincov,
            bounds,
        }),
        design,
        design_toml,
        check,
        threads: 1,
        wall_s: 0.0,
    })
}
