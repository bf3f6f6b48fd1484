//! The tidy result tables, built from the journal's records sorted by run:
//!
//! - `summary`: one row per run: `run, point, replicate, seed`, one column per varied
//!   parameter (named by its dotted key), one per kept metric, `status, error, wall_s`;
//! - `series`: one row per sample: `run, t_s`, one column per kept series metric.
//!
//! Each is written as CSV and, with the `parquet` feature, as Parquet (typed columns:
//! unsigned ids and seeds, integers, floats, booleans, strings; empty cells are nulls).

use crate::journal::RunRecord;
use crate::manifest::Manifest;
use crate::value::Value;

/// A column's type, inferred from its values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Unsigned 64-bit (ids, seeds).
    UInt,
    /// Signed 64-bit integers.
    Int,
    /// 64-bit floats (integers mixed with floats become floats).
    Float,
    /// Booleans.
    Bool,
    /// Strings (anything mixed).
    Text,
}

/// The cells of a column.
#[derive(Clone, Debug, PartialEq)]
pub enum Cells {
    /// Unsigned integers, never null.
    UInt(Vec<u64>),
    /// Values of one inferred kind; `None` is an empty cell.
    Values(Kind, Vec<Option<Value>>),
}

/// A named column.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// Header.
    pub name: String,
    /// Cells, one per row.
    pub cells: Cells,
}

impl Column {
    pub(crate) fn uint(name: &str, cells: Vec<u64>) -> Self {
        Column {
            name: name.to_owned(),
            cells: Cells::UInt(cells),
        }
    }

    pub(crate) fn values(name: &str, cells: Vec<Option<Value>>) -> Self {
        let kind = infer(&cells);
        let cells = cells
            .into_iter()
            .map(|c| match (kind, c) {
                (Kind::Float, Some(Value::Int(i))) => Some(Value::Float(i as f64)),
                (Kind::Text, Some(v @ Value::Text(_))) => Some(v),
                (Kind::Text, Some(v)) => Some(Value::Text(v.to_string())),
                (_, c) => c,
            })
            .collect();
        Column {
            name: name.to_owned(),
            cells: Cells::Values(kind, cells),
        }
    }

    /// The column's type.
    pub fn kind(&self) -> Kind {
        match &self.cells {
            Cells::UInt(_) => Kind::UInt,
            Cells::Values(k, _) => *k,
        }
    }

    /// The cell of row `i` as CSV text (empty for null).
    pub fn text(&self, i: usize) -> String {
        match &self.cells {
            Cells::UInt(v) => v[i].to_string(),
            Cells::Values(_, v) => v[i].as_ref().map_or_else(String::new, Value::to_string),
        }
    }
}

fn infer(cells: &[Option<Value>]) -> Kind {
    let mut kind: Option<Kind> = None;
    for v in cells.iter().flatten() {
        let k = match v {
            Value::Int(_) => Kind::Int,
            Value::Float(_) => Kind::Float,
            Value::Bool(_) => Kind::Bool,
            Value::Text(_) => Kind::Text,
        };
        kind = Some(match (kind, k) {
            (None, k) => k,
            (Some(a), b) if a == b => a,
            (Some(Kind::Int | Kind::Float), Kind::Int | Kind::Float) => Kind::Float,
            _ => Kind::Text,
        });
    }
    kind.unwrap_or(Kind::Float)
}

/// A table: named columns of equal length.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// The columns.
    pub columns: Vec<Column>,
    /// Number of rows.
    pub rows: usize,
}

impl Table {
    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.name == name)
    }

    /// The table as CSV (a header line, then one line per row).
    pub fn to_csv(&self) -> Result<Vec<u8>, csv::Error> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(self.columns.iter().map(|c| c.name.as_str()))?;
        for i in 0..self.rows {
            w.write_record(self.columns.iter().map(|c| c.text(i)))?;
        }
        w.into_inner().map_err(|e| e.into_error().into())
    }
}

/// The summary table of `records` (sorted by run).
pub fn summary(manifest: &Manifest, records: &[RunRecord]) -> Table {
    let mut columns = vec![
        Column::uint("run", records.iter().map(|r| r.run).collect()),
        Column::uint("point", records.iter().map(|r| r.point).collect()),
        Column::uint(
            "replicate",
            records.iter().map(|r| u64::from(r.replicate)).collect(),
        ),
        Column::uint("seed", records.iter().map(|r| r.seed).collect()),
    ];
    for p in &manifest.parameters {
        let cells = records.iter().map(|r| r.params.get(&p.path).cloned());
        columns.push(Column::values(&p.path, cells.collect()));
    }
    for m in &manifest.keep.metrics {
        let cells = records.iter().map(|r| r.metrics.get(m).cloned());
        columns.push(Column::values(m, cells.collect()));
    }
    let status = records.iter().map(|r| Some(r.status.as_str().into()));
    columns.push(Column::values("status", status.collect()));
    let error = records.iter().map(|r| r.error.clone().map(Value::Text));
    columns.push(Column {
        name: "error".into(),
        cells: Cells::Values(Kind::Text, error.collect()),
    });
    let wall = records.iter().map(|r| Some(Value::Float(r.wall_s)));
    columns.push(Column::values("wall_s", wall.collect()));
    Table {
        columns,
        rows: records.len(),
    }
}

/// The series table of `records` (sorted by run; samples in time order).
pub fn series(manifest: &Manifest, records: &[RunRecord]) -> Table {
    let rows: Vec<(u64, &crate::runner::SeriesRow)> = records
        .iter()
        .flat_map(|r| r.series.iter().map(move |s| (r.run, s)))
        .collect();
    let mut columns = vec![
        Column::uint("run", rows.iter().map(|(k, _)| *k).collect()),
        Column::values(
            "t_s",
            rows.iter()
                .map(|(_, s)| Some(Value::Float(s.t_s)))
                .collect(),
        ),
    ];
    for m in &manifest.keep.series {
        let cells = rows.iter().map(|(_, s)| s.values.get(m).cloned());
        columns.push(Column::values(m, cells.collect()));
    }
    Table {
        columns,
        rows: rows.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_inferred() {
        let c = Column::values(
            "x",
            vec![Some(Value::Int(1)), None, Some(Value::Float(0.5))],
        );
        assert_eq!(c.kind(), Kind::Float);
        assert_eq!(c.text(0), "1.0");
        assert_eq!(c.text(1), "");
        let c = Column::values("x", vec![Some(Value::Int(1)), Some("a".into())]);
        assert_eq!(c.kind(), Kind::Text);
        assert_eq!(c.text(0), "1");
        assert_eq!(Column::values("x", vec![None]).kind(), Kind::Float);
        let c = Column::values("b", vec![Some(Value::Bool(true))]);
        assert_eq!((c.kind(), c.text(0)), (Kind::Bool, "true".to_owned()));
    }

    #[test]
    fn csv_quotes_what_needs_it() {
        let t = Table {
            columns: vec![
                Column::uint("run", vec![0, 1]),
                Column::values("error", vec![Some("a, \"b\"".into()), None]),
            ],
            rows: 2,
        };
        let csv = String::from_utf8(t.to_csv().unwrap()).unwrap();
        assert_eq!(csv, "run,error\n0,\"a, \"\"b\"\"\"\n1,\n");
    }
}
