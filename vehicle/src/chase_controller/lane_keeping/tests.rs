//! Lane keeping and cruising on a kinematic chase: a bicycle model whose speed follows the
//! controller's speed reference with a lag, and a scripted lead seen by a perfect sensor.

use super::*;
use crate::clock::{Step, PHYSICS_DT_S, STEPS_PER_FRAME};
use crate::controls::Controls;
use crate::route::RouteBuilder;
use crate::vehicle_params::VehicleParams;
use crate::Odometry;
use rapier3d::math::Rotation;

/// The estimates' latency, steps (125 ms).
const LATENCY_STEPS: u64 = 15;
/// Half the lane's width, m.
const HALF_WIDTH_M: f32 = 1.75;
/// The lag of the kinematic chase's speed behind the reference, s.
const SPEED_LAG_S: f32 = 0.3;

/// A straight lane along +x at z = 0.
fn straight_lane() -> Route {
    RouteBuilder::new(Vector::new(-50.0, 0.0, 0.0), 0.0)
        .straight(3000.0)
        .build()
        .unwrap()
}

fn lane_config(cruise_speed_mps: Option<f32>) -> ChaseControllerConfig {
    ChaseControllerConfig {
        lane_keeping: true,
        cruise_speed_mps,
        ..ChaseControllerConfig::default()
    }
}

struct Drive {
    c: ChaseController,
    x: f32,
    z: f32,
    heading: f32,
    v: f32,
    step: u64,
    wheelbase_m: f32,
    vehicle_from_camera: Pose,
    queue: Vec<LeadEstimate>,
    modes: Vec<ChaseMode>,
}

impl Drive {
    /// The chase at (0, `z`) heading +x at `v`, with the straight lane set.
    fn new(config: ChaseControllerConfig, z: f32, v: f32) -> Drive {
        let params = VehicleParams::hmmwv_m998();
        let vehicle_from_camera = config.camera_mount.vehicle_from_camera();
        let mut c = ChaseController::new(config, &params, v).unwrap();
        c.set_lane(straight_lane(), HALF_WIDTH_M);
        Drive {
            c,
            x: 0.0,
            z,
            heading: 0.0,
            v,
            step: 0,
            wheelbase_m: params.wheelbase_m,
            vehicle_from_camera,
            queue: Vec::new(),
            modes: Vec::new(),
        }
    }

    fn pose(&self) -> Pose {
        Pose::from_parts(
            Vector::new(self.x, 0.0, self.z),
            Rotation::from_rotation_y(self.heading),
        )
    }

    fn seconds(&self) -> f32 {
        self.step as f32 * PHYSICS_DT_S
    }

    /// One physics step; `lead` is the target's world position and the tracker's status at
    /// this step (`None`: no estimate). Returns the controls.
    fn step(&mut self, lead: Option<(Vector, TrackStatus)>) -> Controls {
        let now = Step(self.step);
        if let (true, Some((p, status))) = (now.is_frame_start(), lead) {
            let world_from_camera = self.pose() * self.vehicle_from_camera;
            self.queue.push(LeadEstimate {
                capture_step: now,
                target_in_camera_m: world_from_camera.inverse_transform_point(p),
                status,
                camera_pan_rad: 0.0,
            });
        }
        let (due, later): (Vec<_>, Vec<_>) = self
            .queue
            .iter()
            .partition(|e| e.capture_step.0 + LATENCY_STEPS <= self.step);
        self.queue = later;
        for e in due {
            self.c.receive(e);
        }
        let controls = self.c.update(&Odometry {
            step: now,
            world_from_chase: self.pose(),
            forward_speed_mps: self.v,
            camera_pan_rad: 0.0,
        });
        self.modes.push(self.c.mode());
        let dt = PHYSICS_DT_S;
        let t = self.c.telemetry();
        let speed_ref = if t.emergency { 0.0 } else { t.speed_ref_mps };
        self.v = (self.v + (speed_ref - self.v) * dt / SPEED_LAG_S).max(0.0);
        self.heading += self.v * controls.steer_rad.tan() / self.wheelbase_m * dt;
        self.x += self.v * self.heading.cos() * dt;
        self.z -= self.v * self.heading.sin() * dt;
        self.step += 1;
        controls
    }

