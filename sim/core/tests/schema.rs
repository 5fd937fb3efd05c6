//! The scenario format's JSON Schema: `scenarios/carfollow-scenario.schema.json` is the one
//! the scenario types give (`carfollow schema`), so an editor checks a file against the
//! format as it is; every shipped scenario names it on its first line, for taplo. (The
//! Python tests validate every shipped scenario against it, and an unknown key fails it.)
//! Run with `cargo test -p sim-core --test schema`; after changing a scenario type, write
//! the file again with `cargo run --release -- schema > scenarios/carfollow-scenario.schema.json`.

use std::path::Path;

fn scenarios_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

#[test]
fn the_committed_schema_is_the_one_the_types_give() {
    let path = scenarios_dir().join(sim_core::SCHEMA_FILE_NAME);
    let committed = std::fs::read_to_string(&path).unwrap();
    assert!(
        committed == sim_core::scenario_schema_json(),
        "{} is out of date: write it again with `cargo run --release -- schema > {}`",
        path.display(),
        path.display()
    );
    let schema: serde_json::Value = serde_json::from_str(&committed).unwrap();
    assert_eq!(schema["additionalProperties"], false);
    assert!(schema["properties"]["expect"].is_object());
}

#[test]
fn every_shipped_scenario_names_the_schema_on_its_first_line() {
    let line = format!("#:schema ./{}", sim_core::SCHEMA_FILE_NAME);
    for name in sim_core::shipped_scenarios() {
        let text = std::fs::read_to_string(scenarios_dir().join(format!("{name}.toml"))).unwrap();
        assert_eq!(text.lines().next(), Some(line.as_str()), "{name}");
    }
}

/// Every field of a table (not of an array of tables) with a range or a list of values in
/// the schema, with its dotted path: `(path, schema)`.
fn bounded_fields(schema: &serde_json::Value) -> Vec<(String, serde_json::Value)> {
    fn resolve<'a>(root: &'a serde_json::Value, s: &'a serde_json::Value) -> &'a serde_json::Value {
        match s["$ref"].as_str() {
            Some(r) => &root["$defs"][r.trim_start_matches("#/$defs/")],
            None => s,
        }
    }
    fn walk(
        root: &serde_json::Value,
        table: &serde_json::Value,
        prefix: &str,
        out: &mut Vec<(String, serde_json::Value)>,
    ) {
        let Some(props) = table["properties"].as_object() else {
            return;
        };
        for (name, field) in props {
            let path = format!("{prefix}{name}");
            // An optional table: `anyOf` of the table and null.
            let inner = field["anyOf"]
                .as_array()
                .and_then(|v| v.iter().find(|s| s["$ref"].is_string()))
                .unwrap_or(field);
            let inner = resolve(root, inner);
            if inner["properties"].is_object() {
                walk(root, inner, &format!("{path}."), out);
            } else if [
                "minimum",
                "maximum",
                "exclusiveMinimum",
                "exclusiveMaximum",
                "enum",
            ]
            .iter()
            .any(|k| !field[*k].is_null())
            {
                out.push((path, field.clone()));
            }
        }
    }
    let mut out = Vec::new();
    walk(schema, schema, "", &mut out);
    out
}

