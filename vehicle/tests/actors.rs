//! Guarantees the traffic's scripted vehicles keep on the rapier physics: every preset
//! holds a speed profile; a lane change lands in the next lane without overshoot; a stop
//! stops where its deceleration says; a vehicle scripted to stand still does not creep; a
//! driver with no events is the lead's driver bit for bit; and runs repeat bit for bit.
//!
//! Run: `CARGO_TARGET_DIR=/work/wt-events/target cargo test -p vehicle --release --test actors`

use vehicle::*;

const LANES: Lanes = Lanes {
    width_m: 3.5,
    count: 2,
    route_lane: 1,
    widths_m: None,
};

fn straight(length_m: f32) -> Route {
    RouteBuilder::new(Vector::ZERO, 0.0)
        .straight(length_m)
        .build()
        .unwrap()
}

fn script(toml_text: &str) -> EventScript {
    #[derive(serde::Deserialize)]
    struct File {
        #[serde(default)]
        events: EventScript,
    }
    toml::from_str::<File>(toml_text).unwrap().events
}

/// One step of a run: time, arc length, left offset from the route, speed, the controls.
#[derive(Copy, Clone, Debug, PartialEq)]
struct Sample {
    t_s: f64,
    s_m: f32,
    left_m: f32,
    speed_mps: f32,
    controls: Controls,
    x_m: f32,
    z_m: f32,
}

/// Drives one vehicle of `params` alone on `route` from its start at the profile's first
/// speed, scripted by `events` (as the only vehicle of the traffic), for `seconds`.
fn drive(
    params: &VehicleParams,
    route: &Route,
    profile: SpeedProfile,
    events: &str,
    seconds: f64,
) -> (Vec<Sample>, Vec<Fired>) {
    let mut world = World::new(&WorldConfig::default()).unwrap();
    let start = Pose::from_parts(
        route.point_at(0.0),
        Rotation::from_rotation_y(direction_heading(route.tangent_at(0.0))),
    );
    let id = world
        .add_vehicle(params, start, profile.speed_at(0.0))
        .unwrap();
    let lead =
        LeadDriver::new(route.clone(), profile, LeadDriverConfig::default(), params).unwrap();
    let events = Events::new(&script(events), &["me"], LANES).unwrap();
    let mut driver = ActorDriver::new(lead, events);
    let mut samples = Vec::new();
    let mut log = Vec::new();
    let mut s_hint = 0.0;
    while world.now().seconds() < seconds {
        let state = world.vehicle_state(id);
        let p = route.project_near(state.world_from_vehicle.translation, s_hint, 20.0);
        s_hint = p.s_m;
        let view = [VehicleView {
            station_m: f64::from(p.s_m),
            left_offset_m: f64::from(p.left_offset_m),
            speed_mps: f64::from(state.forward_speed_mps),
            front_m: f64::from(p.s_m + params.front_bumper_x_m()),
            rear_m: f64::from(p.s_m + params.rear_bumper_x_m()),
            touching: 0,
        }];
        let (controls, fired) = driver.update(world.now(), &state, &view, 0);
        log.extend(fired);
        samples.push(Sample {
            t_s: world.now().seconds(),
            s_m: p.s_m,
            left_m: p.left_offset_m,
            speed_mps: state.forward_speed_mps,
            controls,
            x_m: state.world_from_vehicle.translation.x,
            z_m: state.world_from_vehicle.translation.z,
        });
        world.set_controls(id, controls);
        world.step();
    }
    (samples, log)
}

