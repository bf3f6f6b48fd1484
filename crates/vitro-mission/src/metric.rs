//! One value of a run's report, and a mission's metrics declared once as a table.

use serde::Serialize;
use std::collections::BTreeMap;

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

    /// The value as a number for plots (`true` is 1), `None` for a text or a missing value.
    pub fn number(&self) -> Option<f64> {
        match self {
            Metric::Bool(b) => Some(if *b { 1.0 } else { 0.0 }),
            Metric::Int(n) => Some(*n as f64),
            Metric::Float(x) => Some(*x),
            Metric::Text(_) | Metric::Missing => None,
        }
    }
}

impl From<Option<f64>> for Metric {
    fn from(v: Option<f64>) -> Metric {
        v.map_or(Metric::Missing, Metric::Float)
    }
}

/// A field of a metrics struct as a [`Metric`]: what [`metric_table!`](crate::metric_table)
/// turns each named field into.
pub trait ToMetric {
    /// The value as a metric.
    fn to_metric(&self) -> Metric;
}

impl ToMetric for bool {
    fn to_metric(&self) -> Metric {
        Metric::Bool(*self)
    }
}

impl ToMetric for f64 {
    fn to_metric(&self) -> Metric {
        Metric::Float(*self)
    }
}

impl ToMetric for Option<f64> {
    fn to_metric(&self) -> Metric {
        (*self).into()
    }
}

impl ToMetric for String {
    fn to_metric(&self) -> Metric {
        Metric::Text(self.clone())
    }
}

impl ToMetric for u64 {
    fn to_metric(&self) -> Metric {
        Metric::count(*self)
    }
}

impl ToMetric for u32 {
    fn to_metric(&self) -> Metric {
        Metric::count(u64::from(*self))
    }
}

impl ToMetric for usize {
    fn to_metric(&self) -> Metric {
        Metric::count(u64::try_from(*self).unwrap_or(u64::MAX))
    }
}

/// A mission's metrics, declared once as a table of named values: the table gives the batch
/// summary's columns ([`names`](Self::names), in its order), the values of
/// [`Run::metrics`](crate::Run::metrics), the keys of `vitro run --json`
/// ([`json`](Self::json)) and the plotted numbers of each frame ([`numbers`](Self::numbers)).
///
/// ```
/// use vitro_mission::{Metric, MetricTable, metric_table};
///
/// #[derive(Default)]
/// struct Tally {
///     found: u32,
///     mean_time_s: Option<f64>,
///     done: bool,
/// }
///
/// impl MetricTable for Tally {
///     fn table(&self) -> Vec<(&'static str, Metric)> {
///         metric_table!(self; found, mean_time_s, done)
///     }
/// }
///
/// assert_eq!(Tally::names(), ["found", "mean_time_s", "done"]);
/// let t = Tally { found: 3, mean_time_s: None, done: true };
/// assert_eq!(t.json()["found"], 3);
/// assert!(t.json()["mean_time_s"].is_null());
/// assert_eq!(t.numbers()["done"], 1.0);
/// assert!(!t.numbers().contains_key("mean_time_s"));
/// ```
pub trait MetricTable: Default {
    /// The metrics as named values, in summary-column order.
    fn table(&self) -> Vec<(&'static str, Metric)>;

    /// The names of the table, in its order.
    fn names() -> Vec<&'static str> {
        Self::default()
            .table()
            .into_iter()
            .map(|(k, _)| k)
            .collect()
    }

    /// The table as a JSON object.
    fn json(&self) -> serde_json::Map<String, serde_json::Value> {
        (self.table().into_iter())
            .map(|(k, v)| (k.to_owned(), serde_json::to_value(v).unwrap_or_default()))
            .collect()
    }

    /// The numeric values by name (texts and missing values left out), for a frame.
    fn numbers(&self) -> BTreeMap<String, f64> {
        (self.table().into_iter())
            .filter_map(|(k, v)| Some((k.to_owned(), v.number()?)))
            .collect()
    }
}

/// The table of a metrics struct's fields, each named as the field and turned into a
/// [`Metric`] by [`ToMetric`]: `metric_table!(m; success, casualties, time_s)`.
#[macro_export]
macro_rules! metric_table {
    ($m:expr; $($field:ident),* $(,)?) => {
        vec![$((stringify!($field), $crate::ToMetric::to_metric(&$m.$field)),)*]
    };
}
