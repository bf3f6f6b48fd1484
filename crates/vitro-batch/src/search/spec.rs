//! The `[search]` table of an experiment file: what counts as a failure (or what to maximise
//! or minimise), the parameters to search and their ranges, the budget. `check` turns it
//! into a [`Search`], reporting a bad table with its place.
//!
//! ```toml
//! [search]
//! budget = 120                    # evaluations (default 120; --budget overrides)
//! population = 20                 # evaluations per generation (default 20)
//! elite = 0.2                     # share of the evaluations that steer the next generation
//! shrink = 3                      # distinct failures to shrink (default 3; 0: none)
//! shrink_budget = 60              # runs each shrink may use (default 60)
//!
//! [search.objective]
//! failure = "vip_down == true"    # METRIC OP VALUE, OP one of == != < <= > >=
//! maximise = "shots"              # optional guide: ranks the runs that do not fail
//!
//! [search.parameters]
//! "channel.loss" = [0.0, 0.6]     # a float key: an interval
//! "entity.4.count" = [2, 12]      # an integer key: integers, both ends included
//! "repair.strategy" = { values = ["lazy", "replan"] }   # a choice
//! seed = [1, 100000]              # the run's seed: a choice among these integers
//! ```

use crate::keys::scenario_kind;
use crate::value::Value;
use schemars::JsonSchema;
use serde::Deserialize;
use std::collections::BTreeMap;

/// Most evaluations one search may make.
pub const MAX_BUDGET: u64 = 1_000_000;

/// The `[search]` table as written.
#[derive(Clone, Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SearchFile {
    /// What the search looks for.
    pub objective: ObjectiveFile,
    /// The parameters searched, by dotted scenario key (or `seed`): `[low, high]` for a
    /// number, `{ values = [...] }` for a choice.
    #[schemars(with = "BTreeMap<String, serde_json::Value>")]
    #[schemars(extend("minProperties" = 1))]
    pub parameters: BTreeMap<String, toml::Value>,
    /// Evaluations (runs) of the search (default 120; `--budget` overrides).
    #[schemars(range(min = 1, max = 1_000_000))]
    pub budget: Option<u64>,
    /// Evaluations per generation (default 20).
    #[schemars(range(min = 2, max = 10_000))]
    pub population: Option<u32>,
    /// Share of the evaluations so far whose parameters steer the next generation of the
    /// adaptive strategy (default 0.2).
    #[schemars(extend("exclusiveMinimum" = 0.0, "exclusiveMaximum" = 1.0))]
    pub elite: Option<f64>,
    /// Distinct failures to shrink to a minimal scenario (default 3; 0 for none).
    pub shrink: Option<u32>,
    /// Runs each shrink may use (default 60).
    #[schemars(range(min = 1))]
    pub shrink_budget: Option<u32>,
}

/// The objective as written: a failure condition, a metric to maximise or minimise, or both
/// (then failing runs rank first, the rest by the metric).
#[derive(Clone, Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(extend("anyOf" = [
    { "required": ["failure"] },
    { "required": ["maximise"] },
    { "required": ["minimise"] }
]))]
pub struct ObjectiveFile {
    /// What counts as a failure: `METRIC OP VALUE` (`vip_down == true`, `casualties >= 2`).
    pub failure: Option<String>,
    /// A metric to maximise.
    pub maximise: Option<String>,
    /// A metric to minimise.
    pub minimise: Option<String>,
}

/// A comparison operator of a failure condition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
}

impl Op {
    fn symbol(self) -> &'static str {
        match self {
            Op::Eq => "==",
            Op::Ne => "!=",
            Op::Lt => "<",
            Op::Le => "<=",
            Op::Gt => ">",
            Op::Ge => ">=",
        }
    }
}

/// `METRIC OP VALUE`: when a run counts as a failure.
#[derive(Clone, Debug, PartialEq)]
pub struct Condition {
    /// The metric.
    pub metric: String,
    /// The comparison.
    pub op: Op,
    /// The value compared with.
    pub value: Value,
}

impl Condition {
    /// Whether a run with `metrics` meets the condition (a missing or NaN metric does not;
    /// numbers compare as numbers, booleans and texts only by `==` and `!=`).
    pub fn holds(&self, metrics: &BTreeMap<String, Value>) -> bool {
        let Some(got) = metrics.get(&self.metric) else {
            return false;
        };
        if let (Some(a), Some(b)) = (got.as_f64(), self.value.as_f64()) {
            return match self.op {
                Op::Eq => a == b,
                Op::Ne => a != b && !a.is_nan(),
                Op::Lt => a < b,
                Op::Le => a <= b,
                Op::Gt => a > b,
                Op::Ge => a >= b,
            };
        }
        match self.op {
            Op::Eq => *got == self.value,
            Op::Ne => *got != self.value,
            _ => false,
        }
    }
}

