//! Times the three ABM comparison models on Vitro: for each model and size, `RUNS` runs
//! with seeds 1..=RUNS (each timed from building the model to the end of its last step),
//! and prints the median wall time with the medians of the model's statistics.
//!
//! `cargo run --release -p vitro-abm --example abm_bench -- [RUNS] [MODEL-SIZE ...]`
//!
//! `MODEL-SIZE`: `flocking-small`, `flocking-large`, `schelling-small`, `schelling-large`,
//! `wolfsheep-small`, `wolfsheep-large` (default: all). One line each:
//!
//! `vitro schelling small median_ms 12.3 cpu_ms 12.1 happy 0.912 ...` (wall and thread CPU
//! time medians)
//!
//! The statistics: Schelling's share of happy households after 20 steps; Flocking's
//! polarisation (length of the mean unit velocity) and mean neighbour count after 100 steps;
//! WolfSheep's sheep and wolves after 100 steps (and the step the wolves died out, if they
//! did). `scripts/abm_compare.sh` prints them next to krABMaga's.

use std::time::Instant;
use vitro_abm::flocking::{self, Flocking};
use vitro_abm::median;
use vitro_abm::schelling::{self, Schelling};
use vitro_abm::wolfsheep::{self, WolfSheep};

/// The calling thread's CPU time in milliseconds (`CLOCK_THREAD_CPUTIME_ID`: steadier than
/// wall time on a loaded machine, and exact to the nanosecond; NaN where unavailable).
fn thread_cpu_ms() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes the timespec it is given, which lives on this stack.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc == 0 {
        ts.tv_sec as f64 * 1e3 + ts.tv_nsec as f64 / 1e6
    } else {
        f64::NAN
    }
}

/// Times `f` over seeds `1..=runs`; returns the median wall and CPU milliseconds and the
/// statistics of each run.
fn bench<T>(runs: u64, mut f: impl FnMut(u64) -> T) -> ((f64, f64), Vec<T>) {
    let (mut times, mut cpu) = (Vec::new(), Vec::new());
    let mut outs = Vec::new();
    for seed in 1..=runs {
        let (t, c) = (Instant::now(), thread_cpu_ms());
        let out = f(seed);
        times.push(t.elapsed().as_secs_f64() * 1e3);
        cpu.push(thread_cpu_ms() - c);
        outs.push(out);
    }
    ((median(&times), median(&cpu)), outs)
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let runs: u64 = match args.first() {
        Some(a) => a
            .parse()
            .map_err(|_| format!("RUNS must be a number, not `{a}`"))?,
        None => 100,
    };
    let all = [
        "flocking-small",
        "flocking-large",
        "schelling-small",
        "schelling-large",
        "wolfsheep-small",
        "wolfsheep-large",
    ];
    let cases: Vec<&str> = if args.len() > 1 {
        args[1..].iter().map(String::as_str).collect()
    } else {
        all.to_vec()
    };
    for case in cases {
        let (model, size) = case
            .split_once('-')
            .ok_or(format!("`{case}` is not MODEL-SIZE"))?;
        let large = match size {
            "small" => false,
            "large" => true,
            other => return Err(format!("unknown size `{other}`")),
        };
        let line = match model {
            "schelling" => {
                let p = if large {
                    Schelling::LARGE
                } else {
                    Schelling::SMALL
                };
                let ((ms, cpu), outs) = bench(runs, |s| schelling::run(&p, s));
                let happy: Vec<f64> = outs
                    .iter()
                    .map(|o| f64::from(o.happy) / f64::from(o.agents))
                    .collect();
                format!(
                    "median_ms {ms:.3} cpu_ms {cpu:.3} happy {:.3}",
                    median(&happy)
                )
            }
            "flocking" => {
                let p = if large {
                    Flocking::LARGE
                } else {
                    Flocking::SMALL
                };
                let ((ms, cpu), outs) = bench(runs, |s| flocking::run(&p, s));
                let pol: Vec<f64> = outs.iter().map(|o| o.polarisation).collect();
                let nb: Vec<f64> = outs.iter().map(|o| o.neighbours).collect();
                format!(
                    "median_ms {ms:.3} cpu_ms {cpu:.3} polarisation {:.3} neighbours {:.2}",
                    median(&pol),
                    median(&nb)
                )
            }
            "wolfsheep" => {
                let p = if large {
                    WolfSheep::LARGE
                } else {
                    WolfSheep::SMALL
                };
                let ((ms, cpu), outs) = bench(runs, |s| wolfsheep::run(&p, s));
                let last = |o: &wolfsheep::Outcome| o.counts.last().copied().unwrap_or((0, 0));
                let sheep: Vec<f64> = outs.iter().map(|o| f64::from(last(o).0)).collect();
                let wolves: Vec<f64> = outs.iter().map(|o| f64::from(last(o).1)).collect();
                let peak: Vec<f64> = outs
                    .iter()
                    .map(|o| {
                        f64::from(o.counts.iter().map(|c| c.0).max().unwrap_or(0).max(p.sheep))
                    })
                    .collect();
                format!(
                    "median_ms {ms:.3} cpu_ms {cpu:.3} sheep {:.0} wolves {:.0} sheep_peak {:.0}",
                    median(&sheep),
                    median(&wolves),
                    median(&peak)
                )
            }
            other => return Err(format!("unknown model `{other}`")),
        };
        println!("vitro {model} {size} {line}");
    }
    Ok(())
}
