//! The interpreter: one deliberation cycle of a program against an agent's modules.

use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use std::fmt;

use rand::Rng;

use super::ast::{Literal, Stmt};
use super::error::{ErrorKind, Pos, RuleError};
use super::kb::{ModuleSet, Query, Update};
use super::macros::expand;
use super::parser::parse_program;
use super::term::{Bindings, Term, unify};

/// A parsed program, its macros expanded and its variables checked.
///
/// ```
/// use vitro_algo::rules::Program;
/// let p = Program::parse("guard.jz", "when beliefs [enemy(X)] then add goals [attack(X)]")?;
/// assert_eq!(p.modules(), ["beliefs", "goals"]);
/// # Ok::<(), vitro_algo::rules::RuleError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Program {
    name: String,
    body: Stmt,
}

impl Program {
    /// Parses `text`, named `name` in error messages.
    ///
    /// # Errors
    /// The first syntax, macro or variable error, with its line and column.
    pub fn parse(name: &str, text: &str) -> Result<Self, RuleError> {
        let parsed = parse_program(name, text)?;
        let body = expand(name, parsed)?;
        Ok(Program {
            name: name.to_string(),
            body,
        })
    }

    /// The name given at parsing.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The modules the program refers to, sorted.
    pub fn modules(&self) -> Vec<&str> {
        let mut names = BTreeSet::new();
        self.body.visit(&mut |s| match s {
            Stmt::When { query, .. } => {
                for l in query {
                    if let Literal::Ask { module, .. } = l {
                        names.insert(module.as_str());
                    }
                }
            }
            Stmt::Update { module, .. } => {
                names.insert(module.as_str());
            }
            _ => {}
        });
        names.into_iter().collect()
    }
}

/// An update that failed during a cycle.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CycleError {
    /// Where the update is written.
    pub pos: Pos,
    /// The module.
    pub module: String,
    /// The update.
    pub update: String,
    /// Why it failed.
    pub message: String,
}

impl fmt::Display for CycleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}: {} {}: {}",
            self.pos.line, self.pos.column, self.module, self.update, self.message
        )
    }
}

/// What one deliberation cycle did.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Cycle {
    /// Rules whose query succeeded and whose body ran.
    pub fired: usize,
    /// Updates applied, in order, as `op module [term]`.
    pub updates: Vec<String>,
    /// Updates that failed.
    pub errors: Vec<CycleError>,
}

/// A program ready to run against a set of modules (names and operations checked).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Interpreter {
    program: Program,
}

impl Interpreter {
    /// Checks that every module the program names is in `modules` and offers the operations
    /// the program uses.
    ///
    /// # Errors
    /// [`ErrorKind::UnknownModule`] or [`ErrorKind::UnknownOperation`] at the first use.
    pub fn new(program: Program, modules: &impl ModuleSet) -> Result<Self, RuleError> {
        let mut error = None;
        program.body.visit(&mut |s| {
            let mut check = |module: &str, op: Option<&str>, pos: Pos| {
                if error.is_some() {
                    return;
                }
                let kind = match (modules.find(module), op) {
                    (None, _) => ErrorKind::UnknownModule(module.to_string()),
                    (Some(m), Some(op)) if !modules.supports(m, op) => {
                        ErrorKind::UnknownOperation {
                            module: module.to_string(),
                            op: op.to_string(),
                        }
                    }
                    _ => return,
                };
                error = Some(RuleError::new(&program.name, pos, kind));
            };
            match s {
                Stmt::When { query, .. } => {
                    for l in query {
                        if let Literal::Ask { module, pos, .. } = l {
                            check(module, None, *pos);
                        }
                    }
                }
                Stmt::Update {
                    op, module, pos, ..
                } => check(module, Some(op), *pos),
                _ => {}
            }
        });
        match error {
            Some(e) => Err(e),
            None => Ok(Interpreter { program }),
        }
    }

    /// The program.
    pub fn program(&self) -> &Program {
        &self.program
    }