    fn left_lane_events(&self) -> Vec<(Step, f32)> {
        self.c
            .events()
            .iter()
            .filter_map(|e| match e.kind {
                ControllerEventKind::TargetLeftLane { offset_m } => Some((e.step, offset_m)),
                _ => None,
            })
            .collect()
    }

    fn count(&self, kind: ControllerEventKind) -> usize {
        self.c.events().iter().filter(|e| e.kind == kind).count()
    }
}

/// The lead at 10 m/s along the lane from `x0` at `z`, its target 1.2 m up.
fn lead_at(t: f32, x0: f32, z: f32) -> Vector {
    Vector::new(x0 + 10.0 * t, 1.2, z)
}

#[test]
fn with_nothing_tracked_it_keeps_its_lane_at_the_cruise_speed() {
    // The lane's centre line is 1 m to the left of the chase.
    let mut d = Drive::new(lane_config(Some(15.0)), 1.0, 10.0);
    let first = d.step(None);
    assert!(first.steer_rad > 0.0, "steers left: {first:?}");
    while d.seconds() < 20.0 {
        d.step(None);
    }
    println!("z {:.4} m, v {:.3} m/s, heading {:.5}", d.z, d.v, d.heading);
    assert!(d.z.abs() < 0.1, "lateral error {} m", d.z);
    assert!(d.heading.abs() < 0.01, "heading {}", d.heading);
    assert!((d.v - 15.0).abs() < 0.1, "speed {}", d.v);
    assert!(d.modes.iter().all(|&m| m == ChaseMode::Cruising));
    assert!(d.c.events().is_empty(), "{:?}", d.c.events());
    // The reference rose at the gap keeper's 1.5 m/s²: 5 m/s in about 3.3 s.
    let aim = d.c.telemetry().lookahead_world_m.unwrap();
    assert!(aim.z.abs() < 1e-3 && aim.x > d.x, "{aim}");
}

#[test]
fn cruising_it_stops_short_of_its_lanes_end() {
    // A lane of 200 m from x = −50: its end at x = 150, 150 m ahead of the chase.
    let mut d = Drive::new(lane_config(Some(15.0)), 0.0, 15.0);
    let short = RouteBuilder::new(Vector::new(-50.0, 0.0, 0.0), 0.0)
        .straight(200.0)
        .build()
        .unwrap();
    d.c.set_lane(short, HALF_WIDTH_M);
    let mut slowest_ref_change = 0.0f32;
    let mut last_ref = 15.0f32;
    while d.seconds() < 30.0 {
        d.step(None);
        let r = d.c.telemetry().speed_ref_mps;
        slowest_ref_change = slowest_ref_change.min((r - last_ref) / PHYSICS_DT_S);
        last_ref = r;
    }
    println!("stopped at x {:.2} m, v {:.3} m/s", d.x, d.v);
    let stop_at = 150.0 - STOP_SHORT_OF_END_M;
    assert!(d.v < 0.05, "still at {} m/s", d.v);
    assert!(
        d.x <= stop_at + 0.5 && d.x > stop_at - 3.0,
        "stopped at {}",
        d.x
    );
    // Within the gap keeper's deceleration.
    let g = &ChaseControllerConfig::default().gap_keeper;
    assert!(
        slowest_ref_change >= -g.max_decel_mps2 - 1e-3,
        "{slowest_ref_change}"
    );
    assert!(d.modes.iter().all(|&m| m == ChaseMode::Cruising));
    // On the long lane it keeps its speed over the same stretch.
    let mut far = Drive::new(lane_config(Some(15.0)), 0.0, 15.0);
    while far.seconds() < 10.0 {
        far.step(None);
    }
    assert!((far.v - 15.0).abs() < 0.05, "{}", far.v);
}

