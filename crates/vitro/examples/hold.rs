//! The hold benchmark: the event core's throughput with a steady number of pending events.
//!
//! `cargo run --release -p vitro --example hold -- PENDING EVENTS [--no-payload-trace] [--only PART]`
//!
//! PENDING events are queued at start, spread over [`AGENTS`] agents at times drawn from
//! Exp(mean 1 s). Every fired event's handler schedules one new event for its agent at
//! now + Exp(mean 1 s), drawn from the agent's own random stream, so the queue holds PENDING
//! events throughout. EVENTS events are fired through the real driver
//! ([`Simulation::run`]: control checks, trace hashing, dispatch to the agent, scheduling
//! through its [`Context`]) in the Simulation's default configuration (event payloads hashed
//! into the trace; `--no-payload-trace` turns that off).
//!
//! The same run is then repeated on a bare `std::collections::BinaryHeap` of
//! `(Reverse((time_ns, seq)), payload)` with the same random numbers: the floor, with no
//! driver, no trace and no cancellation handles. Its payload is what the model's events carry
//! (the agent and the event, 16 bytes). Last, the run is repeated on a bare [`EventQueue`]
//! with that payload, to tell the queue's cost from the driver's. All three runs fire the same
//! events in the same order, which the benchmark checks (same final time).
//!
//! Output, one per line: `events/s: X` (the simulation), `floor events/s: Y`, `peak RSS MiB: Z`
//! (the simulation's VmHWM), `ratio: X/Y`, then the floor's peak memory, the bare queue's rate,
//! and the three rates per second of CPU time (steadier than wall time on a loaded machine).
//!
//! `--only simulation`, `--only floor` or `--only queue` runs that part alone and prints its
//! rate: for counting one part's instructions and cache misses (`valgrind --tool=cachegrind`),
//! which a loaded machine cannot disturb.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;
use std::process::ExitCode;
use std::time::Instant;
use vitro::event::EventQueue;
use vitro::prelude::*;
use vitro::rng::Owner;

/// Number of agents the events are spread over.
const AGENTS: u32 = 16;
/// Mean of the exponential hold time, in nanoseconds (1 s).
const MEAN_NS: f64 = 1e9;
/// Master seed of both runs.
const SEED: u64 = 2024;

/// An Exp(mean 1 s) draw in nanoseconds.
fn exp_ns(rng: &mut ChaCha8Rng) -> u64 {
    let u: f64 = rng.random();
    (-libm::log(1.0 - u) * MEAN_NS) as u64
}

struct HoldModel;
impl Model for HoldModel {
    type Env = ();
    /// How many events led to this one.
    type Event = u64;
    type Msg = ();
    type Agent = Holder;
}

/// Reschedules every event it receives.
struct Holder;
impl Agent<HoldModel> for Holder {
    fn handle(&mut self, input: Input<'_, HoldModel>, cx: &mut Context<'_, HoldModel>) {
        if let Input::Event(&hops) = input {
            let dt = exp_ns(cx.rng("hold"));
            cx.schedule_in(SimDuration::from_nanos(dt), hops + 1);
        }
    }
}

/// The initial events: (agent index, time), the same for both runs (generated on the fly,
/// so that no list of them counts in the peak memory).
fn initial_events(pending: u64) -> impl Iterator<Item = (u32, u64)> {
    let mut rng = vitro::rng::RngStreams::new(SEED).fresh(Owner::Global, "hold-init");
    (0..pending).map(move |i| ((i % u64::from(AGENTS)) as u32, exp_ns(&mut rng)))
}

/// Runs the hold model through the simulation driver. Returns its duration and final time.
fn run_simulation(
    pending: u64,
    events: u64,
    trace_payloads: bool,
) -> Result<(Elapsed, SimTime), String> {
    let mut sim = Simulation::<HoldModel>::new((), SEED);
    sim.set_trace_payloads(trace_payloads);
    let agents: Vec<EntityId> = (0..AGENTS)
        .map(|i| sim.add_agent(format!("holder-{i}"), Holder))
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    for (a, t) in initial_events(pending) {
        sim.schedule(
            SimTime::from_nanos(t),
            Target::Entity(agents[a as usize]),
            0,
        )
        .map_err(|e| e.to_string())?;
    }
    let watch = Stopwatch::start();
    let stop = sim.run(SimTime::MAX, |s| s.events_fired() >= events);
    let secs = watch.stop();
    if stop != StopReason::Condition {
        return Err(format!("the run stopped early: {stop:?}"));
    }
    Ok((secs, sim.now()))
}

