//! Plug-ins in the loop, from Rust: the built-ins behind the traits drive as the built-ins
//! do (which pins the traits' sign conventions), and a plug-in's failure ends the run with
//! its frame and time.

use sim::{Simulation, SimulationOptions};
use sim_core::{
    BuiltinController, BuiltinTracker, Command, ControlInput, Controller, ControllerChoice,
    LoopError, Plan, PluginError, Scenario, TrackerChoice,
};
use sim_render::Backend;

fn plan(name: &str, seconds: f64) -> Plan {
    let set = [format!("duration_s={seconds}")];
    let scenario = Scenario::shipped(name, &set)
        .expect("shipped")
        .expect("valid");
    Plan::new(&scenario).expect("plans")
}

/// The rows of frames.csv a run writes, with these choices.
fn rows(name: &str, tracker: TrackerChoice, controller: ControllerChoice) -> Vec<Vec<String>> {
    let dir = tempfile::tempdir().unwrap();
    let plan = plan(name, 6.0);
    let mut sim = Simulation::new(
        plan,
        SimulationOptions {
            renderers: 1,
            tracker,
            controller,
            out: Some(dir.path().to_path_buf()),
            ..SimulationOptions::new(Backend::choose(None).unwrap())
        },
    )
    .unwrap();
    while sim.step().unwrap().is_some() {}
    sim.finish().unwrap();
    let text = std::fs::read_to_string(dir.path().join("frames.csv")).unwrap();
    text.lines()
        .map(|l| l.split(',').map(String::from).collect())
        .collect()
}

fn column(rows: &[Vec<String>], name: &str) -> Vec<String> {
    let i = rows[0].iter().position(|c| c == name).expect(name);
    rows[1..].iter().map(|r| r[i].clone()).collect()
}

/// The paper's tracker and the built-in controller, run through the traits, give the run
/// the loop gives them directly: the same estimates, the same driving. A sign turned the
/// wrong way at the traits' boundary (steering, yaw rate) would send the chase off the road.
#[test]
fn the_builtins_behind_the_traits_drive_as_the_builtins() {
    let name = "weave";
    let scenario = plan(name, 6.0).scenario().clone();
    let direct = rows(name, TrackerChoice::Builtin, ControllerChoice::Builtin);
    let tracker = TrackerChoice::Plugin(Box::new(BuiltinTracker::new(scenario.tracker.clone())));
    let controller = ControllerChoice::Plugin(Box::new(
        BuiltinController::new(scenario.chase.clone(), scenario.chase_initial_speed_mps).unwrap(),
    ));
    let traits = rows(name, tracker, controller);
    assert_eq!(direct.len(), traits.len());
    for c in [
        "est_range_m",
        "est_lateral_m",
        "est_cx_px",
        "status",
        "gap_m",
        "chase_speed_mps",
        "steering_rad",
        "throttle",
        "brake",
        "lateral_deviation_m",
    ] {
        assert_eq!(column(&direct, c), column(&traits, c), "{c}");
    }
}

struct FailsAt(f64);

impl Controller for FailsAt {
    fn name(&self) -> String {
        "fails".into()
    }
    fn control(&mut self, input: &ControlInput) -> Result<Command, PluginError> {
        if input.t_s >= self.0 {
            return Err(PluginError::Failed("the solver diverged".into()));
        }
        Ok(Command {
            steering_rad: 0.0,
            throttle: 0.2,
            brake: 0.0,
            pan_rate_rad_s: 0.0,
        })
    }
}

/// A plug-in's error ends the run, saying which plug-in, its message and the time.
#[test]
fn a_failing_controller_ends_the_run_with_its_frame_and_time() {
    let mut sim = Simulation::new(
        plan("nist-grounds", 3.0),
        SimulationOptions {
            renderers: 1,
            controller: ControllerChoice::Plugin(Box::new(FailsAt(1.0))),
            ..SimulationOptions::new(Backend::choose(None).unwrap())
        },
    )
    .unwrap();
    let err = loop {
        match sim.step() {
            Ok(Some(_)) => {}
            Ok(None) => panic!("the run should have failed"),
            Err(e) => break e,
        }
    };
    let text = err.to_string();
    assert!(text.contains("the solver diverged"), "{text}");
    assert!(text.contains("controller"), "{text}");
    match err {
        sim::RunError::Loop(LoopError::Plugin { t_s: Some(t), .. }) => {
            assert!((1.0..1.2).contains(&t), "{t}")
        }
        other => panic!("{other:?}"),
    }
    assert!(
        sim.step().unwrap().is_none(),
        "nothing steps after a failure"
    );
}
