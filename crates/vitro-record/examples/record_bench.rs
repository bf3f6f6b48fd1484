//! Recording and replay speed and size for a long run.
//!
//! ```sh
//! cargo run --release -p vitro-record --example record_bench -- [FRAMES] [ENTITIES]
//! ```
//!
//! Defaults: 3600 frames (an hour at 1 Hz) of 40 synthetic entities. Frames are made first,
//! then recorded to a temporary file (with and without the Foxglove channels); then the
//! recording is opened (from its summary and by a full scan), seeked at random, read in
//! order, and, for comparison with the index, loaded whole into memory.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use vitro_record::{Frame, RecordOptions, Recorder, Replay, synthetic};

/// The system allocator, counting the bytes live.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract is passed on.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract is passed on.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// CPU seconds this process has used (Linux: /proc/self/stat; `None` elsewhere). The
/// recorder is single-threaded, so on a busy machine this is the fairer figure.
fn cpu_s() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold spaces) start at ") ".
    let rest = stat.rsplit_once(") ")?.1;
    let fields: Vec<&str> = rest.split(' ').collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    // Clock ticks are 1/100 s on Linux.
    Some(ticks / 100.0)
}

/// Wall and CPU seconds of `f`.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64, Option<f64>) {
    let (cpu0, start) = (cpu_s(), Instant::now());
    let out = f();
    let cpu = cpu_s().zip(cpu0).map(|(b, a)| b - a);
    (out, start.elapsed().as_secs_f64(), cpu)
}

fn cpu_text(cpu: Option<f64>) -> String {
    cpu.map_or_else(String::new, |c| format!(", {c:.2} s CPU"))
}

fn mb(bytes: u64) -> String {
    format!("{:.1} MB", bytes as f64 / 1e6)
}

/// Records `frames`: (wall s, CPU s, file size, JSON payload bytes).
fn record(
    path: &std::path::Path,
    frames: &[Frame],
    options: &RecordOptions,
) -> (f64, Option<f64>, u64, u64) {
    let scene = synthetic::scene();
    let (payload, wall, cpu) = timed(|| {
        let mut rec = Recorder::create_with(path, &scene, options).expect("create");
        for f in frames {
            rec.frame(f).expect("frame");
        }
        let payload = rec.stats().payload_bytes;
        rec.finish().expect("finish");
        payload
    });
    let size = std::fs::metadata(path).expect("file").len();
    (wall, cpu, size, payload)
}

fn main() {
    let args: Vec<u64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let n = args.first().copied().unwrap_or(3600);
    let entities = args.get(1).copied().unwrap_or(40) as usize;
    let scene = synthetic::scene();
    let frames: Vec<Frame> = (0..n)
        .map(|i| synthetic::frame(&scene, i, entities))
        .collect();
    println!(
        "record_bench: {n} frames ({:.2} h at 1 Hz), {entities} entities, synthetic town",
        n as f64 / 3600.0
    );
    let path = std::env::temp_dir().join(format!("vitro-record-bench-{}.mcap", std::process::id()));
    let vitro_only = RecordOptions {
        foxglove: false,
        ..RecordOptions::default()
    };
    for (what, options) in [
        ("Foxglove + Vitro channels", RecordOptions::default()),
        ("Vitro channels only", vitro_only),
    ] {
        let (wall, cpu, size, payload) = record(&path, &frames, &options);
        let per_cpu = cpu.map_or_else(String::new, |c| {
            format!(", {:.0} per CPU second", n as f64 / c)
        });
        println!(
            "write, {what}: {:.0} frames/s ({wall:.2} s wall{}){per_cpu}; {:.0} bytes/frame, file {} ({} of JSON before zstd)",
            n as f64 / wall,
            cpu_text(cpu),
            size as f64 / n as f64,
            mb(size),
            mb(payload)
        );
    }
    // The full recording for the reading side.
    record(&path, &frames, &RecordOptions::default());

    let before = LIVE.load(Ordering::Relaxed);
    let start = Instant::now();
    let mut replay = Replay::open(&path).expect("open");
    let open_s = start.elapsed().as_secs_f64();
    let index_bytes = LIVE.load(Ordering::Relaxed).saturating_sub(before);
    let (scanned, scan_s, scan_cpu) = timed(|| Replay::scan(&path).expect("scan"));
    assert_eq!(scanned.len(), replay.len());
    drop(scanned);
    println!(
        "open: {:.1} ms from the summary (index and scene: {}), {:.0} ms by a full scan{}",
        open_s * 1e3,
        mb(index_bytes as u64),
        scan_s * 1e3,
        cpu_text(scan_cpu)
    );

    let end = replay.time_range().map_or(0, |(_, e)| e);
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let seeks = 1000;
    let ((), seek_wall, seek_cpu) = timed(|| {
        for _ in 0..seeks {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let t = x % (end + 1);
            let f = replay.frame_at(t).expect("seek").expect("a frame");
            assert!(f.t_ns <= t);
        }
    });
    let (read, read_wall, read_cpu) = timed(|| {
        let mut read = 0;
        for f in replay.frames() {
            f.expect("frame");
            read += 1;
        }
        read
    });
    println!(
        "seek: {:.2} ms per random frame_at (wall{}); read in order: {:.0} frames/s (wall{})",
        seek_wall * 1e3 / seeks as f64,
        cpu_text(seek_cpu),
        read as f64 / read_wall,
        cpu_text(read_cpu)
    );

    drop(frames);
    let before = LIVE.load(Ordering::Relaxed);
    let start = Instant::now();
    let all: Vec<Frame> = replay.frames().collect::<Result<_, _>>().expect("frames");
    let load_s = start.elapsed().as_secs_f64();
    let all_bytes = LIVE.load(Ordering::Relaxed).saturating_sub(before);
    println!(
        "load every frame instead: {:.2} s, {} in memory ({} frames)",
        load_s,
        mb(all_bytes as u64),
        all.len()
    );
    std::fs::remove_file(&path).ok();
}