/// The payload the floor carries: what the model's events carry (a target and the event).
struct FloorEvent {
    agent: u32,
    hops: u64,
}

/// A floor entry, ordered by its key only (keys are unique: the sequence number breaks ties).
struct FloorEntry(Reverse<(u64, u64)>, FloorEvent);
impl PartialEq for FloorEntry {
    fn eq(&self, o: &Self) -> bool {
        self.0 == o.0
    }
}
impl Eq for FloorEntry {}
impl PartialOrd for FloorEntry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for FloorEntry {
    fn cmp(&self, o: &Self) -> Ordering {
        self.0.cmp(&o.0)
    }
}

/// The same hold model on a bare binary heap. Returns its duration and final time.
fn run_floor(pending: u64, events: u64) -> (Elapsed, SimTime) {
    let streams = vitro::rng::RngStreams::new(SEED);
    // Simulation entity ids are 0..AGENTS in creation order: the same streams as the agents'.
    let mut rngs: Vec<ChaCha8Rng> = (0..AGENTS)
        .map(|i| streams.fresh(Owner::Entity(EntityId(i)), "hold"))
        .collect();
    let mut heap = BinaryHeap::new();
    let mut seq = 0u64;
    for (agent, t) in initial_events(pending) {
        heap.push(FloorEntry(Reverse((t, seq)), FloorEvent { agent, hops: 0 }));
        seq += 1;
    }
    let mut now = 0;
    let watch = Stopwatch::start();
    for _ in 0..events {
        let Some(FloorEntry(Reverse((t, _)), ev)) = heap.pop() else {
            break;
        };
        now = t;
        let dt = exp_ns(&mut rngs[ev.agent as usize]);
        let next = FloorEvent {
            agent: ev.agent,
            hops: ev.hops + 1,
        };
        heap.push(FloorEntry(Reverse((t + dt, seq)), next));
        seq += 1;
    }
    let secs = watch.stop();
    (secs, SimTime::from_nanos(now))
}

/// The same hold model on a bare [`EventQueue`] (no driver). Returns its duration and final time.
fn run_bare_queue(pending: u64, events: u64) -> Result<(Elapsed, SimTime), String> {
    let streams = vitro::rng::RngStreams::new(SEED);
    let mut rngs: Vec<ChaCha8Rng> = (0..AGENTS)
        .map(|i| streams.fresh(Owner::Entity(EntityId(i)), "hold"))
        .collect();
    let mut queue = EventQueue::new();
    for (agent, t) in initial_events(pending) {
        queue
            .push(SimTime::from_nanos(t), FloorEvent { agent, hops: 0 })
            .map_err(|e| e.to_string())?;
    }
    let watch = Stopwatch::start();
    for _ in 0..events {
        let Some(p) = queue.pop() else {
            break;
        };
        let dt = exp_ns(&mut rngs[p.payload.agent as usize]);
        let next = FloorEvent {
            agent: p.payload.agent,
            hops: p.payload.hops + 1,
        };
        queue
            .push(p.time + SimDuration::from_nanos(dt), next)
            .map_err(|e| e.to_string())?;
    }
    let secs = watch.stop();
    Ok((secs, queue.now()))
}

/// A stopwatch of wall time and of the thread's CPU time (Linux; the CPU time shows what a
/// run costs when other processes compete for the cores).
struct Stopwatch {
    wall: Instant,
    cpu_ns: Option<u64>,
}

/// Seconds of a run: wall clock and, where known, CPU.
#[derive(Copy, Clone)]
struct Elapsed {
    wall: f64,
    cpu: Option<f64>,
}

/// The calling thread's CPU time in nanoseconds, from `/proc/thread-self/schedstat`.
fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

