//! What an exported file carries besides the standard's elements: carfollow's own settings,
//! as root parameters named `carfollow.<field>` whose value is the field's TOML value
//! (`carfollow.camera.focal_length_mm = "16.0"`, `carfollow.tracker.mode = "\"robust\""`).
//!
//! The exporter computes them as the difference between the scenario and what the importer
//! reads from the file's elements alone ([`carried`]: both resolved, every default filled
//! in); the importer applies them to what it read, as `--set` applies its assignments
//! ([`apply`]). So a field is carried exactly when the elements do not say it as carfollow
//! reads them back, and the scenario imported is the scenario exported.

use super::super::error::OscError;
use super::super::xml::{child, children, Xml};
use serde_json::Value;
use std::path::Path;

/// The prefix of a carried parameter's name.
pub const CARRIED_PREFIX: &str = "carfollow.";

/// The fields the road file says (the route's shape and lanes), compared as the route
/// itself, never carried: a route given by `segments` and one given by `opendrive` are the
/// same route when their segments are.
const ROUTE_FIELDS: [&str; 6] = [
    "segments",
    "opendrive",
    "lanes",
    "lane_width_m",
    "lane_widths_m",
    "median_m",
];

/// One carried field: its dotted path and its value as TOML text.
#[derive(Clone, Debug, PartialEq)]
pub struct Carried {
    /// `camera.focal_length_mm`, `actors.0.start`, ...
    pub path: String,
    /// The value, TOML (`16.0`, `"robust"`, `[[0.0, 10.0]]`, `{ x = 1 }`).
    pub value: String,
}

/// The chase controller's fields that are not scenario fields: set from `[camera]`.
const FROM_THE_CAMERA: [&str; 3] = ["camera_mount", "pan_head", "half_fov_deg"];

/// Whether the field at `path` (keys from the root) of the scenario `root` is compared
/// elsewhere (the route, the target), or follows from other fields (the controller's view
/// of the camera; its speed mode, from `chase.speed_profile` where that is given).
fn excluded(path: &[String], root: &Value) -> bool {
    let manual = !is_null(root.pointer("/chase/speed_profile"));
    match path {
        [chase, controller, field]
            if manual
                && chase == "chase"
                && controller == "controller"
                && field == "speed_mode" =>
        {
            true
        }
        [route, field] if route == "route" => ROUTE_FIELDS.contains(&field.as_str()),
        [tracker, target] => tracker == "tracker" && target == "target",
        [chase, controller, field] => {
            chase == "chase"
                && controller == "controller"
                && FROM_THE_CAMERA.contains(&field.as_str())
        }
        _ => false,
    }
}

/// `v` (the value at `path`) without its excluded fields.
fn prune(v: &mut Value, path: &mut Vec<String>, root: &Value) {
    if let Value::Object(map) = v {
        map.retain(|k, _| {
            path.push(k.clone());
            let keep = !excluded(path, root);
            path.pop();
            keep
        });
        for (k, x) in map.iter_mut() {
            path.push(k.clone());
            prune(x, path, root);
            path.pop();
        }
    }
}

fn is_null(v: Option<&Value>) -> bool {
    v.is_none_or(Value::is_null)
}

/// The fields `original` (a scenario's resolved JSON) holds that `imported` (the resolved
/// JSON of what the importer reads of its file's elements) does not hold alike: a table the
/// imported one sets a field of that the original leaves unset is carried whole (a `--set`
/// cannot unset a field); other tables field by field; lists and values whole. `Err` names
/// a field whose value TOML cannot hold.
pub fn carried(original: &Value, imported: &Value) -> Result<Vec<Carried>, String> {
    let mut out = Vec::new();
    walk(original, imported, &mut Vec::new(), &mut out, original)?;
    Ok(out)
}

