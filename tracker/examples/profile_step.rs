//! Runs the tracker on one synthetic frame many times, for profilers (callgrind, perf):
//! `cargo build --release -p tracker --example profile_step`, then
//! `valgrind --tool=callgrind target/release/examples/profile_step`.

use tracker::synth::{benchmark_frame, nist_ten_segment};
use tracker::{Camera, GrayView, Tracker, TrackerConfig};

fn main() {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let (at, px) = benchmark_frame(&model, &camera);
    let image = GrayView::new(256, 242, &px).expect("frame");
    let mut tracker = Tracker::new(model, camera, TrackerConfig::default(), at).expect("tracker");
    let mut points = 0;
    let started = std::time::Instant::now();
    let n = 2000;
    for k in 0..n {
        let out = tracker.step(image, f64::from(k) / 15.0);
        points += out.features.iter().map(|f| f.points).sum::<usize>();
    }
    let per = started.elapsed().as_secs_f64() / f64::from(n) * 1e6;
    println!(
        "{per:.1} µs per step; {} associated points per frame",
        points / n as usize
    );
}
