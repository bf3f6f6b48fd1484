//! The levels of a varied parameter: explicit lists and ranges as written in experiment
//! files, turned into values of the scenario key's own type.

use crate::value::Value;
use schemars::JsonSchema;
use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer};
use std::fmt;

/// Most levels one range may produce.
pub const MAX_LEVELS: u64 = 100_000;

/// The levels of one parameter: explicit values or a range.
#[derive(Clone, Debug, PartialEq)]
pub enum Levels {
    /// Explicit levels, in order.
    List(Vec<Value>),
    /// Evenly spaced levels from `start` to `stop` (included) by `step`.
    Range(RangeSpec),
}

/// `{ start, stop, step }`: integers give integer levels; floats are rounded to the decimals
/// written in `start` and `step`, so `0.0..=0.3 by 0.1` gives `0.3`, not `0.30000000000000004`.
#[derive(Clone, Debug, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RangeSpec {
    /// First level.
    pub start: Number,
    /// Last level (included when a whole number of steps away).
    pub stop: Number,
    /// Distance between levels (positive).
    pub step: Number,
}

/// A number as written: integer or float.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Number {
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
}

impl Number {
    fn get(self) -> f64 {
        match self {
            Number::Int(i) => i as f64,
            Number::Float(f) => f,
        }
    }
}

/// A level in the scenario key's own type: integers where the scenario has an integer
/// (whole floats accepted), floats where it has a float.
pub(crate) fn coerce(v: &Value, kind: &Value, path: &str) -> Result<Value, String> {
    match (kind, v) {
        (Value::Int(_), Value::Int(_))
        | (Value::Float(_), Value::Float(_))
        | (Value::Bool(_), Value::Bool(_))
        | (Value::Text(_), Value::Text(_)) => Ok(v.clone()),
        (Value::Int(_), Value::Float(f)) if f.fract() == 0.0 && f.abs() < 9.0e15 => {
            Ok(Value::Int(*f as i64))
        }
        (Value::Float(_), Value::Int(i)) => Ok(Value::Float(*i as f64)),
        _ => Err(format!(
            "level {v} of `{path}` is {}, but the scenario's value is {}",
            v.kind(),
            kind.kind()
        )),
    }
}

/// The levels of a range.
pub(crate) fn range_levels(r: &RangeSpec) -> Result<Vec<Value>, String> {
    if let (Number::Int(start), Number::Int(stop), Number::Int(step)) = (r.start, r.stop, r.step) {
        if step <= 0 || stop < start {
            return Err(format!(
                "invalid range {start}..={stop} by {step}, expected start <= stop and step > 0"
            ));
        }
        let n = (i128::from(stop) - i128::from(start)) / i128::from(step) + 1;
        if n > i128::from(MAX_LEVELS) {
            return Err(format!(
                "range has {n} levels, at most {MAX_LEVELS} allowed"
            ));
        }
        return Ok((0..n as i64)
            .map(|i| Value::Int(start + i * step))
            .collect());
    }
    let (start, stop, step) = (r.start.get(), r.stop.get(), r.step.get());
    if !(start.is_finite() && stop.is_finite() && step.is_finite() && step > 0.0 && stop >= start) {
        return Err(format!(
            "invalid range {start}..={stop} by {step}, expected start <= stop and step > 0"
        ));
    }
    let steps = ((stop - start) / step * (1.0 + 1e-12) + 1e-9).floor();
    if steps + 1.0 > MAX_LEVELS as f64 {
        return Err(format!(
            "range has too many levels, at most {MAX_LEVELS} allowed"
        ));
    }
    let decimals = decimals(start).max(decimals(step));
    let scale = 10f64.powi(decimals as i32);
    Ok((0..=steps as u64)
        .map(|i| {
            let x = start + i as f64 * step;
            Value::Float(if decimals < 15 {
                (x * scale).round() / scale
            } else {
                x
            })
        })
        .collect())
}

/// Digits after the decimal point in the shortest form of `x` (at most 15).
fn decimals(x: f64) -> usize {
    let s = format!("{x}");
    s.split_once('.').map_or(0, |(_, frac)| frac.len()).min(15)
}

impl<'de> Deserialize<'de> for Levels {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Levels;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a list of levels or a range { start, stop, step }")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Levels, A::Error> {
                let mut out = Vec::new();
                while let Some(v) = seq.next_element::<Value>()? {
                    out.push(v);
                }
                Ok(Levels::List(out))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Levels, A::Error> {
                RangeSpec::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(Levels::Range)
            }
        }
        d.deserialize_any(V)
    }
}

impl JsonSchema for Levels {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Levels".into()
    }
    fn json_schema(g: &mut schemars::SchemaGenerator) -> schemars::Schema {
        let value = g.subschema_for::<Value>();
        let range = g.subschema_for::<RangeSpec>();
        schemars::json_schema!({
            "description": "A list of levels, or a range { start, stop, step } (stop included).",
            "oneOf": [
                { "type": "array", "items": value, "minItems": 1 },
                range
            ]
        })
    }
}

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Number;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Number, E> {
                Ok(Number::Int(v))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Number, E> {
                i64::try_from(v)
                    .map(Number::Int)
                    .map_err(|_| E::custom("integer too large"))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Number, E> {
                Ok(Number::Float(v))
            }
        }
        d.deserialize_any(V)
    }
}

impl JsonSchema for Number {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Number".into()
    }
    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({ "type": "number" })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_ranges_have_clean_levels() {
        let r = RangeSpec {
            start: Number::Float(0.0),
            stop: Number::Float(1.0),
            step: Number::Float(0.1),
        };
        let levels = range_levels(&r).unwrap();
        assert_eq!(levels.len(), 11);
        assert_eq!(levels[3], Value::Float(0.3));
        assert_eq!(levels[10], Value::Float(1.0));
        let r = RangeSpec {
            start: Number::Float(0.05),
            stop: Number::Float(0.2),
            step: Number::Float(0.05),
        };
        assert_eq!(range_levels(&r).unwrap().len(), 4);
    }

    #[test]
    fn coercion_follows_the_scenario() {
        let int = Value::Int(0);
        assert_eq!(coerce(&Value::Float(3.0), &int, "k"), Ok(Value::Int(3)));
        assert!(coerce(&Value::Float(3.5), &int, "k").is_err());
        assert_eq!(
            coerce(&Value::Int(2), &Value::Float(0.0), "k"),
            Ok(Value::Float(2.0))
        );
        assert!(coerce(&Value::Bool(true), &Value::Text("a".into()), "k").is_err());
    }
}
