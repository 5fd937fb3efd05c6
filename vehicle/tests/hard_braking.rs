//! Guarantees that when the lead brakes as hard as it can (0.85 g) from the default speed
//! (10 m/s = 36 km/h) at the default gap (10 m), the chase vehicle, seeing it only through
//! the 128 ms delay line, stops without touching it.
//!
//! Run: `CARGO_TARGET_DIR=/work/main/target cargo test -p vehicle --release --test hard_braking`

mod common;
use common::*;
use vehicle::*;

#[test]
fn chase_stops_without_collision_when_the_lead_brakes_hard() {
    let profile =
        SpeedProfile::new(ProfileBasis::Time, &[(0.0, 10.0), (8.0, 10.0), (8.01, 0.0)]).unwrap();
    let mut rig = Rig::new(RigOptions::straight(600.0, profile));
    rig.run_for(16.0);

    let brake_start = rig
        .samples
        .iter()
        .find(|s| s.step.seconds() >= 8.0)
        .unwrap()
        .chase
        .world_from_vehicle
        .translation;
    let end = rig.samples.last().unwrap();
    let stopping_distance = end
        .chase
        .world_from_vehicle
        .translation
        .distance(brake_start);
    let min_bumper_gap = rig
        .samples
        .iter()
        .map(|s| s.bumper_gap_m)
        .fold(f32::INFINITY, f32::min);
    let peak_decel = rig
        .samples
        .windows(2)
        .map(|w| (w[0].chase.forward_speed_mps - w[1].chase.forward_speed_mps) * PHYSICS_HZ as f32)
        .fold(0.0f32, f32::max);
    let touched = rig.samples.iter().any(|s| s.touching);
    println!(
        "stopping distance {stopping_distance:.2} m, min bumper gap {min_bumper_gap:.2} m, final gap {:.2} m, peak decel {peak_decel:.1} m/s², events {:?}",
        end.gap_m,
        rig.chase.events()
    );
    assert!(!touched, "the vehicles touched");
    assert!(
        min_bumper_gap > 0.5,
        "bumpers came within {min_bumper_gap} m"
    );
    assert!(
        end.chase.forward_speed_mps.abs() < 0.1,
        "chase still moving"
    );
    assert!(end.lead.forward_speed_mps.abs() < 0.1, "lead still moving");
}
