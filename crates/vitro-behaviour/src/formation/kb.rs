//! What the formation controllers share with the rule interpreter: module names and
//! operations (checked when a program is loaded), answers from lists of facts, and running
//! one cycle with the choices drawn from the agent's `"rules"` stream.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vitro::sim::Context;
use vitro_algo::rules::{
    Bindings, Cycle, Interpreter, KbError, ModuleSet, Program, Query, RuleError, Term, Update,
    unify,
};
use vitro_tactical::model::Tactical;
use vitro_tactical::radio::Message;

/// A controller's modules: names and the update operations each offers.
pub(crate) type Signature = &'static [(&'static str, &'static [&'static str])];

/// The modules of a signature, for checking a program before any context exists.
struct Names(Signature);

impl ModuleSet for Names {
    fn find(&self, name: &str) -> Option<usize> {
        self.0.iter().position(|(n, _)| *n == name)
    }
    fn supports(&self, module: usize, op: &str) -> bool {
        self.0.get(module).is_some_and(|(_, ops)| ops.contains(&op))
    }
    fn query(&mut self, _: usize, _: &Query) -> Vec<Bindings> {
        Vec::new()
    }
    fn update(&mut self, _: usize, _: &Update) -> Result<(), KbError> {
        Err(KbError::Refused("not running".into()))
    }
}

/// Parses `source` (named `name` in errors) and checks it against `modules`.
pub(crate) fn load(name: &str, source: &str, modules: Signature) -> Result<Interpreter, RuleError> {
    let program = Program::parse(name, source)?;
    Interpreter::new(program, &Names(modules))
}

/// A seed for one cycle's choices, from the agent's `"rules"` stream.
pub(crate) fn seed<M: Message>(cx: &mut Context<'_, Tactical<M>>) -> u64 {
    cx.rng("rules").random()
}

/// Runs one cycle of `interp` against `set`, the choices of `;` drawn from a generator
/// seeded with `seed` (from [`seed`]).
pub(crate) fn cycle(interp: &Interpreter, set: &mut impl ModuleSet, seed: u64) -> Cycle {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    interp.cycle(set, &mut rng)
}

/// The answers to `q` among `facts`, in their order.
pub(crate) fn answers(q: &Query, facts: impl IntoIterator<Item = Term>) -> Vec<Bindings> {
    facts
        .into_iter()
        .filter_map(|f| {
            let mut b = Bindings::new();
            unify(&q.term, &f, &mut b).then_some(b)
        })
        .collect()
}

/// `name(arg)` as a term.
pub(crate) fn fact(name: &str, arg: Term) -> Term {
    Term::compound(name, vec![arg])
}

/// The atom an update's term is.
pub(crate) fn atom(u: &Update) -> Result<&str, KbError> {
    match &u.term {
        Term::Atom(a) => Ok(a),
        other => Err(KbError::Refused(format!("{other} is not a name"))),
    }
}

/// Index of module `name` in `modules`.
pub(crate) fn index(modules: Signature, name: &str) -> Option<usize> {
    modules.iter().position(|(n, _)| *n == name)
}
