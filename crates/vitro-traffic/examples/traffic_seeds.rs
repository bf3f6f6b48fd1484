//! The traffic scenario (`scenarios/traffic.toml`: 20 vehicles, 10 troopers) at the physical
//! level over many seeds, each beside the same seed at the calibrated discrete level: stalls
//! per 20 vehicle-hours (with a 95 % Poisson interval), the longest commanded wait, and the
//! physical trip times against the discrete level's for the same trips.
//!
//! `cargo run --release -p vitro-traffic --example traffic_seeds [FIRST_SEED] [LAST_SEED] [SIM_SECONDS]`
//!
//! Trip k of a vehicle goes to the same destination at both levels (each vehicle draws its
//! destinations from its own stream); it is compared while neither level has stalled that
//! vehicle before it (a stall changes where the next trip starts).

use std::path::PathBuf;
use std::time::Instant;
use vitro::time::SimTime;
use vitro_mission::Run;
use vitro_tactical::actuate::by_level::Drive;
use vitro_tactical::scenario::Preset;
use vitro_traffic::{Streets, Tour, TrafficRun};

fn run(
    text: &str,
    seed: u64,
    preset: Preset,
    secs: u64,
) -> Result<TrafficRun, Box<dyn std::error::Error>> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/traffic.toml");
    let mut run = Streets::from_text(&path, text, Some(seed), Some(preset))?;
    let end = SimTime::from_secs(secs);
    Run::set_end(&mut run, end);
    while Run::advance(&mut run, end)? {}
    Ok(run)
}

/// Each vehicle's trips (durations, seconds) before its first stall.
fn clean_trips(run: &TrafficRun) -> Vec<Vec<f64>> {
    (run.members.iter())
        .filter_map(|m| run.sim.agent(m.id)?.as_any().downcast_ref::<Tour<Drive>>())
        .map(|t| {
            let first_stall = t.stalls.first().map_or(SimTime::MAX, |s| s.0);
            (t.trips.iter())
                .filter(|(_, end)| *end <= first_stall)
                .map(|(a, b)| (*b - *a).as_secs_f64())
                .collect()
        })
        .collect()
}

fn metric(run: &TrafficRun, name: &str) -> f64 {
    (Run::metrics(run).into_iter())
        .find(|(k, _)| *k == name)
        .and_then(|(_, v)| v.number())
        .unwrap_or(f64::NAN)
}

/// P(X <= k) for X ~ Poisson(mu), its terms summed in log space (no underflow for large
/// `mu`).
fn poisson_cdf(k: u64, mu: f64) -> f64 {
    if mu <= 0.0 {
        return 1.0;
    }
    let ln_mu = libm::log(mu);
    (0..=k)
        .map(|i| libm::exp(-mu + i as f64 * ln_mu - libm::lgamma(i as f64 + 1.0)))
        .sum()
}

/// The exact (Garwood) 95 % interval of a Poisson mean from `k` events.
fn poisson_interval(k: u64) -> (f64, f64) {
    let solve = |f: &dyn Fn(f64) -> f64| {
        let (mut lo, mut hi) = (0.0, 10.0 + 10.0 * k as f64);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if f(mid) > 0.0 { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    };
    // P(X >= k) rises with mu, P(X <= k) falls: each crosses 0.025 once.
    let lower = if k == 0 {
        0.0
    } else {
        solve(&|mu| 0.025 - (1.0 - poisson_cdf(k - 1, mu)))
    };
    let upper = solve(&|mu| poisson_cdf(k, mu) - 0.025);
    (lower, upper)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let first: u64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(1);
    let last: u64 = args
        .next()
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(first + 4);
    let secs: u64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(3600);
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/traffic.toml");
    let text = std::fs::read_to_string(&path)?;
    println!(
        "seed  trips  stalls  stalled_vehicles  spent  deadlock_s  mean_trip_s  discrete_trip_s  paired_ratio  wall_s"
    );
    let (mut stalls, mut vh, mut worst, mut ratios) = (0u64, 0.0, 0.0f64, Vec::new());
    let (mut stalled, mut vehicles, mut waits_over_60) = (0u64, 0u64, 0u64);
    for seed in first..=last {
        let t0 = Instant::now();
        let phys = run(&text, seed, Preset::Physical, secs)?;
        let disc = run(&text, seed, Preset::Discrete, secs)?;
        let (p, d) = (clean_trips(&phys), clean_trips(&disc));
        let (mut sp, mut sd) = (0.0, 0.0);
        for (a, b) in p.iter().zip(&d) {
            for (x, y) in a.iter().zip(b) {
                sp += x;
                sd += y;
            }
        }
        let ratio = if sd > 0.0 { sp / sd } else { f64::NAN };
        ratios.push(ratio);
        let s = metric(&phys, "stalls") as u64;
        stalls += s;
        vh += metric(&phys, "vehicle_hours");
        worst = worst.max(metric(&phys, "deadlock_s"));
        waits_over_60 += u64::from(metric(&phys, "deadlock_s") > 60.0);
        stalled += metric(&phys, "vehicles_stalled") as u64;
        vehicles += metric(&phys, "vehicles") as u64;
        println!(
            "{seed:>4}  {:>5}  {s:>6}  {:>16}  {:>5}  {:>10.0}  {:>11.1}  {:>15.1}  {ratio:>12.3}  {:>6.0}",
            metric(&phys, "trips_completed"),
            metric(&phys, "vehicles_stalled"),
            metric(&phys, "stalls_recovery_spent"),
            metric(&phys, "deadlock_s"),
            metric(&phys, "mean_trip_s"),
            metric(&disc, "mean_trip_s"),
            t0.elapsed().as_secs_f64()
        );
    }
    let n = ratios.len() as f64;
    let mean = ratios.iter().sum::<f64>() / n;
    let sd = libm::sqrt(
        ratios.iter().map(|r| (r - mean) * (r - mean)).sum::<f64>() / (n - 1.0).max(1.0),
    );
    let (lo, hi) = poisson_interval(stalls);
    let per = |x: f64| x * 20.0 / vh.max(1e-9);
    println!(
        "vehicles that stalled at least once: {stalled} of {vehicles}; runs with a wait over 60 s: {waits_over_60} of {n}"
    );
    println!(
        "seeds {first}..={last} ({n} runs, {vh:.1} vehicle-hours): {stalls} stalls = {:.2} per 20 vehicle-hours (95 % {:.2}..{:.2}); longest wait {worst:.0} s; physical / discrete trip time {mean:.3} +- {:.3} (95 %, over seeds)",
        per(stalls as f64),
        per(lo),
        per(hi),
        1.96 * sd / libm::sqrt(n)
    );
    Ok(())
}
