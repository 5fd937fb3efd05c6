//! Guarantees that with lane keeping and a cruise speed, and nothing tracked, the chase
//! vehicle (the physics model) steers onto its own lane's centre line and holds the cruise
//! speed, cruising throughout.
//!
//! Run: `cargo test -p vehicle --release --test lane_keeping`

mod common;
use common::*;
use vehicle::*;

#[test]
fn with_nothing_tracked_the_chase_cruises_onto_its_lane() {
    let mut opts = RigOptions::straight(600.0, SpeedProfile::constant(15.0));
    opts.sensor = Sensor::SilentAfter(0.0);
    // The lead far ahead and pulling away: nothing in the chase's way.
    opts.lead_start_m = 150.0;
    opts.initial_gap_m = 100.0;
    opts.chase_config.lane_keeping = true;
    opts.chase_config.cruise_speed_mps = Some(12.0);
    let mut rig = Rig::new(opts);
    // The chase's lane: 1 m to the left of the road's centre line it starts on.
    let lane = RouteBuilder::new(Vector::new(-100.0, 0.0, -1.0), 0.0)
        .straight(800.0)
        .build()
        .unwrap();
    rig.chase.set_lane(lane, 1.75);
    rig.run_for(20.0);
    assert!(rig.chase.events().is_empty(), "{:?}", rig.chase.events());
    assert!(rig
        .samples
        .iter()
        .all(|s| s.telemetry.mode == ChaseMode::Cruising));
    let end = rig.samples.last().unwrap();
    let p = end.chase.world_from_vehicle.translation;
    println!(
        "at 20 s: z {:.3} m, speed {:.3} m/s",
        p.z, end.chase.forward_speed_mps
    );
    for s in rig.samples_after(12.0) {
        let z = s.chase.world_from_vehicle.translation.z;
        assert!((z + 1.0).abs() < 0.1, "lateral error {} m", z + 1.0);
    }
    assert!(
        (end.chase.forward_speed_mps - 12.0).abs() < 0.15,
        "speed {}",
        end.chase.forward_speed_mps
    );
}
