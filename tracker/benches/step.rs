//! One full tracker step (stages 1–8) on a 256×242 frame with the target at scale 1, the
//! paper's configuration, with sub-pixel edges, and in robust mode; robust mode's recovery
//! frames (a search near the prediction, a whole-image acquisition, on the benchmark frame
//! and on a textured one with poles); plus stage 1 alone.
//! Run with `cargo bench -p tracker`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use tracker::edges::EdgeExtractor;
use tracker::synth::{benchmark_frame, nist_ten_segment};
use tracker::{Camera, Edges, GrayView, Location, Tracker, TrackerConfig, TrackerMode, Window};

fn bench(c: &mut Criterion) {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let (at, px) = benchmark_frame(&model, &camera);
    let image = GrayView::new(256, 242, &px).unwrap();

    for (name, subpixel_edges, mode) in [
        ("tracker_step_paper", false, TrackerMode::Paper),
        ("tracker_step_subpixel", true, TrackerMode::Paper),
        ("tracker_step_robust", false, TrackerMode::Robust),
    ] {
        let config = TrackerConfig {
            subpixel_edges,
            mode,
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

    // Robust mode's recovery frames, measured apart: each iteration starts a tracker 10 px
    // off the target, so its measurement fails its check and it searches near its
    // prediction; and a tracker with no start, which searches the whole image over scale.
    let robust = TrackerConfig {
        mode: TrackerMode::Robust,
        ..TrackerConfig::default()
    };
    let off = Location::new(at.c_x + 10.0, at.c_y + 6.0, at.scale);
    let fresh = Tracker::new(model.clone(), camera, robust.clone(), off).unwrap();
    assert!(fresh.clone().step(image, 0.0).searched);
    c.bench_function("tracker_recovery_search_robust", |b| {
        b.iter_batched(
            || fresh.clone(),
            |mut t| black_box(t.step(black_box(image), 0.0)),
            criterion::BatchSize::SmallInput,
        )
    });
    let searching = Tracker::new_searching(model.clone(), camera, robust).unwrap();
    assert!(searching.clone().step(image, 0.0).event.is_some());
    c.bench_function("tracker_acquire_whole_image_robust", |b| {
        b.iter_batched(
            || searching.clone(),
            |mut t| black_box(t.step(black_box(image), 0.0)),
            criterion::BatchSize::SmallInput,
        )
    });

    // The same search on a textured background with poles, as a road scene's clutter is:
    // most of the image's positions score far from the target there.
    let scene = tracker::synth::SynthScene {
        noise_sigma: 2.0,
        texture: Some(tracker::synth::Texture {
            seed: 7,
            contrast: 0.35,
        }),
        distractors: [20.0, 70.0, 180.0, 230.0]
            .map(|x| tracker::synth::Rect {
                bounds: [x, 0.0, x + 3.0, 242.0],
                value: 60.0,
            })
            .to_vec(),
        ..Default::default()
    };
    let textured = tracker::synth::draw(&model, &camera, at, &scene, 1);
    let textured = GrayView::new(256, 242, &textured).unwrap();
    assert!(searching.clone().step(textured, 0.0).event.is_some());
    c.bench_function("tracker_acquire_whole_image_robust_textured", |b| {
        b.iter_batched(
            || searching.clone(),
            |mut t| black_box(t.step(black_box(textured), 0.0)),
            criterion::BatchSize::SmallInput,
        )
    });

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
