//! The agent of a plan-execution run: executes its own steps, passes the turn, answers state
//! queries, and repairs the plan when it detects a failure.

use std::sync::Arc;

use serde::Serialize;
use vitro::comm::{Address, Outgoing, Performative};
use vitro::entity::EntityId;
use vitro::env::Effects;
use vitro::protocol::{Handled, Query, QueryEvent, TimerTag};
use vitro::sim::{Agent, Context, CostModel, Input};
use vitro::time::SimDuration;

use super::record::{RepairRecord, RunFailure, Trigger};
use super::world::{Ev, Execute, View, World};
use super::{PLAN_PROTOCOL, TURN_PROTOCOL};
use vitro_algo::planning::FactId;
use vitro_algo::repair::Team;
use vitro_algo::repair::planner::{JointPlan, Repair, StepId, Why, repair};
use vitro_algo::repair::{Strategy, bits};

/// The model: the world above, the [`Worker`] agents and their messages.
pub(crate) struct RepairModel;

impl vitro::sim::Model for RepairModel {
    type Env = World;
    type Event = Ev;
    type Msg = Msg;
    type Agent = Worker;

    fn on_env_event(env: &mut World, event: &Ev, fx: &mut Effects<'_, Ev>) {
        if *event == Ev::Disturb {
            env.disturb(fx);
        }
    }

    fn state_digest(env: &World) -> u64 {
        env.digest()
    }
}

type Cx<'a> = Context<'a, RepairModel>;

/// Message contents.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) enum Msg {
    /// Your step `step` is next; the sender knows plans up to `version`.
    Turn { step: StepId, version: u32 },
    /// What do you observe?
    StateQuery,
    /// The facts of the sender's view that hold.
    State(Vec<FactId>),
    /// A repaired plan.
    Plan(JointPlan),
}

/// What every agent of a run is told at the start.
#[derive(Debug, Clone)]
pub(crate) struct Settings {
    pub strategy: Strategy,
    pub action_time: SimDuration,
    pub cost: CostModel,
    pub max_expansions: Option<u64>,
    pub max_repairs: u32,
    pub answer_deadline: SimDuration,
    /// The entity of each agent, by agent index.
    pub peers: Vec<EntityId>,
}

/// What an agent counted during a run.
#[derive(Debug, Clone, Default)]
pub(crate) struct Tally {
    /// Actions it executed (slipped ones included).
    pub executed: usize,
    /// Failures it detected.
    pub detected: usize,
    /// Steps it skipped because a precondition was false (lazy execution).
    pub skipped: usize,
    /// Repairs it made.
    pub repairs: Vec<RepairRecord>,
    /// How the run ended, if it ended here.
    pub outcome: Option<Result<(), RunFailure>>,
}

enum Phase {
    /// Waiting for a turn, a question or a plan.
    Idle,
    /// Carrying out the step at this position; its view before.
    Acting { index: usize, before: Vec<u64> },
    /// Asking the others for their views.
    Gathering {
        why: Why,
        state: Vec<u64>,
        waiting: usize,
    },
    /// Planning (its simulated time runs).
    Planning { why: Why, repair: Repair },
    /// The run ended here.
    Finished,
}

const ACTION_TIMER: u64 = 1;

/// One member of the team.
pub(crate) struct Worker {
    me: usize,
    team: Arc<Team>,
    settings: Arc<Settings>,
    plan: JointPlan,
    /// The highest plan version this agent has heard of.
    version: u32,
    query: Query,
    phase: Phase,
    /// A turn for a step of a plan not received yet.
    pending: Option<StepId>,
    pub tally: Tally,
}

impl Worker {
    pub fn new(me: usize, team: Arc<Team>, settings: Arc<Settings>) -> Self {
        let plan = JointPlan::original(&team, settings.strategy);
        Worker {
            me,
            team,
            settings,
            plan,
            version: 0,
            query: Query::new(TimerTag(1)),
            phase: Phase::Idle,
            pending: None,
            tally: Tally::default(),
        }
    }

    /// The agent's view now, as a bitset.
    fn observe(&self, cx: &mut Cx<'_>) -> Vec<u64> {
        bits::state(self.team.task.words(), &cx.sense(&View))
    }

    fn owner(&self, index: usize) -> usize {
        self.team.owner[self.plan.steps[index].action as usize]
    }

