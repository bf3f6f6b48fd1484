//! Patrolling instances and their TOML format (documented on [`Instance`]).

use std::ops::Range;
use std::path::Path;

use serde::{Deserialize, Serialize};
use toml::Spanned;

use super::PatrolError;
use super::chain::Track;
use crate::graph::{Graph, NodeId};

/// A patrolling security game: a graph, the targets an attacker may strike, the patrollers.
///
/// The TOML format:
///
/// ```toml
/// [graph]
/// edges = [[0, 1], [1, 2], [2, 3]]   # or: file = "roads.edges" (relative to this file)
/// nodes = 5                          # optional: vertex count (default: largest id + 1)
///
/// [[target]]
/// name = "depot"                     # optional
/// node = 0                           # a static target ...
/// value = 2.0                        # the attacker's gain if the attack succeeds (> 0)
/// deadline = 3                       # attack duration in steps (>= 1)
///
/// [[target]]
/// schedule = [3, 2, 2, 3]            # ... or a moving one: its vertex at steps 0, 1, 2, ...
/// value = 1.0                        #     (repeating); a walk in the graph
/// deadline = 2
///
/// [[patroller]]
/// name = "ugv"                       # optional
/// ```
///
/// Every error names the line and column it comes from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Instance {
    /// Where the patrollers move (one step = one edge, or staying).
    #[serde(skip)]
    pub graph: Graph,
    /// The attack options.
    pub targets: Vec<Target>,
    /// The defenders.
    pub patrollers: Vec<Patroller>,
}

/// A target: where it is, what it is worth, how long an attack on it takes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Target {
    /// A label for reports (defaults to `target<i>`).
    pub name: String,
    /// Where the target is over time.
    pub position: TargetPosition,
    /// The attacker's gain if an attack on it succeeds (positive).
    pub value: f64,
    /// The attack's duration in steps: it fails if the patroller stands on the target at one of
    /// the next `deadline` steps after it starts (at least 1).
    pub deadline: u32,
}

/// Where a target is.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub enum TargetPosition {
    /// Always at this vertex.
    Static(NodeId),
    /// A moving target (a convoy): at step `i` it is at `schedule[i % schedule.len()]`, and
    /// consecutive entries (cyclically) are equal or adjacent; never empty.
    Schedule(Vec<NodeId>),
}

/// A patroller.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Patroller {
    /// A label for reports (defaults to `patroller<i>`).
    pub name: String,
}

impl Instance {
    /// Builds and validates an instance.
    ///
    /// # Errors
    /// [`PatrolError::InvalidInstance`] for an empty graph, no targets or patrollers, a vertex
    /// outside the graph, a schedule that is not a walk, a non-positive or non-finite value, or
    /// a zero deadline.
    pub fn new(
        graph: Graph,
        targets: Vec<Target>,
        patrollers: Vec<Patroller>,
    ) -> Result<Instance, PatrolError> {
        let instance = Instance {
            graph,
            targets,
            patrollers,
        };
        instance.validate()?;
        Ok(instance)
    }

    /// Parses the TOML format shown on [`Instance`]. A `graph.file` is rejected here
    /// (there is no directory to resolve it against): use [`Instance::load`].
    ///
    /// # Errors
    /// [`PatrolError::Parse`] with the line and column of the problem.
    pub fn from_toml_str(text: &str) -> Result<Instance, PatrolError> {
        parse(text, None)
    }

