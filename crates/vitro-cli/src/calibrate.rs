//! `vitro calibrate SCENARIO --from physical [--to discrete,interpolated] --out FILE`: fits
//! the abstract levels' trip times to the concrete level's on sample trips over the
//! scenario's own town and terrain ([`vitro_calibrate`]).

use crate::Failure;
use crate::batch::progress_bar;
use anyhow::anyhow;
use clap::Args;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;
use vitro_batch::plot::{Scatter, plot_residuals};
use vitro_calibrate::fit::{Stamp, calibrate as fit_all, runs_needed};
use vitro_calibrate::flights::{self, FlightSampling, calibrate_air, sample_flights};
use vitro_calibrate::trips::{Sampling, sample};
use vitro_site::map::{MapConfig, TownMap};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::Terrain;
use vitro_tactical::calibration::Residuals;
use vitro_tactical::calibration::{Calibration, site_fingerprint, types_fingerprint};
use vitro_tactical::entity::Level;
use vitro_tactical::setup::Setup;

#[derive(Debug, Args)]
pub(crate) struct CalibrateArgs {
    /// The scenario whose town, terrain and types to calibrate on (its `[site]` table).
    scenario: PathBuf,
    /// The concrete level (vehicles; troopers are fitted to their directed level).
    #[arg(long, default_value = "physical")]
    from: String,
    /// The abstract levels to calibrate, comma separated.
    #[arg(long, default_value = "discrete,interpolated", value_delimiter = ',')]
    to: Vec<String>,
    /// The calibration file to write (TOML).
    #[arg(long)]
    out: PathBuf,
    /// Seed of the trip sample.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Fitted trips per entity type.
    #[arg(long, default_value_t = 16)]
    trips: usize,
    /// Held-out trips per entity type (evaluated, not fitted).
    #[arg(long, default_value_t = 8)]
    held_out: usize,
    /// Fitted flights per aircraft type (the lattice against the kinematic and dynamic
    /// levels; 0: no aircraft calibration).
    #[arg(long, default_value_t = 12)]
    flights: usize,
    /// Held-out flights per aircraft type.
    #[arg(long, default_value_t = 6)]
    held_out_flights: usize,
    /// Longest vehicle trip, metres (walks: a third of it).
    #[arg(long, default_value_t = 1600.0)]
    max_m: f64,
    /// Threads (the result does not depend on them).
    #[arg(long, default_value_t = 2)]
    jobs: usize,
    /// Draws predicted against concrete trip times to PLOT.png and PLOT.svg.
    #[arg(long)]
    plot: Option<PathBuf>,
}

/// The `[site]` of a scenario file: map, terrain (absolute) and offset.
fn site_of(scenario: &Path) -> Result<(PathBuf, PathBuf, Option<[f64; 2]>), Failure> {
    let bad = |m: String| Failure::Input(anyhow!("{}: {m}", scenario.display()));
    vitro_tools::input_file(scenario)?;
    let text = std::fs::read_to_string(scenario).map_err(|e| bad(e.to_string()))?;
    let doc: toml::Table = toml::from_str(&text).map_err(|e| bad(e.to_string()))?;
    let site = doc
        .get("site")
        .and_then(|s| s.as_table())
        .ok_or_else(|| bad("no [site] table (map, terrain)".into()))?;
    let dir = scenario.parent().unwrap_or(Path::new(""));
    let file = |k: &str| {
        site.get(k)
            .and_then(|v| v.as_str())
            .map(|p| dir.join(p))
            .ok_or_else(|| bad(format!("[site] has no `{k}` path")))
    };
    let offset = match site.get("offset").and_then(|v| v.as_array()) {
        Some(a) if a.len() == 2 => {
            let n = |v: &toml::Value| v.as_float().or(v.as_integer().map(|i| i as f64));
            match (n(&a[0]), n(&a[1])) {
                (Some(x), Some(y)) => Some([x, y]),
                _ => return Err(bad("[site] offset: expected [east, north] metres".into())),
            }
        }
        Some(_) => return Err(bad("[site] offset: expected [east, north] metres".into())),
        None => None,
    };
    Ok((file("map")?, file("terrain")?, offset))
}

fn level(name: &str) -> Result<Level, Failure> {
    match name {
        "discrete" => Ok(Level::Discrete),
        "interpolated" => Ok(Level::Interpolated),
        "physical" => Ok(Level::Physical),
        other => Err(Failure::Input(anyhow!(
            "unknown level `{other}`: expected discrete, interpolated or physical"
        ))),
    }
}

