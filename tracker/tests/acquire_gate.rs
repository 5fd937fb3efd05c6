//! Robust mode's whole-image search keeps only fits inside its acquisition gate: a target
//! outside the gate's columns is not acquired, one inside is, and a target released is
//! searched for again. Run with `cargo test --release -p tracker --test
//! acquire_gate`.

use tracker::synth::{benchmark_frame, nist_ten_segment};
use tracker::{AcquireGate, Camera, GrayView, Status, Tracker, TrackerConfig, TrackerMode};

fn searching() -> (Tracker, tracker::Location, Vec<u8>) {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let (at, pixels) = benchmark_frame(&model, &camera);
    let config = TrackerConfig {
        mode: TrackerMode::Robust,
        ..TrackerConfig::default()
    };
    let tracker = Tracker::new_searching(model, camera, config).unwrap();
    (tracker, at, pixels)
}

/// A gate of the columns `[lo, hi]` at every scale the search tries.
fn columns(lo: f64, hi: f64) -> AcquireGate {
    AcquireGate::columns(lo, hi, [0.1, 10.0])
}

#[test]
fn a_target_outside_the_gate_is_not_acquired_and_one_inside_is() {
    let (mut outside, at, pixels) = searching();
    let image = GrayView::new(256, 242, &pixels).unwrap();
    outside.set_acquire_gate(Some(columns(at.c_x + 30.0, at.c_x + 90.0)));
    for k in 0..3 {
        let out = outside.step(image, k as f64 / 15.0);
        assert_eq!(
            out.status,
            Status::Lost,
            "frame {k}: acquired outside the gate"
        );
    }
    let (mut inside, _, _) = searching();
    inside.set_acquire_gate(Some(columns(at.c_x - 10.0, at.c_x + 10.0)));
    let out = inside.step(image, 0.0);
    assert_eq!(out.status, Status::Tracking);
    assert!((out.estimate.c_x - at.c_x).abs() < 2.0 && (out.estimate.c_y - at.c_y).abs() < 2.0);
    // Released, it searches again (and, the gate now elsewhere, finds nothing).
    inside.release();
    assert!(!inside.is_locked());
    inside.set_acquire_gate(Some(columns(at.c_x + 30.0, at.c_x + 90.0)));
    assert_eq!(inside.step(image, 1.0 / 15.0).status, Status::Lost);
}
