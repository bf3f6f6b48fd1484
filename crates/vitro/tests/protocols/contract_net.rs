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