fn walk(
    original: &Value,
    imported: &Value,
    path: &mut Vec<String>,
    out: &mut Vec<Carried>,
    root: &Value,
) -> Result<(), String> {
    if original == imported || excluded(path, root) {
        return Ok(());
    }
    if let (Value::Object(o), Value::Object(i)) = (original, imported) {
        let keys: Vec<String> = o
            .keys()
            .chain(i.keys().filter(|k| !o.contains_key(*k)))
            .cloned()
            .collect();
        let unset: Vec<&String> = keys
            .iter()
            .filter(|k| {
                path.push((*k).clone());
                let unset = !excluded(path, root) && is_null(o.get(*k)) && !is_null(i.get(*k));
                path.pop();
                unset
            })
            .collect();
        if let (true, Some(k)) = (path.is_empty(), unset.first()) {
            return Err(format!("`{k}` cannot be unset"));
        }
        if unset.is_empty() {
            for k in keys {
                let a = o.get(&k).unwrap_or(&Value::Null);
                let b = i.get(&k).unwrap_or(&Value::Null);
                path.push(k);
                walk(a, b, path, out, root)?;
                path.pop();
            }
            return Ok(());
        }
    }
    let mut value = original.clone();
    drop_nulls(&mut value);
    prune(&mut value, path, root);
    let toml_value =
        toml::Value::try_from(&value).map_err(|e| format!("`{}`: {e}", path.join(".")))?;
    out.push(Carried {
        path: path.join("."),
        value: toml_value.to_string(),
    });
    Ok(())
}

/// `v` without its null fields (TOML has no null: a field left out is unset).
fn drop_nulls(v: &mut Value) {
    match v {
        Value::Object(map) => {
            map.retain(|_, x| !x.is_null());
            map.values_mut().for_each(drop_nulls);
        }
        Value::Array(items) => items.iter_mut().for_each(drop_nulls),
        _ => {}
    }
}

/// The route whole, as `[route]`'s `segments` give it: carried when the road file cannot
/// give its segments back bit for bit (an arc whose radius and angle no pair of doubles
/// `curvature`, `length` reproduce as carfollow reads them), so that the file's road is
/// then the route to within a unit in the last place, and carfollow's the route exactly.
pub fn route(route: &sim_render::RouteSpec) -> Carried {
    use sim_render::{PRange, RouteSegment};
    use toml::Value as T;
    let floats = |v: &[f64]| T::Array(v.iter().map(|&x| T::Float(x)).collect());
    let segments = route
        .segments
        .iter()
        .map(|s| {
            let mut t = toml::Table::new();
            match *s {
                RouteSegment::Straight { length_m } => {
                    t.insert("straight_m".into(), T::Float(length_m));
                }
                RouteSegment::Arc {
                    radius_m,
                    angle_deg,
                } => {
                    t.insert("arc_radius_m".into(), T::Float(radius_m));
                    t.insert("arc_angle_deg".into(), T::Float(angle_deg));
                }
                RouteSegment::Spiral {
                    length_m,
                    curvature_start,
                    curvature_end,
                } => {
                    t.insert("spiral_m".into(), T::Float(length_m));
                    t.insert("curvature_start".into(), T::Float(curvature_start));
                    t.insert("curvature_end".into(), T::Float(curvature_end));
                }
                RouteSegment::Poly3 { length_m, v } => {
                    t.insert("poly3_m".into(), T::Float(length_m));
                    t.insert("poly3".into(), floats(&v));
                }
                RouteSegment::ParamPoly3 {
                    length_m,
                    u,
                    v,
                    p_range,
                } => {
                    t.insert("param_poly3_m".into(), T::Float(length_m));
                    t.insert("u".into(), floats(&u));
                    t.insert("v".into(), floats(&v));
                    let p = if p_range == PRange::Normalized {
                        "normalized"
                    } else {
                        "arc_length"
                    };
                    t.insert("p_range".into(), T::String(p.into()));
                }
            }
            T::Table(t)
        })
        .collect();
    let mut t = toml::Table::new();
    t.insert("lanes".into(), T::Integer(i64::from(route.lanes)));
    if route.lane_widths_m.is_empty() {
        t.insert("lane_width_m".into(), T::Float(route.lane_width_m));
    } else {
        t.insert("lane_widths_m".into(), floats(&route.lane_widths_m));
    }
    if route.median_m != 0.0 {
        t.insert("median_m".into(), T::Float(route.median_m));
    }
    t.insert("intersections_m".into(), floats(&route.intersections_m));
    t.insert("segments".into(), T::Array(segments));
    Carried {
        path: "route".into(),
        value: T::Table(t).to_string(),
    }
}

/// `path` relative to the folder `base` (`..` where they part).
pub fn relative(path: &Path, base: &Path) -> std::path::PathBuf {
    super::super::write::relative(path, base)
}

/// The JSON pointers at which two resolved scenarios differ, the route's fields and the
/// target's path left out (compared as the route and the target model).
pub fn differences(a: &Value, b: &Value) -> Vec<String> {
    let mut out = Vec::new();
    differ(a, b, &mut Vec::new(), &mut out, a);
    out
}