    /// Reads a TOML instance file; `graph.file` is resolved against the file's directory.
    ///
    /// # Errors
    /// [`PatrolError::Io`] or [`PatrolError::Parse`].
    pub fn load(path: impl AsRef<Path>) -> Result<Instance, PatrolError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| PatrolError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        parse(&text, Some(path.parent().unwrap_or(Path::new("."))))
    }

    fn validate(&self) -> Result<(), PatrolError> {
        let invalid = |message: String| Err(PatrolError::InvalidInstance(message));
        let n = self.graph.node_count();
        if n == 0 {
            return invalid("the graph has no vertices".into());
        }
        if self.targets.is_empty() {
            return invalid("there are no targets".into());
        }
        if self.patrollers.is_empty() {
            return invalid("there are no patrollers".into());
        }
        for target in &self.targets {
            let name = &target.name;
            if let Err(message) = check_target(&self.graph, target) {
                return invalid(format!("target {name}: {message}"));
            }
        }
        Ok(())
    }

    /// The schedule period: the least common multiple of the schedules' lengths (1 when every
    /// target is static).
    ///
    /// # Errors
    /// [`PatrolError::Unsupported`] if it exceeds [`MAX_PERIOD`].
    pub fn period(&self) -> Result<usize, PatrolError> {
        let mut period = 1usize;
        for target in &self.targets {
            if let TargetPosition::Schedule(nodes) = &target.position {
                period = lcm(period, nodes.len());
                if period > MAX_PERIOD {
                    return Err(PatrolError::Unsupported(format!(
                        "the schedules' common period exceeds {MAX_PERIOD} steps"
                    )));
                }
            }
        }
        Ok(period)
    }

    /// The period and `(vertex at each phase, deadline, value)` of every target.
    pub(crate) fn timeline(&self) -> Result<(usize, Vec<Track>), PatrolError> {
        self.validate()?;
        let period = self.period()?;
        let targets = self
            .targets
            .iter()
            .map(|t| {
                let nodes = (0..period)
                    .map(|phase| t.position.at(phase).unwrap_or(0))
                    .collect();
                (nodes, t.deadline as usize, t.value)
            })
            .collect();
        Ok((period, targets))
    }
}

/// The longest common schedule period handled (the product state space grows with it).
pub const MAX_PERIOD: usize = 1024;

fn lcm(a: usize, b: usize) -> usize {
    let (mut x, mut y) = (a, b);
    while y != 0 {
        (x, y) = (y, x % y);
    }
    a / x.max(1) * b
}

impl TargetPosition {
    /// The target's vertex at step `step` (schedules repeat); `None` for an empty schedule.
    pub fn at(&self, step: usize) -> Option<NodeId> {
        match self {
            TargetPosition::Static(v) => Some(*v),
            TargetPosition::Schedule(nodes) => nodes.get(step % nodes.len().max(1)).copied(),
        }
    }
}

fn check_target(graph: &Graph, target: &Target) -> Result<(), String> {
    let n = graph.node_count();
    match &target.position {
        TargetPosition::Static(v) if *v >= n => {
            return Err(format!("vertex {v} is not in the graph (0..{n})"));
        }
        TargetPosition::Static(_) => {}
        TargetPosition::Schedule(nodes) => check_schedule(graph, nodes)?,
    }
    if !(target.value.is_finite() && target.value > 0.0) {
        return Err(format!("value {} is not a positive number", target.value));
    }
    if target.deadline == 0 {
        return Err("deadline must be at least 1 step".into());
    }
    Ok(())
}

