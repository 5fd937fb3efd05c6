//! One sequence, frame by frame (SYNTH_TRACE output): `cargo run --release -p tracker
//! --example trace KIND MODE SEED [noinit]`.

use tracker::synth::{nist_ten_segment, score_sequence, sequence, SequenceKind};
use tracker::{Camera, Location, Tracker, TrackerConfig, TrackerMode};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let kind = SequenceKind::parse(&a[1]).unwrap();
    let mode = if a[2] == "robust" {
        TrackerMode::Robust
    } else {
        TrackerMode::Paper
    };
    let seed: u64 = a[3].parse().unwrap();
    let model = nist_ten_segment();
    let camera = Camera::default();
    let half = model
        .size_m()
        .map(|m| 0.5 * m * camera.focal_px()[0] / model.nominal_range_m());
    let seq = sequence(kind, Location::new(128.0, 110.0, 1.0), 150, half, seed);
    let config = TrackerConfig {
        mode,
        ..TrackerConfig::default()
    };
    let mut t = if a.len() > 4 {
        Tracker::new_searching(model.clone(), camera, config).unwrap()
    } else {
        Tracker::new(model.clone(), camera, config, seq.truth[0]).unwrap()
    };
    std::env::set_var("SYNTH_TRACE", "1");
    let s = score_sequence(&mut t, &model, &camera, &seq, seed);
    println!("{s:?}");
}
