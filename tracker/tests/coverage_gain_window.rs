//! The coverage-gain test (`tracker::robust::coverage_gain`) reads only
//! `coverage_gain_window`, and counts its 25 coverages from maps spread across the features:
//! over that box it gives exactly the gain of moving each feature and counting its samples
//! (`EdgeMaps::coverage_counts`) over the whole window the box lies in, for any features,
//! alias spacings, images and edge settings. The tracker reads that box rather than its
//! window grown by the largest move, so this is what keeps its coverage checks (and every
//! estimate) as they were. Run with `cargo test --release -p tracker --test
//! coverage_gain_window`.

use proptest::prelude::*;
use tracker::edges::EdgeExtractor;
use tracker::prediction::PredictedFeature;
use tracker::robust::{coverage_gain, coverage_gain_window, EdgeMaps, SpreadMaps, PEAK_PROBE_PX};
use tracker::window::Window;
use tracker::{Edges, GrayView, Orientation, TrackerConfig};

const W: usize = 96;
const H: usize = 80;

/// An image of a few bright and dark rectangles over noise of `noise` grey levels at most:
/// edges of both classes, strong and weak, near every part of the window. Without noise a
/// rectangle's sides are ties of the edge suppression, whose sub-pixel points round into
/// the neighbouring pixel.
fn image(rects: &[(usize, usize, usize, usize, u8)], seed: u64, noise: u64) -> Vec<u8> {
    let mut px: Vec<u8> = (0..W * H)
        .map(|i| {
            let h = (i as u64 ^ seed).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 58;
            100 + (h % (noise + 1)) as u8
        })
        .collect();
    for &(x, y, w, h, g) in rects {
        for yy in y..(y + h).min(H) {
            for xx in x..(x + w).min(W) {
                px[yy * W + xx] = g;
            }
        }
    }
    px
}

/// Edge maps over `over`.
fn maps_over(px: &[u8], over: Window, config: &TrackerConfig) -> EdgeMaps {
    let view = GrayView::new(W, H, px).unwrap();
    let (mut extractor, mut edges, mut maps) = (
        EdgeExtractor::default(),
        Edges::default(),
        EdgeMaps::default(),
    );
    extractor.extract(view, over, config, &mut edges, None);
    maps.build(&edges, over);
    maps
}

/// The gain as the test defines it, the long way: each of the 24 moves applied to every
/// feature, and every sample counted in `maps`.
fn gain_by_moving(maps: &EdgeMaps, features: &[PredictedFeature], alias: [f64; 2]) -> f64 {
    let total = |(c, n): ([f64; 2], [usize; 2])| {
        let all = n[0] + n[1];
        if all == 0 {
            0.0
        } else {
            (c[0] * n[0] as f64 + c[1] * n[1] as f64) / all as f64
        }
    };
    let here = total(maps.coverage_counts(features));
    let p = PEAK_PROBE_PX;
    let xs = [-alias[0], -p, 0.0, p, alias[0]];
    let ys = [-alias[1], -p, 0.0, p, alias[1]];
    let mut gain = f64::NEG_INFINITY;
    for &dx in &xs {
        for &dy in &ys {
            if !(dx.is_finite() && dy.is_finite()) || (dx == 0.0 && dy == 0.0) {
                continue;
            }
            let moved: Vec<PredictedFeature> = features
                .iter()
                .map(|f| {
                    let (across, along) = match f.orientation {
                        Orientation::Horizontal => (dy, dx),
                        Orientation::Vertical => (dx, dy),
                    };
                    PredictedFeature {
                        intercept: f.intercept + across,
                        extent: [f.extent[0] + along, f.extent[1] + along],
                        ..*f
                    }
                })
                .collect();
            gain = gain.max(total(maps.coverage_counts(&moved)) - here);
        }
    }
    gain
}

/// The test's gain over the box against the long way's over the whole window, as bits.
fn both(
    px: &[u8],
    within: Window,
    features: &[PredictedFeature],
    alias: [f64; 2],
    config: &TrackerConfig,
) -> (u64, u64) {
    let the_box = coverage_gain_window(features, alias, within);
    let fast = coverage_gain(
        &maps_over(px, the_box, config),
        features,
        alias,
        &mut SpreadMaps::default(),
    );
    let long = gain_by_moving(&maps_over(px, within, config), features, alias);
    (fast.to_bits(), long.to_bits())
}

fn feature() -> impl Strategy<Value = PredictedFeature> {
    (
        any::<bool>(),
        -10.0..100.0f64,
        -10.0..100.0f64,
        0.0..40.0f64,
    )
        .prop_map(|(horizontal, intercept, from, length)| PredictedFeature {
            segment: 0,
            orientation: if horizontal {
                Orientation::Horizontal
            } else {
                Orientation::Vertical
            },
            intercept,
            extent: [from, from + length],
        })
}

