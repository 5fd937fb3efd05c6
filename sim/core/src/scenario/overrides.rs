//! `--set key.path=value`: change any field of a scenario from the command line.

use super::ScenarioError;

/// Applies one `dotted.path=value` to a parsed scenario table. The value is read as TOML
/// (`0.7`, `true`, `"text"`, `[5, 15]`); a bare word that is not TOML is taken as a string.
/// Tables on the path are created as needed; the field's validity is checked later, when
/// the scenario is validated.
pub fn apply_override(root: &mut toml::Table, assignment: &str) -> Result<(), ScenarioError> {
    let err = |message: String| ScenarioError::Override {
        assignment: assignment.to_string(),
        message,
    };
    let (path, value_text) = assignment
        .split_once('=')
        .ok_or_else(|| err("expected KEY.PATH=VALUE".into()))?;
    let path = path.trim();
    let keys: Vec<&str> = path.split('.').collect();
    if keys
        .iter()
        .any(|k| k.is_empty() || !k.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
    {
        return Err(err(format!(
            "`{path}` is not a dotted field path like tracker.lambda"
        )));
    }
    let value_text = value_text.trim();
    let digits = value_text.strip_prefix(['+', '-']).unwrap_or(value_text);
    let integer = !digits.is_empty() && digits.bytes().all(|c| c.is_ascii_digit());
    if integer && !digits.starts_with('0') && value_text.parse::<i64>().is_err() {
        // Not taken for a string: an integer beyond TOML's.
        return Err(err(format!(
            "{value_text} is beyond TOML's integers ({} to {})",
            i64::MIN,
            i64::MAX
        )));
    }
    let value = parse_value(value_text);
    let (last, parents) = keys.split_last().expect("split gives at least one key");
    let mut table = root;
    let mut depth = 0;
    while depth < parents.len() {
        let key = parents[depth];
        // An index into a list the file does not have: there is no item to change.
        if !table.contains_key(key) {
            if let Some(index) = keys.get(depth + 1).and_then(|k| k.parse::<usize>().ok()) {
                return Err(err(format!(
                    "`{}` has no items, so no item {index}: write the list in the file to \
                     change its items",
                    keys[..=depth].join(".")
                )));
            }
        }
        let entry = table
            .entry(key.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        // An array of tables is entered by a 0-based index: `environment.distractors.0.x`.
        let entry = match entry {
            toml::Value::Array(items) => {
                let Some(index) = keys.get(depth + 1).and_then(|k| k.parse::<usize>().ok()) else {
                    return Err(err(format!(
                        "`{}` is a list: name an item by its index, as in `{}.0.{}`",
                        keys[..=depth].join("."),
                        keys[..=depth].join("."),
                        keys[depth + 1]
                    )));
                };
                let len = items.len();
                depth += 1;
                if depth == parents.len() {
                    return Err(err(format!(
                        "`{}` is an item of a list: set one of its fields",
                        keys[..=depth].join(".")
                    )));
                }
                items.get_mut(index).ok_or_else(|| {
                    err(format!(
                        "`{}` has {len} item(s), so no item {index}",
                        keys[..depth].join(".")
                    ))
                })?
            }
            other => other,
        };
        table = match entry {
            toml::Value::Table(t) => t,
            _ => {
                return Err(err(format!(
                    "`{}` is a value, not a table, so it has no field `{}`",
                    keys[..=depth].join("."),
                    keys[depth + 1]
                )))
            }
        };
        depth += 1;
    }
    table.insert(last.to_string(), value);
    Ok(())
}

pub(super) fn parse_value(text: &str) -> toml::Value {
    let wrapped = format!("v = {text}");
    match toml::from_str::<toml::Table>(&wrapped) {
        Ok(mut t) => t.remove("v").expect("key v"),
        Err(_) => toml::Value::String(text.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_integer_beyond_tomls_is_refused_not_taken_for_a_string() {
        let mut root = toml::Table::new();
        apply_override(&mut root, "seed=9223372036854775807").unwrap();
        assert_eq!(root["seed"], toml::Value::Integer(i64::MAX));
        for text in ["18446744073709551615", "-9223372036854775809"] {
            let e = apply_override(&mut root, &format!("seed={text}")).unwrap_err();
            assert!(e.to_string().contains("beyond TOML's integers"), "{e}");
        }
        // Still a string: a word that only starts with digits.
        apply_override(&mut root, "name=2fast").unwrap();
        assert_eq!(root["name"], toml::Value::String("2fast".into()));
    }
}
