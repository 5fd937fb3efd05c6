//! Guarantees the lead driver's repertoire on the rapier pickup: it weaves within its lane
//! when asked, slows for turns to its lateral-acceleration limit, follows a speed profile
//! against distance, and holds the route's centreline otherwise.
//!
//! Run: `CARGO_TARGET_DIR=/work/main/target cargo test -p vehicle --release --test lead_driver`

use vehicle::*;

struct Drive {
    /// (arc length, left offset, speed) per step.
    track: Vec<(f32, f32, f32)>,
}

fn drive(route: Route, profile: SpeedProfile, config: LeadDriverConfig, seconds: f32) -> Drive {
    let params = VehicleParams::pickup();
    let mut world = World::new(&WorldConfig::default()).unwrap();
    let start = Pose::from_parts(
        route.point_at(0.0),
        Rotation::from_rotation_y(direction_heading(route.tangent_at(0.0))),
    );
    let speed0 = profile.speed_at(0.0);
    let id = world.add_vehicle(&params, start, speed0).unwrap();
    let mut driver = LeadDriver::new(route.clone(), profile, config, &params).unwrap();
    let mut track = Vec::new();
    let mut s_hint = 0.0;
    for _ in 0..(seconds * PHYSICS_HZ as f32) as usize {
        let state = world.vehicle_state(id);
        let c = driver.update(world.now(), &state);
        world.set_controls(id, c);
        world.step();
        let p = route.project_near(state.world_from_vehicle.translation, s_hint, 20.0);
        s_hint = p.s_m;
        track.push((p.s_m, p.left_offset_m, state.forward_speed_mps));
    }
    Drive { track }
}

#[test]
fn weaves_within_the_lane() {
    let route = RouteBuilder::new(Vector::ZERO, 0.0)
        .straight(400.0)
        .build()
        .unwrap();
    let config = LeadDriverConfig {
        weave_amplitude_m: 0.6,
        weave_wavelength_m: 40.0,
        ..LeadDriverConfig::default()
    };
    let d = drive(route, SpeedProfile::constant(10.0), config, 25.0);
    let offsets: Vec<f32> = d.track.iter().skip(600).map(|t| t.1).collect();
    let max = offsets.iter().cloned().fold(f32::MIN, f32::max);
    let min = offsets.iter().cloned().fold(f32::MAX, f32::min);
    println!("weave: offset from {min:.2} to {max:.2} m");
    assert!(max > 0.35 && min < -0.35, "hardly weaves: {min}..{max}");
    assert!(max < 0.9 && min > -0.9, "leaves the lane: {min}..{max}");
}

#[test]
fn without_weave_it_holds_the_centreline_and_slows_for_turns() {
    let radius = 20.0;
    let route = RouteBuilder::new(Vector::ZERO, 0.0)
        .straight(120.0)
        .arc(radius, std::f32::consts::FRAC_PI_2)
        .straight(120.0)
        .build()
        .unwrap();
    let config = LeadDriverConfig::default();
    let turn_speed = (config.max_lateral_accel_mps2 * radius).sqrt();
    let d = drive(route, SpeedProfile::constant(14.0), config, 24.0);
    let in_arc: Vec<&(f32, f32, f32)> = d
        .track
        .iter()
        .filter(|t| t.0 > 125.0 && t.0 < 120.0 + radius * 1.5)
        .collect();
    assert!(!in_arc.is_empty());
    let fastest = in_arc.iter().map(|t| t.2).fold(0.0f32, f32::max);
    let worst_offset = d
        .track
        .iter()
        .skip(240)
        .map(|t| t.1.abs())
        .fold(0.0f32, f32::max);
    let cruise = d.track.iter().find(|t| t.0 > 80.0).unwrap().2;
    println!(
        "cruise {cruise:.2} m/s, fastest in the turn {fastest:.2} m/s (limit {turn_speed:.2}), worst offset {worst_offset:.2} m"
    );
    assert!((cruise - 14.0).abs() < 0.3, "cruise {cruise}");
    assert!(fastest < turn_speed + 0.3, "took the turn at {fastest} m/s");
    assert!(
        worst_offset < 0.5,
        "offset from centreline {worst_offset} m"
    );
}

#[test]
fn follows_a_speed_profile_against_distance() {
    let route = RouteBuilder::new(Vector::ZERO, 0.0)
        .straight(500.0)
        .build()
        .unwrap();
    let profile = SpeedProfile::new(
        ProfileBasis::Distance,
        &[(0.0, 6.0), (50.0, 6.0), (100.0, 12.0), (400.0, 12.0)],
    )
    .unwrap();
    let d = drive(route, profile.clone(), LeadDriverConfig::default(), 30.0);
    for at in [40.0f32, 90.0, 200.0] {
        let t = d.track.iter().find(|t| t.0 >= at).unwrap();
        println!(
            "at {at} m: {:.2} m/s (profile {:.2})",
            t.2,
            profile.speed_at(at)
        );
        assert!((t.2 - profile.speed_at(at)).abs() < 0.5);
    }
}
