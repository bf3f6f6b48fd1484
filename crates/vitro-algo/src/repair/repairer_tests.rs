//! Tests of the repairer on two watchers along a line of five spots.
use super::*;
use crate::planning::PddlSource;
use crate::repair::Ownership;

/// Two watchers on a line of five spots; the goal: every spot seen.
fn line() -> Scenario {
    let domain = "(define (domain w) (:requirements :strips :typing) (:types uav spot)
      (:predicates (at ?u - uav ?s - spot) (next ?a ?b - spot) (seen ?s - spot))
      (:action hop :parameters (?u - uav ?a ?b - spot)
        :precondition (and (at ?u ?a) (next ?a ?b))
        :effect (and (at ?u ?b) (not (at ?u ?a)) (seen ?b)))
      (:action look :parameters (?u - uav ?s - spot)
        :precondition (at ?u ?s) :effect (seen ?s)))";
    let problem = "(define (problem p) (:domain w) (:objects v0 v1 - uav s0 s1 s2 s3 s4 - spot)
      (:init (at v0 s0) (at v1 s4)
        (next s0 s1) (next s1 s0) (next s1 s2) (next s2 s1) (next s2 s3) (next s3 s2)
        (next s3 s4) (next s4 s3))
      (:goal (and (seen s1) (seen s2) (seen s3))))";
    Scenario::from_pddl(
        PddlSource::new("w.pddl", domain),
        PddlSource::new("p.pddl", problem),
        &Ownership::first_parameter(),
    )
    .expect("the line scenario plans")
}

const GOAL: [&str; 3] = ["(seen s1)", "(seen s2)", "(seen s3)"];

fn with(strategy: Strategy) -> Repairer {
    let settings = RepairSettings {
        strategy,
        ..RepairSettings::default()
    };
    Repairer::new(&line(), settings)
}

/// Runs the first pending step; returns it.
fn first(r: &mut Repairer) -> PlanStep {
    let s = r.pending()[0].clone();
    r.done(s.id);
    s
}

#[test]
fn start_tells_every_owner_once() {
    let mut r = with(Strategy::Replan);
    let told = r.start();
    let owners: BTreeSet<usize> = r.pending().iter().map(|s| s.agent).collect();
    assert_eq!(told, owners.into_iter().collect::<Vec<_>>());
    assert!(r.start().is_empty(), "nobody is told twice");
}

#[test]
fn back_on_track_tells_only_the_failed_agent() {
    let mut r = with(Strategy::BackOnTrack);
    r.start();
    let s = first(&mut r);
    // Its effect did not come true: the agent moved but did not see.
    let moved = s
        .action
        .split_whitespace()
        .nth(3)
        .map(|x| x.trim_end_matches(')'));
    let (a, other) = if s.agent == 0 {
        ("v0", "(at v1 s4)")
    } else {
        ("v1", "(at v0 s0)")
    };
    let at = format!("(at {a} {})", moved.unwrap_or("s0"));
    let belief = [at.as_str(), other];
    let rev = r
        .repair(Cause::Failed(s.id), &belief, &GOAL)
        .expect("known facts")
        .expect("a repair");
    assert_eq!(rev.kind, RepairKind::BackOnTrack);
    assert!(rev.found && !rev.fell_back);
    assert_eq!(rev.tell, vec![s.agent], "the others keep their steps");
}

#[test]
fn replan_tells_every_agent_with_new_steps() {
    let mut r = with(Strategy::Replan);
    r.start();
    let s = first(&mut r);
    let belief = ["(at v0 s0)", "(at v1 s4)"];
    let rev = r
        .repair(Cause::Failed(s.id), &belief, &GOAL)
        .expect("known facts")
        .expect("a repair");
    assert_eq!(rev.kind, RepairKind::Replan);
    let owners: BTreeSet<usize> = r.pending().iter().map(|s| s.agent).collect();
    assert_eq!(rev.tell, owners.into_iter().collect::<Vec<_>>());
}

#[test]
fn lazy_waits_for_the_plan_end() {
    let mut r = with(Strategy::Lazy);
    r.start();
    let s = first(&mut r);
    let belief = ["(at v0 s0)", "(at v1 s4)"];
    assert_eq!(
        r.repair(Cause::Failed(s.id), &belief, &GOAL).expect("ok"),
        None
    );
    assert_eq!(r.tally().deferred, 1);
    while !r.is_finished() {
        first(&mut r);
    }
    let rev = r
        .repair(Cause::PlanEnd, &belief, &GOAL)
        .expect("ok")
        .expect("a lazy repair");
    assert_eq!(rev.kind, RepairKind::Lazy);
    assert!(
        !r.is_deferred(),
        "lazy repairs the lazy repair plan by replanning"
    );
}

#[test]
fn a_lost_agent_work_goes_to_the_other() {
    let mut r = with(Strategy::BackOnTrack);
    r.start();
    let belief = ["(at v0 s0)", "(at v1 s4)"];
    let rev = r
        .repair(Cause::Lost(0), &belief, &GOAL)
        .expect("ok")
        .expect("a repair");
    assert!(rev.found);
    assert!(r.pending().iter().all(|s| s.agent == 1), "v0 is down");
}

#[test]
fn max_depth_cuts_and_counts() {
    let settings = RepairSettings {
        strategy: Strategy::Replan,
        max_depth: Some(1),
        ..RepairSettings::default()
    };
    let mut r = Repairer::new(&line(), settings);
    r.start();
    let belief = ["(at v0 s0)", "(at v1 s4)"];
    let rev = r
        .repair(Cause::PlanEnd, &belief, &GOAL)
        .expect("ok")
        .expect("repair");
    assert!(rev.cut);
    assert_eq!(r.pending().len(), 1);
    assert_eq!(r.tally().cuts, 1);
}

#[test]
fn unknown_facts_are_errors_and_state_survives_serde() {
    let mut r = with(Strategy::Replan);
    r.start();
    assert!(matches!(
        r.repair(Cause::PlanEnd, &["(at v9 s0)"], &GOAL),
        Err(RepairError::UnknownFact(_))
    ));
    let text = toml::to_string(&r).expect("saves");
    let back: Repairer = toml::from_str(&text).expect("restores");
    assert_eq!(back.pending(), r.pending());
}
