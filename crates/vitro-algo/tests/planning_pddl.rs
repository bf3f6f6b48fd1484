//! PDDL parse errors: every malformed input gets its own message with file, line and
//! column, and no input makes the parser panic.

use vitro_algo::planning::pddl::{ParseErrorKind, parse_domain, parse_problem};

const DWR_DOMAIN: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/planning/dwr/domain.pddl"
));
const DWR_02: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/planning/dwr/problem-02.pddl"
));

const SMALL: &str = "(define (domain d)
  (:requirements :strips :typing)
  (:types ball room)
  (:predicates (at ?b - ball ?r - room) (free ?r - room))
  (:action move
    :parameters (?b - ball ?from ?to - room)
    :precondition (and (at ?b ?from) (free ?to))
    :effect (and (at ?b ?to) (not (at ?b ?from)))))";

fn domain_error(src: &str) -> String {
    match parse_domain(src, "domain.pddl") {
        Ok(_) => panic!("accepted malformed domain:\n{src}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn malformed_domains_give_specific_errors() {
    let cases: &[(&str, &str, &str)] = &[
        (
            "?to - room)\n    :precondition",
            "?to - room\n    :precondition",
            "domain.pddl:7:5: expected ')' after action parameters, found ':precondition'",
        ),
        (
            "(?b - ball ?from ?to - room)\n    :precondition (and (at ?b ?from) (free ?to))\n",
            "(?b - ball ?from ?to - room\n",
            "domain.pddl:7:5: expected ')' after action parameters, found ':effect'",
        ),
        (
            "(free ?to))",
            "(hold ?to))",
            "domain.pddl:7:39: undeclared predicate 'hold'",
        ),
        (
            "(and (at ?b ?from)",
            "(and (at ?b)",
            "domain.pddl:7:25: predicate 'at' takes 2 argument(s), found 1",
        ),
        (
            "(free ?to))",
            "(free ?x))",
            "domain.pddl:7:44: unknown variable '?x' in action 'move'",
        ),
        (
            "(?b - ball ?from",
            "(?b - bal ?from",
            "domain.pddl:6:23: unknown type 'bal'",
        ),
        (
            ":strips :typing)",
            ":strips :adl)",
            "domain.pddl:2:26: unsupported requirement ':adl' (supported: :strips, :typing, :equality)",
        ),
        (
            "(free ?to))",
            "(not (free ?to)))",
            "domain.pddl:7:44: unsupported: negative precondition in action 'move' (only (not (= ...)) is allowed)",
        ),
        (
            "(define (domain d)",
            "(domain d)",
            "domain.pddl:1:2: expected 'define' at the start of the domain, found 'domain'",
        ),
        (
            "(free ?r - room))",
            "(free ?r - room) (at ?x))",
            "domain.pddl:4:59: duplicate predicate 'at'",
        ),
        (
            "(:types ball room)",
            "(:types ball - room room - ball)",
            "domain.pddl:3:4: type 'room' is its own supertype",
        ),
        (
            "?from ?to - room)",
            "?from ?to - (either room ball))",
            "domain.pddl:6:40: unsupported: 'either' types",
        ),
        (
            "(:action move",
            "(:derived (p) (q))\n  (:action move",
            "domain.pddl:5:4: unsupported: section ':derived'",
        ),
        (
            "(and (at ?b ?to)",
            "(and (increase (total-cost) 1) (at ?b ?to)",
            "domain.pddl:8:19: unsupported: 'increase' in the effect of action 'move'",
        ),
        (
            "?to - room)",
            "?to - )",
            "domain.pddl:6:40: expected a type name after '-' in action parameters, found ')'",
        ),
        (
            "(?b - ball ?from",
            "(b - ball ?from",
            "domain.pddl:6:18: expected a ?variable or ')' in action parameters, found 'b'",
        ),
    ];
    for &(from, to, message) in cases {
        assert!(SMALL.contains(from), "case does not apply: {from}");
        let src = SMALL.replacen(from, to, 1);
        assert_eq!(domain_error(&src), message, "source:\n{src}");
    }
}

#[test]
fn truncated_or_padded_domain_reports_where() {
    let cut = &SMALL[..SMALL.len() - 2];
    assert_eq!(
        domain_error(cut),
        "domain.pddl:8:50: expected ')' to end action 'move' (after :parameters, :precondition, \
         :effect), found end of file"
    );
    let padded = format!("{SMALL} (extra)");
    assert_eq!(
        domain_error(&padded),
        "domain.pddl:8:53: expected end of file after the closing ')', found '('"
    );
}

#[test]
fn every_prefix_of_a_real_domain_fails_cleanly() {
    // Trailing whitespace and comments may go; anything more makes the file incomplete.
    let domain = DWR_DOMAIN.trim_end();
    for (i, _) in domain.char_indices().skip(1) {
        let prefix = &domain[..i];
        let err = parse_domain(prefix, "dwr.pddl").expect_err("a strict prefix is incomplete");
        assert!(err.to_string().starts_with("dwr.pddl:"), "{err}");
    }
    let d = parse_domain(DWR_DOMAIN, "dwr.pddl").expect("complete domain");
    let problem = DWR_02.trim_end();
    for (i, _) in problem.char_indices().skip(1) {
        let err = parse_problem(&d, &problem[..i], "p.pddl").expect_err("prefix");
        assert!(err.to_string().starts_with("p.pddl:"), "{err}");
    }
}

const SMALL_PROBLEM: &str = "(define (problem p) (:domain d)
  (:objects b1 - ball r1 r2 - room)
  (:init (at b1 r1) (free r2))
  (:goal (and (at b1 r2))))";

#[test]
fn malformed_problems_give_specific_errors() {
    let d = parse_domain(SMALL, "domain.pddl").expect("domain");
    let cases: &[(&str, &str, &str)] = &[
        (
            "(free r2)",
            "(free r3)",
            "problem.pddl:3:27: unknown object 'r3'",
        ),
        (
            "(:domain d)",
            "(:domain other)",
            "problem.pddl:1:30: problem is for domain 'other', but the domain is 'd'",
        ),
        (
            "(at b1 r1)",
            "(at r1 b1)",
            "problem.pddl:3:14: object 'r1' of type 'room' does not fit argument 1 of 'at' \
             (type 'ball')",
        ),
        (
            "(and (at b1 r2))",
            "(and (not (at b1 r1)))",
            "problem.pddl:4:16: unsupported: 'not' in the goal (only a conjunction of atoms is \
             allowed)",
        ),
        (
            "(:goal (and (at b1 r2))))",
            "(:goal (and (at b1 r2))) (:metric minimize (total-time)))",
            "problem.pddl:4:29: unsupported: problem section ':metric'",
        ),
        (
            "(:objects b1 - ball r1 r2 - room)",
            "(:objects b1 - ball r1 r1 - room)",
            "problem.pddl:2:26: duplicate object 'r1'",
        ),
        (
            "(:init",
            "(:inits",
            "problem.pddl:3:4: expected ':init' (the initial state), found ':inits'",
        ),
    ];
    for &(from, to, message) in cases {
        assert!(SMALL_PROBLEM.contains(from), "case does not apply: {from}");
        let src = SMALL_PROBLEM.replacen(from, to, 1);
        let err = parse_problem(&d, &src, "problem.pddl").expect_err(&src);
        assert_eq!(err.to_string(), message, "source:\n{src}");
    }
    let err = parse_problem(&d, "(define (problem p) (:domain d)", "problem.pddl")
        .expect_err("truncated");
    assert_eq!(
        *err.kind,
        ParseErrorKind::Expected {
            expected: "'(' before ':objects' or ':init'".into(),
            found: "end of file".into(),
        }
    );
    assert_eq!((err.line, err.column), (1, 32));
}

#[test]
fn single_character_edits_never_panic() {
    // Deleting any one character, or inserting a parenthesis anywhere, gives either a
    // domain or a located error.
    let domain = DWR_DOMAIN;
    for (i, c) in domain.char_indices() {
        let deleted = format!("{}{}", &domain[..i], &domain[i + c.len_utf8()..]);
        let opened = format!("{}({}", &domain[..i], &domain[i..]);
        let closed = format!("{}){}", &domain[..i], &domain[i..]);
        for src in [deleted, opened, closed] {
            if let Err(e) = parse_domain(&src, "dwr.pddl") {
                assert!(e.line >= 1 && e.column >= 1, "{e}");
            }
        }
    }
    let d = parse_domain(DWR_DOMAIN, "dwr.pddl").expect("domain");
    for (i, c) in DWR_02.char_indices() {
        let deleted = format!("{}{}", &DWR_02[..i], &DWR_02[i + c.len_utf8()..]);
        if let Err(e) = parse_problem(&d, &deleted, "p.pddl") {
            assert!(e.line >= 1 && e.column >= 1, "{e}");
        }
    }
}
