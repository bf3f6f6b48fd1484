//! Interaction protocols over the simulated network: request/inform, query, subscribe/notify,
//! contract net and token ring, each on a perfect channel and with lost messages.

use serde::Serialize;
use std::sync::{Arc, Mutex};
use vitro::comm::MessageCounts;
use vitro::prelude::*;
use vitro::protocol::{Handled, Reply, TimerTag};

const TAG: TimerTag = TimerTag(1);

fn ms(n: u64) -> SimDuration {
    SimDuration::from_millis(n)
}
fn secs(n: u64) -> SimDuration {
    SimDuration::from_secs(n)
}
fn at(d: SimDuration) -> SimTime {
    SimTime::ZERO + d
}

/// Sets the loss of the directed link `from -> to`, the rest as the default link.
fn set_loss<M: Model>(sim: &mut Simulation<M>, from: EntityId, to: EntityId, loss: f64) {
    let p = LinkParams {
        loss,
        ..*sim.network().default_link()
    };
    sim.network_mut().set_link(from, to, p);
}

/// Every copy sent under `p` was received, lost or bounced.
fn assert_balanced<M: Model>(sim: &Simulation<M>, p: Protocol) {
    let t = sim.network().all_counts().filter(|&(_, q, _)| q == p).fold(
        MessageCounts::default(),
        |mut t, (_, _, c)| {
            t.sent += c.sent;
            t.received += c.received;
            t.lost += c.lost;
            t.bounced += c.bounced;
            t
        },
    );
    assert_eq!(t.sent, t.received + t.lost + t.bounced, "{p:?}: {t:?}");
}

mod request_inform {
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
}

mod query {
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
}

mod subscribe_notify {
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
}

mod contract_net {
    use super::*;
    use serde::Deserialize;
    use std::collections::{BTreeMap, BTreeSet};
    use vitro::protocol::contract_net::{
        Bid, CallFailure, CnetConfig, CnetEvent, ContractNet, Participants,
    };

    struct M;
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    enum Msg {
        Task(u32),
        Offer { task: u32, cost: f64 },
        Busy,
        Report(u32),
    }
    impl Bid for Msg {
        fn bid(&self) -> Option<f64> {
            match self {
                Msg::Offer { cost, .. } => Some(*cost),
                _ => None,
            }
        }
    }
    #[derive(Clone, Debug, Serialize, Deserialize)]
    enum Ev {
        Start,
        Finish(Reply, u32),
    }

    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    enum Outcome {
        Done(EntityId),
        Failed(CallFailure),
    }

    #[derive(Default, Serialize, Deserialize)]
    struct Manager {
        participants: Vec<EntityId>,
        group: Option<GroupId>,
        tasks: u32,
        sequential: bool,
        reannounce: bool,
        next: u32,
        announcements: u32,
        awards: Vec<(SimTime, u32, EntityId, f64, usize)>,
        outcomes: BTreeMap<u32, Outcome>,
    }

    #[derive(Default, Serialize, Deserialize)]
    struct Worker {
        costs: Vec<f64>,
        capacity: usize,
        work: SimDuration,
        reserved: BTreeMap<Reply, u32>,
        working: BTreeSet<Reply>,
        done: Vec<u32>,
    }

    #[derive(Serialize, Deserialize)]
    enum Role {
        Manager(Manager),
        Worker(Worker),
    }

    #[derive(Serialize, Deserialize)]
    struct Node {
        cnet: ContractNet<Msg>,
        role: Role,
    }

    impl Model for M {
        type Env = ();
        type Event = Ev;
        type Msg = Msg;
        type Agent = Node;
    }

    impl Manager {
        fn announce(&mut self, cnet: &mut ContractNet<Msg>, cx: &mut Context<'_, M>, t: u32) {
            self.announcements += 1;
            let to = match self.group {
                Some(g) => Participants::Group(g),
                None => Participants::Agents(&self.participants),
            };
            cnet.announce(cx, to, u64::from(t), Msg::Task(t));
        }
    }

    const MAX_ANNOUNCEMENTS: u32 = 200;

