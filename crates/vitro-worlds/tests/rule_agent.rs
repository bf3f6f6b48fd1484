//! The rule language's simulation adapter: a rule-programmed agent runs one cycle per tick
//! through its actuators, reproducibly, and sees its messages.

use vitro::prelude::*;
use vitro_algo::rules::{Bindings, FactBase, KbError, Program, Query, Term, Update, unify};
use vitro_worlds::rules::{Embodied, EmbodiedModules, RuleAgent};

/// A world with one counter per agent, moved by an actuator and read by a sensor.
#[derive(Default)]
struct Counters {
    value: EntityStorage<i64>,
}

struct Read;
impl Sensor<Counters> for Read {
    type Reading = i64;
    fn read(&self, w: &Counters, me: EntityId, _: &mut Probe<'_>) -> i64 {
        w.value.get(me).copied().unwrap_or(0)
    }
}

struct Add;
impl Actuator<Counters, ()> for Add {
    type Command = i64;
    type Error = std::convert::Infallible;
    fn actuate(
        &self,
        w: &mut Counters,
        me: EntityId,
        by: i64,
        _: &mut Effects<'_, ()>,
    ) -> Result<(), Self::Error> {
        if !w.value.update(me, |v| *v += by) {
            w.value.insert(me, by);
        }
        Ok(())
    }
}

struct Sim;
impl Model for Sim {
    type Env = Counters;
    type Event = ();
    type Msg = String;
    type Agent = RuleAgent<Sim>;
}

/// A module bound to the sensor and actuator: `value(V)` reads the counter, `step(N)`
/// moves it; `say(T)` broadcasts `T`, and `heard(T)` holds for what the agent received.
#[derive(Default)]
struct Counter {
    inbox: Vec<Term>,
}
impl Embodied<Sim> for Counter {
    fn query(&self, q: &Query, cx: &mut Context<'_, Sim>) -> Vec<Bindings> {
        let value = Term::compound("value", vec![Term::Int(cx.sense(&Read))]);
        let heard = self
            .inbox
            .iter()
            .map(|t| Term::compound("heard", vec![t.clone()]));
        std::iter::once(value)
            .chain(heard)
            .filter_map(|fact| {
                let mut b = Bindings::new();
                unify(&q.term, &fact, &mut b).then_some(b)
            })
            .collect()
    }
    fn update(&mut self, u: &Update, cx: &mut Context<'_, Sim>) -> Result<(), KbError> {
        match u.op.as_str() {
            "step" => {
                let n = u
                    .term
                    .as_int()
                    .ok_or(KbError::Refused("not a number".into()))?;
                cx.act(&Add, n).map_err(|e| match e {})
            }
            "say" => {
                cx.send(Outgoing::new(Address::Broadcast, u.term.to_string()));
                Ok(())
            }
            op => Err(KbError::UnknownOperation(op.into())),
        }
    }
    fn supports(&self, op: &str) -> bool {
        matches!(op, "step" | "say")
    }
    fn perceive(&mut self, input: Input<'_, Sim>, _: &mut Context<'_, Sim>) {
        if let Input::Message(env) = input
            && let Ok(t) = Term::parse(&env.body)
        {
            self.inbox.push(t);
        }
    }
}

fn counter_agent(src: &str, period_s: u64) -> RuleAgent<Sim> {
    let modules: EmbodiedModules<Sim> = vec![
        ("counter".into(), Box::new(Counter::default())),
        ("beliefs".into(), Box::new(FactBase::new())),
    ];
    let program = Program::parse("counter.jz", src).expect("parses");
    RuleAgent::new(program, modules, SimDuration::from_secs(period_s)).expect("modules exist")
}

#[test]
fn the_agent_runs_one_cycle_per_tick_through_its_actuators() {
    // Count up by one per cycle until 5, then stop.
    let src = "when counter [value(V)] and not beliefs [done] then {
                 when counter [value(5)] then add beliefs [done] ;
                 when not counter [value(5)] then step counter [1]
               }";
    let mut sim = Simulation::<Sim>::new(Counters::default(), 1);
    let a = sim.add_agent("a", counter_agent(src, 2)).expect("agent");
    sim.schedule(SimTime::from_secs(3), Target::Entity(a), ())
        .expect("schedules");
    sim.run_until(SimTime::from_secs(30));
    // Cycles at 3, 5, 7, ... 29 s: 14 of them; the count reached 5 by the 5th.
    let agent = sim.agent(a).expect("agent");
    assert_eq!(agent.cycles(), 14);
    assert_eq!(sim.env().value.get(a), Some(&5));
    assert!(agent.last_cycle().updates.is_empty());
}

#[test]
fn rule_agents_are_reproducible_and_see_messages() {
    let src = "step counter [1] ; step counter [10] ; step counter [100]";
    let run = |seed| {
        let mut sim = Simulation::<Sim>::new(Counters::default(), seed);
        let a = sim.add_agent("a", counter_agent(src, 1)).expect("agent");
        sim.schedule(SimTime::ZERO, Target::Entity(a), ())
            .expect("schedules");
        sim.run_until(SimTime::from_secs(20));
        (sim.env().value.get(a).copied(), sim.trace_hash())
    };
    assert_eq!(run(4), run(4));
    assert_ne!(run(4).0, run(5).0);
    // Messages reach the modules: `a` says hello once, `b` steps by 7 when it hears it.
    let mut sim = Simulation::<Sim>::new(Counters::default(), 1);
    let talker = "when not beliefs [sent] then { say counter [hello(b)], add beliefs [sent] }";
    let listener = "when counter [heard(hello(Who))] and not beliefs [got] then {
                      add beliefs [got], step counter [7]
                    }";
    let a = sim.add_agent("a", counter_agent(talker, 1)).expect("agent");
    let b = sim
        .add_agent("b", counter_agent(listener, 1))
        .expect("agent");
    for who in [a, b] {
        sim.schedule(SimTime::ZERO, Target::Entity(who), ())
            .expect("schedules");
    }
    sim.run_until(SimTime::from_secs(3));
    assert_eq!(sim.agent(a).expect("agent").cycles(), 4);
    assert_eq!(sim.env().value.get(b), Some(&7));
    assert_eq!(sim.env().value.get(a), None);
    assert_eq!(sim.network().counts(a, Protocol::Plain).sent, 1);
}
