//! The hold benchmark: the event core's throughput with a steady number of pending events.
//!
//! `cargo run --release -p vitro --example hold -- PENDING EVENTS [--no-payload-trace]
//! [--slice N] [--only PART]`
//!
//! PENDING events are queued at start, spread over [`AGENTS`] agents at times drawn from
//! Exp(mean 1 s). Every fired event's handler schedules one new event for its agent at
//! now + Exp(mean 1 s), drawn from the agent's own random stream, so the queue holds PENDING
//! events throughout. EVENTS events are fired through the real driver
//! ([`Simulation::run`]: control checks, trace hashing, dispatch to the agent, scheduling
//! through its [`Context`]) in the Simulation's default configuration (event payloads hashed
//! into the trace; `--no-payload-trace` turns that off).
//!
//! The same events are fired on a bare `std::collections::BinaryHeap` of
//! `(Reverse((time_ns, seq)), payload)` with the same random numbers: the floor, with no
//! driver, no trace and no cancellation handles. Its payload is what the model's events carry
//! (the agent and the event, 16 bytes). And on a bare [`EventQueue`] with that payload, to
//! tell the queue's cost from the driver's. All three fire the same events in the same order,
//! which the benchmark checks (same final time).
//!
//! The three run side by side: set up one after the other, then in turn, SLICE events at a
//! time (default 200,000; the order of the three rotates every slice), so that a change of
//! load on the machine falls on all three alike. Each part's time is the sum of its slices.
//!
//! Output, one per line: `events/s: X` (the simulation), `floor events/s: Y`, `peak RSS MiB: Z`
//! (the simulation's VmHWM after its set-up and first slice, before the others exist),
//! `ratio: X/Y`, then the floor's own peak memory (the growth of VmHWM over its set-up and
//! first slice), the bare queue's rate, the three rates per second of CPU time (steadier
//! than wall time on a loaded machine), the ratio of every slice per CPU second and their
//! median (the figure least moved by a burst of load on the machine). CPU time is the
//! thread's own (`CLOCK_THREAD_CPUTIME_ID`, exact to the nanosecond).
//!
//! `--only simulation`, `--only floor` or `--only queue` runs that part alone and prints its
//! rate: for counting one part's instructions and cache misses (`valgrind --tool=cachegrind`,
//! `scripts/hold_counts.py`), which a loaded machine cannot disturb.

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

/// The hold model through the simulation driver.
struct SimPart {
    sim: Simulation<HoldModel>,
}

impl SimPart {
    fn new(pending: u64, trace_payloads: bool) -> Result<Self, String> {
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
        Ok(SimPart { sim })
    }

    /// Fires `n` more events.
    fn advance(&mut self, n: u64) -> Result<(), String> {
        let target = self.sim.events_fired() + n;
        let stop = self.sim.run(SimTime::MAX, |s| s.events_fired() >= target);
        if stop != StopReason::Condition {
            return Err(format!("the run stopped early: {stop:?}"));
        }
        Ok(())
    }

    fn now(&self) -> SimTime {
        self.sim.now()
    }
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

/// The same hold model on a bare binary heap.
struct FloorPart {
    rngs: Vec<ChaCha8Rng>,
    heap: BinaryHeap<FloorEntry>,
    seq: u64,
    now: u64,
}

impl FloorPart {
    fn new(pending: u64) -> Self {
        let streams = vitro::rng::RngStreams::new(SEED);
        // Simulation entity ids are 0..AGENTS in creation order: the same streams as the agents'.
        let rngs: Vec<ChaCha8Rng> = (0..AGENTS)
            .map(|i| streams.fresh(Owner::Entity(EntityId(i)), "hold"))
            .collect();
        let mut heap = BinaryHeap::new();
        let mut seq = 0u64;
        for (agent, t) in initial_events(pending) {
            heap.push(FloorEntry(Reverse((t, seq)), FloorEvent { agent, hops: 0 }));
            seq += 1;
        }
        FloorPart {
            rngs,
            heap,
            seq,
            now: 0,
        }
    }

    /// Fires `n` more events.
    fn advance(&mut self, n: u64) {
        for _ in 0..n {
            let Some(FloorEntry(Reverse((t, _)), ev)) = self.heap.pop() else {
                break;
            };
            self.now = t;
            let dt = exp_ns(&mut self.rngs[ev.agent as usize]);
            let next = FloorEvent {
                agent: ev.agent,
                hops: ev.hops + 1,
            };
            self.heap
                .push(FloorEntry(Reverse((t + dt, self.seq)), next));
            self.seq += 1;
        }
    }

