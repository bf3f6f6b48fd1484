//! The simulation driver: event order, broadcast, cancellation, stop conditions, listeners,
//! pacing against an injected clock, pause / step / resume from another thread.

use serde::Serialize;
use std::sync::{Arc, Mutex};
use std::time::Duration;
use vitro::prelude::*;
use vitro::sim::ManualClock;

/// A model whose agents log every input they get.
struct Log;
#[derive(Clone, Debug, PartialEq, Serialize)]
enum Ev {
    Mark(u32),
    /// Schedule `Mark(5)` for myself at 5 s and publish its id.
    Plan,
    /// Cancel the published id.
    CancelPlanned,
    Think(u64),
    Thought,
    Stop,
    Timers,
}
#[derive(Default)]
struct Logger {
    seen: Arc<Mutex<Vec<(SimTime, EntityId, String)>>>,
    /// An id one agent scheduled for itself, shared with the others (a forged hand-over).
    planned: Arc<Mutex<Option<OwnEventId>>>,
}
impl Agent<Log> for Logger {
    fn handle(&mut self, input: Input<'_, Log>, cx: &mut Context<'_, Log>) {
        let what = match input {
            Input::Event(Ev::Plan) => {
                let id = cx.schedule_at(SimTime::from_secs(5), Ev::Mark(5));
                *self.planned.lock().expect("lock") = Some(id.expect("future"));
                "plan".into()
            }
            Input::Event(Ev::CancelPlanned) => {
                let id = self.planned.lock().expect("lock").expect("planned");
                format!("cancel:{}", cx.cancel(id))
            }
            Input::Event(Ev::Think(units)) => {
                let cost = CostModel {
                    base: SimDuration::from_millis(5),
                    per_unit: SimDuration::from_micros(10),
                };
                cx.decide_after(&cost, *units, Ev::Thought);
                format!("think:{units}")
            }
            Input::Event(Ev::Timers) => {
                cx.set_timer(SimDuration::from_secs(2), 7);
                let doomed = cx.set_timer(SimDuration::from_secs(1), 8);
                cx.set_timer(SimDuration::from_secs(1), 9);
                assert!(cx.cancel(doomed));
                "timers".into()
            }
            Input::Event(Ev::Stop) => {
                cx.request_stop();
                "stop".into()
            }
            Input::Event(e) => format!("{e:?}"),
            Input::Timer(k) => format!("timer:{k}"),
            _ => "other".into(),
        };
        self.seen
            .lock()
            .expect("lock")
            .push((cx.now(), cx.me(), what));
    }
}
impl Model for Log {
    type Env = ();
    type Event = Ev;
    type Msg = ();
    type Agent = Logger;
}

type Seen = Arc<Mutex<Vec<(SimTime, EntityId, String)>>>;

fn log_sim(n: usize) -> (Simulation<Log>, Seen, Vec<EntityId>) {
    let seen: Seen = Arc::default();
    let planned = Arc::default();
    let mut sim = Simulation::<Log>::new((), 0);
    let ids = (0..n)
        .map(|i| {
            let logger = Logger {
                seen: seen.clone(),
                planned: Arc::clone(&planned),
            };
            sim.add_agent(format!("a{i}"), logger).expect("unique")
        })
        .collect();
    (sim, seen, ids)
}

fn strings(seen: &Seen) -> Vec<String> {
    seen.lock()
        .expect("lock")
        .iter()
        .map(|(_, _, s)| s.clone())
        .collect()
}

#[test]
fn equal_time_events_fire_in_scheduling_order() {
    let (mut sim, seen, ids) = log_sim(3);
    let t = SimTime::from_secs(1);
    for i in 0..30u32 {
        sim.schedule(t, Target::Entity(ids[(i * 7 % 3) as usize]), Ev::Mark(i))
            .expect("future");
    }
    sim.schedule(
        SimTime::ZERO + SimDuration::from_millis(500),
        Target::Entity(ids[2]),
        Ev::Mark(99),
    )
    .expect("future");
    sim.run_until(SimTime::MAX);
    let expected: Vec<String> = std::iter::once(99)
        .chain(0..30)
        .map(|i| format!("Mark({i})"))
        .collect();
    assert_eq!(strings(&seen), expected);
}

#[test]
fn broadcast_reaches_every_agent_in_registration_order() {
    let (mut sim, seen, ids) = log_sim(4);
    sim.add_entity("a passive body").expect("unique");
    sim.schedule(SimTime::ZERO, Target::Broadcast, Ev::Mark(1))
        .expect("future");
    sim.schedule(SimTime::ZERO, Target::Entity(ids[1]), Ev::Mark(2))
        .expect("future");
    sim.run_until(SimTime::MAX);
    let got: Vec<(EntityId, String)> = seen
        .lock()
        .expect("lock")
        .iter()
        .map(|(_, e, s)| (*e, s.clone()))
        .collect();
    let mut expected: Vec<(EntityId, String)> =
        ids.iter().map(|&e| (e, "Mark(1)".into())).collect();
    expected.push((ids[1], "Mark(2)".into()));
    assert_eq!(got, expected);
}

