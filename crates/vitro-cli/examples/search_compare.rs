//! Compares search directories (`vitro search --out DIR`) by strategy: failing runs found
//! with the same budget (mean, standard deviation, range, 95% CI over the search seeds),
//! distinct failing seeds, the paired ratio per search seed; and draws the cumulative
//! failures found against evaluations.
//!
//! ```text
//! cargo run --release -p vitro-cli --example search_compare -- DIR... --out docs/search_failures.png
//! ```
//! (`scripts/search_compare.sh` makes the directories and runs it.)

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use vitro_batch::manifest::Manifest;
use vitro_batch::plot::stats::mean_ci;
use vitro_batch::plot::{SearchCurves, plot_search_curves};

/// One search: its strategy, seed, budget, and the failing runs with their seeds.
struct Found {
    strategy: String,
    seed: u64,
    budget: u64,
    failing: Vec<(u64, String)>,
}

fn read(dir: &Path) -> Result<Found, String> {
    let m = Manifest::load(dir)
        .map_err(|e| e.to_string())?
        .ok_or_else(|| format!("{}: no manifest.json", dir.display()))?;
    let s = m
        .search
        .ok_or_else(|| format!("{}: not a search directory", dir.display()))?;
    let text = std::fs::read_to_string(dir.join("found.csv"))
        .map_err(|e| format!("{}: {e}", dir.display()))?;
    let failing = text
        .lines()
        .skip(1)
        .filter_map(|l| {
            let mut cells = l.split(',');
            let run = cells.next()?.parse().ok()?;
            let seed = cells.nth(1)?.to_owned();
            Some((run, seed))
        })
        .collect();
    Ok(Found {
        strategy: s.strategy,
        seed: s.seed,
        budget: s.budget,
        failing,
    })
}

fn sd(xs: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt()
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let at = args.iter().position(|a| a == "--out");
    let out = at
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("search_failures.png"));
    let dirs: Vec<&String> = args
        .iter()
        .enumerate()
        .filter(|(i, _)| at.is_none_or(|a| *i != a && *i != a + 1))
        .map(|(_, d)| d)
        .collect();
    let mut by: BTreeMap<String, Vec<Found>> = BTreeMap::new();
    for d in dirs {
        let f = read(Path::new(d))?;
        by.entry(f.strategy.clone()).or_default().push(f);
    }
    let budget = by.values().flatten().map(|f| f.budget).min().unwrap_or(0);
    println!("budget {budget} runs per search\n");
    println!(
        "| strategy | n | failing runs: mean | sd | min–max | 95% CI of the mean | distinct failing seeds: mean | min–max |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let mut groups = Vec::new();
    for (strategy, found) in &by {
        let counts: Vec<f64> = found
            .iter()
            .map(|f| f.failing.iter().filter(|(r, _)| *r < budget).count() as f64)
            .collect();
        let seeds: Vec<f64> = found
            .iter()
            .map(|f| {
                let mut s: Vec<&String> = f.failing.iter().map(|(_, s)| s).collect();
                s.sort();
                s.dedup();
                s.len() as f64
            })
            .collect();
        let ci = mean_ci(&counts).ok_or("no searches")?;
        let range = |v: &[f64]| {
            let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            format!("{lo}–{hi}")
        };
        let ms = mean_ci(&seeds).map_or(f64::NAN, |m| m.mean);
        println!(
            "| {strategy} | {} | {:.2} | {:.2} | {} | [{:.2}, {:.2}] | {ms:.2} | {} |",
            counts.len(),
            ci.mean,
            sd(&counts),
            range(&counts),
            ci.lo,
            ci.hi,
            range(&seeds)
        );
        let curves: Vec<Vec<f64>> = found
            .iter()
            .map(|f| {
                (0..budget)
                    .map(|k| f.failing.iter().filter(|(r, _)| *r <= k).count() as f64)
                    .collect()
            })
            .collect();
        groups.push((strategy.clone(), curves));
    }
    if let (Some(a), Some(r)) = (by.get("adaptive"), by.get("random")) {
        let count = |f: &Found| f.failing.iter().filter(|(k, _)| *k < budget).count() as f64;
        let paired: Vec<(u64, f64, f64)> = a
            .iter()
            .filter_map(|fa| {
                let fr = r.iter().find(|fr| fr.seed == fa.seed)?;
                Some((fa.seed, count(fa), count(fr)))
            })
            .collect();
        println!("\nper search seed (adaptive / random):");
        for (s, x, y) in &paired {
            println!("  seed {s}: {x} / {y}");
        }
        let mean = |v: Vec<f64>| v.iter().sum::<f64>() / v.len().max(1) as f64;
        let ma = mean(paired.iter().map(|p| p.1).collect());
        let mr = mean(paired.iter().map(|p| p.2).collect());
        println!("ratio of the means: {:.2}", ma / mr);
    }
    let stem = out.with_extension("");
    let curves = SearchCurves {
        title: "Failing runs found (VIP hit) vs evaluations".into(),
        note: format!(
            "experiments/mission_search.toml, {budget} runs per search; mean over the search seeds with 95% CI band"
        ),
        y_desc: "failing runs found".into(),
        groups,
    };
    let files = plot_search_curves(&curves, &stem).map_err(|e| e.to_string())?;
    for f in files {
        eprintln!("wrote {}", f.display());
    }
    Ok(())
}
