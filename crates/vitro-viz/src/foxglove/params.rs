//! The run's controls as Foxglove parameters: `paused`, `speed` and `step`.
//!
//! Setting one applies the same [`Command`] a page's button does, through the run's
//! [`Control`](vitro::sim::Control) handle: it changes when events fire in wall time, never
//! which.

use super::wire::Parameter;
use crate::live::LiveRun;
use crate::protocol::Command;
use serde_json::Value;

/// Pauses (`true`) or resumes (`false`) the run.
pub const PAUSED: &str = "paused";
/// Simulated seconds per wall second.
pub const SPEED: &str = "speed";
/// Set to `n` (1 to [`MAX_STEP`](crate::protocol::MAX_STEP)): pause and fire exactly `n`
/// more events. Reads 0.
pub const STEP: &str = "step";

/// Every parameter's name.
pub const NAMES: [&str; 3] = [PAUSED, SPEED, STEP];

/// The current value of `name`, if it is a parameter.
pub fn get(run: &LiveRun, name: &str) -> Option<Parameter> {
    let status = run.status();
    let (value, kind) = match name {
        PAUSED => (Value::Bool(status.paused), None),
        // An unpaced run reads 0.
        SPEED => (
            Value::from(status.speed.unwrap_or(0.0)),
            Some("float64".to_owned()),
        ),
        STEP => (Value::from(0), None),
        _ => return None,
    };
    Some(Parameter {
        name: name.to_owned(),
        value,
        kind,
    })
}

/// The current values of `names` (unknown names left out; none named: all).
pub fn get_all(run: &LiveRun, names: &[String]) -> Vec<Parameter> {
    if names.is_empty() {
        NAMES.iter().filter_map(|n| get(run, n)).collect()
    } else {
        names.iter().filter_map(|n| get(run, n)).collect()
    }
}

/// Applies `p` to the run; why not, if it cannot be.
pub fn set(run: &LiveRun, p: &Parameter) -> Result<(), String> {
    let cmd = match (p.name.as_str(), &p.value) {
        (PAUSED, Value::Bool(true)) => Command::Pause {},
        (PAUSED, Value::Bool(false)) => Command::Resume {},
        (SPEED, Value::Number(n)) => Command::Speed {
            factor: n.as_f64().unwrap_or(f64::NAN),
        },
        (STEP, Value::Number(n)) => match n.as_u64() {
            Some(0) => return Ok(()),
            Some(n) => Command::Step { n },
            None => return Err(format!("step {n}: expected a whole number of events")),
        },
        (PAUSED, v) => return Err(format!("paused {v}: expected true or false")),
        (SPEED | STEP, v) => return Err(format!("{} {v}: expected a number", p.name)),
        (name, _) => {
            return Err(format!(
                "{name}: no such parameter (expected one of {})",
                NAMES.join(", ")
            ));
        }
    };
    let cmd = cmd.check().map_err(|e| e.to_string())?;
    run.apply(&cmd).map_err(|e| e.to_string())
}
