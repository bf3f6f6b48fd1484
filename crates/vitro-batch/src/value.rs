//! [`Value`]: one cell of a result table, a parameter level or a metric.

use serde::de::{self, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// A parameter level or a metric value: an integer, a float, a boolean or a text.
///
/// In JSON a float that is not finite is written `null` and read back as NaN, so a metric
/// that has no value in a run (a mean over nothing) survives the round trip as NaN.
///
/// ```
/// use vitro_batch::Value;
/// let v: Value = serde_json::from_str("0.5").unwrap();
/// assert_eq!(v, Value::Float(0.5));
/// assert_eq!(serde_json::from_str::<Value>("3").unwrap(), Value::Int(3));
/// assert_eq!(Value::Float(2.0).to_string(), "2.0");
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A boolean.
    Bool(bool),
    /// A signed integer.
    Int(i64),
    /// A float (NaN when the value is missing).
    Float(f64),
    /// A text.
    Text(String),
}

impl Value {
    /// The value as a float, if it is a number.
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Value::Int(i) => Some(i as f64),
            Value::Float(f) => Some(f),
            Value::Bool(_) | Value::Text(_) => None,
        }
    }

    /// The value as a TOML value, to write into a scenario.
    pub fn to_toml(&self) -> toml::Value {
        match self {
            Value::Bool(b) => toml::Value::Boolean(*b),
            Value::Int(i) => toml::Value::Integer(*i),
            Value::Float(f) => toml::Value::Float(*f),
            Value::Text(s) => toml::Value::String(s.clone()),
        }
    }

    /// A TOML scalar as a value; `None` for arrays, tables and dates.
    pub fn from_toml(v: &toml::Value) -> Option<Value> {
        Some(match v {
            toml::Value::Boolean(b) => Value::Bool(*b),
            toml::Value::Integer(i) => Value::Int(*i),
            toml::Value::Float(f) => Value::Float(*f),
            toml::Value::String(s) => Value::Text(s.clone()),
            toml::Value::Datetime(_) | toml::Value::Array(_) | toml::Value::Table(_) => {
                return None;
            }
        })
    }

    /// What kind of value it is, in words (for messages).
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Bool(_) => "a boolean",
            Value::Int(_) => "an integer",
            Value::Float(_) => "a float",
            Value::Text(_) => "a string",
        }
    }
}

impl fmt::Display for Value {
    /// Integers plainly, floats always with a decimal point or an exponent (`2.0`, `0.1`,
    /// `NaN`), booleans as `true`/`false`, texts as they are.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Bool(b) => write!(f, "{b}"),
            Value::Int(i) => write!(f, "{i}"),
            Value::Float(x) => write!(f, "{x:?}"),
            Value::Text(s) => f.write_str(s),
        }
    }
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Float(x)
    }
}
impl From<i64> for Value {
    fn from(i: i64) -> Self {
        Value::Int(i)
    }
}
impl From<bool> for Value {
    fn from(b: bool) -> Self {
        Value::Bool(b)
    }
}
impl From<&str> for Value {
    fn from(s: &str) -> Self {
        Value::Text(s.to_owned())
    }
}
impl From<String> for Value {
    fn from(s: String) -> Self {
        Value::Text(s)
    }
}

impl Serialize for Value {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Value::Bool(b) => s.serialize_bool(*b),
            Value::Int(i) => s.serialize_i64(*i),
            Value::Float(x) if x.is_finite() => s.serialize_f64(*x),
            Value::Float(_) => s.serialize_none(),
            Value::Text(t) => s.serialize_str(t),
        }
    }
}

impl<'de> Deserialize<'de> for Value {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ValueVisitor)
    }
}

struct ValueVisitor;

impl Visitor<'_> for ValueVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a number, a boolean or a string")
    }
    fn visit_bool<E: de::Error>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Value, E> {
        Ok(Value::Int(v))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Value, E> {
        i64::try_from(v)
            .map(Value::Int)
            .map_err(|_| E::custom(format!("integer {v} is too large (at most {})", i64::MAX)))
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Value, E> {
        Ok(Value::Float(v))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Value, E> {
        Ok(Value::Text(v.to_owned()))
    }
    fn visit_string<E: de::Error>(self, v: String) -> Result<Value, E> {
        Ok(Value::Text(v))
    }
    fn visit_unit<E: de::Error>(self) -> Result<Value, E> {
        Ok(Value::Float(f64::NAN))
    }
    fn visit_none<E: de::Error>(self) -> Result<Value, E> {
        Ok(Value::Float(f64::NAN))
    }
}

/// A schema for [`Value`]: any JSON scalar but null.
impl schemars::JsonSchema for Value {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Value".into()
    }
    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "description": "A number, a boolean or a string.",
            "type": ["number", "integer", "boolean", "string"]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_round_trip_keeps_kinds() {
        for v in [
            Value::Int(-3),
            Value::Float(2.0),
            Value::Float(0.1),
            Value::Bool(true),
            Value::Text("a,b".into()),
        ] {
            let s = serde_json::to_string(&v).unwrap();
            assert_eq!(serde_json::from_str::<Value>(&s).unwrap(), v, "{s}");
        }
    }

    #[test]
    fn non_finite_floats_become_nan() {
        let s = serde_json::to_string(&Value::Float(f64::INFINITY)).unwrap();
        assert_eq!(s, "null");
        let back: Value = serde_json::from_str(&s).unwrap();
        assert!(matches!(back, Value::Float(x) if x.is_nan()));
    }

    #[test]
    fn toml_scalars_convert() {
        let t: toml::Table = toml::from_str("a = 1\nb = 1.5\nc = 'x'\nd = [1]").unwrap();
        assert_eq!(Value::from_toml(&t["a"]), Some(Value::Int(1)));
        assert_eq!(Value::from_toml(&t["b"]), Some(Value::Float(1.5)));
        assert_eq!(Value::from_toml(&t["c"]), Some(Value::Text("x".into())));
        assert_eq!(Value::from_toml(&t["d"]), None);
        assert_eq!(Value::Int(4).to_toml(), toml::Value::Integer(4));
    }
}