#[test]
fn lane_keeping_without_a_lane_steers_straight() {
    let params = VehicleParams::hmmwv_m998();
    let mut c = ChaseController::new(lane_config(Some(15.0)), &params, 10.0).unwrap();
    let controls = c.update(&Odometry {
        step: Step(0),
        world_from_chase: Pose::from_translation(Vector::new(0.0, 0.0, 1.0)),
        forward_speed_mps: 10.0,
        camera_pan_rad: 0.0,
    });
    assert_eq!(controls.steer_rad, 0.0);
    assert_eq!(c.mode(), ChaseMode::Cruising);
}

#[test]
fn a_target_in_the_lane_is_followed_at_the_gap() {
    let mut d = Drive::new(lane_config(Some(15.0)), 0.0, 10.0);
    while d.seconds() < 40.0 {
        let t = d.seconds();
        d.step(Some((lead_at(t, 25.0, 0.0), TrackStatus::Tracking)));
    }
    // Cruising until the range filters have measured the target (one estimate a frame),
    // then following.
    assert_eq!(d.modes[0], ChaseMode::Cruising);
    let switched = d.modes.iter().position(|&m| m == ChaseMode::Following);
    let measured = LATENCY_STEPS as usize + (RESUME_MEASUREMENTS - 1) * STEPS_PER_FRAME as usize;
    assert_eq!(switched, Some(measured));
    assert!(d.modes[measured..]
        .iter()
        .all(|&m| m == ChaseMode::Following));
    assert_eq!(d.c.events().len(), 1, "{:?}", d.c.events());
    assert_eq!(d.c.events()[0].kind, ControllerEventKind::Resumed);
    let t = *d.c.telemetry();
    let gap = t.gap_m.unwrap();
    println!(
        "gap {gap:.2} m, wanted {:.2} m, v {:.2} m/s",
        t.desired_gap_m, d.v
    );
    assert!((gap - t.desired_gap_m).abs() < 1.0, "{t:?}");
    assert!((d.v - 10.0).abs() < 0.2, "speed {}", d.v);
    assert!(d.z.abs() < 0.01, "z {}", d.z);
}

/// The lead follows in the lane for 5 s, brushes the line for two frames (noise, kept),
/// leaves it for a lane to the right from 8 s, and comes back at 14 s. Returns the run and
/// the arrival steps of the estimates captured out of the lane after 8 s.
fn leaves_the_lane(cruise: Option<f32>, until_s: f32) -> (Drive, Vec<Step>) {
    let mut d = Drive::new(lane_config(cruise), 0.0, 10.0);
    let mut out_arrivals = Vec::new();
    while d.seconds() < until_s {
        let t = d.seconds();
        let z = if (5.0..5.1).contains(&t) {
            // Two frames just beyond the margin.
            HALF_WIDTH_M + LANE_MARGIN_M + 0.1
        } else if (8.0..14.0).contains(&t) {
            3.5
        } else {
            0.0
        };
        if t >= 8.0 && z > HALF_WIDTH_M + LANE_MARGIN_M && Step(d.step).is_frame_start() {
            out_arrivals.push(Step(d.step + LATENCY_STEPS));
        }
        d.step(Some((lead_at(t, 25.0, z), TrackStatus::Tracking)));
    }
    (d, out_arrivals)
}

