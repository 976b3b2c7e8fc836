//! The candidate sites of the site selection: the grid sites visible during the whole entry and
//! inside `region`, then the answers to certify (the scenario's own surface sites, the sites of
//! an `optimize ground` JSON file given by `compare`).

use crate::design::failure::study_error;
use crate::design::select_options::{MAX_CANDIDATES, SelectOptions};
use crate::design::sites::scenario_sites;
use crate::error::{StudyError, StudyResult};
use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::{GroundProblem, Site};
use serde_json::Value;
use std::path::Path;

/// The candidates: grid sites first, then the sites of each answer to certify.
#[derive(Debug, Clone)]
pub struct Candidates {
    /// Every candidate.
    pub sites: Vec<Site>,
    /// How many of `sites` are grid sites.
    pub grid_count: usize,
    /// The label and candidate indices of each answer to certify.
    pub extra: Vec<(String, Vec<usize>)>,
}

/// The visible grid inside `region`, then every answer to certify that has exactly k sites,
/// each feasible and inside the region (a note in `notes` names those that are not).
pub fn load_candidates(
    o: &SelectOptions,
    cfg: &ScenarioConfig,
    ground: &GroundProblem,
    notes: &mut Vec<String>,
) -> StudyResult<Candidates> {
    let region = o.region_box()?;
    let inside = |s: &Site| {
        region.is_none_or(|[lat0, lat1, lon0, lon1]| {
            let [lat, lon] = s.degrees();
            (lat0..=lat1).contains(&lat) && (lon0..=lon1).contains(&lon)
        })
    };
    let mut sites = ground.visible_grid(o.grid_deg).map_err(study_error)?;
    sites.retain(inside);
    if sites.is_empty() {
        return Err(StudyError::Refused(format!(
            "no visible grid site lies inside --region {:?}",
            o.region
        )));
    }
    if sites.len() > MAX_CANDIDATES {
        return Err(StudyError::Refused(format!(
            "the grid every {} deg gives {} candidate sites; the relaxation takes at most \
             {MAX_CANDIDATES}: use a larger grid_deg or a smaller region",
            o.grid_deg,
            sites.len()
        )));
    }
    let mut candidates = Candidates {
        grid_count: sites.len(),
        sites,
        extra: Vec::new(),
    };
    let mut add = |label: String, list: Vec<Site>| {
        if list.len() == o.k && list.iter().all(|s| ground.is_feasible(s) && inside(s)) {
            let start = candidates.sites.len();
            candidates.sites.extend(list);
            let indices = (start..candidates.sites.len()).collect();
            candidates.extra.push((label, indices));
        } else {
            notes.push(format!(
                "{label} not certified (needs exactly k = {} sites, each visible during the \
                 whole entry and inside --region)",
                o.k
            ));
        }
    };
    let own = scenario_sites(cfg);
    if !own.is_empty() {
        add(format!("scenario {} sites", cfg.name), own);
    }
    if let Some(path) = &o.compare {
        add(format!("sites of {}", path.display()), compare_sites(path)?);
    }
    Ok(candidates)
}

/// The `sites` (`lat_deg`, `lon_deg`) of an `optimize ground` JSON file.
fn compare_sites(path: &Path) -> StudyResult<Vec<Site>> {
    let shown = path.display();
    let text = crate::input::read_text(path, "compare")?;
    let v: Value = serde_json::from_str(&text)
        .map_err(|e| study_error(e).context(format!("{shown} is not JSON")))?;
    let refuse = |what: &str| StudyError::Refused(format!("{shown}{what}"));
    v["sites"]
        .as_array()
        .ok_or_else(|| refuse(" has no \"sites\" array"))?
        .iter()
        .map(|s| {
            Some(Site::from_degrees(
                s["lat_deg"].as_f64()?,
                s["lon_deg"].as_f64()?,
            ))
        })
        .collect::<Option<Vec<Site>>>()
        .ok_or_else(|| refuse(": sites need lat_deg and lon_deg"))
}