/// The schema's ranges and lists of values are validation's: a value just outside a range
/// is refused by `check` naming the field, and every value a list allows is accepted. (So
/// an editor never flags what `check` accepts, and says the range `check` will hold to.)
#[test]
fn the_schemas_ranges_are_validations() {
    let schema: serde_json::Value =
        serde_json::from_str(&sim_core::scenario_schema_json()).unwrap();
    let fields = bounded_fields(&schema);
    assert!(fields.len() >= 30, "{} bounded fields", fields.len());
    let refused = |path: &str, value: String| {
        let set = format!("{path}={value}");
        match sim_core::Plan::builtin(std::slice::from_ref(&set)) {
            Ok(_) => panic!("`--set {set}` is outside the schema's range but check accepts it"),
            Err(e) => assert!(e.to_string().contains(path), "`--set {set}`: {e}"),
        }
    };
    for (path, field) in &fields {
        let bound = |k: &str| field[k].as_f64();
        if let Some(max) = bound("maximum") {
            refused(path, format!("{:?}", max + 1e-6 * max.abs().max(1.0)));
        }
        if let Some(max) = bound("exclusiveMaximum") {
            refused(path, format!("{max:?}"));
        }
        if let Some(min) = bound("minimum") {
            refused(path, format!("{:?}", min - 1e-6 * min.abs().max(1.0)));
        }
        if let Some(min) = bound("exclusiveMinimum") {
            refused(path, format!("{min:?}"));
        }
        for value in field["enum"].as_array().into_iter().flatten() {
            if value.is_null() {
                continue;
            }
            let set = format!("{path}={value}");
            // A field that applies only with another one set.
            let with: &[&str] = match path.as_str() {
                "chase.speed_basis" => &["chase.speed_profile=[[0.0, 5.0]]"],
                _ => &[],
            };
            let sets: Vec<String> = with
                .iter()
                .map(|s| s.to_string())
                .chain([set.clone()])
                .collect();
            if let Err(e) = sim_core::Plan::builtin(&sets) {
                panic!("the schema allows `--set {set}` but check refuses it: {e}");
            }
        }
    }
}

/// The same for the fields of an actor (`[[actors]]`, an array of tables), set on the
/// shipped `cut-in`'s van: a value just outside a field's range is refused, naming the van,
/// and every kind and speed basis the schema lists is accepted. (An event's fields are the
/// vehicle crate's, whose tests refuse each of them by name.)
#[test]
fn the_schemas_ranges_of_an_actor_are_validations() {
    let schema: serde_json::Value =
        serde_json::from_str(&sim_core::scenario_schema_json()).unwrap();
    let item = &schema["$defs"]["ActorFile"];
    let start = &schema["$defs"]["StartFile"];
    let fields: Vec<(String, &serde_json::Value)> = [("", item), ("start.", start)]
        .into_iter()
        .flat_map(|(prefix, table)| {
            table["properties"]
                .as_object()
                .unwrap()
                .iter()
                .map(move |(name, field)| (format!("{prefix}{name}"), field))
        })
        .collect();
    let path = scenarios_dir().join("cut-in.toml");
    let plan = |sets: &[String]| sim_core::Plan::load(&path, sets).map(|_| ());
    let mut checked = 0;
    for (name, field) in &fields {
        let set = |value: String| format!("actors.0.{name}={value}");
        let bound = |k: &str| field[k].as_f64();
        let integer = field["type"] == "integer";
        let outside = [
            bound("maximum").map(|m| {
                if integer {
                    m + 1.0
                } else {
                    m + 1e-6 * m.abs().max(1.0)
                }
            }),
            bound("minimum").map(|m| {
                if integer {
                    m - 1.0
                } else {
                    m - 1e-6 * m.abs().max(1.0)
                }
            }),
        ];
        for value in outside.into_iter().flatten() {
            let value = if integer {
                format!("{}", value as i64)
            } else {
                format!("{value:?}")
            };
            match plan(&[set(value.clone())]) {
                Ok(()) => panic!(
                    "`--set {}` is outside the schema's range but check accepts it",
                    set(value)
                ),
                Err(e) => assert!(
                    e.to_string().contains("actors[0]"),
                    "`--set {}`: {e}",
                    set(value)
                ),
            }
            checked += 1;
        }
        for value in field["enum"].as_array().into_iter().flatten() {
            let sets = [set(value.to_string())];
            if let Err(e) = plan(&sets) {
                panic!(
                    "the schema allows `--set {}` but check refuses it: {e}",
                    sets[0]
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked} bounds checked");
}