    fn end(&mut self, cx: &mut Cx<'_>, outcome: Result<(), RunFailure>) {
        self.tally.outcome = Some(outcome);
        self.phase = Phase::Finished;
        cx.request_stop();
    }

    /// Starts the step at `index` (this agent's own).
    fn begin_step(&mut self, cx: &mut Cx<'_>, index: usize) {
        let action = self.plan.steps[index].action;
        let before = self.observe(cx);
        // Every precondition of an own action is in the view, so this check is exact and
        // the actuator accepts the action when it passes (it checks again against the world).
        let started =
            self.team.task.applicable(action, &before) && cx.act(&Execute, action).is_ok();
        if !started {
            self.tally.detected += 1;
            if self.plan.deferred {
                self.tally.skipped += 1;
                self.advance(cx, index);
            } else {
                self.gather(cx, Why::Failure(index));
            }
            return;
        }
        self.tally.executed += 1;
        self.phase = Phase::Acting { index, before };
        cx.set_timer(self.settings.action_time, ACTION_TIMER);
    }

    /// The step at `index` is over: checks its effects.
    fn end_step(&mut self, cx: &mut Cx<'_>, index: usize, before: &[u64]) {
        let expected = self.team.apply(self.plan.steps[index].action, before);
        let ok = self.observe(cx) == expected;
        if !ok {
            self.tally.detected += 1;
        }
        if ok || self.plan.deferred {
            self.advance(cx, index);
        } else {
            self.gather(cx, Why::Failure(index));
        }
    }

    /// Hands the turn to the step after `index`, or checks the goal at the end.
    fn advance(&mut self, cx: &mut Cx<'_>, index: usize) {
        self.phase = Phase::Idle;
        let next = index + 1;
        if next >= self.plan.steps.len() {
            self.gather(cx, Why::PlanEnd);
        } else {
            self.hand_over(cx, next);
        }
    }

    /// Starts the step at `index`, or tells its owner to.
    fn hand_over(&mut self, cx: &mut Cx<'_>, index: usize) {
        let owner = self.owner(index);
        if owner == self.me {
            self.begin_step(cx, index);
        } else {
            let body = Msg::Turn {
                step: self.plan.steps[index].id,
                version: self.version,
            };
            cx.send(
                Outgoing::new(Address::Agent(self.settings.peers[owner]), body)
                    .protocol(TURN_PROTOCOL, 0)
                    .performative(Performative::Request)
                    .size(16),
            );
        }
    }

    /// Asks every other agent for its view, to check the goal or repair.
    fn gather(&mut self, cx: &mut Cx<'_>, why: Why) {
        let mut state = bits::state(self.team.task.words(), &self.team.unobserved);
        for (w, o) in state.iter_mut().zip(self.observe(cx)) {
            *w |= o;
        }
        let mut waiting = 0;
        for (i, &peer) in self.settings.peers.iter().enumerate() {
            if i != self.me {
                let deadline = Some(self.settings.answer_deadline);
                self.query.query_ref(cx, peer, Msg::StateQuery, deadline);
                waiting += 1;
            }
        }
        self.phase = Phase::Gathering {
            why,
            state,
            waiting,
        };
        if waiting == 0 {
            self.decide(cx);
        }
    }

    /// Every view is in: the goal holds, or plan a repair.
    fn decide(&mut self, cx: &mut Cx<'_>) {
        let Phase::Gathering { why, state, .. } = std::mem::replace(&mut self.phase, Phase::Idle)
        else {
            return;
        };
        if self.team.task.is_goal(&state) {
            self.end(cx, Ok(()));
            return;
        }
        if self.version >= self.settings.max_repairs {
            self.end(cx, Err(RunFailure::TooManyRepairs(self.version)));
            return;
        }
        let s = &self.settings;
        let r = repair(
            &self.team,
            s.strategy,
            s.max_expansions,
            &self.plan,
            why,
            &state,
            self.version + 1,
        );
        cx.decide_after(&s.cost, r.expanded, Ev::Planned);
        self.phase = Phase::Planning { why, repair: r };
    }

