//! Planning tests: parsing, grounding, both planners, the validator. PDDL error messages
//! are tested in `planning_pddl.rs`.
//! The long optimal runs (dwr problem-02, depot p03) are in `planning_optimal.rs`.

use std::collections::{HashMap, VecDeque};

use vitro_algo::planning::heuristic::{FfHeuristic, HMax, Heuristic, LmCut};
use vitro_algo::planning::pddl::{Domain, Problem, parse_domain, parse_problem};
use vitro_algo::planning::validate::{ValidationError, validate_plan};
use vitro_algo::planning::{
    GroundError, PddlSource, PlanError, Planner, Task, ground, plan_task, solve,
};

const DWR_DOMAIN: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/planning/dwr/domain.pddl"
));
const DWR_02: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/planning/dwr/problem-02.pddl"
));
const DEPOT_DOMAIN: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/planning/depot/domain.pddl"
));
const DEPOT: [&str; 3] = [
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/planning/depot/p01.pddl"
    )),
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/planning/depot/p02.pddl"
    )),
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/planning/depot/p03.pddl"
    )),
];

const BLOCKS: &str = "
(define (domain blocks)
  (:requirements :strips :typing :equality)
  (:types block)
  (:predicates (on ?x ?y - block) (ontable ?x - block) (clear ?x - block)
               (handempty) (holding ?x - block))
  (:action pick-up :parameters (?x - block)
    :precondition (and (clear ?x) (ontable ?x) (handempty))
    :effect (and (not (ontable ?x)) (not (clear ?x)) (not (handempty)) (holding ?x)))
  (:action put-down :parameters (?x - block)
    :precondition (holding ?x)
    :effect (and (not (holding ?x)) (clear ?x) (handempty) (ontable ?x)))
  (:action stack :parameters (?x ?y - block)
    :precondition (and (holding ?x) (clear ?y) (not (= ?x ?y)))
    :effect (and (not (holding ?x)) (not (clear ?y)) (clear ?x) (handempty) (on ?x ?y)))
  (:action unstack :parameters (?x ?y - block)
    :precondition (and (on ?x ?y) (clear ?x) (handempty))
    :effect (and (holding ?x) (clear ?y) (not (clear ?x)) (not (handempty))
                 (not (on ?x ?y)))))";

/// A blocksworld problem over `blocks`; `towers` lists towers bottom first.
fn blocks_problem(blocks: &str, towers: &[&[&str]], goal: &str) -> String {
    let mut init = String::from("(handempty)");
    for t in towers {
        init += &format!(" (ontable {})", t[0]);
        for w in t.windows(2) {
            init += &format!(" (on {} {})", w[1], w[0]);
        }
        init += &format!(" (clear {})", t[t.len() - 1]);
    }
    format!(
        "(define (problem b) (:domain blocks) (:objects {blocks} - block) \
         (:init {init}) (:goal (and {goal})))"
    )
}

fn parsed(domain: &str, problem: &str) -> (Domain, Problem) {
    let d = parse_domain(domain, "domain.pddl").expect("domain parses");
    let p = parse_problem(&d, problem, "problem.pddl").expect("problem parses");
    (d, p)
}

/// Solves and validates with the independent validator; returns the plan length.
fn solve_valid(domain: &str, problem: &str, planner: Planner) -> usize {
    let (d, p) = parsed(domain, problem);
    let result = solve(
        PddlSource::new("domain.pddl", domain),
        PddlSource::new("problem.pddl", problem),
        planner,
    )
    .expect("solvable");
    validate_plan(&d, &p, &result.plan).expect("the returned plan is valid");
    assert_eq!(result.length, result.plan.len());
    result.length
}

/// Shortest plan length by breadth-first search over the ground task (an independent
/// check of A*'s optimality on small tasks).
fn bfs_length(task: &Task) -> Option<usize> {
    let init = task.initial_state();
    let mut dist = HashMap::from([(init.clone(), 0usize)]);
    let mut queue = VecDeque::from([init]);
    let mut next = Vec::new();
    while let Some(s) = queue.pop_front() {
        let d = dist[&s];
        if task.is_goal(&s) {
            return Some(d);
        }
        for a in 0..task.actions.len() as u32 {
            if task.applicable(a, &s) {
                task.apply_into(a, &s, &mut next);
                if !dist.contains_key(&next) {
                    dist.insert(next.clone(), d + 1);
                    queue.push_back(next.clone());
                }
            }
        }
    }
    None
}

