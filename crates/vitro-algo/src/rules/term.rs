//! Terms (Prolog-like: atoms, integers, strings, variables, compounds), substitutions and
//! unification.

use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::BTreeMap;
use std::fmt;
use std::hash::{Hash, Hasher};

use super::error::Pos;

/// A variable: its name and the macro expansion it belongs to (0 outside macros), so that
/// the variables of two expansions of one macro never meet. Its position is where it was
/// written, for messages; it takes no part in comparisons.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Var {
    /// The name as written, e.g. `X`.
    pub name: String,
    /// The expansion it belongs to.
    pub scope: u32,
    /// Where it was written.
    pub pos: Pos,
}

impl Var {
    /// The variable `name` outside any macro.
    pub fn new(name: &str) -> Self {
        Var {
            name: name.to_string(),
            scope: 0,
            pos: Pos::default(),
        }
    }
    fn key(&self) -> (&str, u32) {
        (&self.name, self.scope)
    }
}

impl PartialEq for Var {
    fn eq(&self, o: &Self) -> bool {
        self.key() == o.key()
    }
}
impl Eq for Var {}
impl PartialOrd for Var {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Var {
    fn cmp(&self, o: &Self) -> Ordering {
        self.key().cmp(&o.key())
    }
}
impl Hash for Var {
    fn hash<H: Hasher>(&self, h: &mut H) {
        self.key().hash(h);
    }
}

/// A term.
///
/// ```
/// use vitro_algo::rules::Term;
/// let t = Term::parse("at(guard, 3, \"gate\")")?;
/// assert_eq!(t.to_string(), "at(guard, 3, \"gate\")");
/// assert!(t.is_ground());
/// # Ok::<(), vitro_algo::rules::RuleError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Term {
    /// A name starting with a lower-case letter: `gate`.
    Atom(String),
    /// An integer: `-3`.
    Int(i64),
    /// A string: `"north gate"`.
    Str(String),
    /// A variable: `X`.
    Var(Var),
    /// A functor applied to arguments: `at(guard, gate)`.
    Compound(String, Vec<Term>),
}

/// Values of variables.
pub type Bindings = BTreeMap<Var, Term>;

impl Term {
    /// An atom.
    pub fn atom(name: &str) -> Self {
        Term::Atom(name.to_string())
    }
    /// A compound term.
    pub fn compound(functor: &str, args: Vec<Term>) -> Self {
        Term::Compound(functor.to_string(), args)
    }
    /// A variable outside any macro.
    pub fn var(name: &str) -> Self {
        Term::Var(Var::new(name))
    }

    /// The functor (name) and arity of an atom or compound; `None` for other terms.
    pub fn functor(&self) -> Option<(&str, usize)> {
        match self {
            Term::Atom(a) => Some((a, 0)),
            Term::Compound(f, args) => Some((f, args.len())),
            _ => None,
        }
    }

    /// The arguments of a compound (none for other terms).
    pub fn args(&self) -> &[Term] {
        match self {
            Term::Compound(_, args) => args,
            _ => &[],
        }
    }

    /// Whether the term has no variable.
    pub fn is_ground(&self) -> bool {
        match self {
            Term::Var(_) => false,
            Term::Compound(_, args) => args.iter().all(Term::is_ground),
            _ => true,
        }
    }

    /// The term with bound variables replaced by their values.
    pub fn substitute(&self, b: &Bindings) -> Term {
        match self {
            Term::Var(v) => match b.get(v) {
                Some(t) => t.substitute(b),
                None => self.clone(),
            },
            Term::Compound(f, args) => {
                Term::Compound(f.clone(), args.iter().map(|a| a.substitute(b)).collect())
            }
            _ => self.clone(),
        }
    }

    /// Calls `f` on every variable occurrence, left to right.
    pub fn visit_vars<'a>(&'a self, f: &mut impl FnMut(&'a Var)) {
        match self {
            Term::Var(v) => f(v),
            Term::Compound(_, args) => args.iter().for_each(|a| a.visit_vars(f)),
            _ => {}
        }
    }

    /// The integer, if this is one.
    pub fn as_int(&self) -> Option<i64> {
        match self {
            Term::Int(i) => Some(*i),
            _ => None,
        }
    }
}

/// Extends `b` so that `x` and `y` become equal; false (with `b` possibly extended) if they
/// cannot.
///
/// ```
/// use vitro_algo::rules::{unify, Bindings, Term};
/// let mut b = Bindings::new();
/// assert!(unify(&Term::parse("at(X, 2)")?, &Term::parse("at(gate, Y)")?, &mut b));
/// assert_eq!(Term::parse("p(X, Y)")?.substitute(&b).to_string(), "p(gate, 2)");
/// # Ok::<(), vitro_algo::rules::RuleError>(())
/// ```
pub fn unify(x: &Term, y: &Term, b: &mut Bindings) -> bool {
    let (x, y) = (resolve(x, b), resolve(y, b));
    match (&x, &y) {
        (Term::Var(v), Term::Var(w)) if v == w => true,
        (Term::Var(v), t) | (t, Term::Var(v)) => {
            if occurs(v, t, b) {
                return false;
            }
            b.insert(v.clone(), t.clone());
            true
        }
        (Term::Compound(f, xs), Term::Compound(g, ys)) => {
            f == g && xs.len() == ys.len() && xs.iter().zip(ys).all(|(a, c)| unify(a, c, b))
        }
        _ => x == y,
    }
}

/// `t` with its head variable chain followed (not deep).
fn resolve(t: &Term, b: &Bindings) -> Term {
    let mut t = t;
    while let Term::Var(v) = t {
        match b.get(v) {
            Some(next) => t = next,
            None => break,
        }
    }
    t.clone()
}

fn occurs(v: &Var, t: &Term, b: &Bindings) -> bool {
    match resolve(t, b) {
        Term::Var(w) => *v == w,
        Term::Compound(_, args) => args.iter().any(|a| occurs(v, a, b)),
        _ => false,
    }
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Term::Atom(a) => f.write_str(a),
            Term::Int(i) => write!(f, "{i}"),
            Term::Str(s) => {
                let escaped = s
                    .replace('\\', "\\\\")
                    .replace('"', "\\\"")
                    .replace('\n', "\\n");
                write!(f, "\"{escaped}\"")
            }
            // Anonymous variables are numbered `_#n` inside; they read `_`.
            Term::Var(v) => f.write_str(v.name.split('#').next().unwrap_or("_")),
            Term::Compound(name, args) => {
                write!(f, "{name}(")?;
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    write!(f, "{a}")?;
                }
                f.write_str(")")
            }
        }
    }
}
