//! `entrynav atmosphere generate --out FILE`: write the synthetic test set of truth atmospheres
//! (`entrynav::atmosphere::synthetic_set`) as a Mars-GRAM Monte Carlo set file.

use anyhow::{Context, Result};
use clap::Args;
use entrynav::atmosphere::{
    SyntheticCase, SyntheticSetSpec, generate_synthetic_set, mars_mean_profile,
    synthetic_set_gram_text,
};
use entrynav::planet::Planet;
use entrynav_studies::options;
use std::path::PathBuf;

/// Arguments of `entrynav atmosphere generate`.
#[derive(Args)]
pub struct GenerateArgs {
    /// Output file (Mars-GRAM Monte Carlo layout: `#` header `Var_X DENSTOT Radius`, stacked
    /// profiles; `trade --atmosphere-file FILE` flies profile k mod n in run k).
    #[arg(long)]
    pub out: PathBuf,
    /// Seed of the per-profile perturbation (profile i uses seed + i).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Multiplier of the perturbation envelope (docs/density.md) (0: the scaled mean profiles exactly).
    #[arg(long, default_value_t = 0.5)]
    pub perturbation_scale: f64,
    /// Which cases: `standard` (18: f_above x f_below), `high-latitude` (12: steeper scale height,
    /// twice the perturbation, 0.3-3x upper atmosphere) or `extended` (the 18 then the 12).
    #[arg(long, value_enum, default_value_t = Preset::Standard)]
    pub preset: Preset,
    /// Density factors above 80 km of the standard cases (comma-separated; default
    /// 0.1,0.3,0.5,1,2,3; not with another preset).
    #[arg(long, value_name = "LIST")]
    pub factors_above: Option<String>,
    /// Density factors below 60 km of the standard cases (comma-separated; default 0.7,1,1.3;
    /// not with another preset).
    #[arg(long, value_name = "LIST")]
    pub factors_below: Option<String>,
}

/// The case sets of `entrynav::atmosphere::synthetic_set`.
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Preset {
    /// The 18 cases f_above x f_below.
    Standard,
    /// The 12 high-latitude cases.
    HighLatitude,
    /// The 18 standard cases, then the 12 high-latitude ones.
    Extended,
}

fn list(text: &Option<String>, flag: &str) -> Result<Option<Vec<f64>>> {
    let option = flag.trim_start_matches('-').replace('-', "_");
    let Some(t) = text else { return Ok(None) };
    let values = t
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("{flag} '{t}': expected numbers, e.g. 0.5,1,2"))?;
    options::count(&option, values.len() as i128, 1, MAX_FACTORS)?;
    for v in &values {
        options::real(&option, *v, MIN_FACTOR, MAX_FACTOR)?;
    }
    Ok(Some(values))
}

/// Most factors in one list (the cases are every pair of the two lists: 10 000 profiles at most).
const MAX_FACTORS: usize = 100;
/// Smallest and largest density factor of a case (the synthetic set's own bounds).
const MIN_FACTOR: f64 = 0.01;
const MAX_FACTOR: f64 = 100.0;

/// Run the command.
pub fn run(args: &GenerateArgs) -> Result<()> {
    crate::preflight::check_output_file(&args.out, "--out")?;
    let base = match args.preset {
        Preset::Standard => SyntheticSetSpec::default(),
        Preset::HighLatitude => SyntheticSetSpec::high_latitude(),
        Preset::Extended => SyntheticSetSpec::extended(),
    };
    let mut spec = SyntheticSetSpec {
        seed: args.seed,
        perturbation_scale: args.perturbation_scale,
        ..base
    };
    let above = list(&args.factors_above, "--factors-above")?;
    let below = list(&args.factors_below, "--factors-below")?;
    if (above.is_some() || below.is_some()) && args.preset != Preset::Standard {
        anyhow::bail!(
            "--factors-above/--factors-below set the standard cases; they cannot be combined with \
             --preset high-latitude or extended"
        );
    }
    if above.is_some() || below.is_some() {
        let above = above.unwrap_or_else(|| vec![0.1, 0.3, 0.5, 1.0, 2.0, 3.0]);
        let below = below.unwrap_or_else(|| vec![0.7, 1.0, 1.3]);
        spec.cases = above
            .iter()
            .flat_map(|&factor_above| {
                below
                    .iter()
                    .map(move |&factor_below| SyntheticCase::scaled(factor_above, factor_below))
            })
            .collect();
    }
    let profiles = generate_synthetic_set(&mars_mean_profile(), &spec)?;
    let text = synthetic_set_gram_text(&profiles, &spec, Planet::MARS.radius);
    entrynav_studies::output::atomic_file::write(&args.out, text)?;
    println!(
        "wrote {}: {} profiles, 0-150 km every 1 km, perturbation x {} (times each case's factor), seed {}",
        args.out.display(),
        profiles.len(),
        spec.perturbation_scale,
        spec.seed
    );
    for (i, p) in profiles.iter().enumerate() {
        println!("  profile {i:>3}: {}", p.case.describe());
    }
    Ok(())
}
