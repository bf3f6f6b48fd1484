//! Dotted scenario keys (`channel.loss`, `entity.4.count`): what the scenario holds there,
//! and setting a value there.

use crate::value::Value;

/// The scalar at dotted `path` of the scenario (its kind decides how levels are coerced).
pub(crate) fn scenario_kind(scenario: &toml::Table, path: &str) -> Result<Value, String> {
    let mut table = scenario;
    let parts: Vec<&str> = path.split('.').collect();
    let Some((last, parents)) = parts.split_last() else {
        return Err("empty parameter path".into());
    };
    let mut i = 0;
    while i < parents.len() {
        match table.get(parents[i]) {
            Some(toml::Value::Table(t)) => {
                table = t;
                i += 1;
            }
            Some(toml::Value::Array(items)) => {
                // An array of tables (e.g. `[[entity]]`): the next part is its index.
                let at = parents.get(i + 1).and_then(|p| p.parse::<usize>().ok());
                match at.and_then(|k| items.get(k)) {
                    Some(toml::Value::Table(t)) => {
                        table = t;
                        i += 2;
                    }
                    _ => {
                        return Err(format!(
                            "`{0}` is an array of {1} tables: vary `{0}.<index>.<key>`, \
                             the index below {1}",
                            parts[..=i].join("."),
                            items.len(),
                        ));
                    }
                }
            }
            Some(_) => {
                return Err(format!(
                    "unknown scenario key `{path}`: `{}` is not a table",
                    parts[..=i].join(".")
                ));
            }
            None => return Err(unknown_key(path, &parts[..i], table)),
        }
    }
    match table.get(*last) {
        None => Err(unknown_key(path, parents, table)),
        Some(toml::Value::Table(_)) => Err(format!(
            "`{path}` is a table in the scenario; vary one of its keys, e.g. `{path}.<key>`"
        )),
        Some(v) => Value::from_toml(v).ok_or_else(|| {
            format!("`{path}` is not a number, a boolean or a string in the scenario")
        }),
    }
}

fn unknown_key(path: &str, parent: &[&str], table: &toml::Table) -> String {
    let prefix = if parent.is_empty() {
        String::new()
    } else {
        format!("{}.", parent.join("."))
    };
    let keys: Vec<String> = table.keys().map(|k| format!("{prefix}{k}")).collect();
    format!(
        "unknown scenario key `{path}` (the scenario must set a key to vary it); keys here: {}",
        keys.join(", ")
    )
}

/// Sets the value at dotted `path`, which [`scenario_kind`] found.
pub(crate) fn set_path(table: &mut toml::Table, path: &str, value: toml::Value) {
    let mut parts = path.split('.').peekable();
    let mut table = table;
    while let Some(part) = parts.next() {
        if parts.peek().is_none() {
            table.insert(part.to_owned(), value);
            return;
        }
        match table.get_mut(part) {
            Some(toml::Value::Table(t)) => table = t,
            Some(toml::Value::Array(items)) => {
                // An array of tables: the next part is the index.
                let at = parts.next().and_then(|p| p.parse::<usize>().ok());
                match at.and_then(|k| items.get_mut(k)) {
                    Some(toml::Value::Table(t)) => table = t,
                    _ => return,
                }
            }
            _ => return,
        }
    }
}

/// Sets the scenario key at dotted `path` (`channel.loss`, `entity.4.count`) to `value`, as
/// an experiment's parameter does: the scenario must already hold a scalar there.
///
/// ```
/// let mut s: toml::Table = toml::from_str("[channel]\nloss = 0.1\n").unwrap();
/// vitro_batch::set_scenario_key(&mut s, "channel.loss", toml::Value::Float(0.5)).unwrap();
/// assert_eq!(s["channel"]["loss"].as_float(), Some(0.5));
/// assert!(vitro_batch::set_scenario_key(&mut s, "channel.los", 1.into()).is_err());
/// ```
///
/// # Errors
/// Why the key cannot be set (unknown, a table, not a scalar), listing the keys there.
pub fn set_scenario_key(
    table: &mut toml::Table,
    path: &str,
    value: toml::Value,
) -> Result<(), String> {
    scenario_kind(table, path)?;
    set_path(table, path, value);
    Ok(())
}
