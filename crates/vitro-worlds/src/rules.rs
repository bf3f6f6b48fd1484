//! Rule-programmed agents: the rule language of `vitro_algo::rules` as a vitro agent that runs
//! one deliberation cycle per tick, with modules bound to its sensors and actuators.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vitro::protocol::TimerTag;
use vitro::sim::{Agent, Context, Input, Model};
use vitro::time::SimDuration;

use vitro_algo::rules::{
    Bindings, Cycle, Interpreter, KbError, KnowledgeBase, ModuleSet, Program, Query, RuleError,
    Update,
};

/// A module of a simulated agent: like a [`KnowledgeBase`], but it may use the agent's
/// [`Context`] to read sensors and drive actuators (a motion module bound to whatever
/// actuator the host chooses), and it sees the agent's other inputs (messages, events).
///
/// Every [`KnowledgeBase`] is an `Embodied` module that ignores the context.
pub trait Embodied<M: Model> {
    /// The answers to `q`, in the module's order (see [`KnowledgeBase::query`]).
    fn query(&self, q: &Query, cx: &mut Context<'_, M>) -> Vec<Bindings>;
    /// Applies `u`.
    ///
    /// # Errors
    /// [`KbError`] when the operation is unknown or refused.
    fn update(&mut self, u: &Update, cx: &mut Context<'_, M>) -> Result<(), KbError>;
    /// Whether the module offers operation `op` (checked when the agent is built).
    fn supports(&self, op: &str) -> bool {
        let _ = op;
        true
    }
    /// Sees an input of the agent other than its deliberation tick (a message, an event),
    /// before the next cycle. Does nothing by default.
    fn perceive(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
        let _ = (input, cx);
    }
}

impl<M: Model, K: KnowledgeBase> Embodied<M> for K {
    fn query(&self, q: &Query, _: &mut Context<'_, M>) -> Vec<Bindings> {
        KnowledgeBase::query(self, q)
    }
    fn update(&mut self, u: &Update, _: &mut Context<'_, M>) -> Result<(), KbError> {
        KnowledgeBase::update(self, u)
    }
    fn supports(&self, op: &str) -> bool {
        KnowledgeBase::supports(self, op)
    }
}

/// The named modules of a simulated agent.
pub type EmbodiedModules<M> = Vec<(String, Box<dyn Embodied<M>>)>;

/// The timer tag of the deliberation tick (top 16 bits of the timer key).
pub const RULES_TIMER: TimerTag = TimerTag(0x5255);

/// A rule-programmed agent: one deliberation cycle per tick, every `period` of simulated
/// time.
///
/// The first input of any other kind starts the ticks (a cycle at once, then one every
/// period): schedule an event for the agent when it should start deliberating. Inputs other
/// than its ticks are shown to every module ([`Embodied::perceive`]). The choices of `;` are
/// drawn from a generator seeded, at each cycle, from the agent's random stream `"rules"`,
/// so runs are reproducible.
///
/// A host whose agents are not all rule agents can hold a `RuleAgent` inside its own agent
/// type and call [`handle_input`](Self::handle_input).
pub struct RuleAgent<M: Model> {
    interpreter: Interpreter,
    modules: EmbodiedModules<M>,
    period: SimDuration,
    started: bool,
    cycles: u64,
    last: Cycle,
}

impl<M: Model> RuleAgent<M> {
    /// An agent running `program` against `modules`, deliberating every `period`.
    ///
    /// # Errors
    /// A module the program names is missing, or lacks an operation it uses.
    pub fn new(
        program: Program,
        modules: EmbodiedModules<M>,
        period: SimDuration,
    ) -> Result<Self, RuleError> {
        let interpreter = Interpreter::new(program, &Names(&modules))?;
        Ok(RuleAgent {
            interpreter,
            modules,
            period,
            started: false,
            cycles: 0,
            last: Cycle::default(),
        })
    }

    /// Cycles run so far.
    pub fn cycles(&self) -> u64 {
        self.cycles
    }

    /// What the latest cycle did.
    pub fn last_cycle(&self) -> &Cycle {
        &self.last
    }

    /// Module `name`.
    pub fn module(&self, name: &str) -> Option<&dyn Embodied<M>> {
        self.modules
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, m)| m.as_ref())
    }

    /// Runs one deliberation cycle now.
    pub fn deliberate(&mut self, cx: &mut Context<'_, M>) -> &Cycle {
        let seed: u64 = cx.rng("rules").random();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut bound = Bound {
            modules: &mut self.modules,
            cx,
        };
        self.last = self.interpreter.cycle(&mut bound, &mut rng);
        self.cycles += 1;
        &self.last
    }

    /// Handles one input: a tick runs a cycle and sets the next; anything else goes to the
    /// modules (and starts the ticks the first time). True if the input was a tick.
    pub fn handle_input(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) -> bool {
        if let Input::Timer(key) = input
            && RULES_TIMER.index(key).is_some()
        {
            self.deliberate(cx);
            cx.set_timer(self.period, RULES_TIMER.key(0));
            return true;
        }
        for (_, m) in &mut self.modules {
            m.perceive(input, cx);
        }
        if !self.started {
            self.started = true;
            self.deliberate(cx);
            cx.set_timer(self.period, RULES_TIMER.key(0));
        }
        false
    }
}

impl<M: Model> Agent<M> for RuleAgent<M> {
    fn handle(&mut self, input: Input<'_, M>, cx: &mut Context<'_, M>) {
        self.handle_input(input, cx);
    }
}

/// The modules' names and operations, for checking a program before any context exists.
struct Names<'a, M: Model>(&'a EmbodiedModules<M>);

impl<M: Model> ModuleSet for Names<'_, M> {
    fn find(&self, name: &str) -> Option<usize> {
        self.0.iter().position(|(n, _)| n == name)
    }
    fn supports(&self, module: usize, op: &str) -> bool {
        self.0.get(module).is_some_and(|(_, m)| m.supports(op))
    }
    fn query(&mut self, _: usize, _: &Query) -> Vec<Bindings> {
        Vec::new()
    }
    fn update(&mut self, _: usize, _: &Update) -> Result<(), KbError> {
        Err(KbError::Refused("not running".into()))
    }
}

/// The modules bound to the context of one cycle.
struct Bound<'a, 'c, M: Model> {
    modules: &'a mut EmbodiedModules<M>,
    cx: &'a mut Context<'c, M>,
}

impl<M: Model> ModuleSet for Bound<'_, '_, M> {
    fn find(&self, name: &str) -> Option<usize> {
        self.modules.iter().position(|(n, _)| n == name)
    }
    fn supports(&self, module: usize, op: &str) -> bool {
        self.modules
            .get(module)
            .is_some_and(|(_, m)| m.supports(op))
    }
    fn query(&mut self, module: usize, q: &Query) -> Vec<Bindings> {
        match self.modules.get(module) {
            Some((_, m)) => m.query(q, self.cx),
            None => Vec::new(),
        }
    }
    fn update(&mut self, module: usize, u: &Update) -> Result<(), KbError> {
        match self.modules.get_mut(module) {
            Some((_, m)) => m.update(u, self.cx),
            None => Err(KbError::Refused(format!("no module {module}"))),
        }
    }
}
