//! The rule language: parse errors, macro expansion, the semantics of a cycle.

use std::collections::BTreeMap;
use std::path::Path;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use vitro_algo::rules::{
    Bindings, FactBase, Interpreter, KbError, KnowledgeBase, Modules, Program, Query, Term, Update,
};

fn guard_program() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/rules/guard.jz");
    std::fs::read_to_string(path).expect("the example program is readable")
}

fn error_of(src: &str) -> String {
    match Program::parse("prog.jz", src) {
        Ok(_) => panic!("expected an error for {src:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn malformed_programs_get_exact_messages() {
    let catalogue: &[(&str, &str)] = &[
        (
            "when beliefs [x]\n  { skip }",
            "prog.jz:2:3: expected 'then' after query, found '{'",
        ),
        (
            "when then skip",
            "prog.jz:1:6: expected a query after 'when', found 'then'",
        ),
        (
            "when beliefs [x then skip",
            "prog.jz:1:17: expected ']' after query term, found 'then'",
        ),
        (
            "add beliefs [f(a, )]",
            "prog.jz:1:19: expected a term, found ')'",
        ),
        (
            "skip,\n{ skip",
            "prog.jz:2:7: expected '}' to close the block opened at 2:1, found end of input",
        ),
        (
            "define m(X)\n  skip",
            "prog.jz:2:7: expected 'end' to close macro 'm' defined at 1:1, found end of input",
        ),
        (
            "define m(x) skip end",
            "prog.jz:1:10: expected a variable as macro parameter, found identifier 'x'",
        ),
        (
            "define m skip end\ndefine m skip end\nm",
            "prog.jz:2:1: macro 'm' is already defined at 1:1",
        ),
        ("skip, patrol(a)", "prog.jz:1:7: unknown macro 'patrol'"),
        (
            "define a b end\ndefine b c end\ndefine c a end\na",
            "prog.jz:3:10: recursive macro: a -> b -> c -> a",
        ),
        (
            "define m(X) skip end\nm(a, b)",
            "prog.jz:2:1: macro 'm' takes 1 argument(s), found 2",
        ),
        (
            "when beliefs [p(X)] then add goals [q(X, Y)]",
            "prog.jz:1:42: variable 'Y' is not bound by an enclosing query",
        ),
        (
            "when not beliefs [p(X)] then add goals [q(X)]",
            "prog.jz:1:43: variable 'X' is not bound by an enclosing query",
        ),
        (
            "say radio [\"unterminated]",
            "prog.jz:1:12: unterminated string",
        ),
        ("skip /* forever", "prog.jz:1:6: unterminated comment"),
        (
            "add beliefs [x] $",
            "prog.jz:1:17: unexpected character '$'",
        ),
        (
            "skip skip",
            "prog.jz:1:6: expected ',' or ';' or end of input, found 'skip'",
        ),
        (
            "when beliefs [x] then",
            "prog.jz:1:22: expected a statement after 'then', found end of input",
        ),
        (
            "beliefs [x]",
            "prog.jz:1:9: expected a statement (a query goes after 'when'), found '['",
        ),
        (
            "add beliefs [n(99999999999999999999)]",
            "prog.jz:1:16: integer 99999999999999999999 out of range",
        ),
        (
            "when X then skip",
            "prog.jz:1:8: expected '==' or '!=' after the term (or 'module [term]'), found 'then'",
        ),
        (
            "when not X == a then skip",
            "prog.jz:1:10: expected a module query 'module [term]' after 'not', found variable 'X'",
        ),
        (
            "define m(X, X) skip end",
            "prog.jz:1:13: parameter 'X' appears twice",
        ),
        (
            "skip ; ",
            "prog.jz:1:8: expected a statement, found end of input",
        ),
        (
            "add beliefs [-x]",
            "prog.jz:1:15: expected an integer after '-', found identifier 'x'",
        ),
        (
            "define m skip end\nm(a",
            "prog.jz:2:4: expected ',' or ')' in the arguments of 'm', found end of input",
        ),
        (
            "say radio [\"\\q\"]",
            "prog.jz:1:14: unknown escape '\\q' in string",
        ),
        (
            "define end",
            "prog.jz:1:8: expected a macro name after 'define', found 'end'",
        ),
    ];
    for (src, expected) in catalogue {
        assert_eq!(&error_of(src), expected, "program {src:?}");
    }
}

#[test]
fn unknown_modules_and_operations_are_reported_where_used() {
    let modules = Modules::new()
        .with("beliefs", FactBase::new())
        .with("goals", FactBase::new());
    let check = |src: &str| {
        let p = Program::parse("prog.jz", src).expect("parses");
        Interpreter::new(p, &modules)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    assert_eq!(
        check("when beliefs [a] then add belifs [b]"),
        Err("prog.jz:1:23: unknown module 'belifs'".to_string())
    );
    assert_eq!(
        check("skip,\n  when gaols [a] then skip"),
        Err("prog.jz:2:8: unknown module 'gaols'".to_string())
    );
    assert_eq!(
        check("when beliefs [a] then adopt goals [b]"),
        Err("prog.jz:1:23: module 'goals' has no operation 'adopt'".to_string())
    );
    assert_eq!(check("when beliefs [a] then add goals [b]"), Ok(()));
}

#[test]
fn every_prefix_and_every_one_character_edit_fails_cleanly() {
    let src = guard_program();
    assert!(Program::parse("guard.jz", &src).is_ok());
    let cuts: Vec<usize> = src.char_indices().map(|(i, _)| i).collect();
    for &i in &cuts {
        // Must not panic; a prefix may parse (e.g. one that ends between statements).
        let _ = Program::parse("guard.jz", &src[..i]);
    }
    let replacements = [
        '{', '}', '[', ']', '(', ')', ',', ';', '_', 'X', '"', '/', '*', ' ',
    ];
    for (k, &i) in cuts.iter().enumerate().step_by(3) {
        let c = replacements[k % replacements.len()];
        let mut edited = src.clone();
        let end = cuts.get(k + 1).copied().unwrap_or(src.len());
        edited.replace_range(i..end, &c.to_string());
        if let Err(e) = Program::parse("guard.jz", &edited) {
            assert!(e.to_string().starts_with("guard.jz:"), "{e}");
            assert!(e.pos.line >= 1 && e.pos.column >= 1, "{e}");
        }
    }
}

fn facts(texts: &[&str]) -> FactBase {
    FactBase::from_texts(texts).expect("ground facts")
}

fn run_once(src: &str, modules: &mut Modules, seed: u64) -> vitro_algo::rules::Cycle {
    let p = Program::parse("t.jz", src).expect("parses");
    let interp = Interpreter::new(p, modules).expect("modules exist");
    interp.cycle(modules, &mut ChaCha8Rng::seed_from_u64(seed))
}

fn holds(m: &Modules, module: &str, text: &str) -> bool {
    let q = Query {
        term: Term::parse(text).expect("a term"),
    };
    !m.get(module).expect("module").query(&q).is_empty()
}

#[test]
fn a_rule_fires_when_its_query_succeeds_with_the_first_answer() {
    let mut m = Modules::new()
        .with("beliefs", facts(&["enemy(north)", "enemy(east)"]))
        .with("goals", FactBase::new());
    let c = run_once(
        "when beliefs [enemy(X)] then add goals [attack(X)], when beliefs [friend(X)] then add goals [greet(X)]",
        &mut m,
        0,
    );
    assert_eq!(c.fired, 1);
    // Answers come in term order: east before north.
    assert_eq!(c.updates, ["add goals [attack(east)]"]);
    assert!(holds(&m, "goals", "attack(east)") && !holds(&m, "goals", "attack(north)"));
}

#[test]
fn sequence_runs_all_in_order_and_later_parts_see_earlier_updates() {
    let mut m = Modules::new().with("b", FactBase::new());
    let c = run_once(
        "add b [one], when b [one] then add b [two], when b [two] then { remove b [one], add b [three] }",
        &mut m,
        0,
    );
    assert_eq!(
        c.updates,
        [
            "add b [one]",
            "add b [two]",
            "remove b [one]",
            "add b [three]"
        ]
    );
    assert!(!holds(&m, "b", "one") && holds(&m, "b", "two") && holds(&m, "b", "three"));
}

#[test]
fn choice_picks_one_applicable_branch_at_random_reproducibly() {
    let src =
        "when b [never] then add b [x] ; add b [left] ; add b [right] ; when b [never] then skip";
    let mut seen = BTreeMap::new();
    for seed in 0..200 {
        let mut m = Modules::new().with("b", FactBase::new());
        let c = run_once(src, &mut m, seed);
        // Exactly one branch, never an inapplicable one.
        assert_eq!(c.updates.len(), 1);
        assert!(!holds(&m, "b", "x"));
        *seen.entry(c.updates[0].clone()).or_insert(0) += 1;
        // The same seed makes the same choice.
        let mut again = Modules::new().with("b", FactBase::new());
        assert_eq!(run_once(src, &mut again, seed).updates, c.updates);
    }
    let left = seen["add b [left]"];
    let right = seen["add b [right]"];
    assert_eq!(left + right, 200);
    assert!((70..=130).contains(&left), "{seen:?}");
    // No applicable branch: nothing happens.
    let mut m = Modules::new().with("b", FactBase::new());
    let c = run_once(
        "when b [a] then add b [x] ; when b [c] then add b [y]",
        &mut m,
        1,
    );
    assert!(c.updates.is_empty() && c.fired == 0);
}

#[test]
fn nested_blocks_negation_conjunction_and_comparison() {
    let mut m = Modules::new()
        .with(
            "beliefs",
            facts(&[
                "at(a)",
                "edge(a, b)",
                "edge(a, c)",
                "edge(b, c)",
                "blocked(b)",
            ]),
        )
        .with("goals", FactBase::new());
    // The first edge from here to a free place: backtracks past b (blocked) to c.
    let src = "when beliefs [at(X)] then {
                 when beliefs [edge(X, Y)] and not beliefs [blocked(Y)] then add goals [go(Y)],
                 when beliefs [edge(X, Y)] and Y != b and Y == Z then add goals [also(Z)],
                 when not beliefs [at(_)] and beliefs [edge(_, _)] then add goals [never]
               }";
    let c = run_once(src, &mut m, 0);
    assert_eq!(c.updates, ["add goals [go(c)]", "add goals [also(c)]"]);
    assert_eq!(c.fired, 3);
}

#[test]
fn macros_expand_with_their_own_variables() {
    let mut m = Modules::new()
        .with("beliefs", facts(&["p(1)", "q(2)"]))
        .with("goals", FactBase::new());
    // `Y` in the macro is not the caller's `Y`; `X` is the argument.
    let src = "define copy(X) when beliefs [q(Y)] then add goals [pair(X, Y)] end
               when beliefs [p(Y)] then { copy(Y), copy(seven) }";
    let c = run_once(src, &mut m, 0);
    assert_eq!(
        c.updates,
        ["add goals [pair(1, 2)]", "add goals [pair(seven, 2)]"]
    );
    // A macro without parameters, called without parentheses.
    let c = run_once(
        "define tick add goals [ticked] end tick",
        &mut Modules::new().with("goals", FactBase::new()),
        0,
    );
    assert_eq!(c.updates, ["add goals [ticked]"]);
}

#[test]
fn failed_updates_are_reported_and_the_cycle_goes_on() {
    struct Picky;
    impl KnowledgeBase for Picky {
        fn query(&self, _: &Query) -> Vec<Bindings> {
            Vec::new()
        }
        fn update(&mut self, u: &Update) -> Result<(), KbError> {
            Err(KbError::Refused(format!("will not {}", u.op)))
        }
    }
    let mut m = Modules::new()
        .with("picky", Picky)
        .with("b", FactBase::new());
    let c = run_once("add picky [x],\n  add b [y]", &mut m, 0);
    assert_eq!(c.updates, ["add b [y]"]);
    assert_eq!(c.errors.len(), 1);
    assert_eq!(c.errors[0].to_string(), "1:1: picky add [x]: will not add");
}
