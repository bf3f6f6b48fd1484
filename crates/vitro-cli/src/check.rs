//! `vitro check levels`: the cross-level check — every controller on every fidelity level,
//! with its stated properties.

use crate::Failure;
use anyhow::anyhow;
use clap::{Args, Subcommand};
use serde::Serialize;
use std::path::PathBuf;
use std::sync::Arc;
use vitro_calibrate::evaluate::evaluate;
use vitro_calibrate::flights::{FlightSampling, evaluate_air, sample_flights};
use vitro_calibrate::trips::{Sampling, sample};
use vitro_check::{CheckError, Registry, Row};
use vitro_tactical::calibration::{Calibration, site_fingerprint, types_fingerprint};
use vitro_tactical::entity::Level;
use vitro_tactical::setup::Setup;

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
    /// Also checks "the abstract level predicts the concrete one" with this calibration
    /// (made by `vitro calibrate` on the same map and terrain): fresh trips, the trip times
    /// of each abstract level before and after calibration against the concrete level's.
    #[arg(long)]
    calibration: Option<PathBuf>,
    /// Trips per entity type for the prediction property.
    #[arg(long, default_value_t = 4)]
    trips: usize,
    /// Flights per aircraft type for the prediction property (the lattice against the
    /// kinematic and dynamic levels, where the calibration has aircraft fits).
    #[arg(long, default_value_t = 3)]
    flights: usize,
    /// Seed of those trips (pick one the calibration did not use).
    #[arg(long, default_value_t = 1001)]
    trip_seed: u64,
    /// Tolerance of the prediction property: mean absolute relative error, %.
    #[arg(long, default_value_t = 5.0)]
    tolerance_pct: f64,
    /// Threads for the prediction property's trips.
    #[arg(long, default_value_t = 2)]
    jobs: usize,
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
    // The calibration is read (and refused for another town) before any run.
    let calibration = match &args.calibration {
        Some(path) => Some(read_calibration(path, args)?),
        None => None,
    };
    let mut report = Registry::standard(&setup)
        .and_then(|r| r.run(&setup))
        .map_err(|e: CheckError| Failure::Runtime(e.into()))?;
    if let Some(cal) = calibration {
        let rows = predictions(&setup, cal, args)?;
        report.pass &= rows.iter().all(|r| r.pass);
        report.rows.extend(rows);
    }
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

/// Reads the calibration and refuses one made for another map, terrain or type set.
fn read_calibration(
    path: &std::path::Path,
    args: &LevelsArgs,
) -> Result<Arc<Calibration>, Failure> {
    let input = |m: String| Failure::Input(anyhow!(m));
    let cal = Calibration::read(path).map_err(|e| input(e.to_string()))?;
    let site =
        site_fingerprint(&args.map, &args.terrain, None).map_err(|e| input(e.to_string()))?;
    let types = types_fingerprint(vitro_tactical::types::TypeBook::builtin());
    cal.check(&site, &types)
        .map_err(|e| input(format!("{}: {e}", path.display())))?;
    Ok(Arc::new(cal))
}

/// The rows of "the abstract level predicts the concrete one": per entity type and abstract
/// level, the mean absolute relative error of its trip times after calibration (before, in
/// the limit column) on fresh trips.
fn predictions(
    setup: &Setup,
    cal: Arc<Calibration>,
    args: &LevelsArgs,
) -> Result<Vec<Row>, Failure> {
    let trips = sample(
        setup,
        &Sampling {
            fit_per_type: 0,
            held_out_per_type: args.trips,
            seed: args.trip_seed,
            ..Sampling::default()
        },
    );
    let to = [Level::Discrete, Level::Interpolated];
    let mut out = evaluate(
        setup,
        &cal,
        &trips,
        &to,
        args.tolerance_pct,
        args.jobs,
        &|| {},
    )
    .map_err(|e| Failure::Runtime(e.into()))?;
    if !cal.aircraft.is_empty() && args.flights > 0 {
        let flights = sample_flights(
            setup,
            &FlightSampling {
                fit_per_type: 0,
                held_out_per_type: args.flights,
                seed: args.trip_seed,
                ..FlightSampling::default()
            },
        );
        out.extend(
            evaluate_air(setup, &cal, &flights, args.tolerance_pct, args.jobs, &|| {})
                .map_err(|e| Failure::Runtime(e.into()))?,
        );
    }
    Ok(out
        .into_iter()
        .map(|p| {
            let r = &p.residuals;
            let what = if matches!(p.concrete, Level::Kinematic | Level::Dynamic) {
                "flights"
            } else {
                "trips"
            };
            Row {
                entity: p.entity,
                level: p.level,
                property: format!("predicts {}", p.concrete.name()),
                pass: p.pass,
                value: r.mape_pct_after,
                limit: format!(
                    "mean |error| <= {:.1} % over {} {what} (uncalibrated {:.1} %, bias {:+.1} -> {:+.1} %)",
                    p.tolerance_pct, r.n, r.mape_pct_before, r.bias_pct_before, r.bias_pct_after
                ),
            }
        })
        .collect())
}