    /// The planning time is over: adopts and distributes the repaired plan.
    fn adopt(&mut self, cx: &mut Cx<'_>) {
        let Phase::Planning { why, repair } = std::mem::replace(&mut self.phase, Phase::Idle)
        else {
            return;
        };
        let trigger = match why {
            Why::Failure(i) => Trigger::Failure {
                action: self.team.action_name(self.plan.steps[i].action).to_string(),
            },
            Why::PlanEnd => Trigger::PlanEnd,
        };
        let mut record = RepairRecord {
            time: cx.now(),
            by: self.team.agents[self.me].clone(),
            trigger,
            kind: repair.kind,
            fell_back: repair.fell_back,
            expanded: repair.expanded,
            truncated: repair.truncated,
            planning_time: self.settings.cost.cost(repair.expanded),
            new_steps: repair.new_steps,
            notified: 0,
        };
        let Some(plan) = repair.plan else {
            self.tally.repairs.push(record);
            let repairs = self.tally.repairs.len() as u32;
            self.end(cx, Err(RunFailure::NoPlan { repairs }));
            return;
        };
        // Tell the owners of the new steps (the rest they know already).
        let mut told = vec![false; self.team.agents.len()];
        told[self.me] = true;
        for s in plan.steps.iter().filter(|s| s.id.version == plan.version) {
            let owner = self.team.owner[s.action as usize];
            if !told[owner] {
                told[owner] = true;
                record.notified += 1;
                let size = 32 + 8 * plan.steps.len() + 8 * plan.start.len();
                cx.send(
                    Outgoing::new(
                        Address::Agent(self.settings.peers[owner]),
                        Msg::Plan(plan.clone()),
                    )
                    .protocol(PLAN_PROTOCOL, u64::from(plan.version))
                    .size(u32::try_from(size).unwrap_or(u32::MAX)),
                );
            }
        }
        self.tally.repairs.push(record);
        self.version = plan.version;
        self.plan = plan;
        if self.plan.steps.is_empty() {
            self.gather(cx, Why::PlanEnd);
        } else {
            self.hand_over(cx, 0);
        }
    }

    /// A turn for step `step`: starts it once its plan is known.
    fn on_turn(&mut self, cx: &mut Cx<'_>, step: StepId) {
        match self.plan.position(step) {
            Some(i) if self.owner(i) == self.me => {
                self.pending = None;
                self.begin_step(cx, i);
            }
            _ => self.pending = Some(step),
        }
    }
}

impl Agent<RepairModel> for Worker {
    fn handle(&mut self, input: Input<'_, RepairModel>, cx: &mut Cx<'_>) {
        if matches!(self.phase, Phase::Finished) {
            return;
        }
        let ev = match self.query.handle(input, cx) {
            Handled::NotMine => None,
            Handled::Consumed => return,
            Handled::Event(ev) => Some(ev),
        };
        if let Some(ev) = ev {
            let peer = match ev {
                QueryEvent::Asked { reply, .. } => {
                    let view = cx.sense(&View);
                    self.query.inform(cx, reply, Msg::State(view));
                    return;
                }
                QueryEvent::Answered { answer } => {
                    if let (Msg::State(facts), Phase::Gathering { state, waiting, .. }) =
                        (&answer.body, &mut self.phase)
                    {
                        for &f in facts {
                            bits::set(state, f);
                        }
                        *waiting = waiting.saturating_sub(1);
                        if *waiting == 0 {
                            self.decide(cx);
                        }
                    }
                    return;
                }
                QueryEvent::TimedOut { peer, .. } | QueryEvent::Undeliverable { peer, .. } => peer,
                QueryEvent::Refused { reply } | QueryEvent::Failed { reply } => reply.from,
            };
            let agent = cx.name_of(peer).unwrap_or("?").to_string();
            self.end(cx, Err(RunFailure::NoAnswer { agent }));
            return;
        }
        match input {
            Input::Event(Ev::Start) => {
                if self.plan.steps.is_empty() {
                    self.gather(cx, Why::PlanEnd);
                } else {
                    self.hand_over(cx, 0);
                }
            }
            Input::Event(Ev::Planned) => self.adopt(cx),
            Input::Timer(ACTION_TIMER) => {
                if let Phase::Acting { index, before } =
                    std::mem::replace(&mut self.phase, Phase::Idle)
                {
                    self.end_step(cx, index, &before);
                }
            }
            Input::Message(env) => match &env.body {
                Msg::Turn { step, version } => {
                    self.version = self.version.max(*version);
                    self.on_turn(cx, *step);
                }
                Msg::Plan(plan) => {
                    self.version = self.version.max(plan.version);
                    self.plan = plan.clone();
                    if let Some(step) = self.pending {
                        self.on_turn(cx, step);
                    }
                }
                Msg::StateQuery | Msg::State(_) => {}
            },
            _ => {}
        }
    }
}
