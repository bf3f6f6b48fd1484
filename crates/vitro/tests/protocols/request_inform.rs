use super::*;
use vitro::protocol::request::{RequestEvent, RequestInform};

struct M;
#[derive(Clone, Debug, PartialEq, Serialize)]
enum Msg {
    Double(u32),
    Ok,
    No,
    Result(u32),
}
#[derive(Clone, Debug, Serialize)]
enum Ev {
    Ask(u32),
    Finish(Reply, u32),
}
#[derive(Debug, PartialEq)]
enum Outcome {
    Agreed,
    Refused,
    Done(u32),
    TimedOut { agreed: bool },
    Undeliverable,
}
struct Node {
    rq: RequestInform,
    server: EntityId,
    retries: u32,
    outcomes: Vec<(SimTime, Outcome)>,
    last: u32,
}
impl Model for M {
    type Env = ();
    type Event = Ev;
    type Msg = Msg;
    type Agent = Node;
}
impl Agent<M> for Node {
    fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
        let deadline = Some(secs(5));
        match input {
            Input::Event(&Ev::Ask(x)) => {
                self.last = x;
                self.rq.request(cx, self.server, Msg::Double(x), deadline);
            }
            // The server: odd numbers are refused, even ones doubled after 1 s of work.
            Input::Event(&Ev::Finish(reply, y)) => self.rq.done(cx, reply, Msg::Result(y)),
            _ => {
                let Handled::Event(ev) = self.rq.handle(input, cx) else {
                    return;
                };
                let outcome = match ev {
                    RequestEvent::Requested { reply, request } => {
                        let Msg::Double(x) = request.body else {
                            return self.rq.refuse(cx, reply, Msg::No);
                        };
                        if x % 2 == 1 {
                            self.rq.refuse(cx, reply, Msg::No);
                        } else {
                            self.rq.agree(cx, reply, Msg::Ok);
                            cx.schedule_in(secs(1), Ev::Finish(reply, 2 * x));
                        }
                        return;
                    }
                    RequestEvent::Agreed { .. } => Outcome::Agreed,
                    RequestEvent::Refused { .. } => Outcome::Refused,
                    RequestEvent::Done { reply } => match reply.body {
                        Msg::Result(y) => Outcome::Done(y),
                        _ => panic!("unexpected done body"),
                    },
                    RequestEvent::Failed { .. } => panic!("no failure expected"),
                    RequestEvent::TimedOut { agreed, .. } => {
                        if self.retries > 0 {
                            self.retries -= 1;
                            self.rq
                                .request(cx, self.server, Msg::Double(self.last), deadline);
                        }
                        Outcome::TimedOut { agreed }
                    }
                    RequestEvent::Undeliverable { .. } => Outcome::Undeliverable,
                };
                self.outcomes.push((cx.now(), outcome));
            }
        }
    }
}

fn setup(retries: u32) -> (Simulation<M>, EntityId, EntityId) {
    let mut sim = Simulation::<M>::new((), 1);
    let node = |server, retries| Node {
        rq: RequestInform::new(TAG),
        server,
        retries,
        outcomes: Vec::new(),
        last: 0,
    };
    let s = sim.add_agent("server", node(EntityId(0), 0)).unwrap();
    let c = sim.add_agent("client", node(s, retries)).unwrap();
    (sim, s, c)
}

fn outcomes(sim: &Simulation<M>, c: EntityId) -> Vec<Outcome> {
    let node = sim.agent(c).unwrap();
    assert_eq!(node.rq.open().count(), 0, "every conversation closed");
    node.outcomes.iter().map(|(_, o)| o).cloned().collect()
}

impl Clone for Outcome {
    fn clone(&self) -> Self {
        match self {
            Outcome::Agreed => Outcome::Agreed,
            Outcome::Refused => Outcome::Refused,
            Outcome::Done(y) => Outcome::Done(*y),
            Outcome::TimedOut { agreed } => Outcome::TimedOut { agreed: *agreed },
            Outcome::Undeliverable => Outcome::Undeliverable,
        }
    }
}

