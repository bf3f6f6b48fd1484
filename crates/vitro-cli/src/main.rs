//! `vitro`: the command-line front end of the Vitro toolkit (the library `vitro_cli` is the
//! command; this binary runs it with the stock missions).

use std::process::ExitCode;

fn main() -> ExitCode {
    ExitCode::from(vitro_cli::run(Vec::new(), std::env::args_os()))
}