impl std::fmt::Display for Condition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {} {}", self.metric, self.op.symbol(), self.value)
    }
}

/// Whether a guide metric is maximised or minimised.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Goal {
    /// Larger is better.
    Maximise,
    /// Smaller is better.
    Minimise,
}

/// A checked objective.
#[derive(Clone, Debug, PartialEq)]
pub struct Objective {
    /// When a run is a failure.
    pub failure: Option<Condition>,
    /// The metric that ranks runs (among failing and among other runs).
    pub guide: Option<(String, Goal)>,
}

impl Objective {
    /// Whether a run with `metrics` is a failure.
    pub fn fails(&self, metrics: &BTreeMap<String, Value>) -> bool {
        self.failure.as_ref().is_some_and(|c| c.holds(metrics))
    }

    /// The guide metric, signed so that larger is better (NaN or missing: -inf; 0 without
    /// a guide).
    pub fn score(&self, metrics: &BTreeMap<String, Value>) -> f64 {
        let Some((m, goal)) = &self.guide else {
            return 0.0;
        };
        match metrics.get(m).and_then(Value::as_f64) {
            Some(x) if !x.is_nan() => match goal {
                Goal::Maximise => x,
                Goal::Minimise => -x,
            },
            _ => f64::NEG_INFINITY,
        }
    }

    /// The value reported as the objective: the guide metric if any, else the failure's.
    pub fn value(&self, metrics: &BTreeMap<String, Value>) -> Option<Value> {
        let name = self
            .guide
            .as_ref()
            .map(|(m, _)| m)
            .or(self.failure.as_ref().map(|c| &c.metric))?;
        metrics.get(name).cloned()
    }

    /// The metrics the objective reads.
    pub fn metrics(&self) -> Vec<String> {
        let mut m: Vec<String> = self.failure.iter().map(|c| c.metric.clone()).collect();
        m.extend(self.guide.iter().map(|(g, _)| g.clone()));
        m.dedup();
        m
    }

    /// One line for reports: `vip_down == true, then maximise shots`.
    pub fn describe(&self) -> String {
        let guide = self.guide.as_ref().map(|(m, g)| match g {
            Goal::Maximise => format!("maximise {m}"),
            Goal::Minimise => format!("minimise {m}"),
        });
        match (&self.failure, guide) {
            (Some(c), Some(g)) => format!("fails when {c}; otherwise {g}"),
            (Some(c), None) => format!("fails when {c}"),
            (None, Some(g)) => g,
            (None, None) => String::new(),
        }
    }
}

/// The range of a searched parameter.
#[derive(Clone, Debug, PartialEq)]
pub enum Range {
    /// A float in `[low, high]`.
    Float {
        /// Lower end.
        low: f64,
        /// Upper end.
        high: f64,
    },
    /// An integer in `low..=high` (ordered: the adaptive strategy moves along it).
    Int {
        /// Lower end.
        low: i64,
        /// Upper end.
        high: i64,
    },
    /// The run's seed, an integer in `low..=high`. Neighbouring seeds have nothing in
    /// common, so the adaptive strategy treats it as a choice, not as an ordered range.
    Seed {
        /// Lower end.
        low: u64,
        /// Upper end.
        high: u64,
    },
    /// One of these values.
    Choice(Vec<Value>),
}

/// A searched parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Dim {
    /// Dotted scenario key, or `seed` for the run's seed.
    pub path: String,
    /// Its range.
    pub range: Range,
    /// The scenario's own value (shrinking moves toward it), if the scenario sets one.
    pub default: Option<Value>,
}

/// A checked `[search]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct Search {
    /// What to look for.
    pub objective: Objective,
    /// The searched parameters, in the order written.
    pub dims: Vec<Dim>,
    /// Default number of evaluations.
    pub budget: u64,
    /// Evaluations per generation.
    pub population: u32,
    /// Share of the evaluations that steer the adaptive strategy.
    pub elite: f64,
    /// Failures to shrink.
    pub shrink: u32,
    /// Runs per shrink.
    pub shrink_budget: u32,
}

/// A problem with the table: the key path it is about and the message.
pub(crate) type Problem = (Vec<String>, String);

fn at(keys: &[&str], message: String) -> Problem {
    (keys.iter().map(|k| (*k).to_owned()).collect(), message)
}

