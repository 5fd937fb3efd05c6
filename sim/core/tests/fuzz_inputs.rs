//! Fuzzing of scenario and target files: mutated copies of every shipped scenario (as
//! written, and as resolved with every default written out) and of the shipped target, and
//! random `--set` overrides, go through parsing and validation, which must answer with a
//! value or an error and never panic. Each error is one line.
//!
//! A proptest harness rather than cargo-fuzz, so that it runs on stable Rust in the normal
//! test suite: a bounded run (`FUZZ_CASES`, a few seconds) in CI; more with
//! `CARFOLLOW_FUZZ_CASES=100000 cargo test --release -p sim --test fuzz_inputs`.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use sim_core::{Plan, Scenario};
use std::path::{Path, PathBuf};

/// Cases per harness in CI.
const FUZZ_CASES: u32 = 20_000;

fn cases() -> u32 {
    std::env::var("CARFOLLOW_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(FUZZ_CASES)
}

fn scenarios_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

/// Every shipped scenario's text, sorted by file name.
fn shipped() -> Vec<String> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(scenarios_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 8, "{paths:?}");
    let mut texts: Vec<String> = paths
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    // And each as resolved, every default written out, so that every field gets mutated
    // (the controllers' look-ahead, gains and the like are absent from the files).
    for p in &paths {
        let resolved = Scenario::load(p, &[]).unwrap().resolved.clone();
        texts.push(toml::to_string(&resolved).unwrap());
    }
    texts
}

fn target_text() -> String {
    std::fs::read_to_string(scenarios_dir().join("targets/nist-ten-segment.toml")).unwrap()
}

/// Values that have broken parsers and validators before: extremes, non-finite numbers,
/// wrong types, arrays of the wrong length.
const NASTY: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551615",
    "0.5",
    "3",
    "60",
    "1000000",
    "\"\"",
    "\"time\"",
    "\"../../etc/passwd\"",
    "true",
    "[]",
    "[0]",
    "[1e308, -1e308]",
    "[0, 0, 0, 0]",
    "[[0, 0]]",
    "[[1e308, 1]]",
    "{}",
    "{ straight_m = 1e308 }",
    "[{ arc_radius_m = 1e308, arc_angle_deg = 360 }]",
    "[{ straight_m = 0.001 }]",
];

/// Every path to a leaf value of a TOML table (`route.segments.0.straight_m`), arrays
/// indexed.
fn leaves(value: &toml::Value, prefix: &str, out: &mut Vec<String>) {
    match value {
        toml::Value::Table(t) => {
            for (k, v) in t {
                let p = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                out.push(p.clone());
                leaves(v, &p, out);
            }
        }
        toml::Value::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                leaves(v, &format!("{prefix}.{i}"), out);
            }
        }
        _ => {}
    }
}

/// The value at a leaf path, mutably.
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

fn nasty_value(i: usize) -> toml::Value {
    // As `--set` reads a value: TOML if it is, else a string (2^64 - 1 is no TOML integer).
    let raw = NASTY[i % NASTY.len()];
    toml::from_str::<toml::Table>(&format!("v = {raw}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(raw.to_string()))
}

/// One mutation of a TOML text.
#[derive(Clone, Debug)]
enum Mutation {
    /// Replace the value at the `n`-th leaf with the `v`-th nasty value.
    Replace { n: usize, v: usize },
    /// Remove the `n`-th leaf.
    Remove { n: usize },
    /// Scale the `n`-th number by `k`.
    Scale { n: usize, k: f64 },
    /// Overwrite a byte of the text with `c`.
    Byte { at: usize, c: char },
    /// Cut the text at a byte.
    Truncate { at: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), any::<usize>()).prop_map(|(n, v)| Mutation::Replace { n, v }),
        1 => any::<usize>().prop_map(|n| Mutation::Remove { n }),
        3 => (any::<usize>(), prop_oneof![Just(-1.0), Just(0.0), Just(1e-9), Just(1e9), Just(1e300), -1e4..1e4f64])
            .prop_map(|(n, k)| Mutation::Scale { n, k }),
        1 => (any::<usize>(), prop::sample::select(vec!['=', '[', ']', '{', '"', '\n', '.', '-', 'e', '9', '#', ',']))
            .prop_map(|(at, c)| Mutation::Byte { at, c }),
        1 => any::<usize>().prop_map(|at| Mutation::Truncate { at }),
    ]
}

