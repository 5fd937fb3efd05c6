//! `Tracker::last_read` bounds every pixel a step reads: the same state stepped on an image
//! that agrees with the frame only inside that rectangle (everything outside replaced by
//! unrelated grey levels) gives the same output, bit for bit, in both modes, while tracking,
//! searching near a prediction and acquiring. A renderer that draws only that part of a
//! frame relies on it. Run with `cargo test --release -p tracker --test read_region`.

use tracker::synth::{draw, nist_ten_segment, sequence, SequenceKind};
use tracker::{Camera, GrayView, Location, PixelRect, Tracker, TrackerConfig, TrackerMode};

const FRAMES: usize = 90;

/// `pixels` with everything outside `keep` replaced by a pattern unrelated to the frame.
fn masked(pixels: &[u8], width: usize, keep: PixelRect, k: usize) -> Vec<u8> {
    pixels
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let (x, y) = (i % width, i / width);
            let inside = (keep.x0..keep.x1).contains(&x) && (keep.y0..keep.y1).contains(&y);
            if inside {
                p
            } else {
                ((x * 37 + y * 101 + k * 13) % 251) as u8
            }
        })
        .collect()
}

fn check(kind: SequenceKind, mode: TrackerMode, start_on_target: bool) -> (usize, usize) {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let half = model
        .size_m()
        .map(|m| 0.5 * m * camera.focal_px()[0] / model.nominal_range_m());
    let seq = sequence(kind, Location::new(128.0, 110.0, 1.0), FRAMES, half, 7);
    let config = TrackerConfig {
        mode,
        ..TrackerConfig::default()
    };
    let mut tracker = if start_on_target {
        Tracker::new(model.clone(), camera, config, seq.truth[0]).unwrap()
    } else {
        Tracker::new_searching(model.clone(), camera, config).unwrap()
    };
    let (mut partial, mut whole) = (0, 0);
    for (k, (at, scene)) in seq.truth.iter().zip(&seq.scenes).enumerate() {
        let (w, h) = (scene.width, scene.height);
        let pixels = draw(&model, &camera, *at, scene, k as u64);
        let before = tracker.clone();
        let t_s = k as f64 / 15.0;
        let (full, full_edges) =
            tracker.step_with_diagnostics(GrayView::new(w, h, &pixels).unwrap(), t_s);
        let read = tracker.last_read();
        // (A window wholly outside the image reads nothing.)
        if !read.is_empty() && read != PixelRect::whole(w, h) {
            partial += 1;
        } else {
            whole += 1;
        }
        let other = masked(&pixels, w, read, k);
        let mut again = before;
        let (out, edges) = again.step_with_diagnostics(GrayView::new(w, h, &other).unwrap(), t_s);
        assert_eq!(out, full, "{kind:?} {mode:?} frame {k}: output differs");
        assert_eq!(
            edges, full_edges,
            "{kind:?} {mode:?} frame {k}: edges differ"
        );
        assert_eq!(again.last_read(), read);
    }
    (partial, whole)
}

#[test]
fn a_step_reads_nothing_outside_its_last_read() {
    // (The paper's mode loses the shaken sequence, and its window leaves the image.)
    let (mut partial, mut steps) = (0, 0);
    for kind in SequenceKind::ALL {
        for mode in [TrackerMode::Paper, TrackerMode::Robust] {
            partial += check(kind, mode, true).0;
            steps += FRAMES;
        }
    }
    assert!(
        partial > steps * 3 / 4,
        "only {partial} of {steps} steps read part of the frame"
    );
}

#[test]
fn an_acquiring_step_reads_the_whole_frame_and_then_less() {
    let (partial, whole) = check(SequenceKind::Clutter, TrackerMode::Robust, false);
    assert!(whole >= 1, "the acquisition reads the whole frame");
    assert!(partial >= 1, "once locked, steps read part of the frame");
}
