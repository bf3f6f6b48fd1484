use super::*;
use vitro::protocol::query::{Query, QueryEvent, QueryKind};

struct M;
#[derive(Clone, Debug, PartialEq, Serialize)]
enum Msg {
    Temperature,
    IsHot,
    Pressure,
    Celsius(i32),
    Yes(bool),
    Unknown,
}
#[derive(Clone, Debug, Serialize)]
enum Ev {
    AskRef(bool),
    AskIf,
}
struct Node {
    q: Query,
    server: EntityId,
    temp: i32,
    answers: Vec<(SimTime, Result<Msg, &'static str>)>,
}
impl Model for M {
    type Env = ();
    type Event = Ev;
    type Msg = Msg;
    type Agent = Node;
}
impl Agent<M> for Node {
    fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
        let deadline = Some(secs(1));
        match input {
            Input::Event(&Ev::AskRef(known)) => {
                let what = if known {
                    Msg::Temperature
                } else {
                    Msg::Pressure
                };
                self.q.query_ref(cx, self.server, what, deadline);
            }
            Input::Event(Ev::AskIf) => {
                self.q.query_if(cx, self.server, Msg::IsHot, deadline);
            }
            _ => {
                let Handled::Event(ev) = self.q.handle(input, cx) else {
                    return;
                };
                let answer = match ev {
                    QueryEvent::Asked { reply, kind, query } => {
                        match (kind, &query.body) {
                            (QueryKind::Ref, Msg::Temperature) => {
                                self.q.inform(cx, reply, Msg::Celsius(self.temp))
                            }
                            (QueryKind::If, Msg::IsHot) => {
                                self.q.inform(cx, reply, Msg::Yes(self.temp > 30))
                            }
                            _ => self.q.refuse(cx, reply, Msg::Unknown),
                        }
                        return;
                    }
                    QueryEvent::Answered { answer } => Ok(answer.body.clone()),
                    QueryEvent::Refused { .. } => Err("refused"),
                    QueryEvent::Failed { .. } => Err("failed"),
                    QueryEvent::TimedOut { .. } => Err("timed out"),
                    QueryEvent::Undeliverable { .. } => Err("undeliverable"),
                };
                self.answers.push((cx.now(), answer));
            }
        }
    }
}

fn setup() -> (Simulation<M>, EntityId, EntityId) {
    let mut sim = Simulation::<M>::new((), 2);
    let node = |server| Node {
        q: Query::new(TAG),
        server,
        temp: 35,
        answers: Vec::new(),
    };
    let s = sim.add_agent("thermometer", node(EntityId(0))).unwrap();
    let c = sim.add_agent("asker", node(s)).unwrap();
    (sim, s, c)
}

fn answers(sim: &Simulation<M>, c: EntityId) -> Vec<Result<Msg, &'static str>> {
    let n = sim.agent(c).unwrap();
    assert_eq!(n.q.open().count(), 0);
    n.answers.iter().map(|a| a.1.clone()).collect()
}

#[test]
fn query_ref_and_query_if_are_answered() {
    let (mut sim, s, c) = setup();
    sim.schedule(SimTime::ZERO, Target::Entity(c), Ev::AskRef(true))
        .unwrap();
    sim.schedule(at(secs(1)), Target::Entity(c), Ev::AskIf)
        .unwrap();
    sim.schedule(at(secs(2)), Target::Entity(c), Ev::AskRef(false))
        .unwrap();
    sim.run_until(SimTime::MAX);
    assert_eq!(
        answers(&sim, c),
        [Ok(Msg::Celsius(35)), Ok(Msg::Yes(true)), Err("refused")]
    );
    let cc = sim.network().counts(c, Protocol::Query);
    let sc = sim.network().counts(s, Protocol::Query);
    assert_eq!((cc.sent, cc.received, sc.sent, sc.received), (3, 3, 3, 3));
    assert_balanced(&sim, Protocol::Query);
}

#[test]
fn lost_or_late_answers_time_out() {
    let (mut sim, s, c) = setup();
    set_loss(&mut sim, s, c, 1.0);
    sim.schedule(SimTime::ZERO, Target::Entity(c), Ev::AskRef(true))
        .unwrap();
    sim.run_until(at(secs(3)));
    // A slow answer (2 s > the 1 s deadline) arrives late: dropped.
    let slow = LinkParams {
        delay: secs(2),
        ..LinkParams::default()
    };
    sim.network_mut().set_link(s, c, slow);
    sim.schedule(at(secs(3)), Target::Entity(c), Ev::AskIf)
        .unwrap();
    sim.run_until(SimTime::MAX);
    assert_eq!(answers(&sim, c), [Err("timed out"), Err("timed out")]);
    let times: Vec<SimTime> = sim.agent(c).unwrap().answers.iter().map(|a| a.0).collect();
    assert_eq!(times, [at(secs(1)), at(secs(4))]);
    let cc = sim.network().counts(c, Protocol::Query);
    let sc = sim.network().counts(s, Protocol::Query);
    assert_eq!((sc.sent, sc.lost, cc.received), (2, 1, 1));
    assert_balanced(&sim, Protocol::Query);
}