#[test]
fn cancellation_and_scheduling_in_the_past() {
    let (mut sim, seen, ids) = log_sim(1);
    let a = ids[0];
    let doomed = sim
        .schedule(SimTime::from_secs(5), Target::Entity(a), Ev::Mark(5))
        .expect("future");
    sim.schedule(SimTime::from_secs(3), Target::Entity(a), Ev::Mark(3))
        .expect("future");
    assert!(sim.cancel(doomed));
    assert!(!sim.cancel(doomed));
    sim.run_until(SimTime::MAX);
    assert_eq!(strings(&seen), ["Mark(3)"]);
    assert!(
        sim.schedule(SimTime::from_secs(1), Target::Entity(a), Ev::Mark(0))
            .is_err()
    );
    assert!(!sim.cancel(doomed));
}

#[test]
fn an_agent_cancels_its_own_events_only() {
    let (mut sim, seen, ids) = log_sim(2);
    let (a, b) = (ids[0], ids[1]);
    // a schedules Mark(5) for itself; b, handed a's id, cannot cancel it; a can, once.
    sim.schedule(SimTime::from_secs(1), Target::Entity(a), Ev::Plan)
        .expect("future");
    sim.schedule(SimTime::from_secs(2), Target::Entity(b), Ev::CancelPlanned)
        .expect("future");
    sim.schedule(SimTime::from_secs(3), Target::Entity(a), Ev::CancelPlanned)
        .expect("future");
    sim.schedule(SimTime::from_secs(4), Target::Entity(a), Ev::CancelPlanned)
        .expect("future");
    sim.run_until(SimTime::MAX);
    assert_eq!(
        strings(&seen),
        ["plan", "cancel:false", "cancel:true", "cancel:false"]
    );

    // Not cancelled: the event fires at a.
    let (mut sim, seen, ids) = log_sim(2);
    sim.schedule(SimTime::from_secs(1), Target::Entity(ids[0]), Ev::Plan)
        .expect("future");
    sim.schedule(
        SimTime::from_secs(2),
        Target::Entity(ids[1]),
        Ev::CancelPlanned,
    )
    .expect("future");
    sim.run_until(SimTime::MAX);
    let got: Vec<(EntityId, String)> = seen
        .lock()
        .expect("lock")
        .iter()
        .map(|(_, e, s)| (*e, s.clone()))
        .collect();
    assert_eq!(
        got,
        [
            (ids[0], "plan".to_string()),
            (ids[1], "cancel:false".to_string()),
            (ids[0], "Mark(5)".to_string())
        ]
    );
}

#[test]
fn stop_at_time_condition_request_and_empty_queue() {
    let (mut sim, seen, ids) = log_sim(1);
    for s in 1..=10 {
        sim.schedule(
            SimTime::from_secs(s),
            Target::Entity(ids[0]),
            Ev::Mark(s as u32),
        )
        .expect("future");
    }
    sim.schedule(SimTime::from_secs(8), Target::Entity(ids[0]), Ev::Stop)
        .expect("future");
    assert_eq!(sim.run_until(SimTime::from_secs(3)), StopReason::Time);
    assert_eq!(sim.now(), SimTime::from_secs(3));
    assert_eq!(
        sim.run(SimTime::MAX, |s| s.events_fired() == 5),
        StopReason::Condition
    );
    assert_eq!(sim.now(), SimTime::from_secs(5));
    assert_eq!(sim.run_until(SimTime::MAX), StopReason::Requested);
    assert_eq!(strings(&seen).last().map(String::as_str), Some("stop"));
    assert_eq!(sim.run_until(SimTime::MAX), StopReason::QueueEmpty);
    assert_eq!(sim.events_fired(), 11);
}

#[test]
fn thinking_takes_simulated_time_from_the_cost_model() {
    let (mut sim, seen, ids) = log_sim(1);
    sim.schedule(
        SimTime::from_secs(1),
        Target::Entity(ids[0]),
        Ev::Think(1000),
    )
    .expect("future");
    sim.run_until(SimTime::MAX);
    let log = seen.lock().expect("lock").clone();
    assert_eq!(log[1].2, "Thought");
    // 5 ms + 1000 × 10 µs = 15 ms after the trigger.
    assert_eq!(log[1].0 - log[0].0, SimDuration::from_millis(15));
}

#[test]
fn listeners_see_every_event_after_it_is_handled() {
    let (mut sim, _, ids) = log_sim(2);
    let heard = Arc::new(Mutex::new(Vec::new()));
    let h2 = heard.clone();
    sim.add_listener(move |f| {
        h2.lock()
            .expect("lock")
            .push((f.time, f.id.seq(), f.target))
    });
    sim.schedule(SimTime::from_secs(2), Target::Broadcast, Ev::Mark(0))
        .expect("future");
    sim.schedule(SimTime::from_secs(1), Target::Entity(ids[1]), Ev::Mark(1))
        .expect("future");
    sim.run_until(SimTime::MAX);
    assert_eq!(
        *heard.lock().expect("lock"),
        [
            (SimTime::from_secs(1), 1, Target::Entity(ids[1])),
            (SimTime::from_secs(2), 0, Target::Broadcast)
        ]
    );
}

