//! `vitro check levels`: the cross-level check — every controller on every fidelity level,
//! with its stated properties.

use crate::Failure;
use anyhow::anyhow;
use clap::{Args, Subcommand};
use serde::Serialize;
use std::path::PathBuf;
use vitro_tactical::check::{CheckError, Registry, Setup};

#[derive(Debug, Subcommand)]
pub(crate) enum CheckCommand {
    /// Runs each controller on each level of fidelity and checks its properties.
    Levels(LevelsArgs),
}

#[derive(Debug, Args)]
pub(crate) struct LevelsArgs {
    /// The town (.osm.pbf).
    #[arg(long, default_value = "data/maps/kotka.osm.pbf")]
    map: PathBuf,
    /// The terrain the town stands on (ESRI ASCII grid or GeoTIFF).
    #[arg(long, default_value = "data/terrain/valley_64x64_90m.asc")]
    terrain: PathBuf,
    /// Prints the rows as a JSON list of {"entity","level","property","pass","value","limit"}.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct JsonRow<'a> {
    entity: &'a str,
    level: &'a str,
    property: &'a str,
    pass: bool,
    value: f64,
    limit: &'a str,
}

pub(crate) fn check(cmd: &CheckCommand) -> Result<(), Failure> {
    let CheckCommand::Levels(args) = cmd;
    let setup =
        Setup::from_files(&args.map, &args.terrain).map_err(|e| Failure::Input(e.into()))?;
    let report = Registry::standard(&setup)
        .and_then(|r| r.run(&setup))
        .map_err(|e: CheckError| Failure::Runtime(e.into()))?;
    if args.json {
        let rows: Vec<JsonRow<'_>> = report
            .rows
            .iter()
            .map(|r| JsonRow {
                entity: &r.entity,
                level: r.level.name(),
                property: &r.property,
                pass: r.pass,
                value: r.value,
                limit: &r.limit,
            })
            .collect();
        let line = serde_json::to_string(&rows).map_err(|e| Failure::Runtime(anyhow!(e)))?;
        println!("{line}");
    } else {
        print!("{}", report.table());
    }
    if report.pass {
        Ok(())
    } else {
        let failed = report.rows.iter().filter(|r| !r.pass).count();
        Err(Failure::Check(anyhow!("{failed} propert(ies) fail")))
    }
}