// ---- parsing ------------------------------------------------------------------------------

#[test]
fn reference_files_parse() {
    let (d, p) = parsed(DWR_DOMAIN, DWR_02);
    assert_eq!(d.name, "dock-worker-robot-pos");
    assert_eq!(d.actions.len(), 5);
    assert_eq!(d.constants[0].name, "pallet");
    // The constant comes first, then the 15 declared objects.
    assert_eq!(p.objects.len(), 16);
    assert_eq!(p.objects[1].name, "r1");
    assert_eq!(p.goal.len(), 6);
    let d = parse_domain(DEPOT_DOMAIN, "depot.pddl").expect("depot domain");
    for src in DEPOT {
        parse_problem(&d, src, "p.pddl").expect("depot problem");
    }
}

#[test]
fn symbols_are_case_insensitive() {
    let upper = BLOCKS.to_uppercase();
    let problem = blocks_problem("A B", &[&["A"], &["B"]], "(ON A B)");
    let (d1, p1) = parsed(&upper, &problem);
    let (d2, p2) = parsed(BLOCKS, &problem.to_lowercase());
    assert_eq!(d1, d2);
    assert_eq!(p1, p2);
}

// ---- grounding ----------------------------------------------------------------------------

#[test]
fn grounding_folds_static_predicates_and_keeps_reachable_actions() {
    let (d, p) = parsed(DWR_DOMAIN, DWR_02);
    let task = ground(&d, &p).expect("grounds");
    for f in &task.facts {
        for stat in ["(adjacent ", "(attached ", "(belong "] {
            assert!(!f.starts_with(stat), "static fact kept: {f}");
        }
    }
    assert!(task.facts.iter().any(|f| f == "(atl r1 l1)"));
    let names: Vec<&str> = task.actions.iter().map(|a| a.name.as_str()).collect();
    assert!(names.contains(&"(move r1 l1 l2)"));
    // l1 is not adjacent to itself, so this binding is never grounded.
    assert!(!names.contains(&"(move r1 l1 l1)"));
    for a in &task.actions {
        assert!(a.pre.windows(2).all(|w| w[0] < w[1]), "sorted pre");
        assert!(a.del.iter().all(|f| !a.add.contains(f)), "del ∩ add = ∅");
    }

    // Blocksworld, 3 blocks: 3 pick-up, 3 put-down, 6 stack, 6 unstack are reachable;
    // (not (= ?x ?y)) removes (stack a a) and friends.
    let prob = blocks_problem("a b c", &[&["a"], &["b"], &["c"]], "(on a b)");
    let (d, p) = parsed(BLOCKS, &prob);
    let task = ground(&d, &p).expect("grounds");
    assert_eq!(task.actions.len(), 18);
    assert!(!task.actions.iter().any(|a| a.name == "(stack a a)"));
}

#[test]
fn unreachable_goal_is_reported_before_search() {
    // Nothing ever makes a block hold itself up.
    let prob = blocks_problem("a b", &[&["a"], &["b"]], "(on a a)");
    let err = solve(
        PddlSource::new("d", BLOCKS),
        PddlSource::new("p", &prob),
        Planner::Optimal,
    )
    .expect_err("unsolvable");
    assert!(
        matches!(err, PlanError::Ground(GroundError::UnreachableGoal(ref g)) if g == "(on a a)")
    );
    assert_eq!(
        err.to_string(),
        "no plan: goal (on a a) is unreachable, even ignoring delete effects"
    );
}

/// One token, two places, moves only between distinct places.
const TOKEN_DOMAIN: &str = "(define (domain token) (:predicates (at ?p))
  (:action go :parameters (?from ?to) :precondition (and (at ?from) (not (= ?from ?to)))
   :effect (and (at ?to) (not (at ?from)))))";
