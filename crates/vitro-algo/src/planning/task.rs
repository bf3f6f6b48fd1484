//! The compact ground STRIPS task the planners search: dense fact ids, actions with
//! sorted precondition/add/delete lists, states as bitsets.

/// Dense index of a ground fact in [`Task::facts`].
pub type FactId = u32;
/// Dense index of a ground action in [`Task::actions`].
pub type ActionId = u32;

/// A ground STRIPS action.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GroundAction {
    /// PDDL form, e.g. `(move r1 l1 l2)`.
    pub name: String,
    /// Facts that must hold (sorted, no duplicates).
    pub pre: Vec<FactId>,
    /// Facts made true (sorted, no duplicates).
    pub add: Vec<FactId>,
    /// Facts made false (sorted, no duplicates, disjoint from `add`).
    pub del: Vec<FactId>,
    /// Cost of applying the action (1 for unit-cost tasks).
    pub cost: u32,
}

/// A ground STRIPS task. States are bitsets over facts (see [`Task::words`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Task {
    /// Fact names in PDDL form, e.g. `(at r1 l1)`, indexed by [`FactId`].
    pub facts: Vec<String>,
    /// Ground actions, indexed by [`ActionId`].
    pub actions: Vec<GroundAction>,
    /// Facts true initially (sorted).
    pub init: Vec<FactId>,
    /// Facts that must hold at the end (sorted).
    pub goal: Vec<FactId>,
}

impl Task {
    /// Number of `u64` words in a state bitset.
    pub fn words(&self) -> usize {
        self.facts.len().div_ceil(64).max(1)
    }

    /// The initial state as a bitset.
    pub fn initial_state(&self) -> Vec<u64> {
        let mut s = vec![0; self.words()];
        for &f in &self.init {
            set(&mut s, f);
        }
        s
    }

    /// Whether every goal fact holds in `state`.
    pub fn is_goal(&self, state: &[u64]) -> bool {
        self.goal.iter().all(|&f| has(state, f))
    }

    /// Whether `action` is applicable in `state`.
    pub fn applicable(&self, action: ActionId, state: &[u64]) -> bool {
        self.actions[action as usize]
            .pre
            .iter()
            .all(|&f| has(state, f))
    }

    /// Writes into `out` the state that results from applying `action` in `state`
    /// (deletes, then adds). Does not check applicability.
    pub fn apply_into(&self, action: ActionId, state: &[u64], out: &mut Vec<u64>) {
        let a = &self.actions[action as usize];
        out.clear();
        out.extend_from_slice(state);
        for &f in &a.del {
            clear(out, f);
        }
        for &f in &a.add {
            set(out, f);
        }
    }
}

/// Whether fact `f` is set in bitset `s`.
#[inline]
pub(crate) fn has(s: &[u64], f: FactId) -> bool {
    s[(f / 64) as usize] >> (f % 64) & 1 == 1
}

/// Sets fact `f` in bitset `s`.
#[inline]
pub(crate) fn set(s: &mut [u64], f: FactId) {
    s[(f / 64) as usize] |= 1 << (f % 64);
}

/// Clears fact `f` in bitset `s`.
#[inline]
pub(crate) fn clear(s: &mut [u64], f: FactId) {
    s[(f / 64) as usize] &= !(1 << (f % 64));
}

/// Calls `visit` on every set fact of `s`, in increasing order.
#[inline]
pub(crate) fn for_each_fact(s: &[u64], mut visit: impl FnMut(FactId)) {
    for (w, &word) in s.iter().enumerate() {
        let mut bits = word;
        while bits != 0 {
            let b = bits.trailing_zeros();
            visit(w as FactId * 64 + b);
            bits &= bits - 1;
        }
    }
}
