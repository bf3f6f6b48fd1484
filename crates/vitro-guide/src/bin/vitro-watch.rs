//! The `vitro` command with the guide's perimeter watch beside the stock missions: what a
//! mission crate's own `src/bin/vitro.rs` holds.

// ANCHOR: bin
use vitro_guide::watch::PerimeterWatch;

static WATCH: PerimeterWatch = PerimeterWatch;

fn main() -> std::process::ExitCode {
    vitro_cli::run(vec![&WATCH], std::env::args_os()).into()
}
// ANCHOR_END: bin
