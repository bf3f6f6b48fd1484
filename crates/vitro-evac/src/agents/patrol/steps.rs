//! The umpire's record of the patrol: what each Skeldar did at every patrol step, and the
//! game's capture probability from every state (what the attacks are judged and computed
//! with).

use serde::{Deserialize, Serialize};
use vitro_algo::graph::NodeId;

/// What a Skeldar did at one patrol step: the umpire's record.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum StepKind {
    /// Drew its next checkpoint from its policy.
    Policy,
    /// Stayed, the phase held (the truck late, no track of it, or the trip over).
    Hold,
    /// Stepped back towards its patrol (the truck early).
    Rejoin,
}

/// One patrol step of a Skeldar: when (seconds), the checkpoint it flies to, its phase.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepLog {
    /// Simulated time of the step, seconds.
    pub t: f64,
    /// The checkpoint it flies to (or hovers over).
    pub at: Option<NodeId>,
    /// Its phase after the step.
    pub phase: usize,
    /// What it did.
    pub kind: StepKind,
    /// The game it played: the step of the mission's timetable that game starts at (0: the
    /// mission's game; after a re-solve, where it re-timed the trip from).
    #[serde(default)]
    pub plan: usize,
}

/// Per plan unit, target and phase: the capture probability of an attack started with the
/// unit at each of its states, `(vertex, probability)`.
pub(crate) type CaptureTable = Vec<Vec<Vec<Vec<(NodeId, f64)>>>>;

/// The capture table of `plan` against `targets` (the game it was solved for).
pub(crate) fn capture_table(
    plan: &vitro_algo::patrol::PatrolPlan,
    targets: &[vitro_algo::patrol::Target],
) -> Result<CaptureTable, String> {
    use vitro_algo::patrol::{Instance, Patroller};
    let patrollers = (0..plan.units())
        .map(|i| Patroller {
            name: format!("unit{i}"),
        })
        .collect();
    let instance = Instance::new(plan.graph.clone(), targets.to_vec(), patrollers)
        .map_err(|e| e.to_string())?;
    let period = plan.period.max(1);
    plan.policies
        .iter()
        .map(|policy| {
            let mut table = vec![vec![Vec::new(); period]; targets.len()];
            for a in policy.attacks(&instance).map_err(|e| e.to_string())? {
                if let Some(slot) = table
                    .get_mut(a.target)
                    .and_then(|t| t.get_mut(a.phase % period))
                {
                    slot.push((a.from, a.capture_probability));
                }
            }
            Ok(table)
        })
        .collect()
}
