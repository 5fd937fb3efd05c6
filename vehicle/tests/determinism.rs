//! Guarantees that identical runs are bit-identical: the whole closed loop (bumpy ground,
//! weaving lead, jittery and lossy delay line) run twice gives the same poses, speeds and
//! commands to the last bit, while another seed gives a different run (so the comparison
//! can fail).
//!
//! Run: `CARGO_TARGET_DIR=/work/main/target cargo test -p vehicle --release --test determinism`

mod common;
use common::*;
use vehicle::*;

/// Every float of a run, as bits.
fn fingerprint(seed: u64) -> Vec<u32> {
    let route = RouteBuilder::new(Vector::ZERO, 0.0)
        .straight(60.0)
        .arc(25.0, 1.2)
        .straight(100.0)
        .build()
        .unwrap();
    let mut opts = RigOptions::straight(10.0, SpeedProfile::constant(8.0));
    opts.route = route;
    opts.initial_speed_mps = 8.0;
    opts.lead_config.weave_amplitude_m = 0.5;
    opts.world = WorldConfig {
        ground: GroundConfig {
            bumps: Some(BumpsConfig {
                half_extent_m: 150.0,
                seed,
                ..BumpsConfig::default()
            }),
            ..GroundConfig::default()
        },
    };
    opts.delay = DelayLineConfig {
        jitter_ms: 30.0,
        drop_probability: 0.1,
        seed,
        ..DelayLineConfig::default()
    };
    let mut rig = Rig::new(opts);
    rig.run_for(12.0);
    let mut bits = Vec::new();
    for s in &rig.samples {
        for state in [s.chase, s.lead] {
            let p = state.world_from_vehicle;
            bits.extend(p.translation.to_array().map(f32::to_bits));
            bits.extend(p.rotation.to_array().map(f32::to_bits));
            bits.push(state.forward_speed_mps.to_bits());
        }
        let c = s.chase_controls;
        bits.extend([c.steer_rad, c.throttle, c.brake].map(f32::to_bits));
    }
    bits
}

#[test]
fn identical_runs_are_bit_identical() {
    let a = fingerprint(7);
    let b = fingerprint(7);
    assert_eq!(a.len(), b.len());
    let first_difference = a.iter().zip(&b).position(|(x, y)| x != y);
    assert_eq!(
        first_difference, None,
        "runs differ at value {first_difference:?}"
    );
    let c = fingerprint(8);
    assert_ne!(a, c, "a different seed should change the run");
}
