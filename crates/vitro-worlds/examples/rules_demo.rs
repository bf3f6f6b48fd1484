//! Two guards programmed in the rule language (`data/rules/guard.jz`) patrol a ring of
//! posts, chase intruders they see or hear about on the radio, and arrest them.
//!
//! ```text
//! cargo run -p vitro-worlds --example rules_demo -- [SEED] [HOURS]
//! ```
//!
//! The program is the same for both guards; their modules bind it to the world: `motion`
//! (a GPS sensor and a walking actuator), `eyes` (a camera sensor and an arrest actuator),
//! `radio` (broadcast messages) and `beliefs` (a fact base holding the ring). Prints the
//! first events, then the counts, and checks that a second run with the same seed has the
//! same trace hash.

use std::path::Path;
use std::process::ExitCode;

use rand::Rng;
use vitro::prelude::*;
use vitro_algo::rules::{Bindings, FactBase, KbError, Program, Query, Term, Update, unify};
use vitro_worlds::rules::{Embodied, EmbodiedModules, RuleAgent};

const POSTS: u32 = 8;
const WALK: SimDuration = SimDuration::from_secs(20);
const TICK: SimDuration = SimDuration::from_secs(2);
/// An intruder not arrested within this time gets away.
const STAY: SimDuration = SimDuration::from_secs(90);

/// Where a guard is: at a post, or walking to the next one.
#[derive(Clone, Copy, serde::Serialize)]
struct Body {
    at: u32,
    to: Option<u32>,
}

#[derive(Default)]
struct World {
    guards: EntityStorage<Body>,
    /// Post -> when its intruder arrived.
    intruders: KeyValueStorage<u32, SimTime>,
    log: Vec<String>,
    spawned: u32,
    escaped: u32,
    /// Time from arrival to arrest, per arrest.
    arrests: Vec<SimDuration>,
}

#[derive(Clone, serde::Serialize)]
enum Ev {
    Start,
    Arrive(EntityId),
    Spawn,
    Leave(u32, SimTime),
}

struct Guarding;
impl Model for Guarding {
    type Env = World;
    type Event = Ev;
    type Msg = String;
    type Agent = RuleAgent<Guarding>;

    fn on_env_event(w: &mut World, ev: &Ev, fx: &mut Effects<'_, Ev>) {
        match *ev {
            Ev::Arrive(g) => {
                w.guards.update(g, |b| {
                    if let Some(to) = b.to.take() {
                        b.at = to;
                    }
                });
            }
            Ev::Spawn => {
                let post = fx.rng("intruders").random_range(0..POSTS);
                if w.intruders.get(&post).is_none() {
                    let now = fx.now();
                    w.intruders.set(post, now);
                    w.spawned += 1;
                    w.log.push(format!(
                        "{:>7.0} s  intruder at post {post}",
                        now.as_secs_f64()
                    ));
                    fx.schedule_in(STAY, Target::Env, Ev::Leave(post, now));
                }
                let gap = fx.rng("intruders").random_range(30..150);
                fx.schedule_in(SimDuration::from_secs(gap), Target::Env, Ev::Spawn);
            }
            Ev::Leave(post, since) => {
                if w.intruders.get(&post) == Some(&since) {
                    w.intruders.remove(&post);
                    w.escaped += 1;
                    let t = fx.now().as_secs_f64();
                    w.log
                        .push(format!("{t:>7.0} s  intruder at post {post} got away"));
                }
            }
            Ev::Start => {}
        }
    }

    fn state_digest(w: &World) -> u64 {
        w.guards.digest() ^ w.intruders.digest().rotate_left(1)
    }
}

fn neighbours(p: u32) -> [u32; 2] {
    [(p + 1) % POSTS, (p + POSTS - 1) % POSTS]
}

// ---- Sensors and actuators ----

struct Gps;
impl Sensor<World> for Gps {
    type Reading = Option<Body>;
    fn read(&self, w: &World, me: EntityId, _: &mut Probe<'_>) -> Option<Body> {
        w.guards.get(me).copied()
    }
}

/// Intruders at the guard's post and the two next to it (nothing while walking).
struct Camera;
impl Sensor<World> for Camera {
    type Reading = Vec<u32>;
    fn read(&self, w: &World, me: EntityId, _: &mut Probe<'_>) -> Vec<u32> {
        match w.guards.get(me) {
            Some(Body { at, to: None }) => {
                let mut seen: Vec<u32> = std::iter::once(*at)
                    .chain(neighbours(*at))
                    .filter(|p| w.intruders.get(p).is_some())
                    .collect();
                seen.sort_unstable();
                seen.dedup();
                seen
            }
            _ => Vec::new(),
        }
    }
}