/// The goal wants the token in both places at once: relaxed-reachable, unsolvable.
const TOKEN_PROBLEM: &str = "(define (problem both) (:domain token) (:objects x y)
  (:init (at x)) (:goal (and (at x) (at y))))";

#[test]
fn relaxed_reachable_but_unsolvable_is_exhausted() {
    for planner in [Planner::Optimal, Planner::Satisficing] {
        let err = solve(
            PddlSource::new("d", TOKEN_DOMAIN),
            PddlSource::new("p", TOKEN_PROBLEM),
            planner,
        )
        .expect_err("unsolvable");
        assert!(
            matches!(err, PlanError::Unsolvable { expanded: 2 }),
            "{planner}: {err}"
        );
    }
}

// ---- planners -----------------------------------------------------------------------------

#[test]
fn blocksworld_optimal_lengths_match_breadth_first_search() {
    let cases: &[(&[&[&str]], &str, usize)] = &[
        // The Sussman anomaly.
        (&[&["a", "c"], &["b"]], "(on a b) (on b c)", 6),
        // Invert a tower.
        (&[&["c", "b", "a"]], "(on c b) (on b a)", 6),
        // Already solved.
        (&[&["a", "b"], &["c"]], "(on b a)", 0),
        (&[&["a"], &["b"], &["c"]], "(on a b) (on b c)", 4),
    ];
    for &(towers, goal, expected) in cases {
        let prob = blocks_problem("a b c", towers, goal);
        let (d, p) = parsed(BLOCKS, &prob);
        let task = ground(&d, &p).expect("grounds");
        assert_eq!(bfs_length(&task), Some(expected), "BFS on {goal}");
        assert_eq!(solve_valid(BLOCKS, &prob, Planner::Optimal), expected);
        assert!(solve_valid(BLOCKS, &prob, Planner::Satisficing) >= expected);
    }
    // Four blocks, a few scrambles.
    let four: &[(&[&[&str]], &str)] = &[
        (&[&["a", "b", "c", "d"]], "(on a b) (on b c) (on c d)"),
        (&[&["d", "a"], &["b", "c"]], "(on c a) (on a d) (on b c)"),
        (&[&["b"], &["a", "d", "c"]], "(on d b) (on a c)"),
    ];
    for &(towers, goal) in four {
        let prob = blocks_problem("a b c d", towers, goal);
        let (d, p) = parsed(BLOCKS, &prob);
        let task = ground(&d, &p).expect("grounds");
        let optimal = bfs_length(&task).expect("solvable");
        assert_eq!(
            solve_valid(BLOCKS, &prob, Planner::Optimal),
            optimal,
            "{goal}"
        );
    }
}

#[test]
fn depot_small_problems_are_solved_optimally() {
    assert_eq!(solve_valid(DEPOT_DOMAIN, DEPOT[0], Planner::Optimal), 10);
    assert_eq!(solve_valid(DEPOT_DOMAIN, DEPOT[1], Planner::Optimal), 15);
}

#[test]
fn satisficing_planner_solves_every_reference_problem() {
    let optimal = [(DWR_DOMAIN, DWR_02, 35)].into_iter().chain(
        DEPOT
            .iter()
            .zip([10, 15, 27])
            .map(|(p, n)| (DEPOT_DOMAIN, *p, n)),
    );
    for (domain, problem, best) in optimal {
        let length = solve_valid(domain, problem, Planner::Satisficing);
        assert!(length >= best, "shorter than optimal: {length} < {best}");
    }
}

#[test]
fn search_is_deterministic() {
    for planner in [Planner::Optimal, Planner::Satisficing] {
        let run = || {
            solve(
                PddlSource::new("d", DEPOT_DOMAIN),
                PddlSource::new("p", DEPOT[1]),
                planner,
            )
            .expect("solves")
        };
        assert_eq!(run(), run());
    }
}

