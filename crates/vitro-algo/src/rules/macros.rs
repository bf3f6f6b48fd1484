//! Macro expansion (with recursion detection) and the check that every variable of an
//! update is bound by an enclosing query.

use std::collections::{BTreeMap, BTreeSet};

use super::ast::{Literal, MacroDef, Stmt};
use super::error::{ErrorKind, Pos, RuleError};
use super::parser::Parsed;
use super::term::{Term, Var};

/// Statements one program may expand to.
pub(crate) const MAX_STATEMENTS: usize = 100_000;

/// Expands every macro call of `parsed` and checks variable safety.
///
/// Every definition is expanded once on its own too, so an unknown macro, a wrong number of
/// arguments or a recursion is reported even in a macro that is never called.
pub(crate) fn expand(file: &str, parsed: Parsed) -> Result<Stmt, RuleError> {
    let mut defs: BTreeMap<&str, &MacroDef> = BTreeMap::new();
    for d in &parsed.macros {
        if let Some(first) = defs.insert(&d.name, d) {
            let kind = ErrorKind::DuplicateMacro {
                name: d.name.clone(),
                first: first.pos,
            };
            return Err(RuleError::new(file, d.pos, kind));
        }
    }
    let mut x = Expander {
        file,
        defs,
        scopes: 0,
        statements: 0,
        at: Pos::default(),
    };
    for d in &parsed.macros {
        x.stmt(&d.body, &mut vec![d.name.clone()])?;
    }
    let body = x.stmt(&parsed.body, &mut Vec::new())?;
    check_bound(file, &body, &BTreeSet::new())?;
    Ok(body)
}

struct Expander<'a> {
    file: &'a str,
    defs: BTreeMap<&'a str, &'a MacroDef>,
    /// Expansions so far (each gets its own variable scope).
    scopes: u32,
    statements: usize,
    /// The latest macro call expanded (where a too-large expansion is reported).
    at: Pos,
}

impl Expander<'_> {
    fn stmt(&mut self, s: &Stmt, stack: &mut Vec<String>) -> Result<Stmt, RuleError> {
        self.statements += 1;
        if self.statements > MAX_STATEMENTS {
            let kind = ErrorKind::ExpansionTooLarge(MAX_STATEMENTS);
            return Err(RuleError::new(self.file, self.at, kind));
        }
        Ok(match s {
            Stmt::When { query, body } => Stmt::When {
                query: query.clone(),
                body: Box::new(self.stmt(body, stack)?),
            },
            Stmt::Seq(list) => Stmt::Seq(self.list(list, stack)?),
            Stmt::Choice(list) => Stmt::Choice(self.list(list, stack)?),
            Stmt::Update { .. } | Stmt::Skip => s.clone(),
            Stmt::Call { name, args, pos } => {
                self.at = *pos;
                let err = |kind| RuleError::new(self.file, *pos, kind);
                let def = *self
                    .defs
                    .get(name.as_str())
                    .ok_or_else(|| err(ErrorKind::UnknownMacro(name.clone())))?;
                if def.params.len() != args.len() {
                    return Err(err(ErrorKind::MacroArity {
                        name: name.clone(),
                        expected: def.params.len(),
                        found: args.len(),
                    }));
                }
                if let Some(at) = stack.iter().position(|n| n == name) {
                    let mut cycle = stack[at..].to_vec();
                    cycle.push(name.clone());
                    return Err(err(ErrorKind::RecursiveMacro(cycle)));
                }
                self.scopes += 1;
                let mut sub: BTreeMap<&Term, &Term> = def.params.iter().zip(args).collect();
                let body = instantiate(&def.body, &mut sub, self.scopes);
                stack.push(name.clone());
                let out = self.stmt(&body, stack);
                stack.pop();
                out?
            }
        })
    }

    fn list(&mut self, list: &[Stmt], stack: &mut Vec<String>) -> Result<Vec<Stmt>, RuleError> {
        list.iter().map(|s| self.stmt(s, stack)).collect()
    }
}

/// A macro body with its parameters replaced by the arguments and its other variables moved
/// to `scope`.
fn instantiate(s: &Stmt, sub: &mut BTreeMap<&Term, &Term>, scope: u32) -> Stmt {
    let t = |t: &Term| rename(t, sub, scope);
    match s {
        Stmt::When { query, body } => Stmt::When {
            query: query
                .iter()
                .map(|l| match l {
                    Literal::Ask {
                        module,
                        term,
                        negated,
                        pos,
                    } => Literal::Ask {
                        module: module.clone(),
                        term: t(term),
                        negated: *negated,
                        pos: *pos,
                    },
                    Literal::Compare { left, right, equal } => Literal::Compare {
                        left: t(left),
                        right: t(right),
                        equal: *equal,
                    },
                })
                .collect(),
            body: Box::new(instantiate(body, sub, scope)),
        },
        Stmt::Update {
            op,
            module,
            term,
            pos,
        } => Stmt::Update {
            op: op.clone(),
            module: module.clone(),
            term: t(term),
            pos: *pos,
        },
        Stmt::Skip => Stmt::Skip,
        Stmt::Seq(list) => Stmt::Seq(list.iter().map(|x| instantiate(x, sub, scope)).collect()),
        Stmt::Choice(list) => {
            Stmt::Choice(list.iter().map(|x| instantiate(x, sub, scope)).collect())
        }
        Stmt::Call { name, args, pos } => Stmt::Call {
            name: name.clone(),
            args: args.iter().map(t).collect(),
            pos: *pos,
        },
    }
}

fn rename(t: &Term, sub: &BTreeMap<&Term, &Term>, scope: u32) -> Term {
    match t {
        Term::Var(v) => match sub.get(t) {
            Some(arg) => (*arg).clone(),
            None => Term::Var(Var {
                name: v.name.clone(),
                scope,
                pos: v.pos,
            }),
        },
        Term::Compound(f, args) => Term::Compound(
            f.clone(),
            args.iter().map(|a| rename(a, sub, scope)).collect(),
        ),
        _ => t.clone(),
    }
}

/// Every variable of an update must be bound by a positive query of an enclosing rule.
fn check_bound(file: &str, s: &Stmt, bound: &BTreeSet<Var>) -> Result<(), RuleError> {
    match s {
        Stmt::When { query, body } => {
            let mut inner = bound.clone();
            for l in query {
                match l {
                    Literal::Ask {
                        term,
                        negated: false,
                        ..
                    } => term.visit_vars(&mut |v| {
                        inner.insert(v.clone());
                    }),
                    Literal::Compare {
                        left,
                        right,
                        equal: true,
                    } => {
                        left.visit_vars(&mut |v| {
                            inner.insert(v.clone());
                        });
                        right.visit_vars(&mut |v| {
                            inner.insert(v.clone());
                        });
                    }
                    _ => {}
                }
            }
            check_bound(file, body, &inner)
        }
        Stmt::Update { term, .. } => {
            let mut unbound = None;
            term.visit_vars(&mut |v| {
                if unbound.is_none() && !bound.contains(v) {
                    unbound = Some(v.clone());
                }
            });
            match unbound {
                Some(v) => {
                    // Anonymous variables are numbered `_#n` inside; they read `_`.
                    let name = v.name.split('#').next().unwrap_or_default().to_string();
                    Err(RuleError::new(file, v.pos, ErrorKind::Unbound(name)))
                }
                None => Ok(()),
            }
        }
        Stmt::Seq(list) | Stmt::Choice(list) => {
            list.iter().try_for_each(|x| check_bound(file, x, bound))
        }
        Stmt::Skip | Stmt::Call { .. } => Ok(()),
    }
}