pub(crate) fn calibrate(args: &CalibrateArgs) -> Result<(), Failure> {
    let t0 = Instant::now();
    if level(&args.from)? != Level::Physical {
        return Err(Failure::Input(anyhow!(
            "--from {}: only the physical level is a concrete level to calibrate from",
            args.from
        )));
    }
    let to: Vec<Level> = args.to.iter().map(|l| level(l)).collect::<Result<_, _>>()?;
    if to.contains(&Level::Physical) {
        return Err(Failure::Input(anyhow!(
            "--to: the abstract levels are discrete and interpolated"
        )));
    }
    let (map, terrain, offset) = site_of(&args.scenario)?;
    let input = |e: String| Failure::Input(anyhow!(e));
    let town = TownMap::load(&map, &MapConfig::default()).map_err(|e| input(e.to_string()))?;
    let ground = Terrain::load(&terrain).map_err(|e| input(e.to_string()))?;
    let config = SiteConfig {
        offset,
        ..SiteConfig::default()
    };
    let site = Site::new(town, ground, &config).map_err(|e| input(e.to_string()))?;
    let setup = Setup {
        seed: args.seed,
        ..Setup::new(Arc::new(site))
    };
    let sampling = Sampling {
        fit_per_type: args.trips,
        held_out_per_type: args.held_out,
        drive_m: (150.0f64.min(args.max_m / 2.0), args.max_m),
        walk_m: (50.0f64.min(args.max_m / 6.0), args.max_m / 3.0),
        seed: args.seed,
        ..Sampling::default()
    };
    let trips = sample(&setup, &sampling);
    let stamp = Stamp {
        scenario: args.scenario.display().to_string(),
        map: map
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default(),
        site_fingerprint: site_fingerprint(&map, &terrain, offset)
            .map_err(|e| input(e.to_string()))?,
        types_fingerprint: types_fingerprint(&setup.types),
        seed: args.seed,
    };
    // The aircraft have one abstract level, the lattice (discrete).
    let air = if to.contains(&Level::Discrete) && args.flights > 0 {
        let sampling = FlightSampling {
            fit_per_type: args.flights,
            held_out_per_type: args.held_out_flights,
            seed: args.seed,
            ..FlightSampling::default()
        };
        sample_flights(&setup, &sampling)
    } else {
        Vec::new()
    };
    let bar = progress_bar();
    bar.set_length((runs_needed(&trips, &to) + flights::runs_needed(&air)) as u64);
    let tick = || bar.inc(1);
    let mut cal = fit_all(&setup, &trips, &to, &stamp, args.jobs, &tick)
        .map_err(|e| Failure::Runtime(e.into()))?;
    if !air.is_empty() {
        calibrate_air(&setup, &air, &mut cal, args.jobs, &tick)
            .map_err(|e| Failure::Runtime(e.into()))?;
    }
    bar.finish_and_clear();
    cal.wall_s = (t0.elapsed().as_secs_f64() * 10.0).round() / 10.0;
    let text = cal.to_toml().map_err(|e| Failure::Runtime(anyhow!(e)))?;
    std::fs::write(&args.out, text)
        .map_err(|e| Failure::Runtime(anyhow!("cannot write {}: {e}", args.out.display())))?;
    print!("{}", summary(&cal));
    println!(
        "{} trips, {} flights, {:.1} s wall on {} threads; written to {}",
        cal.trips.len(),
        cal.flights.len(),
        cal.wall_s,
        args.jobs,
        args.out.display()
    );
    if let Some(stem) = &args.plot {
        let mut files =
            plot_residuals(&scatter(&cal), 5.0, stem).map_err(|e| Failure::Runtime(e.into()))?;
        if !cal.flights.is_empty() {
            let mut air = stem.as_os_str().to_owned();
            air.push("_air");
            files.extend(
                plot_residuals(&air_scatter(&cal), 5.0, Path::new(&air))
                    .map_err(|e| Failure::Runtime(e.into()))?,
            );
        }
        for f in files {
            println!("plot: {}", f.display());
        }
    }
    Ok(())
}

/// One fit's table row: its name, level, the parameters (alpha, beta, kappa, gamma, delta,
/// and epsilon for a trip fit) and its residuals on the fitted and the held-out trips.
fn fit_row(name: &str, level: &str, p: &[f64], r: &Residuals, h: &Residuals) -> String {
    let extra: String = p.iter().skip(5).map(|x| format!(" {x:.2} |")).collect();
    format!(
        "| {name} | {level} | {:.3} | {:.1} | {:.2} | {:.3} | {:.2} |{extra} {:+.1} -> {:+.1} ({:.1} -> {:.1}), n={} | {:+.1} -> {:+.1} ({:.1} -> {:.1}, max {:.1}), n={} |\n",
        p[0],
        p[1],
        p[2],
        p[3],
        p[4],
        r.bias_pct_before,
        r.bias_pct_after,
        r.mape_pct_before,
        r.mape_pct_after,
        r.n,
        h.bias_pct_before,
        h.bias_pct_after,
        h.mape_pct_before,
        h.mape_pct_after,
        h.max_pct_after,
        h.n
    )
}