fn check_schedule(graph: &Graph, nodes: &[NodeId]) -> Result<(), String> {
    let n = graph.node_count();
    if nodes.is_empty() {
        return Err("the schedule is empty".into());
    }
    if let Some(v) = nodes.iter().find(|&&v| v >= n) {
        return Err(format!("schedule vertex {v} is not in the graph (0..{n})"));
    }
    let wrap = nodes
        .last()
        .copied()
        .into_iter()
        .chain(nodes.iter().copied());
    for (a, b) in wrap.clone().zip(wrap.skip(1)) {
        if a != b && !graph.has_edge(a, b) {
            return Err(format!(
                "the schedule jumps from {a} to {b}, which are not adjacent"
            ));
        }
    }
    Ok(())
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawInstance {
    graph: Spanned<RawGraph>,
    #[serde(default)]
    target: Vec<Spanned<RawTarget>>,
    #[serde(default)]
    patroller: Vec<Spanned<RawPatroller>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGraph {
    nodes: Option<Spanned<usize>>,
    edges: Option<Vec<Spanned<[NodeId; 2]>>>,
    file: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTarget {
    name: Option<String>,
    node: Option<Spanned<NodeId>>,
    schedule: Option<Spanned<Vec<NodeId>>>,
    value: Spanned<f64>,
    deadline: Spanned<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPatroller {
    name: Option<String>,
}

/// 1-based (line, column) of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

fn error_at(text: &str, span: Range<usize>, message: impl Into<String>) -> PatrolError {
    let (line, column) = line_column(text, span.start);
    PatrolError::Parse {
        line,
        column,
        message: message.into(),
    }
}

fn parse(text: &str, base: Option<&Path>) -> Result<Instance, PatrolError> {
    let raw: RawInstance = toml::from_str(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        error_at(text, span, e.message().trim())
    })?;
    let graph_span = raw.graph.span();
    let raw_graph = raw.graph.into_inner();
    let graph = match (&raw_graph.edges, &raw_graph.file) {
        (Some(_), Some(file)) => {
            return Err(error_at(
                text,
                file.span(),
                "give either `edges` or `file`, not both",
            ));
        }
        (None, None) => {
            return Err(error_at(
                text,
                graph_span,
                "the graph needs `edges` or `file`",
            ));
        }
        (Some(edges), None) => {
            let mut n = edges
                .iter()
                .map(|e| e.get_ref()[0].max(e.get_ref()[1]) + 1)
                .max();
            if let Some(nodes) = &raw_graph.nodes {
                let declared = *nodes.get_ref();
                if let Some(e) = edges
                    .iter()
                    .find(|e| e.get_ref().iter().any(|&v| v >= declared))
                {
                    return Err(error_at(
                        text,
                        e.span(),
                        format!("edge names a vertex outside 0..{declared}"),
                    ));
                }
                n = Some(declared);
            }
            let pairs: Vec<_> = edges
                .iter()
                .map(|e| (e.get_ref()[0], e.get_ref()[1]))
                .collect();
            Graph::from_edges(n.unwrap_or(0), &pairs)
                .map_err(|e| error_at(text, graph_span.clone(), e.to_string()))?
        }
        (None, Some(file)) => {
            let Some(base) = base else {
                return Err(error_at(
                    text,
                    file.span(),
                    "`graph.file` needs a directory to resolve against: load the instance from a file",
                ));
            };
            let path = base.join(file.get_ref());
            let mut graph = Graph::load(&path)
                .map_err(|e| error_at(text, file.span(), format!("{}: {e}", path.display())))?;
            if let Some(nodes) = &raw_graph.nodes {
                let declared = *nodes.get_ref();
                if declared < graph.node_count() {
                    return Err(error_at(
                        text,
                        nodes.span(),
                        format!("the file has {} vertices", graph.node_count()),
                    ));
                }
                let edges: Vec<_> = graph.edges().collect();
                graph = Graph::from_edges(declared, &edges)
                    .map_err(|e| error_at(text, nodes.span(), e.to_string()))?;
            }
            graph
        }
    };
    if graph.node_count() == 0 {
        return Err(error_at(text, graph_span, "the graph has no vertices"));
    }
    let mut targets = Vec::with_capacity(raw.target.len());
    for (i, spanned) in raw.target.into_iter().enumerate() {
        let span = spanned.span();
        let raw_target = spanned.into_inner();
        let position = match (raw_target.node, raw_target.schedule) {
            (Some(node), None) => {
                if *node.get_ref() >= graph.node_count() {
                    return Err(error_at(
                        text,
                        node.span(),
                        format!(
                            "vertex {} is not in the graph (0..{})",
                            node.get_ref(),
                            graph.node_count()
                        ),
                    ));
                }
                TargetPosition::Static(node.into_inner())
            }
            (None, Some(schedule)) => {
                check_schedule(&graph, schedule.get_ref())
                    .map_err(|m| error_at(text, schedule.span(), m))?;
                TargetPosition::Schedule(schedule.into_inner())
            }
            (Some(node), Some(_)) => {
                return Err(error_at(
                    text,
                    node.span(),
                    "give either `node` or `schedule`, not both",
                ));
            }
            (None, None) => {
                return Err(error_at(text, span, "a target needs `node` or `schedule`"));
            }
        };
        let value = *raw_target.value.get_ref();
        if !(value.is_finite() && value > 0.0) {
            return Err(error_at(
                text,
                raw_target.value.span(),
                format!("value {value} is not a positive number"),
            ));
        }
        if *raw_target.deadline.get_ref() == 0 {
            return Err(error_at(
                text,
                raw_target.deadline.span(),
                "deadline must be at least 1 step",
            ));
        }
        targets.push(Target {
            name: raw_target.name.unwrap_or_else(|| format!("target{i}")),
            position,
            value,
            deadline: raw_target.deadline.into_inner(),
        });
    }
    if targets.is_empty() {
        return Err(error_at(
            text,
            0..0,
            "there are no targets (add a [[target]] table)",
        ));
    }
    let patrollers: Vec<Patroller> = raw
        .patroller
        .into_iter()
        .enumerate()
        .map(|(i, p)| Patroller {
            name: p
                .into_inner()
                .name
                .unwrap_or_else(|| format!("patroller{i}")),
        })
        .collect();
    if patrollers.is_empty() {
        return Err(error_at(
            text,
            0..0,
            "there are no patrollers (add a [[patroller]] table)",
        ));
    }
    Instance::new(graph, targets, patrollers)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
[graph]
edges = [[0, 1], [1, 2]]

[[target]]
node = 0
value = 1
deadline = 2

[[target]]
name = "convoy"
schedule = [2, 1, 1, 2]
value = 2.5
deadline = 3

[[patroller]]
"#;

    #[test]
    fn parses_a_good_instance() {
        let instance = Instance::from_toml_str(GOOD).unwrap();
        assert_eq!(instance.graph.node_count(), 3);
        assert_eq!(instance.targets[0].position, TargetPosition::Static(0));
        assert_eq!(instance.targets[0].name, "target0");
        assert_eq!(
            instance.targets[1].position,
            TargetPosition::Schedule(vec![2, 1, 1, 2])
        );
        assert_eq!(instance.patrollers[0].name, "patroller0");
        assert_eq!(instance.period().unwrap(), 4);
        assert_eq!(instance.targets[1].position.at(5), Some(1));
    }

    fn where_(text: &str) -> (usize, usize) {
        match Instance::from_toml_str(text) {
            Err(PatrolError::Parse { line, column, .. }) => (line, column),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    #[test]
    fn errors_point_at_the_culprit() {
        // A vertex outside the graph: line 5, at the value.
        assert_eq!(where_(&GOOD.replace("node = 0", "node = 7")), (6, 8));
        // A schedule that jumps.
        assert_eq!(where_(&GOOD.replace("[2, 1, 1, 2]", "[2, 0]")), (12, 12));
        // A zero deadline.
        assert_eq!(
            where_(&GOOD.replacen("deadline = 2", "deadline = 0", 1)),
            (8, 12)
        );
        // A negative value.
        assert_eq!(where_(&GOOD.replacen("value = 1", "value = -1", 1)), (7, 9));
        // An unknown key.
        assert_eq!(where_(&GOOD.replace("name = \"convoy\"", "nmae = 1")).0, 11);
        // Broken syntax.
        assert_eq!(
            where_(&GOOD.replacen("deadline = 2", "deadline = = 2", 1)).0,
            8
        );
        // No file base.
        assert_eq!(where_("[graph]\nfile = \"x.edges\"\n").0, 2);
    }
}