#[test]
fn lmcut_is_admissible_and_dominates_hmax_along_an_optimal_plan() {
    let (d, p) = parsed(DEPOT_DOMAIN, DEPOT[1]);
    let task = ground(&d, &p).expect("grounds");
    let plan = plan_task(&task, Planner::Optimal).plan.expect("solvable");
    assert_eq!(plan.len(), 15);
    let (mut lmcut, mut hmax, mut ff) =
        (LmCut::new(&task), HMax::new(&task), FfHeuristic::new(&task));
    let mut state = task.initial_state();
    let mut next = Vec::new();
    for (i, &a) in plan.iter().enumerate() {
        let remaining = (plan.len() - i) as u32;
        let lm = lmcut.evaluate(&state).expect("not a dead end");
        let hm = hmax.evaluate(&state).expect("not a dead end");
        assert!(lm <= remaining, "LM-cut {lm} > h* {remaining} at step {i}");
        assert!(hm <= lm, "h^max {hm} > LM-cut {lm} at step {i}");
        assert!(ff.evaluate(&state).expect("not a dead end") > 0);
        assert!(task.applicable(a, &state));
        task.apply_into(a, &state, &mut next);
        std::mem::swap(&mut state, &mut next);
    }
    assert!(task.is_goal(&state));
    assert_eq!(lmcut.evaluate(&state), Some(0));
    assert_eq!(hmax.evaluate(&state), Some(0));
    assert_eq!(ff.evaluate(&state), Some(0));
}

// ---- validator ----------------------------------------------------------------------------

#[test]
fn validator_rejects_broken_plans_with_reasons() {
    let prob = blocks_problem("a b c", &[&["a", "c"], &["b"]], "(on a b) (on b c)");
    let (d, p) = parsed(BLOCKS, &prob);
    let good = [
        "(unstack c a)",
        "(put-down c)",
        "(pick-up b)",
        "(stack b c)",
        "(pick-up a)",
        "(stack a b)",
    ];
    assert_eq!(validate_plan(&d, &p, &good), Ok(()));
    // Case and spacing do not matter.
    assert_eq!(
        validate_plan(&d, &p, &good.map(|s| s.to_uppercase().replace(' ', "  "))),
        Ok(())
    );

    let mut swapped = good;
    swapped.swap(2, 4);
    let err = validate_plan(&d, &p, &swapped).expect_err("b is not held");
    assert_eq!(
        err.to_string(),
        "step 4 (stack b c): precondition (holding b) is false"
    );

    let err = validate_plan(&d, &p, &good[..5]).expect_err("goal not reached");
    assert_eq!(
        err,
        ValidationError::GoalNotReached {
            steps: 5,
            missing: vec!["(on a b)".into()],
        }
    );
    assert_eq!(
        err.to_string(),
        "goal not reached after 5 step(s): (on a b) false"
    );

    let bad_steps: &[(&str, &str)] = &[
        ("(fly c)", "step 1: unknown action 'fly'"),
        (
            "(unstack c)",
            "step 1 (unstack c): 'unstack' takes 2 argument(s), found 1",
        ),
        ("(unstack c z)", "step 1 (unstack c z): unknown object 'z'"),
        (
            "unstack c a",
            "step 1: cannot read 'unstack c a' as a ground action like '(move r1 l1 l2)'",
        ),
        (
            "()",
            "step 1: cannot read '()' as a ground action like '(move r1 l1 l2)'",
        ),
        (
            "(unstack a c)",
            "step 1 (unstack a c): precondition (on a c) is false",
        ),
    ];
    for &(step, message) in bad_steps {
        let err = validate_plan(&d, &p, &[step]).expect_err(step);
        assert_eq!(err.to_string(), message);
    }

    // Equality preconditions and parameter types are checked too.
    let (d, p) = parsed(TOKEN_DOMAIN, TOKEN_PROBLEM);
    let err = validate_plan(&d, &p, &["(go x x)"]).expect_err("from = to");
    assert_eq!(
        err.to_string(),
        "step 1 (go x x): precondition (not (= x x)) is false"
    );
    let (d, p) = parsed(DWR_DOMAIN, DWR_02);
    let err = validate_plan(&d, &p, &["(move l1 l1 l2)"]).expect_err("typed");
    assert_eq!(
        err.to_string(),
        "step 1 (move l1 l1 l2): object 'l1' is not of type 'robot' (parameter ?r)"
    );
}
