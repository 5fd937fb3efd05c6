//! Both tracker modes on every synthetic sequence kind, over several seeds: frames lost by
//! the truth, silent frames, and the mean error. Robust mode also starts without a location.
//! Run with `cargo run --release -p tracker --example modes [SEEDS]`.

use tracker::synth::{nist_ten_segment, score_sequence, sequence, SequenceKind};
use tracker::{Camera, Location, Tracker, TrackerConfig, TrackerMode};

fn main() {
    let seeds: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5);
    let model = nist_ten_segment();
    let camera = Camera::default();
    let half = model
        .size_m()
        .map(|m| 0.5 * m * camera.focal_px()[0] / model.nominal_range_m());
    let start = Location::new(128.0, 110.0, 1.0);
    println!("kind     mode         seeds frames lost_truth silent longest_silence tracking searched mean_err_px");
    for kind in SequenceKind::ALL {
        for (name, mode, init) in [
            ("paper", TrackerMode::Paper, true),
            ("robust", TrackerMode::Robust, true),
            ("robust-noinit", TrackerMode::Robust, false),
        ] {
            let (mut frames, mut lost, mut silent, mut longest, mut tracking, mut searched) =
                (0, 0, 0, 0, 0, 0);
            let mut err = 0.0;
            for seed in 1..=seeds {
                let seq = sequence(kind, start, 150, half, seed);
                let config = TrackerConfig {
                    mode,
                    ..TrackerConfig::default()
                };
                let mut t = if init {
                    Tracker::new(model.clone(), camera, config, seq.truth[0]).unwrap()
                } else {
                    Tracker::new_searching(model.clone(), camera, config).unwrap()
                };
                let s = score_sequence(&mut t, &model, &camera, &seq, seed);
                frames += s.frames;
                lost += s.lost_truth;
                silent += s.silent;
                longest = longest.max(s.longest_silence);
                tracking += s.tracking;
                searched += s.searched;
                err += s.mean_error_px / seeds as f64;
            }
            println!(
                "{:<8} {:<13} {seeds:>4} {frames:>6} {lost:>10} {silent:>6} {longest:>15} {tracking:>8} {searched:>8} {err:>11.3}",
                kind.as_str(),
                name
            );
        }
    }
}
