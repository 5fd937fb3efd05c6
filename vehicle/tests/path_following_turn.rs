//! Guarantees that with perfect (ground-truth) sensing through the default 128 ms delay
//! line, the chase vehicle follows the lead's path through a 90° turn (20 m radius) with a
//! small lateral error: its rear axle stays within 0.5 m of the lead's rear-axle track; and
//! that it follows a lead weaving within its lane.
//!
//! Run: `CARGO_TARGET_DIR=/work/main/target cargo test -p vehicle --release --test path_following_turn`

mod common;
use common::*;
use vehicle::*;

fn lateral_errors(turn_deg: f32) -> (f32, f32) {
    let route = RouteBuilder::new(Vector::ZERO, 0.0)
        .straight(100.0)
        .arc(20.0, turn_deg.to_radians())
        .straight(150.0)
        .build()
        .unwrap();
    let mut opts = RigOptions::straight(10.0, SpeedProfile::constant(9.0));
    opts.route = route;
    opts.initial_speed_mps = 9.0;
    let mut rig = Rig::new(opts);
    rig.run_for(26.0);
    let lead_track: Vec<Vector> = rig
        .samples
        .iter()
        .map(|s| s.lead.world_from_vehicle.translation)
        .collect();
    // Judge the chase once it is on the lead's track (after 3 s), until it nears the end of
    // the recorded track.
    let mut worst: f32 = 0.0;
    let mut sum_sq = 0.0;
    let mut n = 0;
    for s in rig.samples_after(3.0) {
        if s.step.seconds() > 22.0 {
            break;
        }
        let e = distance_to_polyline(&lead_track, s.chase.world_from_vehicle.translation);
        worst = worst.max(e);
        sum_sq += e * e;
        n += 1;
    }
    let end = rig.samples.last().unwrap();
    let heading = direction_heading(end.chase.world_from_vehicle.rotation * Vector::X);
    println!(
        "{turn_deg}° turn: worst lateral error {worst:.3} m, rms {:.3} m, final heading {:.1}°, speed {:.2} m/s",
        (sum_sq / n as f32).sqrt(),
        heading.to_degrees(),
        end.chase.forward_speed_mps
    );
    assert!(
        (heading.to_degrees() - turn_deg).abs() < 3.0,
        "chase did not make the turn: heading {}",
        heading.to_degrees()
    );
    (worst, (sum_sq / n as f32).sqrt())
}

#[test]
fn follows_the_lead_through_a_left_90_degree_turn() {
    let (worst, rms) = lateral_errors(90.0);
    assert!(worst < 0.5, "worst lateral error {worst} m");
    assert!(rms < 0.2, "rms lateral error {rms} m");
}

#[test]
fn follows_the_lead_through_a_right_90_degree_turn() {
    let (worst, rms) = lateral_errors(-90.0);
    assert!(worst < 0.5, "worst lateral error {worst} m");
    assert!(rms < 0.2, "rms lateral error {rms} m");
}

#[test]
fn follows_a_weaving_lead_within_its_lane() {
    let mut opts = RigOptions::straight(500.0, SpeedProfile::constant(9.0));
    opts.initial_speed_mps = 9.0;
    opts.lead_config.weave_amplitude_m = 0.6;
    opts.lead_config.weave_wavelength_m = 40.0;
    let mut rig = Rig::new(opts);
    rig.run_for(30.0);
    let lead_track: Vec<Vector> = rig
        .samples
        .iter()
        .map(|s| s.lead.world_from_vehicle.translation)
        .collect();
    let worst = rig
        .samples_after(5.0)
        .filter(|s| s.step.seconds() < 27.0)
        .map(|s| distance_to_polyline(&lead_track, s.chase.world_from_vehicle.translation))
        .fold(0.0f32, f32::max);
    let chase_swing = rig
        .samples_after(5.0)
        .map(|s| s.chase.world_from_vehicle.translation.z.abs())
        .fold(0.0f32, f32::max);
    println!("weaving lead: worst lateral error {worst:.3} m, chase swings {chase_swing:.2} m");
    assert!(chase_swing > 0.3, "the chase does not follow the weave");
    assert!(worst < 0.3, "worst lateral error {worst} m");
}
