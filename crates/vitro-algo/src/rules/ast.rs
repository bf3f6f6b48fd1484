//! The syntax tree of rule programs.

use super::error::Pos;
use super::term::Term;
use serde::{Deserialize, Serialize};

/// One conjunct of a query.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub(crate) enum Literal {
    /// `module [term]`, or `not module [term]`.
    Ask {
        module: String,
        term: Term,
        negated: bool,
        pos: Pos,
    },
    /// `a == b` (unifies) or `a != b` (the two cannot be unified).
    Compare {
        left: Term,
        right: Term,
        equal: bool,
    },
}

/// A statement.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub(crate) enum Stmt {
    /// `when query then body`.
    When {
        query: Vec<Literal>,
        body: Box<Stmt>,
    },
    /// `op module [term]`.
    Update {
        op: String,
        module: String,
        term: Term,
        pos: Pos,
    },
    /// `skip`: does nothing, always applicable.
    Skip,
    /// `a, b, ...`: all, in order.
    Seq(Vec<Stmt>),
    /// `a; b; ...`: one applicable branch, drawn at random.
    Choice(Vec<Stmt>),
    /// `name(args)`: a macro call (none left after expansion).
    Call {
        name: String,
        args: Vec<Term>,
        pos: Pos,
    },
}

/// `define name(params) body end`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub(crate) struct MacroDef {
    pub name: String,
    pub params: Vec<Term>,
    pub body: Stmt,
    pub pos: Pos,
}

impl Stmt {
    /// Calls `f` on this statement and every statement inside it, outer first.
    pub fn visit<'a>(&'a self, f: &mut impl FnMut(&'a Stmt)) {
        f(self);
        match self {
            Stmt::When { body, .. } => body.visit(f),
            Stmt::Seq(list) | Stmt::Choice(list) => list.iter().for_each(|s| s.visit(f)),
            Stmt::Update { .. } | Stmt::Skip | Stmt::Call { .. } => {}
        }
    }
}
