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
