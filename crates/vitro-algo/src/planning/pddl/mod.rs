//! PDDL (STRIPS with typing and equality): syntax tree and parser.
//!
//! ```
//! use vitro_algo::planning::pddl::{parse_domain, parse_problem};
//!
//! let domain = parse_domain(
//!     "(define (domain d) (:requirements :strips :typing) (:types ball room)
//!        (:predicates (at ?b - ball ?r - room))
//!        (:action move :parameters (?b - ball ?from ?to - room)
//!          :precondition (at ?b ?from)
//!          :effect (and (at ?b ?to) (not (at ?b ?from)))))",
//!     "domain.pddl",
//! )?;
//! let problem = parse_problem(
//!     &domain,
//!     "(define (problem p) (:domain d) (:objects b - ball x y - room)
//!        (:init (at b x)) (:goal (at b y)))",
//!     "problem.pddl",
//! )?;
//! assert_eq!(problem.objects.len(), 3);
//! # Ok::<(), vitro_algo::planning::pddl::ParseError>(())
//! ```

mod domain;
mod error;
mod lexer;
mod parser;
mod problem;

pub use error::{ParseError, ParseErrorKind};
pub use parser::{parse_domain, parse_problem};

/// Index of a type in [`Domain::types`]; type 0 is `object`.
pub type TypeId = usize;
/// Index of a predicate in [`Domain::predicates`].
pub type PredId = usize;
/// Index of an object in [`Problem::objects`] (the domain's constants come first).
pub type ObjId = usize;

/// A declared type and its supertype.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypeDecl {
    /// Lower-cased name.
    pub name: String,
    /// Supertype (`None` only for `object`).
    pub parent: Option<TypeId>,
}

/// A named, typed object or constant.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypedName {
    /// Lower-cased name.
    pub name: String,
    /// Its type.
    pub ty: TypeId,
}

/// A predicate declaration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Predicate {
    /// Lower-cased name.
    pub name: String,
    /// Declared types of the arguments.
    pub params: Vec<TypeId>,
}

/// An argument of an atom in an action schema.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Term {
    /// The action's parameter with this index.
    Param(usize),
    /// A domain constant (an index into [`Domain::constants`], equal to its [`ObjId`]).
    Const(ObjId),
}

/// A predicate applied to terms, inside an action schema.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AtomSchema {
    /// The predicate.
    pub pred: PredId,
    /// Its arguments.
    pub args: Vec<Term>,
}

/// One conjunct of an action precondition.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Condition {
    /// The atom must hold.
    Atom(AtomSchema),
    /// `(= a b)`: both terms denote the same object.
    Equal(Term, Term),
    /// `(not (= a b))`: the terms denote different objects.
    NotEqual(Term, Term),
}

/// An action schema.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ActionSchema {
    /// Lower-cased name.
    pub name: String,
    /// Parameters (without `?`) and their types.
    pub params: Vec<TypedName>,
    /// Conjunctive precondition.
    pub precondition: Vec<Condition>,
    /// Atoms made true.
    pub add: Vec<AtomSchema>,
    /// Atoms made false (deleted before the adds are applied).
    pub del: Vec<AtomSchema>,
}

/// A parsed domain.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Domain {
    /// Lower-cased name.
    pub name: String,
    /// Requirement flags as written (lower-cased, with `:`).
    pub requirements: Vec<String>,
    /// Types; index 0 is `object`.
    pub types: Vec<TypeDecl>,
    /// Constants; their indices are also their [`ObjId`]s in every problem.
    pub constants: Vec<TypedName>,
    /// Predicates.
    pub predicates: Vec<Predicate>,
    /// Action schemas.
    pub actions: Vec<ActionSchema>,
}

impl Domain {
    /// Whether `sub` is `sup` or one of its (transitive) subtypes.
    pub fn is_subtype(&self, sub: TypeId, sup: TypeId) -> bool {
        let mut t = Some(sub);
        // Parse-time checks rule out cycles, so this walk ends at `object`.
        while let Some(cur) = t {
            if cur == sup {
                return true;
            }
            t = self.types[cur].parent;
        }
        false
    }
}

/// A ground atom of a problem.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GroundAtom {
    /// The predicate.
    pub pred: PredId,
    /// Its arguments.
    pub args: Vec<ObjId>,
}

/// A parsed problem, checked against its domain.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// Lower-cased name.
    pub name: String,
    /// All objects: the domain's constants first, then the problem's `:objects`.
    pub objects: Vec<TypedName>,
    /// Initial state (duplicates removed, in order of first appearance).
    pub init: Vec<GroundAtom>,
    /// Goal conjunction.
    pub goal: Vec<GroundAtom>,
}

impl Problem {
    /// Writes a ground atom as PDDL, e.g. `(at r1 l1)`.
    pub fn atom_name(&self, domain: &Domain, atom: &GroundAtom) -> String {
        let mut s = format!("({}", domain.predicates[atom.pred].name);
        for &a in &atom.args {
            s.push(' ');
            s.push_str(&self.objects[a].name);
        }
        s.push(')');
        s
    }
}
