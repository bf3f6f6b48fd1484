//! A small agent-programming language in the spirit of Jazzyk: rules over knowledge-base
//! modules.
//!
//! An agent is a set of named **modules** (beliefs, goals, a motion module bound to its
//! sensors and actuators, ...), each answering queries and taking updates
//! ([`KnowledgeBase`]; `vitro_worlds::rules::Embodied` for modules that use a simulation's
//! context). Its **program** is a tree of rules `when <query> then <statement>`; one
//! **deliberation cycle** evaluates the tree once against the modules.
//! `vitro_worlds::rules::RuleAgent` runs one cycle per tick in a vitro simulation.
//!
//! ```text
//! // guard: report an intruder once, then go for it; otherwise patrol.
//! define report(P)
//!   when not beliefs [reported(P)] then { say radio [intruder(P)], add beliefs [reported(P)] }
//! end
//! when eyes [intruder(P)] then { report(P), go motion [P] } ;
//! when not eyes [intruder(_)] and motion [at(X)] and beliefs [next(X, Y)] then go motion [Y]
//! ```
//!
//! # Syntax
//!
//! ```text
//! program    := { definition } [ choice ] { definition }
//! definition := 'define' name [ '(' Var { ',' Var } ')' ] choice 'end'
//! choice     := sequence { ';' sequence }
//! sequence   := statement { ',' statement }
//! statement  := 'when' query 'then' statement
//!             | '{' choice '}'
//!             | 'skip'
//!             | op module '[' term ']'             (an update, e.g. add beliefs [seen(X)])
//!             | name [ '(' [ term { ',' term } ] ')' ]   (a macro call)
//! query      := literal { 'and' literal }
//! literal    := [ 'not' ] module '[' term ']'       (ask a module)
//!             | term '==' term | term '!=' term
//! term       := Var | integer | '-' integer | "string" | name [ '(' term { ',' term } ')' ]
//! ```
//!
//! Names start with a lower-case letter, variables with an upper-case letter or `_` (each
//! `_` is a variable of its own). `when`, `then`, `define`, `end`, `and`, `not` and `skip`
//! are reserved. Comments run from `//` to the end of the line, or from `/*` to `*/`.
//! `,` binds tighter than `;`, and `when q then a, b` is `(when q then a), b`: write
//! `when q then { a, b }` for both under the rule.
//!
//! # Semantics
//!
//! A cycle evaluates the program's statement under the empty substitution:
//! - `when q then s`: the rule **fires** if `q` has an answer; `s` then runs with the
//!   variables bound by the **first** answer (modules list their answers in a fixed order).
//!   Otherwise nothing happens.
//! - `q1 and q2`: answers depth first, left to right (later literals see earlier bindings;
//!   if a later literal fails, the next answer of an earlier one is tried).
//!   `not m [t]` holds when `m` has no answer to `t` (it binds nothing; its unbound variables
//!   read "any"). `a == b` unifies; `a != b` holds when they cannot be unified.
//! - `op m [t]`: applies the update to module `m`; `t` is ground by then (a variable of an
//!   update must be bound by an enclosing query: checked when the program is loaded).
//! - `a, b`: runs `a`, then `b` (both, in order; `b` sees the updates of `a`).
//! - `a; b`: runs **one applicable** branch, drawn uniformly at random (from the agent's
//!   random stream, so runs are reproducible); nothing if none is applicable. An update or
//!   `skip` is always applicable, a rule if its query holds and its body is applicable, a
//!   sequence or choice if any part is.
//! - Macros (`define name(X, Y) ... end`) are expanded before interpretation: a call is
//!   replaced by the body with the parameters replaced by the arguments; the body's other
//!   variables are its own (each expansion gets fresh ones). A macro that calls itself,
//!   directly or not, is an error.
//!
//! Errors carry the program's name, line and column, e.g.
//! `guard.jz:4:17: expected 'then' after query, found '{'`.

mod ast;
mod error;
mod interp;
mod kb;
mod lexer;
mod macros;
mod parser;
mod term;

pub use error::{ErrorKind, Pos, RuleError};
pub use interp::{Cycle, CycleError, Interpreter, Program};
pub use kb::{FactBase, KbError, KnowledgeBase, ModuleSet, Modules, Query, Update};
pub use term::{Bindings, Term, Var, unify};