fn alias() -> impl Strategy<Value = f64> {
    prop_oneof![0.0..30.0f64, Just(f64::INFINITY), Just(f64::NAN)]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn maps_over_the_box_answer_as_maps_over_the_window(
        features in prop::collection::vec(feature(), 0..8),
        alias_x in alias(),
        alias_y in alias(),
        rects in prop::collection::vec((0..W, 0..H, 1..40usize, 1..40usize, any::<u8>()), 1..6),
        seed in any::<u64>(),
        noise in prop_oneof![Just(0u64), 1..32u64],
        corner in (1..30usize, 1..30usize),
        size in (10..70usize, 10..60usize),
        subpixel in any::<bool>(),
        threshold in 2.0..20.0f64,
    ) {
        let px = image(&rects, seed, noise);
        let within = Window {
            x0: corner.0,
            y0: corner.1,
            x1: (corner.0 + size.0).min(W - 1),
            y1: (corner.1 + size.1).min(H - 1),
            size_index: 0,
        };
        let config = TrackerConfig {
            subpixel_edges: subpixel,
            edge_threshold: threshold,
            ..TrackerConfig::default()
        };
        let alias = [alias_x, alias_y];
        let the_box = coverage_gain_window(&features, alias, within);
        prop_assert!(the_box.x0 >= within.x0 && the_box.x1 <= within.x1);
        prop_assert!(the_box.y0 >= within.y0 && the_box.y1 <= within.y1);
        prop_assert!(the_box.x0 <= the_box.x1 && the_box.y0 <= the_box.y1);
        let (fast, long) = both(&px, within, &features, alias, &config);
        prop_assert_eq!(fast, long);
    }
}

/// The box is the samples' reach, not the window grown by the largest move: a board's
/// features in the middle of a window of twice its size need nothing outside that window.
#[test]
fn the_box_of_a_centred_target_lies_inside_its_window() {
    let feature = |orientation, intercept, extent| PredictedFeature {
        segment: 0,
        orientation,
        intercept,
        extent,
    };
    let features = [
        feature(Orientation::Horizontal, 30.0, [30.0, 60.0]),
        feature(Orientation::Horizontal, 50.0, [30.0, 60.0]),
        feature(Orientation::Vertical, 30.0, [30.0, 50.0]),
        feature(Orientation::Vertical, 60.0, [30.0, 50.0]),
    ];
    let window = Window {
        x0: 15,
        y0: 20,
        x1: 76,
        y1: 61,
        size_index: 0,
    };
    let grown = Window {
        x0: 1,
        y0: 1,
        x1: 95,
        y1: 79,
        ..window
    };
    let the_box = coverage_gain_window(&features, [10.0, 8.0], grown);
    // x from 30 − 10 − 2 (the tolerance) − 1 (a sub-pixel point's rounding) to one past
    // 60 + 10 + 2 + 1; y likewise with 8.
    assert_eq!(
        (the_box.x0, the_box.y0, the_box.x1, the_box.y1),
        (17, 19, 74, 62)
    );
    assert!(the_box.x0 >= window.x0 && the_box.x1 <= window.x1);
}

/// A sub-pixel edge point one row outside the samples' reach rounds into it: a clean step
/// between rows 27 and 28 is a tie of the suppression, whose point (row 27) is placed half
/// a pixel down, at row 28, the lowest row the move of −10 px reaches (40 − 10 − 2). The box
/// must take row 27 in for that move to see it.
#[test]
fn the_box_takes_in_the_points_that_round_into_it() {
    let px: Vec<u8> = (0..W * H)
        .map(|i| if i / W < 28 { 60 } else { 160 })
        .collect();
    let features = [PredictedFeature {
        segment: 0,
        orientation: Orientation::Horizontal,
        intercept: 40.0,
        extent: [20.0, 60.0],
    }];
    let within = Window {
        x0: 1,
        y0: 1,
        x1: W - 1,
        y1: H - 1,
        size_index: 0,
    };
    let config = TrackerConfig {
        subpixel_edges: true,
        ..TrackerConfig::default()
    };
    let alias = [f64::INFINITY, 10.0];
    let the_box = coverage_gain_window(&features, alias, within);
    assert_eq!(the_box.y0, 27);
    let (fast, long) = both(&px, within, &features, alias, &config);
    assert_eq!(
        f64::from_bits(long),
        1.0,
        "the move of −10 px covers it all"
    );
    assert_eq!(fast, long);
}
