use super::*;
use vitro::protocol::token_ring::{RingError, TokenEvent, TokenRing};

struct M;
#[derive(Clone, Debug, PartialEq, Serialize)]
enum Msg {
    /// The number of passes so far.
    Token(u64),
}
#[derive(Clone, Debug, Serialize)]
enum Ev {
    Start,
    Release,
}

type Log = Arc<Mutex<Vec<(SimTime, EntityId, &'static str)>>>;

struct Node {
    ring: TokenRing,
    hold: SimDuration,
    count: u64,
    passes: u64,
    log: Log,
}
impl Model for M {
    type Env = ();
    type Event = Ev;
    type Msg = Msg;
    type Agent = Node;
}
impl Node {
    fn note(&self, cx: &Context<'_, M>, what: &'static str) {
        self.log.lock().unwrap().push((cx.now(), cx.me(), what));
    }
}
impl Agent<M> for Node {
    fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
        match input {
            Input::Event(Ev::Start) => {
                if self.ring.start(cx) {
                    self.note(cx, "created");
                    cx.schedule_in(self.hold, Ev::Release);
                } else {
                    assert_eq!(self.ring.pass(cx, Msg::Token(0)), Err(RingError::NotHolder));
                }
            }
            Input::Event(Ev::Release) => {
                self.count += 1;
                self.passes += 1;
                self.ring.pass(cx, Msg::Token(self.count)).unwrap();
            }
            _ => {
                let Handled::Event(ev) = self.ring.handle(input, cx) else {
                    return;
                };
                let what = match &ev {
                    TokenEvent::Acquired { token } => {
                        let Msg::Token(n) = token.body;
                        self.count = n;
                        "acquired"
                    }
                    TokenEvent::Regenerated { .. } => "regenerated",
                    TokenEvent::Returned { .. } => "returned",
                    TokenEvent::Skipped { .. } => "skipped",
                };
                self.note(cx, what);
                if ev.holds() {
                    cx.schedule_in(self.hold, Ev::Release);
                }
            }
        }
    }
}

const HOLD: SimDuration = SimDuration::from_millis(100);
const TIMEOUT: SimDuration = SimDuration::from_secs(1);

/// A ring of `n` agents (and `passive` entities without agents at the given ring positions).
fn setup(n: usize, passive: &[usize]) -> (Simulation<M>, Vec<EntityId>, Log) {
    let mut sim = Simulation::<M>::new((), 4);
    let log = Log::default();
    // Ids are dense in creation order: the ring is ids 0..n + passive.len().
    let total = n + passive.len();
    let ring: Vec<EntityId> = (0..total as u32).map(EntityId).collect();
    let mut agents = Vec::new();
    for (i, &id) in ring.iter().enumerate() {
        if passive.contains(&i) {
            assert_eq!(sim.add_entity(format!("rock{i}")).unwrap(), id);
        } else {
            let node = Node {
                ring: TokenRing::new(TAG, ring.clone(), id, TIMEOUT).unwrap(),
                hold: HOLD,
                count: 0,
                passes: 0,
                log: log.clone(),
            };
            assert_eq!(sim.add_agent(format!("m{i}"), node).unwrap(), id);
            sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)
                .unwrap();
            agents.push(id);
        }
    }
    (sim, agents, log)
}

/// The holders in time order after `from`.
fn holders(log: &Log, from: SimTime) -> Vec<(SimTime, EntityId)> {
    log.lock()
        .unwrap()
        .iter()
        .filter(|e| e.0 >= from && e.2 != "skipped")
        .map(|e| (e.0, e.1))
        .collect()
}

/// One token: holders follow `order` cyclically, one hold (plus delay) apart.
fn assert_single_token(h: &[(SimTime, EntityId)], order: &[EntityId], step: SimDuration) {
    assert!(h.len() > 2 * order.len());
    let start = order.iter().position(|&m| m == h[0].1).unwrap();
    for (k, w) in h.windows(2).enumerate() {
        assert_eq!(
            w[1].1,
            order[(start + k + 1) % order.len()],
            "order at {}",
            w[1].0
        );
        assert_eq!(w[1].0 - w[0].0, step, "spacing at {}", w[1].0);
    }
}

#[test]
fn ring_membership_is_checked() {
    let ids = [EntityId(0), EntityId(1)];
    let new = |m: Vec<EntityId>, me| TokenRing::new(TAG, m, me, TIMEOUT).map(|_| ());
    assert_eq!(new(vec![], ids[0]), Err(RingError::Empty));
    assert_eq!(
        new(vec![ids[1]], ids[0]),
        Err(RingError::NotAMember(ids[0]))
    );
    assert_eq!(
        new(vec![ids[0], ids[1], ids[0]], ids[0]),
        Err(RingError::Duplicate(ids[0]))
    );
    assert_eq!(new(ids.to_vec(), ids[1]), Ok(()));
}

