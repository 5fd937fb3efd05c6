//! A tracker and a controller of our own in carfollow's loop, judged on the scenario
//! library against the paper's tracker and the built-in controller.
//!
//! ```sh
//! cargo run --release -p sim --example own-plugins -- [--set KEY=VALUE]... [--out DIR] [SCENARIO]...
//! ```
//!
//! Each scenario (a shipped name or a path; all shipped ones by default) runs four times:
//! the built-ins, our tracker with the built-in controller, the paper's tracker with our
//! controller, and ours together. The usual outputs go to `DIR/<pairing>/<scenario>/`
//! (`renders/own-plugins` by default), and a Markdown table of the results to stdout.

mod ncc;
mod stanley;

use sim::{Simulation, SimulationOptions, Summary};
use sim_core::{ControllerChoice, Plan, Scenario, TrackerChoice};
use sim_render::Backend;
use std::path::{Path, PathBuf};

/// Which tracker and controller run.
#[derive(Clone, Copy)]
enum Pairing {
    Builtin,
    OwnTracker,
    OwnController,
    Own,
}

impl Pairing {
    const ALL: [Pairing; 4] = [
        Pairing::Builtin,
        Pairing::OwnTracker,
        Pairing::OwnController,
        Pairing::Own,
    ];

    fn folder(self) -> &'static str {
        match self {
            Pairing::Builtin => "builtin",
            Pairing::OwnTracker => "ncc-tracker",
            Pairing::OwnController => "stanley-pid",
            Pairing::Own => "ncc-and-stanley-pid",
        }
    }

    fn choices(self, scenario: &Scenario) -> (TrackerChoice, ControllerChoice) {
        let tracker = || TrackerChoice::Plugin(Box::new(ncc::NccTracker::new()));
        let controller = || {
            // The gap wanted: the band's lower edge at standstill, half a second more per
            // m/s (the middle of a 5–15 m band at 10 m/s).
            let low = scenario.expect.gap_band_m.map_or(5.0, |[lo, _]| lo);
            ControllerChoice::Plugin(Box::new(stanley::StanleyPid::new(
                scenario.chase.camera_mount,
                f64::from(vehicle::VehicleParams::hmmwv_m998().wheelbase_m),
                low + 0.5,
                0.5,
            )))
        };
        match self {
            Pairing::Builtin => (TrackerChoice::Builtin, ControllerChoice::Builtin),
            Pairing::OwnTracker => (tracker(), ControllerChoice::Builtin),
            Pairing::OwnController => (TrackerChoice::Builtin, controller()),
            Pairing::Own => (tracker(), controller()),
        }
    }
}

fn plan(name: &str, overrides: &[String]) -> Result<Plan, String> {
    let scenario = match Scenario::shipped(name, overrides) {
        Some(s) => s,
        None => Scenario::load(Path::new(name), overrides),
    }
    .map_err(|e| e.to_string())?;
    Plan::new(&scenario).map_err(|e| e.to_string())
}

fn run(name: &str, pairing: Pairing, overrides: &[String], out: &Path) -> Result<Summary, String> {
    let plan = plan(name, overrides)?;
    let (tracker, controller) = pairing.choices(plan.scenario());
    let dir = out.join(pairing.folder()).join(&plan.scenario().name);
    let backend = Backend::choose(None).map_err(|e| e.to_string())?;
    let mut sim = Simulation::new(
        plan,
        SimulationOptions {
            tracker,
            controller,
            out: Some(dir),
            ..SimulationOptions::new(backend)
        },
    )
    .map_err(|e| e.to_string())?;
    while sim.step().map_err(|e| e.to_string())?.is_some() {}
    Ok(sim.finish().map_err(|e| e.to_string())?.0)
}

fn main() {
    let mut overrides = Vec::new();
    let mut out = PathBuf::from("renders/own-plugins");
    let mut scenarios = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--set" => overrides.extend(args.next()),
            "--out" => out = args.next().map(PathBuf::from).unwrap_or(out),
            _ => scenarios.push(arg),
        }
    }
    if scenarios.is_empty() {
        scenarios = sim_core::shipped_scenarios().map(String::from).collect();
    }
    println!("| scenario | tracker | controller | verdict | lost s | gap m | range error p95 m | collisions |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut failed = false;
    for name in &scenarios {
        for pairing in Pairing::ALL {
            match run(name, pairing, &overrides, &out) {
                Ok(s) => println!(
                    "| {} | {} | {} | {} | {:.1} | {:.1}–{:.1} | {} | {} |",
                    s.scenario,
                    s.tracker.as_deref().unwrap_or("?"),
                    s.controller.as_deref().unwrap_or("?"),
                    if s.passed { "pass" } else { "FAIL" },
                    s.tracking_lost_s,
                    s.gap_m.min,
                    s.gap_m.max,
                    s.range_error_m
                        .p95_abs
                        .map_or("–".into(), |e| format!("{e:.2}")),
                    s.collisions,
                ),
                Err(e) => {
                    eprintln!("error: {name} ({}): {e}", pairing.folder());
                    failed = true;
                }
            }
        }
    }
    if failed {
        std::process::exit(3);
    }
}