/// Checks `file` against the scenario and the metrics the runner reports; `order` gives the
/// byte offset of a parameter's key (to keep the written order).
pub(crate) fn check(
    file: &SearchFile,
    scenario: &toml::Table,
    metrics: &[String],
    order: impl Fn(&str) -> usize,
) -> Result<Search, Problem> {
    let known = |m: &str, keys: &[&str]| {
        if metrics.iter().any(|x| x == m) {
            Ok(())
        } else {
            Err(at(
                keys,
                format!(
                    "unknown metric `{m}`, expected one of: {}",
                    metrics.join(", ")
                ),
            ))
        }
    };
    let o = &file.objective;
    let failure = match &o.failure {
        Some(text) => {
            let keys = ["search", "objective", "failure"];
            let c = parse_condition(text).map_err(|m| at(&keys, m))?;
            known(&c.metric, &keys)?;
            Some(c)
        }
        None => None,
    };
    let guide = match (&o.maximise, &o.minimise) {
        (Some(_), Some(_)) => {
            return Err(at(
                &["search", "objective", "minimise"],
                "give `maximise` or `minimise`, not both".into(),
            ));
        }
        (Some(m), None) => {
            known(m, &["search", "objective", "maximise"])?;
            Some((m.clone(), Goal::Maximise))
        }
        (None, Some(m)) => {
            known(m, &["search", "objective", "minimise"])?;
            Some((m.clone(), Goal::Minimise))
        }
        (None, None) => None,
    };
    if failure.is_none() && guide.is_none() {
        return Err(at(
            &["search", "objective"],
            "the objective needs `failure`, `maximise` or `minimise`".into(),
        ));
    }

    if file.parameters.is_empty() {
        return Err(at(
            &["search", "parameters"],
            "expected at least one parameter to search".into(),
        ));
    }
    let mut named: Vec<(&String, &toml::Value)> = file.parameters.iter().collect();
    named.sort_by_key(|(p, _)| order(p));
    let mut dims = Vec::with_capacity(named.len());
    for (p, v) in named {
        let keys = ["search", "parameters", p.as_str()];
        dims.push(dim(p, v, scenario).map_err(|m| at(&keys, m))?);
    }

    let budget = file.budget.unwrap_or(120);
    if !(1..=MAX_BUDGET).contains(&budget) {
        return Err(at(
            &["search", "budget"],
            format!("invalid budget {budget}, expected 1 to {MAX_BUDGET} evaluations"),
        ));
    }
    let population = file.population.unwrap_or(20);
    if !(2..=10_000).contains(&population) {
        return Err(at(
            &["search", "population"],
            format!("invalid population {population}, expected 2 to 10000"),
        ));
    }
    let elite = file.elite.unwrap_or(0.2);
    if !(elite > 0.0 && elite < 1.0) {
        return Err(at(
            &["search", "elite"],
            format!("invalid elite share {elite}, expected a number in (0, 1)"),
        ));
    }
    let shrink_budget = file.shrink_budget.unwrap_or(60);
    if shrink_budget == 0 {
        return Err(at(
            &["search", "shrink_budget"],
            "expected at least 1 run per shrink".into(),
        ));
    }
    Ok(Search {
        objective: Objective { failure, guide },
        dims,
        budget,
        population,
        elite,
        shrink: file.shrink.unwrap_or(3),
        shrink_budget,
    })
}

/// `METRIC OP VALUE`.
fn parse_condition(text: &str) -> Result<Condition, String> {
    const OPS: [(&str, Op); 6] = [
        ("==", Op::Eq),
        ("!=", Op::Ne),
        ("<=", Op::Le),
        (">=", Op::Ge),
        ("<", Op::Lt),
        (">", Op::Gt),
    ];
    let bad = || {
        format!(
            "invalid failure condition `{text}`, expected METRIC OP VALUE with OP one of \
             == != < <= > >= (e.g. `success == false`, `casualties >= 2`)"
        )
    };
    let (at, sym, op) = OPS
        .iter()
        .filter_map(|(s, op)| text.find(s).map(|i| (i, *s, *op)))
        .min_by_key(|(i, s, _)| (*i, std::cmp::Reverse(s.len())))
        .ok_or_else(bad)?;
    let metric = text[..at].trim();
    let raw = text[at + sym.len()..].trim();
    if metric.is_empty() || raw.is_empty() || metric.contains(char::is_whitespace) {
        return Err(bad());
    }
    let value = match raw {
        "true" => Value::Bool(true),
        "false" => Value::Bool(false),
        _ => match (raw.parse::<i64>(), raw.parse::<f64>()) {
            (Ok(i), _) => Value::Int(i),
            (_, Ok(f)) if f.is_finite() => Value::Float(f),
            _ => Value::Text(raw.trim_matches(|c| c == '"' || c == '\'').to_owned()),
        },
    };
    if value.as_f64().is_none() && !matches!(op, Op::Eq | Op::Ne) {
        return Err(format!(
            "`{sym}` compares numbers; `{raw}` is {}, use == or !=",
            value.kind()
        ));
    }
    Ok(Condition {
        metric: metric.to_owned(),
        op,
        value,
    })
}