/// Runs `sim` paced by a manual clock; returns the wall time (clock) at which each event fired.
fn wall_times(speed_changes: Vec<(u64, f64)>, speed: f64) -> Vec<Duration> {
    let (mut sim, _, ids) = log_sim(1);
    for s in 0..=10 {
        sim.schedule(
            SimTime::from_secs(s),
            Target::Entity(ids[0]),
            Ev::Mark(s as u32),
        )
        .expect("future");
    }
    let clock = ManualClock::default();
    clock.advance(Duration::from_secs(100)); // an arbitrary origin
    sim.set_clock(clock.clone());
    let control = sim.control();
    control.set_speed(speed).expect("in range");
    let walls = Arc::new(Mutex::new(Vec::new()));
    let w2 = walls.clone();
    let c2 = clock.clone();
    sim.add_listener(move |f| {
        w2.lock()
            .expect("lock")
            .push(c2.now() - Duration::from_secs(100));
        for &(at, s) in &speed_changes {
            if f.time == SimTime::from_secs(at) {
                control.set_speed(s).expect("in range");
            }
        }
    });
    sim.run_until(SimTime::MAX);
    walls.lock().expect("lock").clone()
}

use vitro::sim::Clock;

#[test]
fn pacing_follows_the_speed_factor_on_an_injected_clock() {
    let w = wall_times(vec![], 2.0);
    let expected: Vec<Duration> = (0..=10).map(|s| Duration::from_millis(500 * s)).collect();
    assert_eq!(w, expected);
    let w = wall_times(vec![], 0.1);
    assert_eq!(w[10], Duration::from_secs(100));
}

#[test]
fn speed_changes_while_running_take_effect_from_the_current_event() {
    // 1x for the first 4 s, then 10x: event 4 at wall 4 s, event 10 at 4 + 0.6 s.
    let w = wall_times(vec![(4, 10.0)], 1.0);
    assert_eq!(w[4], Duration::from_secs(4));
    assert_eq!(w[10], Duration::from_millis(4600));
}

#[test]
fn pause_freezes_step_fires_exactly_one_event_resume_finishes() {
    let (mut sim, _, ids) = log_sim(1);
    for s in 0..100 {
        sim.schedule(
            SimTime::from_secs(s),
            Target::Entity(ids[0]),
            Ev::Mark(s as u32),
        )
        .expect("future");
    }
    let control = sim.control();
    control.pause();
    let worker = std::thread::spawn(move || sim.run_until(SimTime::MAX));
    std::thread::sleep(Duration::from_millis(30));
    assert_eq!(control.events_fired(), 0, "paused before the first event");
    for k in 1..=3 {
        control.step(1);
        let t0 = std::time::Instant::now();
        while control.events_fired() < k && t0.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_millis(1));
        }
        std::thread::sleep(Duration::from_millis(20));
        assert_eq!(control.events_fired(), k, "one step, one event");
        assert_eq!(control.sim_time(), SimTime::from_secs(k - 1));
    }
    control.resume();
    assert_eq!(worker.join().expect("no panic"), StopReason::QueueEmpty);
    assert_eq!(control.events_fired(), 100);
}

#[test]
fn control_stop_ends_a_paused_run_and_speed_is_validated() {
    let (mut sim, _, ids) = log_sim(1);
    sim.schedule(SimTime::from_secs(1), Target::Entity(ids[0]), Ev::Mark(0))
        .expect("future");
    let control = sim.control();
    assert!(control.set_speed(0.05).is_err());
    assert!(control.set_speed(5000.0).is_err());
    assert!(control.set_speed(f64::NAN).is_err());
    control.pause();
    let worker = std::thread::spawn(move || sim.run_until(SimTime::MAX));
    std::thread::sleep(Duration::from_millis(10));
    control.stop();
    assert_eq!(worker.join().expect("no panic"), StopReason::Control);
}

#[test]
fn timers_wake_their_agent_and_can_be_cancelled() {
    let (mut sim, seen, ids) = log_sim(2);
    sim.schedule(SimTime::from_secs(1), Target::Entity(ids[1]), Ev::Timers)
        .expect("future");
    sim.run_until(SimTime::MAX);
    let log = seen.lock().expect("lock").clone();
    let got: Vec<_> = log
        .iter()
        .map(|(t, e, s)| (t.as_nanos() / 1_000_000_000, *e, s.as_str()))
        .collect();
    assert_eq!(
        got,
        [
            (1, ids[1], "timers"),
            (2, ids[1], "timer:9"),
            (3, ids[1], "timer:7")
        ]
    );
}
