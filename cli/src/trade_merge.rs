//! `entrynav trade merge SHARDS…`: the shards of one study combined into exactly its
//! single-process report (`entrynav_studies::trade::merge`), written and printed as `trade` does.

use crate::preflight::is_stdout;
use crate::trade_outputs::{Outputs, check_outputs, command_line, write_csv_dir, write_text};
use crate::trade_tables::print_tables;
use anyhow::Result;
use entrynav_render::chart::labels::WeightNames;
use entrynav_studies::trade::merge::merge_trade_shards;
use std::path::{Path, PathBuf};

/// `trade merge`: combine the shard files into the study's report, write the outputs asked for
/// (first, so a closed standard output never costs one), then print the tables.
pub(crate) fn merge(
    shards: &[PathBuf],
    json: Option<&Path>,
    csv_dir: Option<&Path>,
    plots: Option<&Path>,
    list_runs: bool,
) -> Result<()> {
    check_outputs(json, csv_dir, plots)?;
    let texts = shards
        .iter()
        .map(|p| {
            let text = entrynav_studies::input::read_text(p, "SHARDS file")?;
            Ok((p.display().to_string(), text))
        })
        .collect::<Result<Vec<_>>>()?;
    let merged = merge_trade_shards(&texts)?;
    let (report, delivery) = (&merged.report, merged.delivery.as_ref());
    let to_stdout = json.is_some_and(is_stdout);
    let mut outputs = Outputs::default();
    if let Some(path) = json {
        let provenance = merged.provenance(command_line());
        let done = merged
            .to_json(&provenance)
            .map_err(Into::into)
            .and_then(|text| write_text(path, &text));
        let note = (!to_stdout).then(|| format!("wrote {}", path.display()));
        outputs.record(done.map(|()| note));
    }
    if let Some(dir) = csv_dir {
        let done = write_csv_dir(dir, report);
        outputs.record(done.map(|()| Some(format!("wrote CSV series to {}", dir.display()))));
    }
    let names = WeightNames::of_channels(&report.channels);
    if let Some(dir) = plots {
        let done = crate::figures::trade_plots(dir, report, &names, &Default::default(), delivery);
        outputs.record(done.map(|()| Some(format!("wrote plots to {}", dir.display()))));
    }
    if !to_stdout {
        let wall = format!(
            "{:.2} s wall summed over the {} shards",
            merged.wall_s, merged.shards
        );
        print_tables(report, &wall, list_runs);
        if let Some(d) = delivery {
            crate::guidance::print_table(d);
        }
    }
    outputs.finish(to_stdout)
}