    fn now(&self) -> SimTime {
        SimTime::from_nanos(self.now)
    }
}

/// The same hold model on a bare [`EventQueue`] (no driver).
struct QueuePart {
    rngs: Vec<ChaCha8Rng>,
    queue: EventQueue<FloorEvent>,
}

impl QueuePart {
    fn new(pending: u64) -> Result<Self, String> {
        let streams = vitro::rng::RngStreams::new(SEED);
        let rngs: Vec<ChaCha8Rng> = (0..AGENTS)
            .map(|i| streams.fresh(Owner::Entity(EntityId(i)), "hold"))
            .collect();
        let mut queue = EventQueue::new();
        for (agent, t) in initial_events(pending) {
            queue
                .push(SimTime::from_nanos(t), FloorEvent { agent, hops: 0 })
                .map_err(|e| e.to_string())?;
        }
        Ok(QueuePart { rngs, queue })
    }

    /// Fires `n` more events.
    fn advance(&mut self, n: u64) -> Result<(), String> {
        for _ in 0..n {
            let Some(p) = self.queue.pop() else {
                break;
            };
            let dt = exp_ns(&mut self.rngs[p.payload.agent as usize]);
            let next = FloorEvent {
                agent: p.payload.agent,
                hops: p.payload.hops + 1,
            };
            self.queue
                .push(p.time + SimDuration::from_nanos(dt), next)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    fn now(&self) -> SimTime {
        self.queue.now()
    }
}

/// The three parts, in the order of [`PARTS`].
struct Parts {
    sim: SimPart,
    floor: FloorPart,
    queue: QueuePart,
}

/// The parts' names, for `--only`.
const PARTS: [&str; 3] = ["simulation", "floor", "queue"];

impl Parts {
    /// Fires `n` more events of part `i` and returns how long that took.
    fn advance(&mut self, i: usize, n: u64) -> Result<Elapsed, String> {
        match i {
            0 => timed(|| self.sim.advance(n)),
            1 => timed(|| {
                self.floor.advance(n);
                Ok(())
            }),
            _ => timed(|| self.queue.advance(n)),
        }
    }
}

/// How long `f` took, or its error.
fn timed(f: impl FnOnce() -> Result<(), String>) -> Result<Elapsed, String> {
    let watch = Stopwatch::start();
    f()?;
    Ok(watch.stop())
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

impl Elapsed {
    const ZERO: Elapsed = Elapsed {
        wall: 0.0,
        cpu: Some(0.0),
    };

    fn add(self, o: Elapsed) -> Elapsed {
        Elapsed {
            wall: self.wall + o.wall,
            cpu: self.cpu.zip(o.cpu).map(|(a, b)| a + b),
        }
    }
}

/// The calling thread's CPU time in nanoseconds (`CLOCK_THREAD_CPUTIME_ID`: exact to the
/// nanosecond, where `/proc/thread-self/schedstat` advances in scheduler ticks of 4 ms on the
/// development VM, too coarse for a slice of a few tens of milliseconds).
fn thread_cpu_ns() -> Option<u64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes the timespec it is given, which lives on this stack.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    let (s, ns) = (
        u64::try_from(ts.tv_sec).ok()?,
        u64::try_from(ts.tv_nsec).ok()?,
    );
    (rc == 0).then_some(s * 1_000_000_000 + ns)
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

/// A memory figure of this process from `/proc/self/status` (Linux), in MiB.
fn status_mib(key: &str) -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// The process's peak resident memory (VmHWM) in MiB.
fn peak_rss_mib() -> Option<f64> {
    status_mib("VmHWM:")
}

/// The process's resident memory now (VmRSS) in MiB.
fn current_rss_mib() -> Option<f64> {
    status_mib("VmRSS:")
}

/// Resets the peak-RSS mark (Linux); false where that is not possible.
fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// The command line.
struct Args {
    pending: u64,
    events: u64,
    slice: u64,
    trace_payloads: bool,
    only: Option<usize>,
}

const USAGE: &str = "usage: hold PENDING EVENTS [--no-payload-trace] [--slice N] \
                     [--only simulation|floor|queue]";

fn parse_args(args: &[String]) -> Result<Args, String> {
    let mut nums = Vec::new();
    let (mut slice, mut trace_payloads, mut only) = (200_000, true, None);
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--no-payload-trace" => trace_payloads = false,
            "--slice" => {
                let v = it.next().ok_or("--slice takes a number")?;
                slice = v.parse().map_err(|e| format!("--slice {v}: {e}"))?;
            }
            "--only" => {
                let v = it.next().map_or("", String::as_str);
                only = Some(
                    PARTS
                        .iter()
                        .position(|p| *p == v)
                        .ok_or("--only takes simulation, floor or queue")?,
                );
            }
            _ if a.starts_with("--") => return Err(format!("unknown option {a}")),
            _ => nums.push(a.parse::<u64>().map_err(|e| format!("{a}: {e}"))?),
        }
    }
    let pending = nums.first().copied().unwrap_or(1000);
    let events = nums.get(1).copied().unwrap_or(2_000_000);
    if pending == 0 || slice == 0 || nums.len() > 2 {
        return Err("PENDING and the slice must be > 0, and at most two numbers".into());
    }
    Ok(Args {
        pending,
        events,
        slice,
        trace_payloads,
        only,
    })
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let a = match parse_args(&args) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{USAGE} ({e})");
            return ExitCode::FAILURE;
        }
    };
    match run(&a) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("hold: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs one part alone (`--only`): its rate and final time.
fn run_only(a: &Args, part: usize) -> Result<bool, String> {
    let n = a.events;
    let time = match part {
        0 => {
            let mut p = SimPart::new(a.pending, a.trace_payloads)?;
            (timed(|| p.advance(n))?, p.now())
        }
        1 => {
            let mut p = FloorPart::new(a.pending);
            (
                timed(|| {
                    p.advance(n);
                    Ok(())
                })?,
                p.now(),
            )
        }
        _ => {
            let mut p = QueuePart::new(a.pending)?;
            (timed(|| p.advance(n))?, p.now())
        }
    };
    println!("events/s: {:.0}", a.events as f64 / time.0.wall);
    println!("end: {}", time.1);
    Ok(true)
}

/// Runs the three parts side by side and prints the figures; false if they disagree.
fn run(a: &Args) -> Result<bool, String> {
    if let Some(part) = a.only {
        return run_only(a, part);
    }
    let first = a.slice.min(a.events);
    let mut spent = [Elapsed::ZERO; 3];
    let mut slices: Vec<[Elapsed; 3]> = Vec::new();
    let mut this = [Elapsed::ZERO; 3];

    // Set up each part and run its first slice before the next exists, for its peak memory.
    let mut sim = SimPart::new(a.pending, a.trace_payloads)?;
    this[0] = timed(|| sim.advance(first))?;
    let peak = peak_rss_mib();
    let floor_base = reset_peak_rss().then(current_rss_mib).flatten();
    let mut floor = FloorPart::new(a.pending);
    this[1] = timed(|| {
        floor.advance(first);
        Ok(())
    })?;
    let floor_peak = floor_base.zip(peak_rss_mib()).map(|(b, p)| p - b);
    let mut queue = QueuePart::new(a.pending)?;
    this[2] = timed(|| queue.advance(first))?;
    slices.push(this);
    let mut parts = Parts { sim, floor, queue };

    let mut done = first;
    while done < a.events {
        let n = a.slice.min(a.events - done);
        let k = slices.len();
        for j in 0..3 {
            let i = (j + k) % 3;
            this[i] = parts.advance(i, n)?;
        }
        slices.push(this);
        done += n;
    }
    for s in &slices {
        for i in 0..3 {
            spent[i] = spent[i].add(s[i]);
        }
    }
    let [sim_time, floor_time, bare_time] = spent;

    let ev = a.events as f64;
    println!("events/s: {:.0}", ev / sim_time.wall);
    println!("floor events/s: {:.0}", ev / floor_time.wall);
    match peak {
        Some(p) => println!("peak RSS MiB: {p:.1}"),
        None => println!("peak RSS MiB: unknown"),
    }
    println!("ratio: {:.2}", floor_time.wall / sim_time.wall);
    if let Some(p) = floor_peak {
        println!("floor peak RSS MiB: {p:.1} (growth over its set-up and first slice)");
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
        let mut per: Vec<f64> = slices
            .iter()
            .filter_map(|s| s[1].cpu.zip(s[0].cpu).map(|(f, m)| f / m))
            .collect();
        let text: Vec<String> = per.iter().map(|r| format!("{r:.2}")).collect();
        println!("ratio per CPU second, slice by slice: {}", text.join(" "));
        per.sort_by(f64::total_cmp);
        if let (Some(lo), Some(hi)) = (per.first(), per.last()) {
            let mid = per.len() / 2;
            let median = if per.len() % 2 == 1 {
                per[mid]
            } else {
                0.5 * (per[mid - 1] + per[mid])
            };
            println!(
                "ratio per CPU second, median of {} slices: {median:.2} (range {lo:.2}-{hi:.2})",
                per.len()
            );
        }
    }
    println!(
        "pending: {}, events: {}, slice: {}, payload trace: {}",
        a.pending,
        a.events,
        a.slice,
        if a.trace_payloads { "on" } else { "off" }
    );
    let (sim_end, floor_end, bare_end) = (parts.sim.now(), parts.floor.now(), parts.queue.now());
    if sim_end != floor_end || bare_end != floor_end {
        eprintln!(
            "hold: the runs disagree: simulation ended at {sim_end}, bare queue at {bare_end}, \
             floor at {floor_end}"
        );
        return Ok(false);
    }
    Ok(true)
}
