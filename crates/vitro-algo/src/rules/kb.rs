//! Knowledge-base modules: the interface a program queries and updates, a fact base for
//! beliefs and goals, and a named set of modules.

use std::collections::{BTreeMap, BTreeSet};

use thiserror::Error;

use super::term::{Bindings, Term, unify};

/// A question to a module: a term whose variables the answers bind.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Query {
    /// The pattern, e.g. `enemy(X)`.
    pub term: Term,
}

/// A change asked of a module: an operation on a ground term.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Update {
    /// The operation, e.g. `add`.
    pub op: String,
    /// Its argument, ground.
    pub term: Term,
}

/// Why a module refused an update.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum KbError {
    /// The module has no such operation.
    #[error("no operation '{0}'")]
    UnknownOperation(String),
    /// The module understood the update and refused it.
    #[error("{0}")]
    Refused(String),
}

/// A knowledge-base module: answers queries, takes updates.
///
/// A query returns one [`Bindings`] per answer (empty bindings for a ground query that
/// holds; no answer if it does not), in an order the module fixes: the program takes the
/// first answer, so the order must not depend on anything but the module's state.
pub trait KnowledgeBase {
    /// The answers to `q`, in the module's order.
    fn query(&self, q: &Query) -> Vec<Bindings>;
    /// Applies `u`.
    ///
    /// # Errors
    /// [`KbError`] when the operation is unknown or refused.
    fn update(&mut self, u: &Update) -> Result<(), KbError>;
    /// Whether the module offers operation `op` (checked when a program is loaded).
    fn supports(&self, op: &str) -> bool {
        let _ = op;
        true
    }
}

/// A set of ground terms (beliefs, goals), answering queries by unification, in term
/// order. Operations: `add` and `remove`.
///
/// ```
/// use vitro_algo::rules::{FactBase, KnowledgeBase, Query, Term, Update};
/// let mut kb = FactBase::from_texts(&["enemy(north)", "enemy(east)", "friend(west)"])?;
/// let answers = kb.query(&Query { term: Term::parse("enemy(X)")? });
/// assert_eq!(answers.len(), 2);
/// assert_eq!(answers[0].values().next().map(ToString::to_string).as_deref(), Some("east"));
/// kb.update(&Update { op: "remove".into(), term: Term::parse("enemy(east)")? })?;
/// assert_eq!(kb.len(), 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FactBase {
    /// Facts by (functor, arity); other ground terms (integers, strings) under `("", 0)`.
    facts: BTreeMap<(String, usize), BTreeSet<Term>>,
}

impl FactBase {
    /// An empty fact base.
    pub fn new() -> Self {
        Self::default()
    }

    /// A fact base holding the terms written in `texts`.
    ///
    /// # Errors
    /// The first text that is not a ground term.
    pub fn from_texts(texts: &[&str]) -> Result<Self, KbError> {
        let mut kb = FactBase::new();
        for t in texts {
            let term = Term::parse(t).map_err(|e| KbError::Refused(e.to_string()))?;
            kb.insert(term)?;
        }
        Ok(kb)
    }

    fn key(t: &Term) -> (String, usize) {
        t.functor()
            .map_or((String::new(), 0), |(f, n)| (f.to_string(), n))
    }

    /// Adds a ground term; false if it was there.
    ///
    /// # Errors
    /// [`KbError::Refused`] for a term with variables.
    pub fn insert(&mut self, t: Term) -> Result<bool, KbError> {
        if !t.is_ground() {
            return Err(KbError::Refused(format!("{t} is not ground")));
        }
        Ok(self.facts.entry(Self::key(&t)).or_default().insert(t))
    }

    /// Removes a term; false if it was not there.
    pub fn remove(&mut self, t: &Term) -> bool {
        let key = Self::key(t);
        let Some(set) = self.facts.get_mut(&key) else {
            return false;
        };
        let removed = set.remove(t);
        if set.is_empty() {
            self.facts.remove(&key);
        }
        removed
    }