/// One searched parameter from its written range.
fn dim(path: &str, v: &toml::Value, scenario: &toml::Table) -> Result<Dim, String> {
    let expected = "expected [low, high] for a number or { values = [...] } for a choice";
    let default = if path == "seed" {
        scenario.get("seed").and_then(Value::from_toml)
    } else {
        Some(scenario_kind(scenario, path)?)
    };
    let range = match v {
        toml::Value::Table(t) => {
            if let Some(k) = t.keys().find(|k| *k != "values") {
                return Err(format!(
                    "unknown key `{k}` in the range of `{path}`, {expected}"
                ));
            }
            let Some(toml::Value::Array(items)) = t.get("values") else {
                return Err(format!("invalid range of `{path}`: {expected}"));
            };
            if items.is_empty() {
                return Err(format!("empty range: `{path}` needs at least one value"));
            }
            let mut values = Vec::with_capacity(items.len());
            for item in items {
                let v = Value::from_toml(item)
                    .ok_or_else(|| format!("a value of `{path}` is not a scalar"))?;
                let v = match &default {
                    Some(kind) if path != "seed" => crate::levels::coerce(&v, kind, path)?,
                    _ => v,
                };
                if values.contains(&v) {
                    return Err(format!("value {v} of `{path}` appears twice"));
                }
                values.push(v);
            }
            Range::Choice(values)
        }
        toml::Value::Array(items) => {
            let num = |x: &toml::Value| match x {
                toml::Value::Integer(i) => Some(*i as f64),
                toml::Value::Float(f) => Some(*f),
                _ => None,
            };
            let (lo, hi) = match items.as_slice() {
                [a, b] => match (num(a), num(b)) {
                    (Some(a), Some(b)) => (a, b),
                    _ => return Err(format!("invalid range of `{path}`: {expected}")),
                },
                _ => return Err(format!("invalid range of `{path}`: {expected}")),
            };
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(format!(
                    "empty range [{lo}, {hi}] for `{path}`, expected [low, high] with low < high"
                ));
            }
            let whole = |x: f64| x.fract() == 0.0 && x.abs() < 9.0e15;
            match (path, &default) {
                ("seed", _) if whole(lo) && whole(hi) && lo >= 0.0 => Range::Seed {
                    low: lo as u64,
                    high: hi as u64,
                },
                ("seed", _) => {
                    return Err(format!(
                        "invalid seed range [{lo}, {hi}], expected non-negative integers"
                    ));
                }
                (_, Some(Value::Int(_))) if whole(lo) && whole(hi) => Range::Int {
                    low: lo as i64,
                    high: hi as i64,
                },
                (_, Some(Value::Int(_))) => {
                    return Err(format!(
                        "`{path}` is an integer in the scenario: its range needs whole ends"
                    ));
                }
                (_, Some(Value::Float(_))) => Range::Float { low: lo, high: hi },
                (_, other) => {
                    return Err(format!(
                        "`{path}` is {} in the scenario; give its choices as {{ values = [...] }}",
                        other.as_ref().map_or("missing", Value::kind)
                    ));
                }
            }
        }
        _ => return Err(format!("invalid range of `{path}`: {expected}")),
    };
    Ok(Dim {
        path: path.to_owned(),
        range,
        default,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conditions_parse_and_hold() {
        let c = parse_condition("vip_down == true").unwrap();
        assert_eq!((c.op, &c.value), (Op::Eq, &Value::Bool(true)));
        let c = parse_condition(" casualties>=2 ").unwrap();
        assert_eq!((c.metric.as_str(), c.op), ("casualties", Op::Ge));
        let m = BTreeMap::from([("casualties".to_string(), Value::Int(3))]);
        assert!(c.holds(&m));
        assert!(!parse_condition("casualties < 2").unwrap().holds(&m));
        let nan = BTreeMap::from([("t".to_string(), Value::Float(f64::NAN))]);
        assert!(!parse_condition("t != 1").unwrap().holds(&nan));
        assert!(parse_condition("success >= true").is_err());
        assert!(parse_condition("no operator").is_err());
        assert!(parse_condition("== 3").is_err());
    }
}
