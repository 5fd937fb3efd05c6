//! Mutated traffic scenarios: whatever `check` accepts, `run` runs. Each case changes the
//! shipped traffic scenarios' actors, events, lanes and starts (to plausible values and to
//! nasty ones, and with event fields they do not use: relative speeds, time gaps between
//! axles), plans the result as `carfollow check` does, and runs every scenario that
//! planned for two seconds of the closed loop, which must neither fail nor panic (a trigger's
//! threshold set to a plausible number may fire in them). A refusal must be one line.
//!
//! `CARFOLLOW_TRAFFIC_CASES` sets the number of cases (500 by default).

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use sim_core::{ClosedLoop, Plan, Scenario};
use sim_render::Backend;
use std::path::Path;

fn cases() -> u32 {
    std::env::var("CARFOLLOW_TRAFFIC_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(500)
}

/// The shipped traffic scenarios, two seconds long.
fn shipped() -> Vec<toml::Table> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    [
        "cut-in",
        "cut-out",
        "next-lane-traffic",
        "slow-vehicle-ahead",
    ]
    .iter()
    .map(|name| {
        let text = std::fs::read_to_string(dir.join(format!("{name}.toml"))).unwrap();
        let mut t: toml::Table = toml::from_str(&text).unwrap();
        t.insert("duration_s".into(), toml::Value::Float(2.0));
        t
    })
    .collect()
}

/// Every leaf path under the traffic's fields (`actors.0.start.gap_m`, ...).
fn traffic_leaves(root: &toml::Value, prefix: &str, out: &mut Vec<String>) {
    match root {
        toml::Value::Table(t) => {
            for (k, v) in t {
                let p = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                traffic_leaves(v, &p, out);
            }
        }
        toml::Value::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                traffic_leaves(v, &format!("{prefix}.{i}"), out);
            }
        }
        _ => {
            let traffic = [
                "actors",
                "lead.events",
                "lead.lane",
                "lead.start_m",
                "route.lanes",
            ];
            if traffic.iter().any(|t| prefix.starts_with(t)) {
                out.push(prefix.to_string());
            }
        }
    }
}

/// Every event's `action` and `trigger` table (`actors.0.events.1.action`, ...).
fn event_tables(root: &toml::Value, prefix: &str, out: &mut Vec<String>) {
    let children: Vec<(String, &toml::Value)> = match root {
        toml::Value::Table(t) => t.iter().map(|(k, v)| (k.clone(), v)).collect(),
        toml::Value::Array(a) => a
            .iter()
            .enumerate()
            .map(|(i, v)| (i.to_string(), v))
            .collect(),
        _ => return,
    };
    for (k, v) in children {
        let p = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        if (k == "action" || k == "trigger") && p.contains("events") && v.is_table() {
            out.push(p.clone());
        }
        event_tables(v, &p, out);
    }
}

/// A field an event's action or trigger may be given that the shipped scenarios do not
/// use (relative speeds, time gaps between axles), with a value: plausible or not.
fn extra_field(choice: usize, x: f64) -> (&'static str, toml::Value) {
    let name = |n: &str| toml::Value::String(n.into());
    match choice % 8 {
        0 => ("speed_of", name("chase")),
        1 => ("speed_of", name("lead")),
        2 => ("speed_of", name("nobody")),
        3 => ("speed_factor", toml::Value::Float(x / 20.0)),
        4 => ("speed_factor", toml::Value::Float(-1.0)),
        5 => ("continuous", toml::Value::Boolean(true)),
        6 => ("between_axles", toml::Value::Boolean(true)),
        _ => ("speed_mps", toml::Value::Float(-x / 4.0)),
    }
}

fn at_path<'a>(root: &'a mut toml::Value, path: &str) -> Option<&'a mut toml::Value> {
    let mut v = root;
    for part in path.split('.') {
        v = match v {
            toml::Value::Table(t) => t.get_mut(part)?,
            toml::Value::Array(a) => a.get_mut(part.parse::<usize>().ok()?)?,
            _ => return None,
        };
    }
    Some(v)
}