#[test]
fn a_target_leaving_the_lane_is_dropped_for_the_cruise() {
    let (d, out) = leaves_the_lane(Some(12.0), 12.0);
    let left = d.left_lane_events();
    assert_eq!(left.len(), 1, "{:?}", d.c.events());
    let (at, offset) = left[0];
    // At the third estimate out of the lane, the blip at 5 s notwithstanding.
    assert_eq!(at, out[LEFT_LANE_ARRIVALS as usize - 1]);
    assert!((offset + 3.5).abs() < 0.05, "offset {offset}");
    assert_eq!(d.modes[at.0 as usize - 1], ChaseMode::Following);
    assert!(d.modes[at.0 as usize..]
        .iter()
        .all(|&m| m == ChaseMode::Cruising));
    // Its estimates are no longer fed to the range filters; the chase keeps its lane.
    assert_eq!(d.c.telemetry().gap_m, None);
    assert!(d.z.abs() < 0.01, "z {}", d.z);
    assert!((d.c.telemetry().speed_ref_mps - 12.0).abs() < 1e-3);
    // Back in the lane at 14 s: followed again.
    let (d, _) = leaves_the_lane(Some(12.0), 16.0);
    assert_eq!(d.c.mode(), ChaseMode::Following);
    assert_eq!(
        d.count(ControllerEventKind::Resumed),
        2,
        "{:?}",
        d.c.events()
    );
    assert!(d.c.telemetry().gap_m.is_some());
}

#[test]
fn a_target_leaving_the_lane_stops_the_chase_without_a_cruise_speed() {
    let (d, out) = leaves_the_lane(None, 12.0);
    let left = d.left_lane_events();
    assert_eq!(left.len(), 1, "{:?}", d.c.events());
    let at = left[0].0;
    assert_eq!(at, out[LEFT_LANE_ARRIVALS as usize - 1]);
    assert_eq!(d.modes[at.0 as usize], ChaseMode::Stopping);
    assert_eq!(d.count(ControllerEventKind::TrackLost), 0);
    assert!(matches!(
        d.c.mode(),
        ChaseMode::Stopping | ChaseMode::Stopped
    ));
    // No mode other than following before the lead left: started following, no cruise.
    assert!(d.modes[..at.0 as usize]
        .iter()
        .all(|&m| m == ChaseMode::Following));
}

/// The chase with `config` at 10 m/s, a lead 25 m ahead in its lane tracked for 5 s and
/// lost after, until `until_s`.
fn tracked_then_lost(config: ChaseControllerConfig, until_s: f32) -> Drive {
    let mut d = Drive::new(config, 0.0, 10.0);
    while d.seconds() < until_s {
        let t = d.seconds();
        let status = if t < 5.0 {
            TrackStatus::Tracking
        } else {
            TrackStatus::Lost
        };
        d.step(Some((lead_at(t, 25.0, 0.0), status)));
    }
    d
}

/// The field `ChaseController::new` refuses `config` for, if any.
fn refused_field(config: ChaseControllerConfig) -> Option<&'static str> {
    match ChaseController::new(config, &VehicleParams::hmmwv_m998(), 10.0) {
        Err(VehicleError::InvalidParameter { field, .. }) => Some(field),
        Err(e) => panic!("{e}"),
        Ok(_) => None,
    }
}

#[test]
fn a_target_lost_in_the_lane_stops_the_chase_even_with_a_cruise_speed() {
    let d = tracked_then_lost(lane_config(Some(15.0)), 12.0);
    assert_eq!(d.count(ControllerEventKind::TrackLost), 1);
    assert!(d.left_lane_events().is_empty());
    assert!(d.modes.contains(&ChaseMode::Stopping));
    assert_eq!(d.c.mode(), ChaseMode::Stopped);
    assert!(d.v < 0.1, "speed {}", d.v);

    // Cruising, lost estimates change nothing.
    let mut d = Drive::new(lane_config(Some(15.0)), 0.0, 10.0);
    while d.seconds() < 5.0 {
        let t = d.seconds();
        d.step(Some((lead_at(t, 25.0, 0.0), TrackStatus::Lost)));
    }
    assert!(d.modes.iter().all(|&m| m == ChaseMode::Cruising));
    assert!(d.c.events().is_empty(), "{:?}", d.c.events());
}

