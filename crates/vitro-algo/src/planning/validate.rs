//! An independent plan validator: simulates a plan, written as PDDL ground actions, on
//! the parsed domain and problem with the PDDL semantics (no grounding, no task).

use std::collections::{BTreeSet, HashMap};

use thiserror::Error;

use super::pddl::{AtomSchema, Condition, Domain, GroundAtom, ObjId, Problem, Term};

/// Why a plan is not a valid solution. Steps count from 1.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ValidationError {
    /// A step that does not read as `(action object ...)`.
    #[error("step {step}: cannot read '{text}' as a ground action like '(move r1 l1 l2)'")]
    Malformed {
        /// The step.
        step: usize,
        /// The text given.
        text: String,
    },
    /// An action the domain does not define.
    #[error("step {step}: unknown action '{name}'")]
    UnknownAction {
        /// The step.
        step: usize,
        /// The action name.
        name: String,
    },
    /// Wrong number of arguments.
    #[error("step {step} {action}: '{name}' takes {expected} argument(s), found {found}")]
    Arity {
        /// The step.
        step: usize,
        /// The step as written.
        action: String,
        /// The action name.
        name: String,
        /// Number of parameters.
        expected: usize,
        /// Number of arguments given.
        found: usize,
    },
    /// An argument that is not an object of the problem.
    #[error("step {step} {action}: unknown object '{object}'")]
    UnknownObject {
        /// The step.
        step: usize,
        /// The step as written.
        action: String,
        /// The unknown name.
        object: String,
    },
    /// An argument whose type does not fit its parameter.
    #[error(
        "step {step} {action}: object '{object}' is not of type '{expected}' (parameter ?{param})"
    )]
    ParamType {
        /// The step.
        step: usize,
        /// The step as written.
        action: String,
        /// The argument.
        object: String,
        /// The parameter name.
        param: String,
        /// The parameter's type.
        expected: String,
    },
    /// A precondition that does not hold when the step is applied.
    #[error("step {step} {action}: precondition {condition} is false")]
    PreconditionFalse {
        /// The step.
        step: usize,
        /// The step as written.
        action: String,
        /// The failed condition in PDDL form, e.g. `(free l2)`.
        condition: String,
    },
    /// The goal does not hold after the last step.
    #[error("goal not reached after {steps} step(s): {} false", .missing.join(" "))]
    GoalNotReached {
        /// Plan length.
        steps: usize,
        /// Goal atoms that are false at the end, in goal order.
        missing: Vec<String>,
    },
}

/// Checks that `plan` (ground actions such as `(move r1 l1 l2)`, case-insensitive) is
/// applicable from the initial state of `problem` and reaches its goal.
///
/// Each step's arguments must be objects of the parameters' types and its precondition
/// must hold; then its deletes and afterwards its adds are applied.
///
/// ```
/// use vitro_algo::planning::pddl::{parse_domain, parse_problem};
/// use vitro_algo::planning::validate::validate_plan;
///
/// let d = parse_domain("(define (domain d) (:predicates (at ?x) (visited ?x))
///     (:action go :parameters (?a ?b) :precondition (at ?a)
///      :effect (and (at ?b) (visited ?b) (not (at ?a)))))", "d.pddl")?;
/// let p = parse_problem(&d, "(define (problem p) (:domain d) (:objects x y)
///     (:init (at x)) (:goal (visited y)))", "p.pddl")?;
/// assert!(validate_plan(&d, &p, &["(go x y)"]).is_ok());
/// assert!(validate_plan(&d, &p, &["(go y x)"]).is_err());
/// # Ok::<(), vitro_algo::planning::pddl::ParseError>(())
/// ```
///
/// # Errors
/// The first [`ValidationError`] met while simulating.
pub fn validate_plan<S: AsRef<str>>(
    domain: &Domain,
    problem: &Problem,
    plan: &[S],
) -> Result<(), ValidationError> {
    let objects: HashMap<&str, ObjId> = problem
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| (o.name.as_str(), i))
        .collect();
    let mut state: BTreeSet<GroundAtom> = problem.init.iter().cloned().collect();

    for (index, text) in plan.iter().enumerate() {
        let step = index + 1;
        let text = text.as_ref().trim();
        let inner = text
            .strip_prefix('(')
            .and_then(|t| t.strip_suffix(')'))
            .map(|t| t.to_lowercase());
        let words: Vec<&str> = inner
            .as_deref()
            .map_or(Vec::new(), |t| t.split_whitespace().collect());
        let Some((&name, arg_names)) = words.split_first() else {
            return Err(ValidationError::Malformed {
                step,
                text: text.to_string(),
            });
        };
        let action = text.to_string();
        let schema = domain
            .actions
            .iter()
            .find(|a| a.name == name)
            .ok_or_else(|| ValidationError::UnknownAction {
                step,
                name: name.to_string(),
            })?;
        if arg_names.len() != schema.params.len() {
            return Err(ValidationError::Arity {
                step,
                action,
                name: name.to_string(),
                expected: schema.params.len(),
                found: arg_names.len(),
            });
        }
        let mut args = Vec::with_capacity(arg_names.len());
        for (&arg, param) in arg_names.iter().zip(&schema.params) {
            let &obj = objects
                .get(arg)
                .ok_or_else(|| ValidationError::UnknownObject {
                    step,
                    action: action.clone(),
                    object: arg.to_string(),
                })?;
            if !domain.is_subtype(problem.objects[obj].ty, param.ty) {
                return Err(ValidationError::ParamType {
                    step,
                    action,
                    object: arg.to_string(),
                    param: param.name.clone(),
                    expected: domain.types[param.ty].name.clone(),
                });
            }
            args.push(obj);
        }

        for cond in &schema.precondition {
            let holds = match cond {
                Condition::Atom(a) => state.contains(&bind(a, &args)),
                Condition::Equal(x, y) => term(*x, &args) == term(*y, &args),
                Condition::NotEqual(x, y) => term(*x, &args) != term(*y, &args),
            };
            if !holds {
                return Err(ValidationError::PreconditionFalse {
                    step,
                    action,
                    condition: describe(domain, problem, cond, &args),
                });
            }
        }
        for a in &schema.del {
            state.remove(&bind(a, &args));
        }
        for a in &schema.add {
            state.insert(bind(a, &args));
        }
    }

    let missing: Vec<String> = problem
        .goal
        .iter()
        .filter(|g| !state.contains(g))
        .map(|g| problem.atom_name(domain, g))
        .collect();
    if missing.is_empty() {
        Ok(())
    } else {
        Err(ValidationError::GoalNotReached {
            steps: plan.len(),
            missing,
        })
    }
}

fn term(t: Term, args: &[ObjId]) -> ObjId {
    match t {
        Term::Param(i) => args[i],
        Term::Const(c) => c,
    }
}

fn bind(a: &AtomSchema, args: &[ObjId]) -> GroundAtom {
    GroundAtom {
        pred: a.pred,
        args: a.args.iter().map(|&t| term(t, args)).collect(),
    }
}

/// A ground precondition in PDDL form.
fn describe(domain: &Domain, problem: &Problem, cond: &Condition, args: &[ObjId]) -> String {
    let name = |t: Term| problem.objects[term(t, args)].name.as_str();
    match cond {
        Condition::Atom(a) => problem.atom_name(domain, &bind(a, args)),
        Condition::Equal(x, y) => format!("(= {} {})", name(*x), name(*y)),
        Condition::NotEqual(x, y) => format!("(not (= {} {}))", name(*x), name(*y)),
    }
}