fn presets() -> [(&'static str, VehicleParams); 6] {
    [
        ("sedan", VehicleParams::sedan()),
        ("hatchback", VehicleParams::hatchback()),
        ("van", VehicleParams::van()),
        ("truck", VehicleParams::truck()),
        ("pickup", VehicleParams::pickup()),
        ("hmmwv", VehicleParams::hmmwv_m998()),
    ]
}

/// Each kind cruises, speeds up at 0.4 m/s² (what the truck's power allows at 18 m/s) and
/// slows at 1.5 m/s² within half a metre a second of its profile, and keeps to its lane.
#[test]
fn every_preset_holds_a_speed_profile() {
    let route = straight(900.0);
    let profile = SpeedProfile::new(
        ProfileBasis::Time,
        &[
            (0.0, 10.0),
            (5.0, 10.0),
            (25.0, 18.0),
            (32.0, 18.0),
            (37.0, 10.5),
            (45.0, 10.5),
        ],
    )
    .unwrap();
    for (name, params) in presets() {
        let (samples, _) = drive(&params, &route, profile.clone(), "", 45.0);
        let worst = samples
            .iter()
            .filter(|s| s.t_s > 2.0)
            .map(|s| (s.speed_mps - profile.speed_at(s.t_s as f32)).abs())
            .fold(0.0f32, f32::max);
        let worst_left = samples.iter().map(|s| s.left_m.abs()).fold(0.0, f32::max);
        println!("{name}: worst speed error {worst:.3} m/s, worst offset {worst_left:.3} m");
        assert!(worst < 0.5, "{name}: speed error {worst}");
        assert!(worst_left < 0.1, "{name}: offset {worst_left}");
    }
}

/// A lane change of one 3.5 m lane over 3 s at 15 m/s: within 0.2 m of the new lane's
/// centre 3 to 4 s after it starts, never more than 0.3 m beyond it.
#[test]
fn a_lane_change_lands_in_the_next_lane() {
    let events = r#"
        [[events]]
        name = "change"
        trigger = { time_s = 5.0 }
        action = { lane = 2, duration_s = 3.0 }
    "#;
    for (name, params) in presets() {
        let (samples, log) = drive(
            &params,
            &straight(600.0),
            SpeedProfile::constant(15.0),
            events,
            20.0,
        );
        assert_eq!(log[0].step, Step(600));
        // Lane 2 is 3.5 m to the right of the route (lane 1).
        let target = -3.5;
        let arrived = samples
            .iter()
            .find(|s| s.t_s >= 5.0 && (s.left_m - target).abs() <= 0.2)
            .map(|s| s.t_s - 5.0)
            .unwrap_or(f64::INFINITY);
        let beyond = samples
            .iter()
            .map(|s| target - s.left_m)
            .fold(f32::MIN, f32::max);
        let stays = samples
            .iter()
            .filter(|s| s.t_s >= 5.0 + arrived)
            .all(|s| (s.left_m - target).abs() <= 0.2);
        println!("{name}: within 0.2 m after {arrived:.3} s, {beyond:.3} m beyond at most");
        assert!(
            (3.0..=4.0).contains(&arrived),
            "{name}: arrived after {arrived} s"
        );
        assert!(stays, "{name}: left the lane again");
        assert!(beyond < 0.3, "{name}: overshoot {beyond}");
    }
}

/// A stop from 20 m/s at 4 m/s² stops within 15% of v²/2a = 50 m of where it started, and
/// stays stopped.
#[test]
fn a_stop_stops_where_its_deceleration_says() {
    let events = r#"
        [[events]]
        name = "stop"
        trigger = { time_s = 3.0 }
        action = { stop = true, decel_mps2 = 4.0 }
    "#;
    for (name, params) in presets() {
        let (samples, log) = drive(
            &params,
            &straight(600.0),
            SpeedProfile::constant(20.0),
            events,
            25.0,
        );
        let start = samples.iter().find(|s| s.t_s >= 3.0).unwrap();
        let stopped = samples
            .iter()
            .find(|s| s.t_s > 3.0 && s.speed_mps < 0.05)
            .unwrap_or_else(|| panic!("{name}: never stopped"));
        let end = samples.last().unwrap();
        let distance = end.s_m - start.s_m;
        println!(
            "{name}: from {:.2} m/s, stopped in {distance:.2} m after {:.2} s (ended {:?})",
            start.speed_mps,
            stopped.t_s - 3.0,
            log.iter().map(|f| (f.step, f.kind)).collect::<Vec<_>>()
        );
        assert!((distance - 50.0).abs() <= 7.5, "{name}: {distance} m");
        assert!(end.s_m - stopped.s_m < 0.05, "{name}: crept on");
    }
}

/// A vehicle scripted to stand (a constant 0 profile) stays within 5 cm of where it was
/// put for 30 s, holding its brake.
#[test]
fn a_stopped_vehicle_stays_put() {
    for (name, params) in presets() {
        let (samples, _) = drive(
            &params,
            &straight(100.0),
            SpeedProfile::constant(0.0),
            "",
            30.0,
        );
        let first = samples[0];
        let moved = samples
            .iter()
            .map(|s| ((s.x_m - first.x_m).powi(2) + (s.z_m - first.z_m).powi(2)).sqrt())
            .fold(0.0f32, f32::max);
        let last = samples.last().unwrap();
        println!(
            "{name}: moved {moved:.4} m at most; brake {}",
            last.controls.brake
        );
        assert!(moved < 0.05, "{name}: moved {moved} m");
        assert!(last.controls.brake > 0.0 && last.controls.throttle == 0.0);
    }
}

/// With no events, or events that never fire, the actor's driver computes what the lead's
/// driver does, to the bit, on a winding route with a weave and a stop-and-go profile.
#[test]
fn without_events_it_is_the_lead_driver() {
    let route = RouteBuilder::new(Vector::ZERO, 0.0)
        .straight(60.0)
        .arc(25.0, 1.4)
        .straight(30.0)
        .arc(-30.0, 1.0)
        .straight(200.0)
        .build()
        .unwrap();
    let params = VehicleParams::pickup();
    let profile = SpeedProfile::new(
        ProfileBasis::Time,
        &[
            (0.0, 10.0),
            (8.0, 10.0),
            (8.1, 0.0),
            (11.0, 0.0),
            (14.0, 9.0),
        ],
    )
    .unwrap();
    let config = LeadDriverConfig {
        weave_amplitude_m: 0.5,
        ..LeadDriverConfig::default()
    };
    let run = |events: &str| {
        let mut world = World::new(&WorldConfig::default()).unwrap();
        let start = Pose::from_parts(Vector::ZERO, Rotation::IDENTITY);
        let id = world.add_vehicle(&params, start, 10.0).unwrap();
        let lead =
            LeadDriver::new(route.clone(), profile.clone(), config.clone(), &params).unwrap();
        let mut plain = lead.clone();
        let events = Events::new(&script(events), &["me"], LANES).unwrap();
        let mut actor = ActorDriver::new(lead, events);
        let view = [VehicleView::default()];
        for _ in 0..2400 {
            let state = world.vehicle_state(id);
            let c = plain.update(world.now(), &state);
            let (a, _) = actor.update(world.now(), &state, &view, 0);
            assert_eq!(
                [c.steer_rad, c.throttle, c.brake].map(f32::to_bits),
                [a.steer_rad, a.throttle, a.brake].map(f32::to_bits)
            );
            assert_eq!(
                plain.speed_ref_mps().to_bits(),
                actor.driver().speed_ref_mps().to_bits()
            );
            world.set_controls(id, c);
            world.step();
        }
    };
    run("");
    run(r#"
        [[events]]
        name = "never"
        trigger = { time_s = 1000.0 }
        action = { lane = 2, duration_s = 3.0 }
    "#);
}

/// The same scripted run twice: the same samples and events, bit for bit.
#[test]
fn scripted_runs_repeat_bit_for_bit() {
    let events = r#"
        [[events]]
        name = "out"
        trigger = { distance_m = 40.0 }
        action = { lane = 2, lateral_speed_mps = 1.2, shape = "sinusoidal" }
        [[events]]
        name = "slow"
        trigger = { after = "out", delay_s = 1.0 }
        action = { speed_mps = 6.0, duration_s = 2.0, shape = "cubic" }
        [[events]]
        name = "stop"
        trigger = { time_s = 12.0 }
        action = { stop = true, decel_mps2 = 3.0 }
    "#;
    let run = || {
        drive(
            &VehicleParams::van(),
            &straight(400.0),
            SpeedProfile::constant(12.0),
            events,
            18.0,
        )
    };
    let (a, log_a) = run();
    let (b, log_b) = run();
    assert_eq!(log_a, log_b);
    assert_eq!(log_a.len(), 6, "{log_a:?}");
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        let bits = |s: &Sample| {
            [
                s.s_m,
                s.left_m,
                s.speed_mps,
                s.controls.steer_rad,
                s.controls.throttle,
                s.controls.brake,
            ]
            .map(f32::to_bits)
        };
        assert_eq!(bits(x), bits(y));
    }
}