    impl Agent<M> for Node {
        fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
            let cnet = &mut self.cnet;
            match (&mut self.role, input) {
                (Role::Manager(m), Input::Event(Ev::Start)) => {
                    let first = if m.sequential { 1 } else { m.tasks };
                    while m.next < first {
                        m.next += 1;
                        m.announce(cnet, cx, m.next - 1);
                    }
                }
                (Role::Worker(w), Input::Event(&Ev::Finish(reply, task))) => {
                    w.working.remove(&reply);
                    w.done.push(task);
                    cnet.report_done(cx, reply, Msg::Report(task));
                }
                (Role::Manager(m), _) => match cnet.handle(input, cx) {
                    Handled::Event(CnetEvent::Awarded {
                        task,
                        winner,
                        bid,
                        proposals,
                        ..
                    }) => {
                        m.awards
                            .push((cx.now(), task as u32, winner, bid, proposals));
                        if m.sequential && m.next < m.tasks {
                            m.next += 1;
                            m.announce(cnet, cx, m.next - 1);
                        }
                    }
                    Handled::Event(CnetEvent::Done { task, winner, .. }) => {
                        m.outcomes.insert(task as u32, Outcome::Done(winner));
                    }
                    Handled::Event(CnetEvent::Failed { task, reason, .. }) => {
                        if m.reannounce && m.announcements < MAX_ANNOUNCEMENTS {
                            m.announce(cnet, cx, task as u32);
                        } else {
                            m.outcomes.insert(task as u32, Outcome::Failed(reason));
                            if m.sequential && m.next < m.tasks {
                                m.next += 1;
                                m.announce(cnet, cx, m.next - 1);
                            }
                        }
                    }
                    Handled::NotMine => panic!("stray input to the manager"),
                    _ => {}
                },
                (Role::Worker(w), _) => match cnet.handle(input, cx) {
                    Handled::Event(CnetEvent::CallForProposals { reply, cfp }) => {
                        let Msg::Task(task) = cfp.body else {
                            panic!("not a task")
                        };
                        if w.reserved.len() + w.working.len() < w.capacity {
                            let cost = w.costs[task as usize];
                            cnet.propose(cx, reply, Msg::Offer { task, cost });
                            w.reserved.insert(reply, task);
                        } else {
                            cnet.refuse(cx, reply, Msg::Busy);
                        }
                    }
                    Handled::Event(CnetEvent::Accepted {
                        reply,
                        accept,
                        late,
                    }) => {
                        let Msg::Offer { task, .. } = accept.body else {
                            panic!("accept echoes the offer")
                        };
                        if !late {
                            w.reserved.remove(&reply);
                        }
                        if late && w.reserved.len() + w.working.len() >= w.capacity {
                            cnet.report_failure(cx, reply, Msg::Busy);
                        } else {
                            w.working.insert(reply);
                            cx.schedule_in(w.work, Ev::Finish(reply, task));
                        }
                    }
                    Handled::Event(CnetEvent::Rejected { reply })
                    | Handled::Event(CnetEvent::Expired { reply }) => {
                        w.reserved.remove(&reply);
                    }
                    Handled::NotMine => panic!("stray input to a worker"),
                    _ => {}
                },
            }
        }
    }

    /// Costs of 5 tasks (columns) for 4 workers (rows), and how many tasks each may hold.
    const COSTS: [[f64; 5]; 4] = [
        [1.0, 2.0, 9.0, 9.0, 9.0],
        [9.0, 9.0, 3.0, 9.0, 4.0],
        [2.0, 1.0, 9.0, 2.0, 9.0],
        [9.0, 3.0, 9.0, 2.0, 3.0],
    ];
    const CAPACITY: [usize; 4] = [1, 1, 2, 1];

    /// How a run is set up.
    #[derive(Clone, Copy)]
    struct Plan {
        seed: u64,
        cfg: CnetConfig,
        loss: f64,
        work: SimDuration,
        capacity: [usize; 4],
        sequential: bool,
        reannounce: bool,
        multicast: bool,
    }

    impl Default for Plan {
        fn default() -> Self {
            Plan {
                seed: 1,
                cfg: CnetConfig::default(),
                loss: 0.0,
                work: secs(1),
                capacity: CAPACITY,
                sequential: true,
                reannounce: false,
                multicast: false,
            }
        }
    }

    const GROUP: GroupId = GroupId(1);

    /// Four workers, then the manager; the manager starts at 0 s.
    fn setup(plan: Plan) -> (Simulation<M>, EntityId, Vec<EntityId>) {
        let mut sim = Simulation::<M>::new((), plan.seed);
        sim.network_mut().set_default_link(LinkParams {
            loss: plan.loss,
            ..LinkParams::default()
        });
        let workers: Vec<EntityId> = (0..4)
            .map(|i| {
                let w = Worker {
                    costs: COSTS[i].to_vec(),
                    capacity: plan.capacity[i],
                    work: plan.work,
                    ..Worker::default()
                };
                let node = Node {
                    cnet: ContractNet::new(TAG, plan.cfg),
                    role: Role::Worker(w),
                };
                sim.add_agent(format!("worker{i}"), node).unwrap()
            })
            .collect();
        for &w in &workers {
            sim.network_mut().join(GROUP, w);
        }
        let m = Manager {
            participants: workers.clone(),
            group: plan.multicast.then_some(GROUP),
            tasks: 5,
            sequential: plan.sequential,
            reannounce: plan.reannounce,
            ..Manager::default()
        };
        let node = Node {
            cnet: ContractNet::new(TAG, plan.cfg),
            role: Role::Manager(m),
        };
        let manager = sim.add_agent("manager", node).unwrap();
        sim.schedule(SimTime::ZERO, Target::Entity(manager), Ev::Start)
            .unwrap();
        (sim, manager, workers)
    }

    fn manager(sim: &Simulation<M>, id: EntityId) -> &Manager {
        match &sim.agent(id).unwrap().role {
            Role::Manager(m) => m,
            Role::Worker(_) => panic!("not the manager"),
        }
    }
    fn worker(sim: &Simulation<M>, id: EntityId) -> &Worker {
        match &sim.agent(id).unwrap().role {
            Role::Worker(w) => w,
            Role::Manager(_) => panic!("not a worker"),
        }
    }

    /// Task `t` goes to the cheapest worker with room left (ties to the lowest id).
    fn greedy(capacity: [usize; 4]) -> Vec<(u32, usize)> {
        let mut room = capacity;
        (0..5)
            .map(|t| {
                let w = (0..4)
                    .filter(|&w| room[w] > 0)
                    .min_by(|&a, &b| COSTS[a][t].total_cmp(&COSTS[b][t]).then(a.cmp(&b)))
                    .unwrap();
                room[w] -= 1;
                (t as u32, w)
            })
            .collect()
    }

    fn run(plan: Plan) -> (Simulation<M>, EntityId, Vec<EntityId>) {
        let (mut sim, m, workers) = setup(plan);
        assert_eq!(
            sim.run_until(SimTime::MAX),
            StopReason::QueueEmpty,
            "never hangs"
        );
        // Nothing is left open anywhere.
        assert_eq!(sim.agent(m).unwrap().cnet.open_calls().count(), 0);
        for &w in &workers {
            let wk = worker(&sim, w);
            assert!(wk.reserved.is_empty() && wk.working.is_empty());
            assert_eq!(sim.agent(w).unwrap().cnet.pending_proposals().count(), 0);
        }
        assert_balanced(&sim, Protocol::ContractNet);
        (sim, m, workers)
    }

    #[test]
    fn allocates_each_task_to_the_cheapest_available_bidder() {
        assert_eq!(greedy(CAPACITY), [(0, 0), (1, 2), (2, 1), (3, 2), (4, 3)]);
        for multicast in [false, true] {
            let plan = Plan {
                work: secs(1000), // nobody finishes while tasks are allocated
                cfg: CnetConfig {
                    report_deadline: secs(2000),
                    ..CnetConfig::default()
                },
                multicast,
                ..Plan::default()
            };
            let (sim, m, workers) = run(plan);
            let mgr = manager(&sim, m);
            let expected: Vec<(SimTime, u32, EntityId, f64)> = greedy(CAPACITY)
                .into_iter()
                .map(|(t, w)| {
                    // Decided as soon as all four answered: call + answer = 2 ms after the
                    // previous award, well before the 1 s deadline.
                    let when = at(ms(2 * (u64::from(t) + 1)));
                    (when, t, workers[w], COSTS[w][t as usize])
                })
                .collect();
            let awards: Vec<(SimTime, u32, EntityId, f64)> =
                mgr.awards.iter().map(|a| (a.0, a.1, a.2, a.3)).collect();
            assert_eq!(awards, expected);
            for (_, t, w, _) in &expected {
                assert_eq!(mgr.outcomes[t], Outcome::Done(*w));
                let wi = workers.iter().position(|x| x == w).unwrap();
                assert!(worker(&sim, workers[wi]).done.contains(t));
            }
            assert_eq!(mgr.announcements, 5);
            // Counts: 4 calls per task, then 1 accept + rejects = one per proposal; each worker
            // answers every call and reports each task it won.
            let proposals: u64 = mgr.awards.iter().map(|a| a.4 as u64).sum();
            let cm = sim.network().counts(m, Protocol::ContractNet);
            assert_eq!(cm.sent, 5 * 4 + proposals);
            assert_eq!(cm.received, 5 * 4 + 5);
            for (i, &w) in workers.iter().enumerate() {
                let won = greedy(CAPACITY).iter().filter(|x| x.1 == i).count() as u64;
                let c = sim.network().counts(w, Protocol::ContractNet);
                assert_eq!(c.sent, 5 + won, "worker {i}");
            }
        }
    }

    #[test]
    fn no_bidder_fails_the_call_explicitly() {
        // Room for 4 tasks only: the fifth call is refused by all.
        let plan = Plan {
            work: secs(1000),
            capacity: [1, 1, 1, 1],
            cfg: CnetConfig {
                report_deadline: secs(2000),
                ..CnetConfig::default()
            },
            ..Plan::default()
        };
        let (sim, m, _) = run(plan);
        let mgr = manager(&sim, m);
        assert_eq!(mgr.outcomes.len(), 5);
        assert_eq!(mgr.outcomes[&4], Outcome::Failed(CallFailure::NoProposals));
        assert_eq!(mgr.awards.len(), 4);
    }

    fn lossy(seed: u64, reannounce: bool) -> Plan {
        Plan {
            seed,
            loss: 0.3,
            sequential: false, // all five tasks at once
            reannounce,
            capacity: [2; 4],
            work: secs(1),
            cfg: CnetConfig {
                proposal_deadline: secs(1),
                report_deadline: secs(3),
                proposal_expiry: secs(2),
            },
            ..Plan::default()
        }
    }

    #[test]
    fn with_lost_messages_every_call_ends_and_reannouncing_allocates_all() {
        let (sim, m, workers) = run(lossy(7, true));
        let mgr = manager(&sim, m);
        assert_eq!(mgr.outcomes.len(), 5);
        for (t, o) in &mgr.outcomes {
            let Outcome::Done(w) = o else {
                panic!("task {t} ended {o:?}")
            };
            assert!(worker(&sim, *w).done.contains(t), "{w} did task {t}");
            assert!(workers.contains(w));
        }
        assert!(mgr.announcements > 5, "losses forced re-announcements");
        assert!(mgr.announcements < MAX_ANNOUNCEMENTS);
        let lost: u64 = sim.network().all_counts().map(|(_, _, c)| c.lost).sum();
        assert!(lost > 0);
    }

    #[test]
    fn with_lost_messages_and_no_reannouncing_every_call_still_ends() {
        let (mut done, mut failed) = (0, 0);
        for seed in 0..20 {
            let (sim, m, _) = run(lossy(seed, false));
            let mgr = manager(&sim, m);
            assert_eq!(
                mgr.outcomes.len(),
                5,
                "seed {seed}: every task has an outcome"
            );
            assert_eq!(mgr.announcements, 5);
            for o in mgr.outcomes.values() {
                match o {
                    Outcome::Done(_) => done += 1,
                    Outcome::Failed(_) => failed += 1,
                }
            }
            assert!(sim.now() < at(secs(10)), "ends within the deadlines");
        }
        assert!(done > 0 && failed > 0, "done {done}, failed {failed}");
    }

    #[test]
    fn same_seed_same_trace() {
        let hash = |seed| run(lossy(seed, true)).0.trace_hash();
        assert_eq!(hash(3), hash(3));
        assert_ne!(hash(3), hash(4));
    }

    #[test]
    fn a_snapshot_mid_allocation_resumes_identically() {
        let plan = lossy(5, true);
        let (mut whole, ..) = setup(plan);
        whole.run_until(SimTime::MAX);

        let (mut first, m, _) = setup(plan);
        first.run_until(at(ms(2500)));
        assert!(
            first.agent(m).unwrap().cnet.open_calls().count() > 0,
            "mid-way"
        );
        let mut bytes = Vec::new();
        first.save_snapshot(&mut bytes).unwrap();
        let mut resumed = Simulation::<M>::load_snapshot(&bytes[..]).unwrap();
        resumed.run_until(SimTime::MAX);
        assert_eq!(resumed.trace_hash(), whole.trace_hash());
        assert_eq!(manager(&resumed, m).outcomes, manager(&whole, m).outcomes);
    }
}

mod token_ring {
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
}
