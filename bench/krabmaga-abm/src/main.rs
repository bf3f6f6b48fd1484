//! The ABM comparison's models with krABMaga 0.6: for each model and size, `RUNS` runs with
//! seeds 1..=RUNS, each timed from building the model to the end of its last step; prints
//! the median wall time and the medians of the statistics, in the format of Vitro's
//! `abm_bench` example (`crates/vitro-abm/examples/abm_bench.rs`).
//!
//! `krabmaga-abm [RUNS] [MODEL-SIZE ...]`

mod flocking;
mod schelling;
mod wolfsheep;

use std::time::Instant;

/// A parameter set of the declarations.
#[derive(Copy, Clone)]
pub enum Size {
    Small,
    Large,
}

/// The statistics of one run.
pub enum Outcome {
    Flocking { polarisation: f64, neighbours: f64 },
    Schelling { happy: f64 },
    WolfSheep { sheep: u32, wolves: u32, peak: u32 },
}

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

fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let runs: u64 = match args.first() {
        Some(a) => a.parse().map_err(|_| format!("RUNS must be a number, not `{a}`"))?,
        None => 100,
    };
    let all = ["flocking-small", "flocking-large", "schelling-small", "schelling-large", "wolfsheep-small", "wolfsheep-large"];
    let cases: Vec<&str> = if args.len() > 1 { args[1..].iter().map(String::as_str).collect() } else { all.to_vec() };
    for case in cases {
        let (model, size) = case.split_once('-').ok_or(format!("`{case}` is not MODEL-SIZE"))?;
        let s = match size {
            "small" => Size::Small,
            "large" => Size::Large,
            other => return Err(format!("unknown size `{other}`")),
        };
        let run: fn(Size, u64) -> Outcome = match model {
            "flocking" => flocking::run,
            "schelling" => schelling::run,
            "wolfsheep" => wolfsheep::run,
            other => return Err(format!("unknown model `{other}`")),
        };
        let (mut times, mut cpu, mut outs) = (Vec::new(), Vec::new(), Vec::new());
        for seed in 1..=runs {
            let (t, c) = (Instant::now(), thread_cpu_ms());
            outs.push(run(s, seed));
            times.push(t.elapsed().as_secs_f64() * 1e3);
            cpu.push(thread_cpu_ms() - c);
        }
        let (ms, cpu) = (median(&times), median(&cpu));
        let stat = |f: &dyn Fn(&Outcome) -> Option<f64>| median(&outs.iter().filter_map(f).collect::<Vec<_>>());
        let line = match model {
            "flocking" => format!(
                "median_ms {ms:.3} cpu_ms {cpu:.3} polarisation {:.3} neighbours {:.2}",
                stat(&|o| if let Outcome::Flocking { polarisation, .. } = o { Some(*polarisation) } else { None }),
                stat(&|o| if let Outcome::Flocking { neighbours, .. } = o { Some(*neighbours) } else { None }),
            ),
            "schelling" => format!(
                "median_ms {ms:.3} cpu_ms {cpu:.3} happy {:.3}",
                stat(&|o| if let Outcome::Schelling { happy } = o { Some(*happy) } else { None }),
            ),
            _ => format!(
                "median_ms {ms:.3} cpu_ms {cpu:.3} sheep {:.0} wolves {:.0} sheep_peak {:.0}",
                stat(&|o| if let Outcome::WolfSheep { sheep, .. } = o { Some(f64::from(*sheep)) } else { None }),
                stat(&|o| if let Outcome::WolfSheep { wolves, .. } = o { Some(f64::from(*wolves)) } else { None }),
                stat(&|o| if let Outcome::WolfSheep { peak, .. } = o { Some(f64::from(*peak)) } else { None }),
            ),
        };
        println!("krabmaga {model} {size} {line}");
    }
    Ok(())
}