fn differ(a: &Value, b: &Value, path: &mut Vec<String>, out: &mut Vec<String>, root: &Value) {
    if a == b || excluded(path, root) {
        return;
    }
    if let (Value::Object(x), Value::Object(y)) = (a, b) {
        for k in x.keys().chain(y.keys().filter(|k| !x.contains_key(*k))) {
            path.push(k.clone());
            differ(
                x.get(k).unwrap_or(&Value::Null),
                y.get(k).unwrap_or(&Value::Null),
                path,
                out,
                root,
            );
            path.pop();
        }
        return;
    }
    out.push(format!("/{}", path.join("/")));
}

/// The scenario text `text` (what the importer made of the file's elements) with the
/// file's carried parameters applied, in the order declared (a `--param` given for one
/// stands in for its value). `tracker.target`, a path, is written relative to the file's
/// folder `dir`; it is made relative to `out_base`, the written scenario's folder, when it
/// names a file there. The text is returned as it was when nothing is carried.
pub fn apply(xml: &Xml, text: &str, dir: &Path, out_base: &Path) -> Result<String, OscError> {
    let root = xml.doc.root_element();
    let Some(decls) = child(root, "ParameterDeclarations") else {
        return Ok(text.to_string());
    };
    let mut assignments = Vec::new();
    for d in children(decls, "ParameterDeclaration") {
        let Some(name) = d.attribute("name") else {
            continue;
        };
        let Some(path) = name.strip_prefix(CARRIED_PREFIX) else {
            continue;
        };
        let mut value = xml.param_value(root, name)?;
        if path == "tracker.target" {
            let target = toml::from_str::<toml::Table>(&format!("v = {value}"))
                .ok()
                .and_then(|mut t| t.remove("v"));
            if let Some(toml::Value::String(target)) = target {
                if dir.join(&target).is_file() {
                    let rebased = super::super::write::relative(&dir.join(&target), out_base);
                    value = toml::Value::String(rebased.to_string_lossy().replace('\\', "/"))
                        .to_string();
                }
            }
        }
        assignments.push((d, format!("{path}={value}")));
    }
    if assignments.is_empty() {
        return Ok(text.to_string());
    }
    let mut table: toml::Table = toml::from_str(text).map_err(|e| OscError::File {
        path: xml.path.clone(),
        message: format!("the scenario read: {e}"),
    })?;
    for (node, assignment) in &assignments {
        crate::scenario::apply_override(&mut table, assignment)
            .map_err(|e| xml.at(*node, format!("<ParameterDeclaration>: {e}")))?;
    }
    let body = toml::to_string(&table).map_err(|e| OscError::File {
        path: xml.path.clone(),
        message: format!("cannot write the scenario: {e}"),
    })?;
    let header: String = text
        .lines()
        .take_while(|l| l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    Ok(format!(
        "{header}# With carfollow's own settings, which the file carries as {CARRIED_PREFIX}* parameters.\n{body}"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn only_what_differs_is_carried_and_unset_fields_carry_their_table() {
        let original = json!({
            "name": "x",
            "camera": { "focal_length_mm": 16.0, "pan": { "enabled": false } },
            "tracker": { "target": "a.toml", "mode": "robust" },
            "route": { "segments": [1], "intersections_m": [5.0] },
            "chase": { "controller": { "cruise_speed_mps": null, "lane_keeping": false } },
            "lead": { "events": [] },
        });
        let imported = json!({
            "name": "x",
            "camera": { "focal_length_mm": 8.0, "pan": { "enabled": false } },
            "tracker": { "target": "b.toml", "mode": "paper" },
            "route": { "opendrive": { "file": "x.xodr" }, "intersections_m": [] },
            "chase": { "controller": { "cruise_speed_mps": 10.0, "lane_keeping": true } },
            "lead": { "events": [{ "name": "e" }] },
        });
        let got = carried(&original, &imported).unwrap();
        let got: Vec<(String, String)> = got.into_iter().map(|c| (c.path, c.value)).collect();
        assert_eq!(
            got,
            vec![
                ("camera.focal_length_mm".into(), "16.0".into()),
                ("chase.controller".into(), "{ lane_keeping = false }".into()),
                ("lead.events".into(), "[]".into()),
                ("route.intersections_m".into(), "[5.0]".into()),
                ("tracker.mode".into(), "\"robust\"".into()),
            ]
        );
        assert!(differences(&original, &original).is_empty());
        assert_eq!(differences(&original, &imported).len(), 6);
    }
}