    /// Whether the ground term `t` is in.
    pub fn contains(&self, t: &Term) -> bool {
        self.facts.get(&Self::key(t)).is_some_and(|s| s.contains(t))
    }

    /// Number of facts.
    pub fn len(&self) -> usize {
        self.facts.values().map(BTreeSet::len).sum()
    }

    /// Whether there is no fact.
    pub fn is_empty(&self) -> bool {
        self.facts.is_empty()
    }

    /// The facts, in (functor, arity, term) order.
    pub fn iter(&self) -> impl Iterator<Item = &Term> + '_ {
        self.facts.values().flatten()
    }
}

impl KnowledgeBase for FactBase {
    fn query(&self, q: &Query) -> Vec<Bindings> {
        let answer = |fact: &Term| {
            let mut b = Bindings::new();
            unify(&q.term, fact, &mut b).then_some(b)
        };
        match q.term {
            Term::Var(_) => self.iter().filter_map(answer).collect(),
            _ => self
                .facts
                .get(&Self::key(&q.term))
                .into_iter()
                .flatten()
                .filter_map(answer)
                .collect(),
        }
    }

    fn update(&mut self, u: &Update) -> Result<(), KbError> {
        match u.op.as_str() {
            "add" => self.insert(u.term.clone()).map(|_| ()),
            "remove" => {
                self.remove(&u.term);
                Ok(())
            }
            op => Err(KbError::UnknownOperation(op.to_string())),
        }
    }

    fn supports(&self, op: &str) -> bool {
        matches!(op, "add" | "remove")
    }
}

/// What the interpreter needs of an agent's modules: find them by name, query, update.
///
/// [`Modules`] implements it for plain knowledge bases; the simulation adapter
/// (`vitro_worlds::rules::RuleAgent`) for modules bound to sensors and actuators.
pub trait ModuleSet {
    /// The index of module `name`.
    fn find(&self, name: &str) -> Option<usize>;
    /// Whether module `module` offers `op`.
    fn supports(&self, module: usize, op: &str) -> bool;
    /// Asks module `module`.
    fn query(&mut self, module: usize, q: &Query) -> Vec<Bindings>;
    /// Updates module `module`.
    ///
    /// # Errors
    /// As the module's update.
    fn update(&mut self, module: usize, u: &Update) -> Result<(), KbError>;
}

/// Named knowledge bases (for programs run outside a simulation, and for tests).
#[derive(Default)]
pub struct Modules {
    list: Vec<(String, Box<dyn KnowledgeBase>)>,
}

impl Modules {
    /// No module.
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds (or replaces) module `name`.
    pub fn with(mut self, name: &str, kb: impl KnowledgeBase + 'static) -> Self {
        self.insert(name, kb);
        self
    }
    /// Adds (or replaces) module `name`.
    pub fn insert(&mut self, name: &str, kb: impl KnowledgeBase + 'static) {
        match self.list.iter_mut().find(|(n, _)| n == name) {
            Some(slot) => slot.1 = Box::new(kb),
            None => self.list.push((name.to_string(), Box::new(kb))),
        }
    }
    /// Module `name`.
    pub fn get(&self, name: &str) -> Option<&dyn KnowledgeBase> {
        self.list
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, kb)| kb.as_ref())
    }
}

impl ModuleSet for Modules {
    fn find(&self, name: &str) -> Option<usize> {
        self.list.iter().position(|(n, _)| n == name)
    }
    fn supports(&self, module: usize, op: &str) -> bool {
        self.list.get(module).is_some_and(|(_, kb)| kb.supports(op))
    }
    fn query(&mut self, module: usize, q: &Query) -> Vec<Bindings> {
        self.list
            .get(module)
            .map_or_else(Vec::new, |(_, kb)| kb.query(q))
    }
    fn update(&mut self, module: usize, u: &Update) -> Result<(), KbError> {
        match self.list.get_mut(module) {
            Some((_, kb)) => kb.update(u),
            None => Err(KbError::Refused(format!("no module {module}"))),
        }
    }
}
