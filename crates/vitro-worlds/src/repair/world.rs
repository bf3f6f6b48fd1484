//! The world of a plan-execution run: the ground state in a storage, the view sensor, the
//! action actuator with its failure model, and exogenous disturbances.

use std::sync::Arc;

use rand::Rng;
use serde::Serialize;
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects, EntityStorage, KeyValueStorage, Probe, Sensor};
use vitro::event::Target;
use vitro::time::SimTime;

use super::Disturbance;
use super::record::{Applied, AppliedKind};
use vitro_algo::planning::{ActionId, FactId};
use vitro_algo::repair::Team;
use vitro_algo::repair::bits;

/// Events of the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub(crate) enum Ev {
    /// Starts the execution (sent to the owner of the first step).
    Start,
    /// The repairer's planning time is over.
    Planned,
    /// A draw of the exogenous disturbance (for the environment).
    Disturb,
}

/// The environment: the ground state, which agent each entity is, and the record of what
/// happened (for the experimenter; no sensor reads it).
pub(crate) struct World {
    team: Arc<Team>,
    /// The facts that hold.
    facts: KeyValueStorage<FactId, ()>,
    /// The agent index of each agent entity.
    bodies: EntityStorage<usize>,
    failure_probability: f64,
    disturbance: Option<Disturbance>,
    log: Vec<Applied>,
}

impl World {
    /// The world in the task's initial state.
    pub fn new(
        team: Arc<Team>,
        failure_probability: f64,
        disturbance: Option<Disturbance>,
    ) -> Self {
        let mut facts = KeyValueStorage::default();
        for &f in &team.task.init {
            facts.set(f, ());
        }
        World {
            team,
            facts,
            bodies: EntityStorage::default(),
            failure_probability,
            disturbance,
            log: Vec::new(),
        }
    }

    /// Makes entity `id` the body of agent `index`.
    pub fn embody(&mut self, id: EntityId, index: usize) {
        self.bodies.insert(id, index);
    }

    /// What happened, in order.
    pub fn log(&self) -> &[Applied] {
        &self.log
    }

    /// The current state as a bitset.
    pub fn state(&self) -> Vec<u64> {
        let mut s = vec![0; self.team.task.words()];
        for (&f, ()) in self.facts.iter() {
            bits::set(&mut s, f);
        }
        s
    }

    /// Digest of every change of the state.
    pub fn digest(&self) -> u64 {
        self.facts.digest()
    }

    fn apply(&mut self, action: ActionId) {
        let a = &self.team.task.actions[action as usize];
        for f in &a.del {
            self.facts.remove(f);
        }
        for &f in &a.add {
            self.facts.set(f, ());
        }
    }

    fn record(&mut self, time: SimTime, by: Option<usize>, kind: AppliedKind) {
        let by = by.map(|i| self.team.agents[i].clone());
        self.log.push(Applied { time, by, kind });
    }

    /// One draw of the exogenous disturbance; schedules the next.
    pub fn disturb(&mut self, fx: &mut Effects<'_, Ev>) {
        let Some(d) = self.disturbance else { return };
        let state = self.state();
        let team = Arc::clone(&self.team);
        let rng = fx.rng("disturbance");
        if rng.random::<f64>() < d.probability {
            let options: Vec<ActionId> = (0..team.task.actions.len() as ActionId)
                .filter(|&a| team.task.applicable(a, &state))
                .collect();
            if !options.is_empty() {
                let a = options[rng.random_range(0..options.len())];
                self.apply(a);
                let name = team.action_name(a).to_string();
                self.record(fx.now(), None, AppliedKind::Disturbance { action: name });
            }
        }
        fx.schedule_in(d.period, Target::Env, Ev::Disturb);
    }
}

/// The view sensor: the facts of the agent's view that hold now.
pub(crate) struct View;

impl Sensor<World> for View {
    type Reading = Vec<FactId>;
    fn read(&self, w: &World, me: EntityId, _: &mut Probe<'_>) -> Vec<FactId> {
        match w.bodies.get(me) {
            Some(&i) => w.team.views[i]
                .iter()
                .copied()
                .filter(|f| w.facts.get(f).is_some())
                .collect(),
            None => Vec::new(),
        }
    }
}

/// Why the actuator refused a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub(crate) enum ExecuteError {
    /// The entity is not an agent of the team.
    #[error("not an agent of the team")]
    NotAnAgent,
    /// The action belongs to another agent.
    #[error("the action belongs to another agent")]
    NotOwner,
    /// A precondition is false.
    #[error("a precondition is false")]
    Inapplicable,
}

/// The actuator: carries out one of the agent's own actions, which may slip (see the
/// [module](super) documentation).
pub(crate) struct Execute;

impl Actuator<World, Ev> for Execute {
    type Command = ActionId;
    type Error = ExecuteError;

    fn actuate(
        &self,
        w: &mut World,
        me: EntityId,
        action: ActionId,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), ExecuteError> {
        let &agent = w.bodies.get(me).ok_or(ExecuteError::NotAnAgent)?;
        let team = Arc::clone(&w.team);
        if team.owner.get(action as usize) != Some(&agent) {
            return Err(ExecuteError::NotOwner);
        }
        let state = w.state();
        if !team.task.applicable(action, &state) {
            return Err(ExecuteError::Inapplicable);
        }
        let intended = team.action_name(action).to_string();
        let rng = fx.rng("failure");
        let kind = if rng.random::<f64>() < w.failure_probability {
            let options: Vec<ActionId> = team.actions_of[agent]
                .iter()
                .copied()
                .filter(|&a| a != action && team.task.applicable(a, &state))
                .collect();
            if options.is_empty() {
                AppliedKind::NoEffect { intended }
            } else {
                let slip = options[rng.random_range(0..options.len())];
                w.apply(slip);
                AppliedKind::Slip {
                    intended,
                    actual: team.action_name(slip).to_string(),
                }
            }
        } else {
            w.apply(action);
            AppliedKind::Done { action: intended }
        };
        w.record(fx.now(), Some(agent), kind);
        Ok(())
    }
}
