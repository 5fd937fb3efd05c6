//! The scenario format's JSON Schema, derived from the file types ([`ScenarioFile`] and what
//! it holds) with `schemars`: every table and field, with the documentation of its type (its
//! unit and range, where the doc says them), and `additionalProperties: false` wherever the
//! file refuses unknown keys. Editors that validate TOML against a JSON Schema (taplo, "Even
//! Better TOML") read it from a shipped scenario's first line,
//! `#:schema ./carfollow-scenario.schema.json`. `carfollow schema` prints it, and
//! `scenarios/carfollow-scenario.schema.json` is kept equal to it by a test.
//!
//! The schema says what a file may hold; `check` says more (ranges between fields, the
//! route, the target file), so a file the schema accepts can still be refused, never the
//! other way round.

use super::ScenarioFile;

/// The name of the schema file beside the shipped scenarios.
pub const SCHEMA_FILE_NAME: &str = "carfollow-scenario.schema.json";

/// The scenario format's JSON Schema (draft 2020-12), as pretty-printed JSON with a final
/// newline: the text of `scenarios/carfollow-scenario.schema.json`.
pub fn scenario_schema_json() -> String {
    let schema = schemars::schema_for!(ScenarioFile);
    let mut text = serde_json::to_string_pretty(&schema).expect("a schema serialises");
    text.push('\n');
    text
}
