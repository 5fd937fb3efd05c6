//! Guarantees the vehicles' physical envelope: the HMMWV reaches 35 km/h and more, stops
//! hard (about 0.8 g) from 36 km/h, respects its steering limit and rate, and pitches and
//! rolls a little (but not much) on the bumpy ground.
//!
//! Run: `CARGO_TARGET_DIR=/work/main/target cargo test -p vehicle --release --test vehicle_dynamics`

use vehicle::*;

fn world_with(ground: GroundConfig) -> (World, VehicleId, VehicleParams) {
    let mut world = World::new(&WorldConfig { ground }).unwrap();
    let params = VehicleParams::hmmwv_m998();
    let id = world
        .add_vehicle(&params, Pose::from_translation(Vector::ZERO), 0.0)
        .unwrap();
    (world, id, params)
}

fn run(world: &mut World, id: VehicleId, controls: Controls, seconds: f32) {
    world.set_controls(id, controls);
    for _ in 0..(seconds * PHYSICS_HZ as f32) as usize {
        world.step();
    }
}

#[test]
fn hmmwv_accelerates_past_35_kmh_and_stops_hard() {
    let (mut world, id, _) = world_with(GroundConfig::default());
    let full = Controls {
        steer_rad: 0.0,
        throttle: 1.0,
        brake: 0.0,
    };
    run(&mut world, id, full, 12.0);
    let top = world.vehicle_state(id).forward_speed_mps * 3.6;
    println!("speed after 12 s full throttle: {top:.1} km/h");
    assert!(top > 40.0, "only {top} km/h");
    assert!(top < 75.0, "{top} km/h: too quick for an M998");

    // Settle to 10 m/s, then full brake.
    let mut speed = SpeedController::new(&VehicleParams::hmmwv_m998(), SpeedGains::default());
    for _ in 0..(20 * PHYSICS_HZ) {
        let v = world.vehicle_state(id).forward_speed_mps;
        let p = speed.update(10.0, 0.0, v, PHYSICS_DT_S);
        world.set_controls(
            id,
            Controls {
                steer_rad: 0.0,
                throttle: p.throttle,
                brake: p.brake,
            },
        );
        world.step();
    }
    let start = world.vehicle_state(id);
    assert!((start.forward_speed_mps - 10.0).abs() < 0.05);
    let mut min_pitch: f32 = 0.0;
    let mut steps = 0;
    world.set_controls(id, Controls::full_brake());
    while world.vehicle_state(id).forward_speed_mps > 0.01 && steps < 10 * PHYSICS_HZ {
        world.step();
        min_pitch = min_pitch.min(world.vehicle_state(id).pitch_rad);
        steps += 1;
    }
    let end = world.vehicle_state(id);
    let distance = end
        .world_from_vehicle
        .translation
        .distance(start.world_from_vehicle.translation);
    let mean_decel = 100.0 / (2.0 * distance);
    println!(
        "full brake from 10 m/s: {distance:.2} m in {:.2} s (mean {mean_decel:.2} m/s²), nose dive {:.2}°",
        steps as f32 / PHYSICS_HZ as f32,
        min_pitch.to_degrees()
    );
    assert!(
        (6.2..=7.5).contains(&distance),
        "stopping distance {distance}"
    );
    assert!(
        min_pitch < -0.5f32.to_radians(),
        "no nose dive under braking"
    );
}

#[test]
fn steering_is_rate_and_angle_limited() {
    let (mut world, id, params) = world_with(GroundConfig::default());
    world.set_controls(
        id,
        Controls {
            steer_rad: 1.0,
            throttle: 0.0,
            brake: 0.0,
        },
    );
    let mut last = 0.0;
    for _ in 0..(3 * PHYSICS_HZ) {
        world.step();
        let s = world.vehicle_state(id).steer_rad;
        assert!(s - last <= params.steer_rate_radps * PHYSICS_DT_S + 1e-6);
        last = s;
    }
    assert!((last - params.max_steer_rad).abs() < 1e-5, "steer {last}");
}

#[test]
fn bumps_pitch_and_roll_the_chassis_gently() {
    let ground = GroundConfig {
        bumps: Some(BumpsConfig {
            half_extent_m: 120.0,
            ..BumpsConfig::default()
        }),
        ..GroundConfig::default()
    };
    let (mut world, id, params) = world_with(ground);
    let mut speed = SpeedController::new(&params, SpeedGains::default());
    let (mut max_pitch, mut max_roll): (f32, f32) = (0.0, 0.0);
    for i in 0..(10 * PHYSICS_HZ) {
        let state = world.vehicle_state(id);
        let p = speed.update(8.0, 0.0, state.forward_speed_mps, PHYSICS_DT_S);
        world.set_controls(
            id,
            Controls {
                steer_rad: 0.05,
                throttle: p.throttle,
                brake: p.brake,
            },
        );
        world.step();
        if i > 3 * PHYSICS_HZ {
            max_pitch = max_pitch.max(state.pitch_rad.abs());
            max_roll = max_roll.max(state.roll_rad.abs());
        }
    }
    println!(
        "on bumps: max |pitch| {:.2}°, max |roll| {:.2}°",
        max_pitch.to_degrees(),
        max_roll.to_degrees()
    );
    for (name, angle) in [("pitch", max_pitch), ("roll", max_roll)] {
        assert!(angle > 0.2f32.to_radians(), "{name} too small: {angle}");
        assert!(angle < 5.0f32.to_radians(), "{name} too large: {angle}");
    }
}