#[test]
fn agree_then_done_or_refuse() {
    let (mut sim, s, c) = setup(0);
    sim.schedule(SimTime::ZERO, Target::Entity(c), Ev::Ask(21))
        .unwrap();
    sim.schedule(at(secs(10)), Target::Entity(c), Ev::Ask(4))
        .unwrap();
    assert_eq!(sim.run_until(SimTime::MAX), StopReason::QueueEmpty);
    assert_eq!(
        outcomes(&sim, c),
        [Outcome::Refused, Outcome::Agreed, Outcome::Done(8)]
    );
    let times: Vec<SimTime> = sim.agent(c).unwrap().outcomes.iter().map(|o| o.0).collect();
    assert_eq!(
        times,
        [at(ms(2)), at(secs(10) + ms(2)), at(secs(11) + ms(2))]
    );
    let (cc, sc) = (
        sim.network().counts(c, Protocol::Request),
        sim.network().counts(s, Protocol::Request),
    );
    assert_eq!((cc.sent, cc.received), (2, 3));
    assert_eq!((sc.sent, sc.received), (3, 2));
    assert_balanced(&sim, Protocol::Request);
}

#[test]
fn lost_request_times_out_and_the_retry_succeeds() {
    let (mut sim, s, c) = setup(1);
    set_loss(&mut sim, c, s, 1.0);
    sim.schedule(SimTime::ZERO, Target::Entity(c), Ev::Ask(5 * 2))
        .unwrap();
    sim.run_until(at(secs(3)));
    set_loss(&mut sim, c, s, 0.0);
    sim.run_until(SimTime::MAX);
    assert_eq!(
        outcomes(&sim, c),
        [
            Outcome::TimedOut { agreed: false },
            Outcome::Agreed,
            Outcome::Done(20)
        ]
    );
    assert_eq!(sim.agent(c).unwrap().outcomes[0].0, at(secs(5)));
    let cc = sim.network().counts(c, Protocol::Request);
    assert_eq!((cc.sent, cc.lost, cc.received), (2, 1, 2));
    assert_eq!(sim.network().counts(s, Protocol::Request).received, 1);
    assert_balanced(&sim, Protocol::Request);
}

#[test]
fn lost_outcome_times_out_after_agree_and_late_replies_are_dropped() {
    let (mut sim, s, c) = setup(0);
    sim.schedule(SimTime::ZERO, Target::Entity(c), Ev::Ask(2))
        .unwrap();
    sim.run_until(at(ms(500))); // the agree is in
    set_loss(&mut sim, s, c, 1.0);
    sim.run_until(SimTime::MAX);
    assert_eq!(
        outcomes(&sim, c),
        [Outcome::Agreed, Outcome::TimedOut { agreed: true }]
    );
    assert_eq!(sim.network().counts(s, Protocol::Request).lost, 1);

    // A reply slower than the deadline arrives after the timeout and is dropped.
    let (mut sim, s, c) = setup(0);
    let slow = LinkParams {
        delay: secs(6),
        ..LinkParams::default()
    };
    sim.network_mut().set_link(s, c, slow);
    sim.schedule(SimTime::ZERO, Target::Entity(c), Ev::Ask(3))
        .unwrap();
    sim.run_until(SimTime::MAX);
    assert_eq!(outcomes(&sim, c), [Outcome::TimedOut { agreed: false }]);
    assert_eq!(sim.network().counts(c, Protocol::Request).received, 1);
}

#[test]
fn request_to_nobody_is_undeliverable() {
    let mut sim = Simulation::<M>::new((), 1);
    let c = sim
        .add_agent(
            "client",
            Node {
                rq: RequestInform::new(TAG),
                server: EntityId(7),
                retries: 0,
                outcomes: Vec::new(),
                last: 0,
            },
        )
        .unwrap();
    sim.schedule(SimTime::ZERO, Target::Entity(c), Ev::Ask(2))
        .unwrap();
    assert_eq!(sim.run_until(SimTime::MAX), StopReason::QueueEmpty);
    assert_eq!(outcomes(&sim, c), [Outcome::Undeliverable]);
}
