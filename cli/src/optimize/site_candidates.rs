//! The candidate sites of `entrynav optimize select`: the grid sites visible during the whole
//! entry and inside `--region`, then the heuristic answers to certify (the scenario's own
//! surface sites, the sites of an `optimize ground --json` file given by `--compare`).

use super::ground_sites::scenario_sites;
use super::*;

/// The candidates: grid sites first, then the sites of each answer to certify.
pub(super) struct Candidates {
    pub sites: Vec<Site>,
    /// How many of `sites` are grid sites.
    pub grid_count: usize,
    /// The label and candidate indices of each answer to certify.
    pub extra: Vec<(String, Vec<usize>)>,
}

/// The visible grid inside `--region`, then every answer to certify that has exactly k sites,
/// each feasible and inside the region (a note names those that are not).
pub(super) fn load_candidates(
    a: &SelectArgs,
    cfg: &ScenarioConfig,
    ground: &GroundProblem,
) -> Result<Candidates> {
    let inside = region_filter(&a.region)?;
    let mut sites = ground.visible_grid(a.grid_deg)?;
    sites.retain(&inside);
    if sites.is_empty() {
        bail!("no visible grid site lies inside --region {:?}", a.region);
    }
    let mut candidates = Candidates {
        grid_count: sites.len(),
        sites,
        extra: Vec::new(),
    };
    let mut add = |label: String, list: Vec<Site>| {
        if list.len() == a.k && list.iter().all(|s| ground.is_feasible(s) && inside(s)) {
            let start = candidates.sites.len();
            candidates.sites.extend(list);
            let indices = (start..candidates.sites.len()).collect();
            candidates.extra.push((label, indices));
        } else {
            println!(
                "note: {label} not certified (needs exactly k = {} sites, each visible during the \
                 whole entry and inside --region)",
                a.k
            );
        }
    };
    let own = scenario_sites(cfg);
    if !own.is_empty() {
        add(format!("scenario {} sites", cfg.name), own);
    }
    if let Some(path) = &a.compare {
        add(format!("sites of {}", path.display()), compare_sites(path)?);
    }
    Ok(candidates)
}

/// The `sites` (`lat_deg`, `lon_deg`) of an `optimize ground --json` file.
fn compare_sites(path: &Path) -> Result<Vec<Site>> {
    let text = entrynav_loader::read_text(path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let v: Value =
        serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))?;
    v["sites"]
        .as_array()
        .with_context(|| format!("{} has no \"sites\" array", path.display()))?
        .iter()
        .map(|s| {
            Some(Site::from_degrees(
                s["lat_deg"].as_f64()?,
                s["lon_deg"].as_f64()?,
            ))
        })
        .collect::<Option<Vec<Site>>>()
        .with_context(|| format!("{}: sites need lat_deg and lon_deg", path.display()))
}

/// `--region LAT_MIN,LAT_MAX,LON_MIN,LON_MAX` as a predicate on sites.
fn region_filter(region: &Option<Vec<f64>>) -> Result<impl Fn(&Site) -> bool + use<>> {
    let b = match region.as_deref() {
        None => None,
        Some(&[lat0, lat1, lon0, lon1]) if lat0 <= lat1 && lon0 <= lon1 => {
            Some([lat0, lat1, lon0, lon1])
        }
        Some(v) => {
            bail!("--region needs LAT_MIN,LAT_MAX,LON_MIN,LON_MAX with min <= max (deg), got {v:?}")
        }
    };
    Ok(move |s: &Site| {
        b.is_none_or(|[lat0, lat1, lon0, lon1]| {
            let [lat, lon] = s.degrees();
            (lat0..=lat1).contains(&lat) && (lon0..=lon1).contains(&lon)
        })
    })
}