struct Walk;
impl Actuator<World, Ev> for Walk {
    type Command = u32;
    type Error = String;
    fn actuate(
        &self,
        w: &mut World,
        me: EntityId,
        to: u32,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), String> {
        let body = w.guards.get(me).copied().ok_or("no body")?;
        if body.to.is_some() || !neighbours(body.at).contains(&to) {
            return Err(format!("cannot walk from {} to {to}", body.at));
        }
        w.guards.update(me, |b| b.to = Some(to));
        fx.schedule_in(WALK, Target::Env, Ev::Arrive(me));
        Ok(())
    }
}

struct Arrest;
impl Actuator<World, Ev> for Arrest {
    type Command = u32;
    type Error = String;
    fn actuate(
        &self,
        w: &mut World,
        me: EntityId,
        post: u32,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), String> {
        let here = w
            .guards
            .get(me)
            .is_some_and(|b| b.at == post && b.to.is_none());
        let since = w.intruders.get(&post).copied();
        match (here, since) {
            (true, Some(since)) => {
                w.intruders.remove(&post);
                w.arrests.push(fx.now() - since);
                w.log.push(format!(
                    "{:>7.0} s  guard{} arrests the intruder at post {post}",
                    fx.now().as_secs_f64(),
                    me.0
                ));
                Ok(())
            }
            _ => Err(format!("no intruder to arrest at {post}")),
        }
    }
}

// ---- Modules ----

fn answers(q: &Query, facts: impl IntoIterator<Item = Term>) -> Vec<Bindings> {
    facts
        .into_iter()
        .filter_map(|f| {
            let mut b = Bindings::new();
            unify(&q.term, &f, &mut b).then_some(b)
        })
        .collect()
}

fn post_of(t: &Term) -> Result<u32, KbError> {
    t.as_int()
        .and_then(|i| u32::try_from(i).ok())
        .ok_or_else(|| KbError::Refused(format!("{t} is not a post")))
}

fn int(p: u32) -> Term {
    Term::Int(i64::from(p))
}

/// `at(P)`, `idle`, `route(T, Q)` (next post Q on a shortest way to T); `go(Q)`.
struct Motion;
impl Embodied<Guarding> for Motion {
    fn query(&self, q: &Query, cx: &mut Context<'_, Guarding>) -> Vec<Bindings> {
        let Some(body) = cx.sense(&Gps) else {
            return Vec::new();
        };
        let mut facts = Vec::new();
        if body.to.is_none() {
            facts.push(Term::compound("at", vec![int(body.at)]));
            facts.push(Term::atom("idle"));
            for target in (0..POSTS).filter(|&t| t != body.at) {
                let cw = (target + POSTS - body.at) % POSTS;
                let next = if cw <= POSTS / 2 {
                    neighbours(body.at)[0]
                } else {
                    neighbours(body.at)[1]
                };
                facts.push(Term::compound("route", vec![int(target), int(next)]));
            }
        }
        answers(q, facts)
    }
    fn update(&mut self, u: &Update, cx: &mut Context<'_, Guarding>) -> Result<(), KbError> {
        match u.op.as_str() {
            "go" => cx.act(&Walk, post_of(&u.term)?).map_err(KbError::Refused),
            op => Err(KbError::UnknownOperation(op.into())),
        }
    }
    fn supports(&self, op: &str) -> bool {
        op == "go"
    }
}

/// `intruder(P)`; `arrest(P)`.
struct Eyes;
impl Embodied<Guarding> for Eyes {
    fn query(&self, q: &Query, cx: &mut Context<'_, Guarding>) -> Vec<Bindings> {
        let seen = cx.sense(&Camera);
        answers(
            q,
            seen.into_iter()
                .map(|p| Term::compound("intruder", vec![int(p)])),
        )
    }
    fn update(&mut self, u: &Update, cx: &mut Context<'_, Guarding>) -> Result<(), KbError> {
        match u.op.as_str() {
            "arrest" => cx.act(&Arrest, post_of(&u.term)?).map_err(KbError::Refused),
            op => Err(KbError::UnknownOperation(op.into())),
        }
    }
    fn supports(&self, op: &str) -> bool {
        op == "arrest"
    }
}