/// Applies `m` to `text`; `None` when it does not apply (the text is not TOML any more).
fn mutate(text: &str, m: &Mutation) -> String {
    let structural = |f: &dyn Fn(&mut toml::Value, &[String])| -> String {
        let Ok(table) = toml::from_str::<toml::Table>(text) else {
            return text.to_string();
        };
        let mut root = toml::Value::Table(table);
        let mut paths = Vec::new();
        leaves(&root, "", &mut paths);
        if paths.is_empty() {
            return text.to_string();
        }
        f(&mut root, &paths);
        toml::to_string(&root).unwrap_or_else(|_| text.to_string())
    };
    match *m {
        Mutation::Replace { n, v } => structural(&|root, paths| {
            if let Some(slot) = at_path(root, &paths[n % paths.len()]) {
                *slot = nasty_value(v);
            }
        }),
        Mutation::Remove { n } => structural(&|root, paths| {
            let path = &paths[n % paths.len()];
            let (parent, last) = path.rsplit_once('.').unwrap_or(("", path));
            let holder = if parent.is_empty() {
                Some(&mut *root)
            } else {
                at_path(root, parent)
            };
            match holder {
                Some(toml::Value::Table(t)) => {
                    t.remove(last);
                }
                Some(toml::Value::Array(a)) => {
                    if let Ok(i) = last.parse::<usize>() {
                        if i < a.len() {
                            a.remove(i);
                        }
                    }
                }
                _ => {}
            }
        }),
        Mutation::Scale { n, k } => structural(&|root, paths| {
            let numbers: Vec<&String> = paths.iter().collect();
            for off in 0..numbers.len() {
                let p = numbers[(n + off) % numbers.len()];
                match at_path(root, p) {
                    Some(toml::Value::Float(x)) => {
                        *x *= k;
                        return;
                    }
                    Some(toml::Value::Integer(x)) => {
                        *x = (*x as f64 * k) as i64;
                        return;
                    }
                    _ => {}
                }
            }
        }),
        Mutation::Byte { at, c } => {
            let mut bytes: Vec<char> = text.chars().collect();
            if !bytes.is_empty() {
                let i = at % bytes.len();
                bytes[i] = c;
            }
            bytes.into_iter().collect()
        }
        Mutation::Truncate { at } => {
            let chars: Vec<char> = text.chars().collect();
            chars[..at % (chars.len() + 1)].iter().collect()
        }
    }
}

/// A random `--set` from the leaf paths of a scenario and the nasty values.
fn override_for(text: &str, n: usize, v: usize) -> Option<String> {
    let table: toml::Table = toml::from_str(text).ok()?;
    let mut paths = Vec::new();
    leaves(&toml::Value::Table(table), "", &mut paths);
    // `--set` addresses tables, not array elements.
    let paths: Vec<_> = paths
        .into_iter()
        .filter(|p| !p.split('.').any(|k| k.parse::<usize>().is_ok()))
        .collect();
    let path = paths.get(n % paths.len().max(1))?;
    Some(format!("{path}={}", NASTY[v % NASTY.len()]))
}

fn assert_one_line(e: &dyn std::fmt::Display) {
    let text = e.to_string();
    assert!(!text.is_empty());
    assert!(!text.contains('\n'), "not one line: {text:?}");
}

#[test]
fn mutated_scenarios_and_overrides_never_panic() {
    let texts = shipped();
    let target = target_text();
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: cases(),
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let strategy = (
        0..texts.len(),
        prop::collection::vec(mutation(), 1..4),
        prop::option::of((any::<usize>(), any::<usize>())),
    );
    let (ok, refused) = (std::cell::Cell::new(0u32), std::cell::Cell::new(0u32));
    runner
        .run(&strategy, |(which, mutations, set)| {
            let mut text = texts[which].clone();
            for m in &mutations {
                text = mutate(&text, m);
            }
            let overrides: Vec<String> = set
                .and_then(|(n, v)| override_for(&texts[which], n, v))
                .into_iter()
                .collect();
            let result = Scenario::parse(&text, Path::new("fuzz.toml"), &overrides, |t| {
                sim_core::parse_target(&target, &Path::new("scenarios").join(t))
            });
            // As `carfollow check` does: the scenario, then its plan.
            match result.and_then(|s| Plan::new(&s)) {
                Ok(plan) => {
                    ok.set(ok.get() + 1);
                    let s = plan.scenario();
                    prop_assert!(s.duration_s.is_finite() && s.duration_s > 0.0);
                    prop_assert!(plan.chase_start_m() >= 0.0);
                }
                Err(e) => {
                    refused.set(refused.get() + 1);
                    assert_one_line(&e);
                }
            }
            Ok(())
        })
        .unwrap();
    // The harness must exercise both sides.
    let (ok, refused) = (ok.get(), refused.get());
    assert!(ok > 0 && refused > 0, "{ok} accepted, {refused} refused");
    eprintln!("{ok} accepted, {refused} refused");
}

#[test]
fn mutated_targets_never_panic() {
    let text = target_text();
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: cases(),
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let (ok, refused) = (std::cell::Cell::new(0u32), std::cell::Cell::new(0u32));
    runner
        .run(&prop::collection::vec(mutation(), 1..4), |mutations| {
            let mut t = text.clone();
            for m in &mutations {
                t = mutate(&t, m);
            }
            match sim_core::parse_target(&t, Path::new("fuzz.toml")) {
                Ok(model) => {
                    ok.set(ok.get() + 1);
                    // What `carfollow target` does with an accepted model must not
                    // overflow either.
                    let [w, h] = model.size_m();
                    prop_assert!(w.is_finite() && h.is_finite());
                }
                Err(e) => {
                    refused.set(refused.get() + 1);
                    assert_one_line(&e);
                }
            }
            Ok(())
        })
        .unwrap();
    let (ok, refused) = (ok.get(), refused.get());
    assert!(ok > 0 && refused > 0, "{ok} accepted, {refused} refused");
    eprintln!("{ok} accepted, {refused} refused");
}