#[test]
fn token_circulates_in_ring_order() {
    let (mut sim, agents, log) = setup(4, &[]);
    sim.run_until(at(secs(10)));
    let d = LinkParams::default().delay;
    let h = holders(&log, SimTime::ZERO);
    assert_eq!(h[0], (SimTime::ZERO, agents[0]));
    assert_single_token(&h, &agents, HOLD + d);
    assert_eq!(h.len(), 1 + (10_000 / 101) as usize);
    let passes: u64 = agents.iter().map(|&a| sim.agent(a).unwrap().passes).sum();
    assert_eq!(passes as usize, h.len() - 1);
    for &a in &agents {
        let node = sim.agent(a).unwrap();
        assert_eq!(node.ring.regenerations(), 0);
        let c = sim.network().counts(a, Protocol::TokenRing);
        assert_eq!(c.sent, node.passes);
        assert_eq!(c.lost + c.bounced, 0);
    }
    // The body rides along: the count of passes.
    let last = h.last().unwrap().1;
    assert_eq!(sim.agent(last).unwrap().count, passes);
}

#[test]
fn lost_token_is_regenerated() {
    let (mut sim, agents, log) = setup(4, &[]);
    sim.run_until(at(secs(2)));
    set_loss(&mut sim, agents[1], agents[2], 1.0);
    sim.run_until(at(ms(2500)));
    set_loss(&mut sim, agents[1], agents[2], 0.0);
    sim.run_until(at(secs(10)));
    let lost = sim.network().counts(agents[1], Protocol::TokenRing).lost;
    assert_eq!(lost, 1);
    let regens: Vec<(SimTime, EntityId)> = log
        .lock()
        .unwrap()
        .iter()
        .filter(|e| e.2 == "regenerated")
        .map(|e| (e.0, e.1))
        .collect();
    // The monitor (the first member) regenerates, once; nobody else does.
    assert_eq!(regens.len(), 1, "{regens:?}");
    assert_eq!(regens[0].1, agents[0]);
    assert!(regens[0].0 < at(secs(4)));
    let d = LinkParams::default().delay;
    assert_single_token(&holders(&log, at(secs(4))), &agents, HOLD + d);
}

#[test]
fn slow_token_duplicate_dies_out() {
    let (mut sim, agents, log) = setup(4, &[]);
    sim.run_until(at(secs(2)));
    let slow = LinkParams {
        delay: SimDuration::from_millis(1500),
        ..LinkParams::default()
    };
    sim.network_mut().set_link(agents[1], agents[2], slow);
    sim.run_until(at(ms(2300)));
    sim.network_mut()
        .set_link(agents[1], agents[2], LinkParams::default());
    sim.run_until(at(secs(12)));
    let regens = log
        .lock()
        .unwrap()
        .iter()
        .filter(|e| e.2 == "regenerated")
        .count();
    assert_eq!(regens, 1);
    // The slow token reached its receiver after the new one had: dropped, not acquired.
    assert_eq!(sim.network().counts(agents[1], Protocol::TokenRing).lost, 0);
    let acquired = log
        .lock()
        .unwrap()
        .iter()
        .filter(|e| e.1 == agents[2] && e.2 == "acquired")
        .count() as u64;
    let received = sim
        .network()
        .counts(agents[2], Protocol::TokenRing)
        .received;
    assert_eq!(received, acquired + 1);
    let d = LinkParams::default().delay;
    assert_single_token(&holders(&log, at(secs(6))), &agents, HOLD + d);
}

#[test]
fn unreachable_member_is_skipped() {
    // Ring: m0, rock1 (no agent), m2, m3.
    let (mut sim, agents, log) = setup(3, &[1]);
    sim.run_until(at(secs(5)));
    let skips = log
        .lock()
        .unwrap()
        .iter()
        .filter(|e| e.2 == "skipped")
        .count();
    assert!(skips > 5);
    assert_eq!(
        sim.network().counts(agents[0], Protocol::TokenRing).bounced,
        skips as u64
    );
    let regens: u64 = agents
        .iter()
        .map(|&a| sim.agent(a).unwrap().ring.regenerations())
        .sum();
    assert_eq!(regens, 0);
    let h = holders(&log, SimTime::ZERO);
    assert_eq!(
        h.iter().take(4).map(|x| x.1).collect::<Vec<_>>(),
        [agents[0], agents[1], agents[2], agents[0]]
    );
}

#[test]
fn standby_member_regenerates_when_the_monitor_is_gone() {
    // Ring: rock0 (the monitor, without an agent), m1, m2, m3: nobody creates the token;
    // the first standby member makes one after twice the timeout.
    let (mut sim, agents, log) = setup(3, &[0]);
    sim.run_until(at(secs(6)));
    let first = log.lock().unwrap()[0];
    assert_eq!(
        first,
        (SimTime::ZERO + TIMEOUT * 2, agents[0], "regenerated")
    );
    let regens: u64 = agents
        .iter()
        .map(|&a| sim.agent(a).unwrap().ring.regenerations())
        .sum();
    assert_eq!(regens, 1);
    let d = LinkParams::default().delay;
    let h: Vec<(SimTime, EntityId)> = holders(&log, SimTime::ZERO);
    // m3 passes to the absent monitor; the bounce comes back after one delay and the
    // token goes on to m1.
    assert_eq!(h[1].0 - h[0].0, HOLD + d);
    assert_eq!(h[3].0 - h[2].0, HOLD + d + d);
    assert_eq!(h[3].1, agents[0]);
}
