//! Guarantees that with perfect (ground-truth) sensing through the default 128 ms delay
//! line, the chase vehicle holds the commanded gap to within ±0.5 m at steady speed, for
//! both gap policies, starting 3 m off the wanted gap.
//!
//! Run: `CARGO_TARGET_DIR=/work/main/target cargo test -p vehicle --release --test gap_keeping`

mod common;
use common::*;
use vehicle::*;

fn gap_error_after_settling(chase_config: ChaseControllerConfig, speed_mps: f32) -> (f32, f32) {
    let mut opts = RigOptions::straight(900.0, SpeedProfile::constant(speed_mps));
    opts.initial_speed_mps = speed_mps;
    opts.initial_gap_m = 13.0;
    opts.chase_config = chase_config;
    let mut rig = Rig::new(opts);
    rig.run_for(40.0);
    let mut worst: f32 = 0.0;
    let mut wanted = 0.0;
    for s in rig.samples_after(25.0) {
        wanted = s.telemetry.desired_gap_m;
        worst = worst.max((s.gap_m - wanted).abs());
    }
    (worst, wanted)
}

#[test]
fn constant_distance_gap_is_held_within_half_a_metre() {
    let (worst, wanted) = gap_error_after_settling(ChaseControllerConfig::default(), 10.0);
    println!("constant 10 m gap at 10 m/s: worst error {worst:.3} m");
    assert_eq!(wanted, 10.0);
    assert!(worst <= 0.5, "gap error {worst} m exceeds 0.5 m");
}

#[test]
fn time_headway_gap_is_held_within_half_a_metre() {
    let config = ChaseControllerConfig {
        gap_keeper: GapKeeperConfig {
            policy: GapPolicy::TimeHeadway {
                standstill_gap_m: 3.0,
                headway_s: 0.8,
            },
            ..GapKeeperConfig::default()
        },
        ..ChaseControllerConfig::default()
    };
    let (worst, wanted) = gap_error_after_settling(config, 9.0);
    println!("time headway at 9 m/s: wanted {wanted:.2} m, worst error {worst:.3} m");
    assert!((wanted - 10.2).abs() < 0.2, "wanted gap {wanted}");
    assert!(worst <= 0.5, "gap error {worst} m exceeds 0.5 m");
}
