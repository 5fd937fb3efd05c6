//! Guarantees that the chase controller copes with a tracker's noise: with seeded Gaussian
//! noise on the stand-in tracker's output (1 % of range along the line of sight, 5 cm
//! across it), a jittery (±30 ms) delay line that drops 5 % of the frames, the chase
//! vehicle still holds its gap and the lead's path through a turn, and never calls a false
//! emergency brake.
//!
//! Run: `CARGO_TARGET_DIR=/work/main/target cargo test -p vehicle --release --test noisy_following`

mod common;
use common::*;
use vehicle::*;

#[test]
fn noisy_lossy_sensing_still_follows_without_false_alarms() {
    let route = RouteBuilder::new(Vector::ZERO, 0.0)
        .straight(150.0)
        .arc(25.0, std::f32::consts::FRAC_PI_2)
        .straight(200.0)
        .build()
        .unwrap();
    let mut opts = RigOptions::straight(10.0, SpeedProfile::constant(9.0));
    opts.route = route;
    opts.initial_speed_mps = 9.0;
    // A constant gap and no curve-aware cap, so that what is measured is the noise's
    // effect alone (the default time gap moves its aim with the noisy speed, and the cap
    // shortens it in the 25 m turn).
    opts.chase_config.gap_keeper.policy = GapPolicy::ConstantDistance { gap_m: 10.0 };
    opts.chase_config.curve_aware_gap = false;
    opts.noise = Some(SensorNoise {
        lateral_sigma_m: 0.05,
        range_sigma_fraction: 0.01,
        seed: 3,
    });
    opts.delay = DelayLineConfig {
        jitter_ms: 30.0,
        drop_probability: 0.05,
        seed: 3,
        ..DelayLineConfig::default()
    };
    let mut rig = Rig::new(opts);
    rig.run_for(35.0);

    let lead_track: Vec<Vector> = rig
        .samples
        .iter()
        .map(|s| s.lead.world_from_vehicle.translation)
        .collect();
    let (mut worst_gap, mut sum_gap_sq, mut worst_lateral, mut n) = (0.0f32, 0.0f32, 0.0f32, 0);
    let mut worst_accel: f32 = 0.0;
    for w in rig.samples.windows(2).skip(5 * PHYSICS_HZ as usize) {
        let s = &w[1];
        if s.step.seconds() > 31.0 {
            break;
        }
        let e = s.gap_m - s.telemetry.desired_gap_m;
        worst_gap = worst_gap.max(e.abs());
        sum_gap_sq += e * e;
        worst_lateral = worst_lateral.max(distance_to_polyline(
            &lead_track,
            s.chase.world_from_vehicle.translation,
        ));
        worst_accel = worst_accel.max(
            ((s.chase.forward_speed_mps - w[0].chase.forward_speed_mps) * PHYSICS_HZ as f32).abs(),
        );
        n += 1;
    }
    let rms_gap = (sum_gap_sq / n as f32).sqrt();
    println!(
        "noisy: gap error rms {rms_gap:.3} m, worst {worst_gap:.3} m; worst lateral {worst_lateral:.3} m; worst |accel| {worst_accel:.2} m/s²; dropped {}; events {:?}",
        rig.delay.dropped(),
        rig.chase.events()
    );
    assert!(
        rig.chase.events().is_empty(),
        "false alarms: {:?}",
        rig.chase.events()
    );
    // Measured (seed 3): rms 0.48 m, worst 1.63 m (while the lead slows for the turn and
    // speeds up out of it; perfect sensing gives 0.64 m there).
    assert!(rms_gap < 0.6, "rms gap error {rms_gap}");
    assert!(worst_gap < 2.0, "worst gap error {worst_gap}");
    assert!(worst_lateral < 0.6, "worst lateral error {worst_lateral}");
}
