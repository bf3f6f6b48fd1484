//! The leader's modules as the rule interpreter sees them: `eyes`, `squad` and `route` (their
//! queries and updates are listed in `data/rules/formation/leader.jz`).

use super::state::{EYES, Lag, MODULES, Pace, ROUTE, SQUAD, State};
use crate::formation::kb::{self, answers, atom, fact};
use crate::formation::motion::xy;
use crate::formation::pattern::Pattern;
use crate::formation::record::{Arrival, Switch};
use vitro::comm::{Address, Outgoing};
use vitro::sim::Context;
use vitro_algo::rules::{Bindings, KbError, ModuleSet, Query, Term, Update};
use vitro_tactical::entity::Level;
use vitro_tactical::model::Tactical;
use vitro_tactical::radio::{Signal, SquadTalk};

/// The leader's modules bound to its state and context for one cycle.
pub(super) struct Bound<'a, 'c, M: SquadTalk> {
    pub st: &'a mut State,
    pub cx: &'a mut Context<'c, Tactical<M>>,
}

impl<M: SquadTalk> ModuleSet for Bound<'_, '_, M> {
    fn find(&self, name: &str) -> Option<usize> {
        kb::index(MODULES, name)
    }

    fn supports(&self, module: usize, op: &str) -> bool {
        MODULES
            .get(module)
            .is_some_and(|(_, ops)| ops.contains(&op))
    }

    fn query(&mut self, module: usize, q: &Query) -> Vec<Bindings> {
        let st = &*self.st;
        let now = self.cx.now();
        let mut facts = Vec::new();
        match module {
            EYES => {
                if st.contact.is_some() {
                    facts.push(Term::atom("contact"));
                }
                facts.push(fact("ground", Term::atom(st.ground.name())));
            }
            SQUAD => {
                facts.push(fact("formation", Term::atom(st.pattern.name())));
                if st.switched_at.is_none_or(|t| now - t >= st.params.settle) {
                    facts.push(Term::atom("settled"));
                }
                let lag = match st.lag {
                    Lag::None => "none",
                    Lag::Some => "some",
                    Lag::Far => "far",
                };
                facts.push(fact("lag", Term::atom(lag)));
                if st.now_waited_out(now) {
                    facts.push(Term::atom("waited_out"));
                }
                if st.gathered {
                    facts.push(Term::atom("gathered"));
                }
                if st.unbriefed(now) {
                    facts.push(Term::atom("unbriefed"));
                }
            }
            ROUTE => {
                let level = st.pose.map_or(Level::Directed, |p| p.level);
                facts.push(Term::atom(match &st.route {
                    None => "idle",
                    Some(r) if r.follow.done(level) => "at_goal",
                    Some(_) => "under_way",
                }));
            }
            _ => {}
        }
        answers(q, facts)
    }

    fn update(&mut self, module: usize, u: &Update) -> Result<(), KbError> {
        let st = &mut *self.st;
        let cx = &mut *self.cx;
        match (module, u.op.as_str()) {
            (SQUAD, "form") => {
                let name = atom(u)?;
                let to = Pattern::from_name(name)
                    .ok_or_else(|| KbError::Refused(format!("no formation {name}")))?;
                let reason = if st.contact.is_some() {
                    "contact"
                } else {
                    st.ground.name()
                };
                st.switches.push(Switch {
                    t: cx.now(),
                    from: st.pattern,
                    to,
                    reason: reason.into(),
                    at: st.pose.as_ref().map_or([0.0; 2], xy),
                });
                st.pattern = to;
                st.switched_at = Some(cx.now());
                st.briefed = false;
                Ok(())
            }
            (SQUAD, "brief") => {
                st.brief(cx);
                Ok(())
            }
            (ROUTE, "pace") => {
                st.pace = Some(match atom(u)? {
                    "normal" => Pace::Normal,
                    "slow" => Pace::Slow,
                    "halt" => Pace::Halt,
                    other => return Err(KbError::Refused(format!("no pace {other}"))),
                });
                Ok(())
            }
            (ROUTE, "report") => {
                let Some(r) = st.route.take() else {
                    return Err(KbError::Refused("no order to report on".into()));
                };
                let msg = M::from(Signal::new(atom(u)?, ""));
                cx.send(Outgoing::new(Address::Agent(r.requester), msg));
                st.arrivals.push(Arrival {
                    t: cx.now(),
                    requester: r.requester,
                    goal: r.goal,
                    gathered: st.gathered,
                });
                st.at_goal_since = None;
                Ok(())
            }
            (_, op) => Err(KbError::UnknownOperation(op.into())),
        }
    }
}
