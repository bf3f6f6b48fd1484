//! One value of a run's report.

use serde::Serialize;

/// One value of a run's report: a summary column of a batch, a key of `vitro run --json`.
///
/// ```
/// use vitro_mission::Metric;
/// assert_eq!(serde_json::to_string(&Metric::Float(2.5)).unwrap(), "2.5");
/// assert_eq!(serde_json::to_string(&Metric::Missing).unwrap(), "null");
/// assert_eq!(Metric::from(Some(3.0)), Metric::Float(3.0));
/// assert_eq!(Metric::from(None::<f64>), Metric::Missing);
/// ```
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Metric {
    /// A yes or no.
    Bool(bool),
    /// A count.
    Int(i64),
    /// A measure.
    Float(f64),
    /// A text (e.g. a hash).
    Text(String),
    /// No value (e.g. the time of something that did not happen): `null` in JSON.
    Missing,
}

impl Metric {
    /// A count, saturating at `i64::MAX`.
    pub fn count(n: u64) -> Metric {
        Metric::Int(i64::try_from(n).unwrap_or(i64::MAX))
    }
}

impl From<Option<f64>> for Metric {
    fn from(v: Option<f64>) -> Metric {
        v.map_or(Metric::Missing, Metric::Float)
    }
}
