//! `vitro map ...` and `vitro terrain ...`: views of the tactical world's map and terrain.

use crate::Failure;
use anyhow::{Context as _, anyhow};
use clap::{Args, Subcommand};
use std::path::{Path, PathBuf};
use vitro_site::info::map_info;
use vitro_site::map::{MapConfig, TownMap};
use vitro_site::render::{RenderOptions, render_site};
use vitro_site::site::{Site, SiteConfig};
use vitro_site::terrain::{Terrain, TerrainError};
use vitro_site::viewshed::{ViewshedError, viewshed_file};

#[derive(Debug, Subcommand)]
pub(crate) enum MapCommand {
    /// Counts what an OpenStreetMap extract holds and the street graphs built from it.
    Info {
        /// The map (.osm.pbf).
        file: PathBuf,
        /// Prints one JSON object on stdout.
        #[arg(long)]
        json: bool,
    },
    /// Draws the map (streets, buildings, bridges, forbidden zones, terrain shading) to a PNG.
    Render(RenderArgs),
}

#[derive(Debug, Args)]
pub(crate) struct RenderArgs {
    /// The map (.osm.pbf).
    file: PathBuf,
    /// The PNG to write.
    #[arg(long)]
    out: PathBuf,
    /// Terrain (ESRI ASCII grid or GeoTIFF) to set the town on; flat ground if absent.
    #[arg(long)]
    terrain: Option<PathBuf>,
    /// Terrain position of the town's centre, `X,Y` in the terrain's coordinates (default:
    /// the town centred on the terrain).
    #[arg(long, value_parser = parse_pair)]
    offset: Option<[f64; 2]>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1600)]
    width: u32,
}

#[derive(Debug, Subcommand)]
pub(crate) enum TerrainCommand {
    /// Which cells of a terrain grid an observer sees: writes a 0/1 ESRI ASCII grid.
    Viewshed(ViewshedArgs),
}

#[derive(Debug, Args)]
pub(crate) struct ViewshedArgs {
    /// The terrain (ESRI ASCII grid or GeoTIFF).
    file: PathBuf,
    /// Observer position `X,Y` in the file's coordinates.
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true)]
    observer: [f64; 2],
    /// Observer eye height above the ground, metres.
    #[arg(long)]
    observer_height: f64,
    /// Height above the ground of a target standing on a cell centre, metres.
    #[arg(long)]
    target_height: f64,
    /// The mask to write (ESRI ASCII grid, 1 = seen).
    #[arg(long)]
    out: PathBuf,
}

/// A terrain file's problem as bad input, with the file's name before the line and column.
fn terrain_input(path: &Path, e: TerrainError) -> Failure {
    match e {
        TerrainError::Parse { line, column, what } => {
            Failure::Input(anyhow!("{}:{line}:{column}: {what}", path.display()))
        }
        TerrainError::Io { .. } => Failure::Input(e.into()),
        other => Failure::Input(anyhow!("{}: {other}", path.display())),
    }
}

fn parse_pair(s: &str) -> Result<[f64; 2], String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("expected X,Y, found {s:?}"))?;
    let p = |v: &str| {
        v.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("expected a number, found {v:?}"))
    };
    Ok([p(a)?, p(b)?])
}

pub(crate) fn map(cmd: &MapCommand) -> Result<(), Failure> {
    match cmd {
        MapCommand::Info { file, json } => {
            vitro_tools::input_file(file)?;
            let info = map_info(file).map_err(|e| Failure::Input(e.into()))?;
            if *json {
                let line =
                    serde_json::to_string(&info).map_err(|e| Failure::Runtime(anyhow!(e)))?;
                println!("{line}");
            } else {
                println!(
                    "{}: {} nodes, {} ways, {} relations; {} buildings ({} usable footprints), \
                     {} highway ways, {} bridges, {} water areas",
                    file.display(),
                    info.nodes,
                    info.ways,
                    info.relations,
                    info.buildings,
                    info.building_polygons,
                    info.highway_ways,
                    info.bridges,
                    info.water_areas
                );
                println!(
                    "drive graph {} junctions, {} edges; walk graph {} junctions, {} edges; \
                     {:.0} m x {:.0} m",
                    info.drive_graph.nodes,
                    info.drive_graph.edges,
                    info.walk_graph.nodes,
                    info.walk_graph.edges,
                    info.size_m[0],
                    info.size_m[1]
                );
            }
            Ok(())
        }
        MapCommand::Render(args) => render(args),
    }
}

fn render(args: &RenderArgs) -> Result<(), Failure> {
    if !(64..=16384).contains(&args.width) {
        return Err(Failure::Input(anyhow!(
            "--width {}: expected 64 to 16384 pixels",
            args.width
        )));
    }
    vitro_tools::input_file(&args.file)?;
    if let Some(t) = &args.terrain {
        vitro_tools::input_file(t)?;
    }
    let map =
        TownMap::load(&args.file, &MapConfig::default()).map_err(|e| Failure::Input(e.into()))?;
    let terrain = match &args.terrain {
        Some(t) => Terrain::load(t).map_err(|e| terrain_input(t, e))?,
        None => {
            // Flat ground one cell beyond the town on every side.
            let [x0, y0, x1, y1] = map.extent;
            let cell = 10.0;
            let cols = ((x1 - x0) / cell).ceil() as usize + 4;
            let rows = ((y1 - y0) / cell).ceil() as usize + 4;
            Terrain::flat(cols, rows, cell, 0.0).map_err(|e| Failure::Runtime(e.into()))?
        }
    };
    let config = SiteConfig {
        offset: args.offset,
        ..SiteConfig::default()
    };
    let site = Site::new(map, terrain, &config).map_err(|e| Failure::Input(e.into()))?;
    let name = args
        .file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let opts = RenderOptions {
        width: args.width,
        title: match &args.terrain {
            Some(t) => format!("{name} on {}", t.display()),
            None => name,
        },
        ..RenderOptions::default()
    };
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("creating {}", dir.display()))
            .map_err(Failure::Runtime)?;
    }
    let size = render_site(&site, &opts, &args.out).map_err(|e| Failure::Runtime(e.into()))?;
    println!(
        "wrote {} ({} x {} px)",
        args.out.display(),
        size.width,
        size.height
    );
    Ok(())
}

pub(crate) fn terrain(cmd: &TerrainCommand) -> Result<(), Failure> {
    match cmd {
        TerrainCommand::Viewshed(a) => {
            for (name, v) in [
                ("--observer-height", a.observer_height),
                ("--target-height", a.target_height),
            ] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(Failure::Input(anyhow!(
                        "{name} {v}: expected a height of zero or more metres"
                    )));
                }
            }
            vitro_tools::input_file(&a.file)?;
            let sum = viewshed_file(
                &a.file,
                a.observer,
                a.observer_height,
                a.target_height,
                &a.out,
            )
            .map_err(|e| match e {
                ViewshedError::Terrain(t) => terrain_input(&a.file, t),
                ViewshedError::Write { .. } => Failure::Runtime(e.into()),
                other => Failure::Input(other.into()),
            })?;
            println!(
                "wrote {}: {} of {} cells visible ({:.1} %)",
                a.out.display(),
                sum.visible,
                sum.cells,
                100.0 * sum.visible as f64 / sum.cells.max(1) as f64
            );
            Ok(())
        }
    }
}