    /// Runs one deliberation cycle: evaluates the program once against `modules`, drawing
    /// the choices of `;` from `rng`.
    pub fn cycle(&self, modules: &mut impl ModuleSet, rng: &mut impl Rng) -> Cycle {
        let mut run = Run {
            modules,
            rng,
            out: Cycle::default(),
        };
        run.exec(&self.program.body, &Bindings::new());
        run.out
    }
}

struct Run<'a, S, R> {
    modules: &'a mut S,
    rng: &'a mut R,
    out: Cycle,
}

impl<S: ModuleSet, R: Rng> Run<'_, S, R> {
    /// Runs `s`; true if it was applicable.
    fn exec(&mut self, s: &Stmt, b: &Bindings) -> bool {
        match s {
            Stmt::Skip => true,
            Stmt::Update {
                op,
                module,
                term,
                pos,
            } => {
                self.update(op, module, term.substitute(b), *pos);
                true
            }
            Stmt::When { query, body } => match self.solve(query, b.clone()) {
                Some(b2) => {
                    self.out.fired += 1;
                    self.exec(body, &b2);
                    true
                }
                None => false,
            },
            Stmt::Seq(list) => list.iter().fold(false, |any, x| self.exec(x, b) | any),
            Stmt::Choice(list) => {
                let open: Vec<&Stmt> = list.iter().filter(|x| self.applicable(x, b)).collect();
                let pick = match open.len() {
                    0 => return false,
                    1 => 0,
                    n => self.rng.random_range(0..n),
                };
                self.exec(open[pick], b)
            }
            Stmt::Call { .. } => false,
        }
    }

    /// Whether `s` would do something: an update, or a rule whose query holds (and whose
    /// body is applicable).
    fn applicable(&mut self, s: &Stmt, b: &Bindings) -> bool {
        match s {
            Stmt::Skip | Stmt::Update { .. } => true,
            Stmt::When { query, body } => self
                .solve(query, b.clone())
                .is_some_and(|b2| self.applicable(body, &b2)),
            Stmt::Seq(list) | Stmt::Choice(list) => list.iter().any(|x| self.applicable(x, b)),
            Stmt::Call { .. } => false,
        }
    }

    fn update(&mut self, op: &str, module: &str, term: Term, pos: Pos) {
        let text = format!("{op} {module} [{term}]");
        let fail = |message: String| CycleError {
            pos,
            module: module.to_string(),
            update: format!("{op} [{term}]"),
            message,
        };
        let result = if !term.is_ground() {
            Err(fail("the term is not ground".to_string()))
        } else {
            match self.modules.find(module) {
                None => Err(fail("no such module".to_string())),
                Some(m) => {
                    let u = Update {
                        op: op.to_string(),
                        term: term.clone(),
                    };
                    self.modules.update(m, &u).map_err(|e| fail(e.to_string()))
                }
            }
        };
        match result {
            Ok(()) => self.out.updates.push(text),
            Err(e) => self.out.errors.push(e),
        }
    }

    /// The first answer to the conjunction `lits` under `b` (depth first, left to right).
    fn solve(&mut self, lits: &[Literal], b: Bindings) -> Option<Bindings> {
        let Some((first, rest)) = lits.split_first() else {
            return Some(b);
        };
        match first {
            Literal::Ask {
                module,
                term,
                negated,
                ..
            } => {
                let m = self.modules.find(module)?;
                let q = Query {
                    term: term.substitute(&b),
                };
                let answers = self.modules.query(m, &q);
                if *negated {
                    return if answers.is_empty() {
                        self.solve(rest, b)
                    } else {
                        None
                    };
                }
                answers.into_iter().find_map(|answer| {
                    let mut b2 = b.clone();
                    let consistent = answer
                        .into_iter()
                        .all(|(v, t)| unify(&Term::Var(v), &t, &mut b2));
                    if consistent {
                        self.solve(rest, b2)
                    } else {
                        None
                    }
                })
            }
            Literal::Compare { left, right, equal } => {
                let mut b2 = b.clone();
                let unifies = unify(left, right, &mut b2);
                match (unifies, equal) {
                    (true, true) => self.solve(rest, b2),
                    (false, false) => self.solve(rest, b),
                    _ => None,
                }
            }
        }
    }
}