/// `heard(T)` for each message received and not forgotten; `say(T)` to every other agent;
/// `forget(T)`.
#[derive(Default)]
struct Radio {
    heard: FactBase,
}
impl Embodied<Guarding> for Radio {
    fn query(&self, q: &Query, _: &mut Context<'_, Guarding>) -> Vec<Bindings> {
        answers(
            q,
            self.heard
                .iter()
                .map(|t| Term::compound("heard", vec![t.clone()])),
        )
    }
    fn update(&mut self, u: &Update, cx: &mut Context<'_, Guarding>) -> Result<(), KbError> {
        match u.op.as_str() {
            "say" => {
                cx.send(Outgoing::new(Address::Broadcast, u.term.to_string()));
                Ok(())
            }
            "forget" => {
                self.heard.remove(&u.term);
                Ok(())
            }
            op => Err(KbError::UnknownOperation(op.into())),
        }
    }
    fn supports(&self, op: &str) -> bool {
        matches!(op, "say" | "forget")
    }
    fn perceive(&mut self, input: Input<'_, Guarding>, _: &mut Context<'_, Guarding>) {
        if let Input::Message(env) = input
            && let Ok(t) = Term::parse(&env.body)
        {
            let _ = self.heard.insert(t);
        }
    }
}

fn ring() -> Result<FactBase, KbError> {
    let mut kb = FactBase::new();
    for p in 0..POSTS {
        let [cw, ccw] = neighbours(p);
        kb.insert(Term::compound("cw", vec![int(p), int(cw)]))?;
        kb.insert(Term::compound("ccw", vec![int(p), int(ccw)]))?;
    }
    Ok(kb)
}

struct Outcome {
    world_log: Vec<String>,
    spawned: u32,
    escaped: u32,
    arrests: Vec<SimDuration>,
    messages: u64,
    cycles: u64,
    hash: u64,
}

fn simulate(
    program: &Program,
    seed: u64,
    hours: u64,
) -> Result<Outcome, Box<dyn std::error::Error>> {
    let mut sim = Simulation::<Guarding>::new(World::default(), seed);
    let mut guards = Vec::new();
    for (i, start) in [0, POSTS / 2].into_iter().enumerate() {
        let modules: EmbodiedModules<Guarding> = vec![
            ("beliefs".into(), Box::new(ring()?)),
            ("motion".into(), Box::new(Motion)),
            ("eyes".into(), Box::new(Eyes)),
            ("radio".into(), Box::new(Radio::default())),
        ];
        let agent = RuleAgent::new(program.clone(), modules, TICK)?;
        let id = sim.add_agent(format!("guard{i}"), agent)?;
        sim.env_mut().guards.insert(
            id,
            Body {
                at: start,
                to: None,
            },
        );
        sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)?;
        guards.push(id);
    }
    sim.schedule(SimTime::from_secs(10), Target::Env, Ev::Spawn)?;
    sim.run_until(SimTime::from_secs(hours * 3600));
    let w = sim.env();
    Ok(Outcome {
        world_log: w.log.clone(),
        spawned: w.spawned,
        escaped: w.escaped,
        arrests: w.arrests.clone(),
        messages: sim.network().total_sent(),
        cycles: guards
            .iter()
            .filter_map(|&g| sim.agent(g))
            .map(RuleAgent::cycles)
            .sum(),
        hash: sim.trace_hash(),
    })
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let seed = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let hours = args.next().and_then(|s| s.parse().ok()).unwrap_or(4);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/rules/guard.jz");
    let result = std::fs::read_to_string(&path)
        .map_err(|e| format!("{}: {e}", path.display()).into())
        .and_then(|text| Program::parse("guard.jz", &text).map_err(Into::into))
        .and_then(|program| {
            let a = simulate(&program, seed, hours)?;
            let b = simulate(&program, seed, hours)?;
            Ok::<_, Box<dyn std::error::Error>>((a, b.hash))
        });
    let (out, again) = match result {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    println!("two rule-programmed guards, {POSTS} posts, {hours} h, seed {seed}\n");
    for line in out.world_log.iter().take(20) {
        println!("{line}");
    }
    if out.world_log.len() > 20 {
        println!("    ... {} more events", out.world_log.len() - 20);
    }
    let mean =
        out.arrests.iter().map(|d| d.as_secs_f64()).sum::<f64>() / out.arrests.len().max(1) as f64;
    println!(
        "\nintruders {}, arrested {} (mean {:.0} s after arriving), got away {}, still there {}",
        out.spawned,
        out.arrests.len(),
        mean,
        out.escaped,
        out.spawned as usize - out.arrests.len() - out.escaped as usize
    );
    println!(
        "deliberation cycles {}, radio messages {}",
        out.cycles, out.messages
    );
    println!(
        "trace hash {:016x}; same seed again: {}",
        out.hash,
        if again == out.hash {
            "identical"
        } else {
            "DIFFERENT"
        }
    );
    if again == out.hash {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