impl Stopwatch {
    fn start() -> Self {
        let cpu_ns = thread_cpu_ns();
        Stopwatch {
            wall: Instant::now(),
            cpu_ns,
        }
    }
    fn stop(&self) -> Elapsed {
        let wall = self.wall.elapsed().as_secs_f64();
        let cpu = self
            .cpu_ns
            .zip(thread_cpu_ns())
            .map(|(a, b)| b.saturating_sub(a) as f64 * 1e-9);
        Elapsed { wall, cpu }
    }
}

/// The process's peak resident memory (VmHWM) in MiB.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Resets the peak-RSS mark (Linux); false where that is not possible.
fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

fn main() -> ExitCode {
    const USAGE: &str =
        "usage: hold PENDING EVENTS [--no-payload-trace] [--only simulation|floor|queue]";
    let args: Vec<String> = std::env::args().skip(1).collect();
    let trace_payloads = !args.iter().any(|a| a == "--no-payload-trace");
    let only = args
        .iter()
        .position(|a| a == "--only")
        .map(|i| args.get(i + 1).map(String::as_str));
    let nums: Vec<&String> = args
        .iter()
        .enumerate()
        .filter(|(i, a)| !a.starts_with("--") && (*i == 0 || args[i - 1] != "--only"))
        .map(|(_, a)| a)
        .collect();
    let parse = |i: usize, default: u64| -> Result<u64, String> {
        nums.get(i)
            .map_or(Ok(default), |s| s.parse().map_err(|e| format!("{s}: {e}")))
    };
    let (pending, events) = match (parse(0, 1000), parse(1, 2_000_000)) {
        (Ok(p), Ok(e)) if p > 0 => (p, e),
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("{USAGE} ({e})");
            return ExitCode::FAILURE;
        }
        _ => {
            eprintln!("{USAGE} (PENDING must be > 0)");
            return ExitCode::FAILURE;
        }
    };
    if let Some(part) = only {
        let run = match part {
            Some("simulation") => run_simulation(pending, events, trace_payloads),
            Some("floor") => Ok(run_floor(pending, events)),
            Some("queue") => run_bare_queue(pending, events),
            _ => Err(format!("--only takes simulation, floor or queue; {USAGE}")),
        };
        return match run {
            Ok((time, end)) => {
                println!("events/s: {:.0}", events as f64 / time.wall);
                println!("end: {end}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("hold: {e}");
                ExitCode::FAILURE
            }
        };
    }

    let (sim_time, sim_end) = match run_simulation(pending, events, trace_payloads) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("hold: {e}");
            return ExitCode::FAILURE;
        }
    };
    let peak = peak_rss_mib();
    let floor_peak_known = reset_peak_rss();
    let (floor_time, floor_end) = run_floor(pending, events);
    let floor_peak = peak_rss_mib().filter(|_| floor_peak_known);
    let (bare_time, bare_end) = match run_bare_queue(pending, events) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("hold: {e}");
            return ExitCode::FAILURE;
        }
    };

    let ev = events as f64;
    println!("events/s: {:.0}", ev / sim_time.wall);
    println!("floor events/s: {:.0}", ev / floor_time.wall);
    match peak {
        Some(p) => println!("peak RSS MiB: {p:.1}"),
        None => println!("peak RSS MiB: unknown"),
    }
    println!("ratio: {:.2}", floor_time.wall / sim_time.wall);
    if let Some(p) = floor_peak {
        println!("floor peak RSS MiB: {p:.1}");
    }
    println!("bare queue events/s: {:.0}", ev / bare_time.wall);
    if let (Some(sim), Some(floor), Some(bare)) = (sim_time.cpu, floor_time.cpu, bare_time.cpu) {
        println!(
            "per CPU second: events/s {:.0}, floor {:.0}, bare queue {:.0}, ratio {:.2}",
            ev / sim,
            ev / floor,
            ev / bare,
            floor / sim
        );
    }
    println!(
        "pending: {pending}, events: {events}, payload trace: {}",
        if trace_payloads { "on" } else { "off" }
    );
    if sim_end != floor_end || bare_end != floor_end {
        eprintln!(
            "hold: the runs disagree: simulation ended at {sim_end}, bare queue at {bare_end}, \
             floor at {floor_end}"
        );
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
