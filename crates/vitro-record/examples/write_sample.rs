//! Writes a synthetic recording: the CI's sample for the Python MCAP reader and the KML export.
//!
//! ```sh
//! cargo run -p vitro-record --example write_sample -- OUT.mcap [FRAMES] [ENTITIES]
//! ```
//!
//! FRAMES (default 120) frames one simulated second apart, ENTITIES (default 12) entities of
//! every type and side. Prints what it wrote as one JSON object.

use std::process::ExitCode;
use vitro_record::{Recorder, synthetic};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: write_sample OUT.mcap [FRAMES] [ENTITIES]";
    let Some(out) = args.first() else {
        eprintln!("{usage}");
        return ExitCode::from(2);
    };
    let number = |k: usize, default: u64| match args.get(k) {
        None => Some(default),
        Some(s) => s.parse::<u64>().ok(),
    };
    let (Some(frames), Some(entities)) = (number(1, 120), number(2, 12)) else {
        eprintln!("{usage}: FRAMES and ENTITIES are whole numbers");
        return ExitCode::from(2);
    };
    match write(out, frames, entities as usize) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn write(out: &str, frames: u64, entities: usize) -> Result<(), vitro_record::RecordError> {
    let scene = synthetic::scene();
    let mut rec = Recorder::create(out, &scene)?;
    let mut logs = 0;
    for i in 0..frames {
        let f = synthetic::frame(&scene, i, entities);
        logs += f.messages.len() + f.log.len();
        rec.frame(&f)?;
    }
    let stats = rec.stats();
    rec.finish()?;
    println!(
        "{{\"path\": {out:?}, \"frames\": {}, \"entities\": {entities}, \"messages\": {}, \"log_lines\": {logs}}}",
        stats.frames, stats.messages
    );
    Ok(())
}