/// The fits and their residuals as a Markdown table.
pub(crate) fn summary(cal: &Calibration) -> String {
    let mut s = String::from(
        "| entity | level | alpha | beta s | kappa s/rad | gamma s/m | delta s/rad | epsilon s/rad² | fit: bias % before -> after (MAPE) | held out: bias % before -> after (MAPE, max) |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for f in &cal.fits {
        let p = [f.alpha, f.beta, f.kappa, f.gamma, f.delta, f.epsilon];
        let name = if f.excluded > 0 {
            format!("{} ({} left out)", f.entity, f.excluded)
        } else {
            f.entity.clone()
        };
        s.push_str(&fit_row(&name, &f.level, &p, &f.fit_residuals, &f.held_out));
    }
    if !cal.aircraft.is_empty() {
        s.push_str(
            "\n| aircraft | level vs concrete | alpha | beta s | kappa s/rad | gamma s/m | delta s/rad | fit: bias % before -> after (MAPE) | held out: bias % before -> after (MAPE, max) |\n|---|---|---|---|---|---|---|---|---|\n",
        );
    }
    for f in &cal.aircraft {
        let p = [f.alpha, f.beta, f.kappa, f.gamma, f.delta];
        let level = format!("{} vs {}", f.level, f.concrete);
        s.push_str(&fit_row(
            &f.entity,
            &level,
            &p,
            &f.fit_residuals,
            &f.held_out,
        ));
    }
    if !cal.squads.is_empty() {
        s.push_str(
            "\n| squad pace | concrete | normal stretch | slow stretch | calm walks: bias % before -> after (MAPE) | walks in contact: bias % before -> after (MAPE) | escorting a VIP, in contact (held out) |\n|---|---|---|---|---|---|---|\n",
        );
    }
    for f in &cal.squads {
        let (c, k, e) = (&f.calm, &f.contact, &f.escorted);
        s.push_str(&format!(
            "| {} | {} | {:.3} | {:.3} | {:+.1} -> {:+.1} ({:.1} -> {:.1}), n={} | {:+.1} -> {:+.1} ({:.1} -> {:.1}), n={} | {:+.1} -> {:+.1} ({:.1} -> {:.1}), n={} |\n",
            f.level,
            f.concrete,
            f.normal,
            f.slow,
            c.bias_pct_before,
            c.bias_pct_after,
            c.mape_pct_before,
            c.mape_pct_after,
            c.n,
            k.bias_pct_before,
            k.bias_pct_after,
            k.mape_pct_before,
            k.mape_pct_after,
            k.n,
            e.bias_pct_before,
            e.bias_pct_after,
            e.mape_pct_before,
            e.mape_pct_after,
            e.n
        ));
    }
    s
}

/// The abstract levels' relative errors against the concrete trip times, per level,
/// before and after calibration.
fn scatter(cal: &Calibration) -> Scatter {
    let mut groups: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for level in ["discrete", "interpolated"] {
        for (when, after) in [("uncalibrated", false), ("calibrated", true)] {
            let pts: Vec<(f64, f64)> = cal
                .trips
                .iter()
                .filter_map(|t| {
                    let m = if after { &t.after_s } else { &t.before_s };
                    let c = t.concrete_s.max(1e-9);
                    m.get(level).map(|&y| (t.concrete_s, 100.0 * (y - c) / c))
                })
                .collect();
            if !pts.is_empty() {
                groups.push((format!("{level}, {when}"), pts));
            }
        }
    }
    Scatter {
        title: "Abstract-level trip time error against the concrete level".into(),
        note: format!(
            "{} sample trips (vehicles vs physical, troopers vs directed), fitted and held out; map {}; negative = optimistic",
            cal.trips.len(),
            cal.map
        ),
        x_desc: "concrete trip time, s".into(),
        y_desc: "(abstract - concrete) / concrete, %".into(),
        groups,
    }
}

/// The lattice's relative errors against the continuous levels' flight times, per aircraft
/// type, before and after calibration (held-out flights marked apart).
fn air_scatter(cal: &Calibration) -> Scatter {
    let mut groups: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut types: Vec<&str> = cal.flights.iter().map(|f| f.entity.as_str()).collect();
    types.dedup();
    for entity in types {
        for (when, after) in [("uncalibrated", false), ("calibrated", true)] {
            let pts: Vec<(f64, f64)> = cal
                .flights
                .iter()
                .filter(|f| f.entity == entity)
                .map(|f| {
                    let y = if after { f.after_s } else { f.before_s };
                    let c = f.concrete_s.max(1e-9);
                    (f.concrete_s, 100.0 * (y - c) / c)
                })
                .collect();
            if !pts.is_empty() {
                groups.push((format!("{entity}, {when}"), pts));
            }
        }
    }
    Scatter {
        title: "Lattice flight time error against the continuous level".into(),
        note: format!(
            "{} sample flights (procerus vs kinematic, helicopters vs rotor dynamics), fitted and held out; map {}; negative = optimistic",
            cal.flights.len(),
            cal.map
        ),
        x_desc: "concrete flight time, s".into(),
        y_desc: "(lattice - concrete) / concrete, %".into(),
        groups,
    }
}
