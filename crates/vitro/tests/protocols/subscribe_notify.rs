use super::*;
use vitro::protocol::subscribe::{SubscribeEvent, SubscribeNotify};

struct M;
#[derive(Clone, Debug, PartialEq, Serialize)]
enum Msg {
    Watch,
    Ok,
    Value(u32),
    Stop,
}
#[derive(Clone, Debug, Serialize)]
enum Ev {
    Subscribe,
    Cancel,
    Change(u32),
}
struct Node {
    sn: SubscribeNotify,
    publisher: EntityId,
    resubscribe: bool,
    sub: Option<u64>,
    values: Vec<u32>,
    timeouts: u32,
    unsubscribed: Vec<EntityId>,
}
impl Model for M {
    type Env = ();
    type Event = Ev;
    type Msg = Msg;
    type Agent = Node;
}
impl Node {
    fn subscribe(&mut self, cx: &mut Context<'_, M>) {
        let conv = self
            .sn
            .subscribe(cx, self.publisher, Msg::Watch, Some(secs(1)));
        self.sub = Some(conv);
    }
}
impl Agent<M> for Node {
    fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
        match input {
            Input::Event(Ev::Subscribe) => self.subscribe(cx),
            Input::Event(Ev::Cancel) => {
                if let Some(conv) = self.sub.take() {
                    assert!(self.sn.cancel(cx, conv, Msg::Stop));
                }
            }
            Input::Event(&Ev::Change(v)) => {
                self.sn.notify_all(cx, Msg::Value(v));
            }
            _ => match self.sn.handle(input, cx) {
                Handled::Event(SubscribeEvent::SubscribeRequested { reply, .. }) => {
                    self.sn.accept(cx, reply, Msg::Ok)
                }
                Handled::Event(SubscribeEvent::Unsubscribed { subscriber }) => {
                    self.unsubscribed.push(subscriber.to)
                }
                Handled::Event(SubscribeEvent::Notified { notification }) => {
                    if let Msg::Value(v) = notification.body {
                        self.values.push(v);
                    }
                }
                Handled::Event(SubscribeEvent::TimedOut { .. }) => {
                    self.timeouts += 1;
                    if self.resubscribe {
                        self.subscribe(cx);
                    }
                }
                Handled::Event(SubscribeEvent::Confirmed { conversation, .. }) => {
                    assert!(self.sn.is_confirmed(conversation))
                }
                Handled::NotMine => panic!("stray input"),
                _ => {}
            },
        }
    }
}

fn node(publisher: EntityId) -> Node {
    Node {
        sn: SubscribeNotify::new(TAG),
        publisher,
        resubscribe: true,
        sub: None,
        values: Vec::new(),
        timeouts: 0,
        unsubscribed: Vec::new(),
    }
}

/// A publisher whose value changes at 1, 2, ... 5 s; two subscribers from 0 s.
fn setup() -> (Simulation<M>, EntityId, EntityId, EntityId) {
    let mut sim = Simulation::<M>::new((), 3);
    let p = sim.add_agent("publisher", node(EntityId(0))).unwrap();
    let a = sim.add_agent("a", node(p)).unwrap();
    let b = sim.add_agent("b", node(p)).unwrap();
    for v in 1..=5 {
        sim.schedule(at(secs(v as u64)), Target::Entity(p), Ev::Change(v))
            .unwrap();
    }
    for s in [a, b] {
        sim.schedule(SimTime::ZERO, Target::Entity(s), Ev::Subscribe)
            .unwrap();
    }
    (sim, p, a, b)
}

fn subscribers(sim: &Simulation<M>, p: EntityId) -> Vec<EntityId> {
    sim.agent(p)
        .unwrap()
        .sn
        .subscribers()
        .iter()
        .map(|r| r.to)
        .collect()
}

#[test]
fn notify_on_change_until_cancelled() {
    let (mut sim, p, a, b) = setup();
    sim.schedule(at(ms(2500)), Target::Entity(b), Ev::Cancel)
        .unwrap();
    sim.run_until(SimTime::MAX);
    assert_eq!(sim.agent(a).unwrap().values, [1, 2, 3, 4, 5]);
    assert_eq!(sim.agent(b).unwrap().values, [1, 2]);
    assert_eq!(subscribers(&sim, p), [a]);
    assert_eq!(sim.agent(p).unwrap().unsubscribed, [b]);
    let count = |who| sim.network().counts(who, Protocol::Subscribe);
    assert_eq!(count(p).sent, 2 + 5 + 2); // agrees + notifications
    assert_eq!(count(a).sent, 1);
    assert_eq!(count(b).sent, 2); // subscribe + cancel
    assert_eq!(count(p).received, 3);
    assert_balanced(&sim, Protocol::Subscribe);
}

#[test]
fn lost_subscribe_times_out_and_is_repeated() {
    let (mut sim, p, a, b) = setup();
    set_loss(&mut sim, a, p, 1.0);
    sim.run_until(at(ms(1500)));
    set_loss(&mut sim, a, p, 0.0);
    sim.run_until(SimTime::MAX);
    // Lost at 0 s and at 1 s; the third subscribe (2 s) is confirmed after the change at 2 s.
    let na = sim.agent(a).unwrap();
    assert_eq!(na.timeouts, 2);
    assert_eq!(na.values, [3, 4, 5]);
    assert_eq!(sim.agent(b).unwrap().values, [1, 2, 3, 4, 5]);
    assert_eq!(subscribers(&sim, p), [b, a]);
    let ca = sim.network().counts(a, Protocol::Subscribe);
    assert_eq!((ca.sent, ca.lost), (3, 2));
    assert_balanced(&sim, Protocol::Subscribe);
}

#[test]
fn lost_cancel_is_repeated_on_the_next_notification() {
    let (mut sim, p, a, b) = setup();
    sim.schedule(at(ms(2500)), Target::Entity(b), Ev::Cancel)
        .unwrap();
    sim.run_until(at(ms(2400)));
    set_loss(&mut sim, b, p, 1.0);
    sim.run_until(at(ms(3500)));
    set_loss(&mut sim, b, p, 0.0);
    sim.run_until(SimTime::MAX);
    // The cancel (2.5 s) and the automatic re-cancel after the 3 s notification are lost;
    // the one after the 4 s notification gets through.
    assert_eq!(sim.agent(b).unwrap().values, [1, 2]);
    assert_eq!(subscribers(&sim, p), [a]);
    assert_eq!(sim.agent(p).unwrap().unsubscribed, [b]);
    let cb = sim.network().counts(b, Protocol::Subscribe);
    assert_eq!((cb.sent, cb.lost, cb.received), (4, 2, 5));
    assert_eq!(sim.network().counts(p, Protocol::Subscribe).sent, 2 + 5 + 4);
    assert_balanced(&sim, Protocol::Subscribe);
}
