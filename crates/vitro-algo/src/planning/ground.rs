//! Reachability-based grounding of a PDDL problem into a compact STRIPS [`Task`].
//!
//! Only actions whose preconditions are reachable in the delete relaxation are grounded.
//! Static predicates (never changed by an action) are checked during grounding and then
//! folded away: they appear neither as facts nor in preconditions.

use std::collections::{HashMap, HashSet};

use thiserror::Error;

use super::pddl::{
    ActionSchema, AtomSchema, Condition, Domain, GroundAtom, ObjId, PredId, Problem, Term,
};
use super::task::{FactId, GroundAction, Task};

/// Ground actions beyond which grounding gives up rather than exhaust memory.
const MAX_GROUND_ACTIONS: usize = 10_000_000;

/// Why a problem could not be turned into a task.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum GroundError {
    /// A goal atom can never become true (even ignoring delete effects): no plan exists.
    #[error("goal {0} is unreachable, even ignoring delete effects")]
    UnreachableGoal(String),
    /// Too many ground actions.
    #[error("grounding produced more than {limit} actions")]
    TooLarge {
        /// The limit that was passed.
        limit: usize,
    },
}

/// Grounds `problem` (parsed against `domain`) into a STRIPS task.
///
/// Facts are the relaxed-reachable atoms of fluent predicates, numbered in
/// (predicate, arguments) order; actions keep schema order, then binding order. Delete
/// effects that are also added are dropped (PDDL applies deletes before adds), and actions
/// that add nothing beyond their own preconditions are dropped (with positive
/// preconditions and goals they are never needed).
///
/// # Errors
/// [`GroundError::UnreachableGoal`] when a goal atom is relaxed-unreachable,
/// [`GroundError::TooLarge`] past ten million ground actions.
pub fn ground(domain: &Domain, problem: &Problem) -> Result<Task, GroundError> {
    let mut g = Grounder::new(domain, problem);
    g.saturate()?;

    // Number the reachable fluent atoms in (predicate, args) order.
    let mut atoms: Vec<GroundAtom> = g
        .atoms
        .iter()
        .enumerate()
        .filter(|(p, _)| g.fluent[*p])
        .flat_map(|(pred, list)| {
            list.iter().map(move |args| GroundAtom {
                pred,
                args: args.clone(),
            })
        })
        .collect();
    atoms.sort();
    let fact_of: HashMap<&GroundAtom, FactId> = atoms
        .iter()
        .enumerate()
        .map(|(i, a)| (a, i as FactId))
        .collect();

    let mut actions = Vec::new();
    for (index, schema) in domain.actions.iter().enumerate() {
        let mut bindings = Vec::new();
        g.bindings(index, &mut |b| bindings.push(b.to_vec()));
        for binding in bindings {
            let ids = |list: &mut dyn Iterator<Item = &AtomSchema>| -> Vec<FactId> {
                let mut v: Vec<FactId> = list
                    .filter(|a| g.fluent[a.pred])
                    .filter_map(|a| fact_of.get(&instantiate(a, &binding)).copied())
                    .collect();
                v.sort_unstable();
                v.dedup();
                v
            };
            let pre = ids(&mut schema.precondition.iter().filter_map(|c| match c {
                Condition::Atom(a) => Some(a),
                _ => None,
            }));
            let add = ids(&mut schema.add.iter());
            let mut del = ids(&mut schema.del.iter());
            del.retain(|f| add.binary_search(f).is_err());
            if add.iter().all(|f| pre.binary_search(f).is_ok()) {
                continue;
            }
            let mut name = format!("({}", schema.name);
            for &o in &binding {
                name.push(' ');
                name.push_str(&problem.objects[o].name);
            }
            name.push(')');
            actions.push(GroundAction {
                name,
                pre,
                add,
                del,
                cost: 1,
            });
        }
    }

    let mut init: Vec<FactId> = problem
        .init
        .iter()
        .filter_map(|a| fact_of.get(a).copied())
        .collect();
    init.sort_unstable();
    init.dedup();
    let mut goal = Vec::new();
    for atom in &problem.goal {
        let unreachable = || GroundError::UnreachableGoal(problem.atom_name(domain, atom));
        if g.fluent[atom.pred] {
            goal.push(*fact_of.get(atom).ok_or_else(unreachable)?);
        } else if !g.contains(atom.pred, &atom.args) {
            return Err(unreachable());
        }
    }
    goal.sort_unstable();
    goal.dedup();

    let facts = atoms.iter().map(|a| problem.atom_name(domain, a)).collect();
    Ok(Task {
        facts,
        actions,
        init,
        goal,
    })
}

/// The ground atom `schema` denotes under `binding` (parameter index → object).
fn instantiate(schema: &AtomSchema, binding: &[ObjId]) -> GroundAtom {
    GroundAtom {
        pred: schema.pred,
        args: schema.args.iter().map(|t| resolve(*t, binding)).collect(),
    }
}

fn resolve(term: Term, binding: &[ObjId]) -> ObjId {
    match term {
        Term::Param(i) => binding[i],
        Term::Const(c) => c,
    }
}

/// Relaxed reachability state: the atoms reached so far, per predicate.
struct Grounder<'a> {
    domain: &'a Domain,
    /// Whether each predicate is changed by some action.
    fluent: Vec<bool>,
    /// Reached atoms per predicate, in the order they were reached.
    atoms: Vec<Vec<Vec<ObjId>>>,
    /// Membership test for `atoms` (never iterated).
    seen: HashSet<(PredId, Vec<ObjId>)>,
    /// `fits[type][object]`: the object's type is that type or a subtype.
    fits: Vec<Vec<bool>>,
    /// Objects of each type (with subtypes), in object order.
    objects_of: Vec<Vec<ObjId>>,
    /// Per action: precondition atoms in join order (static ones first).
    join_order: Vec<Vec<&'a AtomSchema>>,
}