/// Values a traffic field may be set to: plausible ones mostly, some that must be refused.
fn value(choice: usize, scale: f64) -> toml::Value {
    match choice % 12 {
        0 => toml::Value::Integer(1),
        1 => toml::Value::Integer(2),
        2 => toml::Value::Integer(3),
        3 => toml::Value::Float(0.0),
        4 => toml::Value::Float(-1.0),
        5 => toml::Value::Float(f64::NAN),
        6 => toml::Value::String("chase".into()),
        7 => toml::Value::String("lead".into()),
        8 => toml::Value::String("truck".into()),
        9 => toml::Value::Float(1e9),
        _ => toml::Value::Float(scale),
    }
}

#[test]
fn whatever_check_accepts_of_mutated_traffic_runs() {
    let shipped = shipped();
    let target = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/targets/nist-ten-segment.toml"),
    )
    .unwrap();
    let backend = Backend::choose(None).unwrap();
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: cases(),
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let strategy = (
        0..shipped.len(),
        prop::collection::vec(
            (any::<usize>(), any::<usize>(), 0.0..40.0f64, any::<bool>()),
            1..4,
        ),
    );
    let (ran, refused) = (std::cell::Cell::new(0u32), std::cell::Cell::new(0u32));
    runner
        .run(&strategy, |(which, mutations)| {
            let mut root = toml::Value::Table(shipped[which].clone());
            // Fields no shipped scenario gives, added to an event's action or trigger.
            let mut tables = Vec::new();
            event_tables(&root, "", &mut tables);
            for &(n, v, x, _) in mutations.iter().filter(|m| m.1 % 3 == 0) {
                if tables.is_empty() {
                    break;
                }
                if let Some(toml::Value::Table(t)) = at_path(&mut root, &tables[n % tables.len()]) {
                    // Mostly one that fits: a speed change made relative (and perhaps
                    // continuous) to a vehicle that exists; else any.
                    if t.contains_key("speed_mps") && v % 2 == 0 {
                        let of = ["chase", "lead"][v / 6 % 2];
                        t.insert("speed_of".into(), toml::Value::String(of.into()));
                        t.insert("continuous".into(), toml::Value::Boolean(v % 4 == 0));
                    } else {
                        let (field, value) = extra_field(v / 3, x);
                        t.insert(field.into(), value);
                    }
                }
            }
            let mut paths = Vec::new();
            traffic_leaves(&root, "", &mut paths);
            for &(n, v, x, scale) in &mutations {
                let path = &paths[n % paths.len()];
                if let Some(slot) = at_path(&mut root, path) {
                    *slot = match (scale, &*slot) {
                        // Mostly a plausible number for a number: the scenario still plans.
                        (true, toml::Value::Float(_)) => toml::Value::Float(x),
                        (true, toml::Value::Integer(_)) => toml::Value::Integer(1 + (v % 3) as i64),
                        _ => value(v, x),
                    };
                }
            }
            let text = toml::to_string(&root).unwrap();
            let planned = Scenario::parse(&text, Path::new("fuzz.toml"), &[], |t| {
                sim_core::parse_target(&target, &Path::new("scenarios").join(t))
            })
            .and_then(|s| Plan::new(&s));
            match planned {
                Ok(plan) => {
                    ran.set(ran.get() + 1);
                    let mut looped = ClosedLoop::new(plan, backend, false)
                        .unwrap_or_else(|e| panic!("checked but did not start: {e}\n{text}"));
                    looped.set_whole_frames(false);
                    while let Some(out) = looped
                        .step()
                        .unwrap_or_else(|e| panic!("checked but did not run: {e}\n{text}"))
                    {
                        prop_assert!(out.record.traffic.is_some());
                    }
                }
                Err(e) => {
                    refused.set(refused.get() + 1);
                    let e = e.to_string();
                    prop_assert!(!e.contains('\n'), "not one line: {e}");
                }
            }
            Ok(())
        })
        .unwrap();
    let (ran, refused) = (ran.get(), refused.get());
    eprintln!("{ran} ran, {refused} refused");
    assert!(ran > 0 && refused > 0, "{ran} ran, {refused} refused");
}
