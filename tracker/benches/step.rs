//! One full tracker step (stages 1–8) on a 256×242 frame with the target at scale 1, the
//! paper's configuration, and with sub-pixel edges; plus stage 1 alone.
//! Run with `cargo bench -p tracker`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use tracker::edges::EdgeExtractor;
use tracker::synth::{benchmark_frame, nist_ten_segment};
use tracker::{Camera, Edges, GrayView, Tracker, TrackerConfig, Window};

fn bench(c: &mut Criterion) {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let (at, px) = benchmark_frame(&model, &camera);
    let image = GrayView::new(256, 242, &px).unwrap();

    for (name, subpixel_edges) in [
        ("tracker_step_paper", false),
        ("tracker_step_subpixel", true),
    ] {
        let config = TrackerConfig {
            subpixel_edges,
            ..TrackerConfig::default()
        };
        let mut tracker = Tracker::new(model.clone(), camera, config, at).unwrap();
        let mut t = 0.0;
        c.bench_function(name, |b| {
            b.iter(|| {
                // The same frame again and again: the target is still, so the tracker holds it.
                t += 1.0 / 15.0;
                black_box(tracker.step(black_box(image), t))
            })
        });
    }

    let mut tracker = Tracker::new(model.clone(), camera, TrackerConfig::default(), at).unwrap();
    let window = tracker.step(image, 0.0).window;
    let mut extractor = EdgeExtractor::default();
    let mut edges = Edges::default();
    let config = TrackerConfig::default();
    c.bench_function("stage1_edges_window", |b| {
        b.iter(|| extractor.extract(black_box(image), window, &config, &mut edges, None))
    });
    let full = Window {
        x0: 1,
        y0: 1,
        x1: 255,
        y1: 241,
        size_index: 6,
    };
    c.bench_function("stage1_edges_full_frame", |b| {
        b.iter(|| extractor.extract(black_box(image), full, &config, &mut edges, None))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