impl<'a> Grounder<'a> {
    fn new(domain: &'a Domain, problem: &Problem) -> Self {
        let mut fluent = vec![false; domain.predicates.len()];
        for a in &domain.actions {
            for atom in a.add.iter().chain(&a.del) {
                fluent[atom.pred] = true;
            }
        }
        let fits: Vec<Vec<bool>> = (0..domain.types.len())
            .map(|t| {
                problem
                    .objects
                    .iter()
                    .map(|o| domain.is_subtype(o.ty, t))
                    .collect()
            })
            .collect();
        let objects_of = fits
            .iter()
            .map(|row| (0..row.len()).filter(|&o| row[o]).collect())
            .collect();
        let join_order = domain
            .actions
            .iter()
            .map(|a| {
                let atoms = a.precondition.iter().filter_map(|c| match c {
                    Condition::Atom(atom) => Some(atom),
                    _ => None,
                });
                let (mut order, fluents): (Vec<_>, Vec<_>) =
                    atoms.partition(|atom| !fluent[atom.pred]);
                order.extend(fluents);
                order
            })
            .collect();
        let mut g = Grounder {
            domain,
            fluent,
            atoms: vec![Vec::new(); domain.predicates.len()],
            seen: HashSet::new(),
            fits,
            objects_of,
            join_order,
        };
        for atom in &problem.init {
            g.insert(atom.pred, atom.args.clone());
        }
        g
    }

    fn contains(&self, pred: PredId, args: &[ObjId]) -> bool {
        self.seen.contains(&(pred, args.to_vec()))
    }

    fn insert(&mut self, pred: PredId, args: Vec<ObjId>) -> bool {
        if self.seen.insert((pred, args.clone())) {
            self.atoms[pred].push(args);
            true
        } else {
            false
        }
    }

    /// Adds the add effects of every applicable binding until nothing new is reached.
    fn saturate(&mut self) -> Result<(), GroundError> {
        loop {
            let mut new_atoms = Vec::new();
            let mut count = 0usize;
            for (index, schema) in self.domain.actions.iter().enumerate() {
                self.bindings(index, &mut |b| {
                    count += 1;
                    for a in &schema.add {
                        new_atoms.push(instantiate(a, b));
                    }
                });
            }
            if count > MAX_GROUND_ACTIONS {
                return Err(GroundError::TooLarge {
                    limit: MAX_GROUND_ACTIONS,
                });
            }
            let mut changed = false;
            for atom in new_atoms {
                changed |= self.insert(atom.pred, atom.args);
            }
            if !changed {
                return Ok(());
            }
        }
    }

    /// Calls `emit` with every parameter binding of action `index` whose precondition holds
    /// among the reached atoms (and whose objects fit the parameter types).
    fn bindings(&self, index: usize, emit: &mut dyn FnMut(&[ObjId])) {
        let schema = &self.domain.actions[index];
        let order = &self.join_order[index];
        let mut binding = vec![None; schema.params.len()];
        self.join(schema, order, 0, &mut binding, emit);
    }

    fn join(
        &self,
        schema: &ActionSchema,
        order: &[&AtomSchema],
        depth: usize,
        binding: &mut Vec<Option<ObjId>>,
        emit: &mut dyn FnMut(&[ObjId]),
    ) {
        let Some(atom) = order.get(depth) else {
            self.complete(schema, 0, binding, emit);
            return;
        };
        let mut newly = Vec::with_capacity(atom.args.len());
        for args in &self.atoms[atom.pred] {
            newly.clear();
            let fits = atom.args.iter().zip(args).all(|(term, &obj)| match *term {
                Term::Const(c) => c == obj,
                Term::Param(p) => match binding[p] {
                    Some(b) => b == obj,
                    None if self.fits[schema.params[p].ty][obj] => {
                        binding[p] = Some(obj);
                        newly.push(p);
                        true
                    }
                    None => false,
                },
            });
            if fits {
                self.join(schema, order, depth + 1, binding, emit);
            }
            for &p in &newly {
                binding[p] = None;
            }
        }
    }

    /// Binds the parameters no precondition atom mentions to every object of their type,
    /// then checks equality constraints.
    fn complete(
        &self,
        schema: &ActionSchema,
        from: usize,
        binding: &mut Vec<Option<ObjId>>,
        emit: &mut dyn FnMut(&[ObjId]),
    ) {
        match (from..binding.len()).find(|&p| binding[p].is_none()) {
            Some(p) => {
                for &o in &self.objects_of[schema.params[p].ty] {
                    binding[p] = Some(o);
                    self.complete(schema, p + 1, binding, emit);
                }
                binding[p] = None;
            }
            None => {
                let full: Vec<ObjId> = binding.iter().map(|b| b.unwrap_or_default()).collect();
                let ok = schema.precondition.iter().all(|c| match *c {
                    Condition::Equal(x, y) => resolve(x, &full) == resolve(y, &full),
                    Condition::NotEqual(x, y) => resolve(x, &full) != resolve(y, &full),
                    Condition::Atom(_) => true,
                });
                if ok {
                    emit(&full);
                }
            }
        }
    }
}