#[test]
fn stopped_after_a_loss_it_cruises_again_after_resume_after_s() {
    let config = ChaseControllerConfig {
        resume_after_s: Some(2.0),
        ..lane_config(Some(15.0))
    };
    let d = tracked_then_lost(config, 30.0);
    let at = |kind: ControllerEventKind| {
        let e = d.c.events().iter().find(|e| e.kind == kind);
        e.unwrap_or_else(|| panic!("no {kind:?}: {:?}", d.c.events()))
            .step
    };
    let stood_s = at(ControllerEventKind::CruiseResumed).since(at(ControllerEventKind::Stopped))
        as f32
        * PHYSICS_DT_S;
    assert!(
        (2.0..2.0 + PHYSICS_DT_S * 1.5).contains(&stood_s),
        "{stood_s} s"
    );
    assert_eq!(d.count(ControllerEventKind::CruiseResumed), 1);
    assert_eq!(d.c.mode(), ChaseMode::Cruising);
    assert!((d.v - 15.0).abs() < 0.5, "speed {}", d.v);
    // The order of the modes: cruising to the first target, following, stopping,
    // standing, cruising.
    let mut seen = d.modes.clone();
    seen.dedup();
    assert_eq!(
        seen,
        [
            ChaseMode::Cruising,
            ChaseMode::Following,
            ChaseMode::Stopping,
            ChaseMode::Stopped,
            ChaseMode::Cruising
        ]
    );
}

#[test]
fn resume_after_s_is_checked() {
    let with = |cruise: Option<f32>, resume: f32| ChaseControllerConfig {
        resume_after_s: Some(resume),
        ..lane_config(cruise)
    };
    assert_eq!(refused_field(with(None, 2.0)), Some("resume_after_s"));
    for bad in [-0.1, 600.5, f32::NAN] {
        assert_eq!(
            refused_field(with(Some(15.0), bad)),
            Some("resume_after_s"),
            "{bad}"
        );
    }
    for good in [0.0, 2.0, 600.0] {
        assert_eq!(refused_field(with(Some(15.0), good)), None, "{good}");
    }
}

#[test]
fn the_cruise_speed_is_checked() {
    // Without lane keeping nothing steers the chase while nothing is tracked.
    let no_lane = ChaseControllerConfig {
        cruise_speed_mps: Some(15.0),
        ..ChaseControllerConfig::default()
    };
    assert_eq!(refused_field(no_lane), Some("cruise_speed_mps"));
    for bad in [0.4, 70.5, f32::NAN, -3.0] {
        assert_eq!(
            refused_field(lane_config(Some(bad))),
            Some("cruise_speed_mps"),
            "{bad}"
        );
    }
    for good in [0.5, 15.0, 70.0] {
        assert_eq!(refused_field(lane_config(Some(good))), None, "{good}");
    }
    assert_eq!(refused_field(lane_config(None)), None);
}

#[test]
fn the_new_fields_are_written_only_when_set() {
    // The serializer is TOML's (the crate's only one in its tests), through the same
    // `Serialize` as JSON: a skipped field is skipped for both.
    let keys = |config: &ChaseControllerConfig| -> Vec<String> {
        match toml::Value::try_from(config).unwrap() {
            toml::Value::Table(t) => t.keys().cloned().collect(),
            other => panic!("{other:?}"),
        }
    };
    let default = keys(&ChaseControllerConfig::default());
    assert!(
        default.contains(&"loss_decel_mps2".to_string()),
        "{default:?}"
    );
    assert!(
        !default.contains(&"lane_keeping".to_string()),
        "{default:?}"
    );
    assert!(
        !default.contains(&"cruise_speed_mps".to_string()),
        "{default:?}"
    );
    let set = keys(&lane_config(Some(15.0)));
    assert!(set.contains(&"lane_keeping".to_string()), "{set:?}");
    assert!(set.contains(&"cruise_speed_mps".to_string()), "{set:?}");
    // And a config without them reads back as the default.
    let text = toml::to_string(&ChaseControllerConfig::default()).unwrap();
    let back: ChaseControllerConfig = toml::from_str(&text).unwrap();
    assert_eq!(back, ChaseControllerConfig::default());
}
