//! Stages 2 and 3 on synthetic edge sets with known answers: the extent test (eq. 8, 10),
//! nearest feature within ζ (eq. 9, 11), mean intercept and 1/σ (eq. 12–13), the 0.3 ×
//! length support rule and the σ² floor (eq. 14).
//! Run with `cargo test -p tracker --test association`.

use tracker::association::associate;
use tracker::feature_location::locate_features;
use tracker::{EdgeFate, EdgePoint, Edges, Orientation, PredictedFeature, TrackerConfig};

fn h(segment: usize, y: f64, x0: f64, x1: f64) -> PredictedFeature {
    PredictedFeature {
        segment,
        orientation: Orientation::Horizontal,
        intercept: y,
        extent: [x0, x1],
    }
}
fn v(segment: usize, x: f64, y0: f64, y1: f64) -> PredictedFeature {
    PredictedFeature {
        segment,
        orientation: Orientation::Vertical,
        intercept: x,
        extent: [y0, y1],
    }
}
fn pt(x: f32, y: f32) -> EdgePoint {
    EdgePoint { x, y }
}

#[test]
fn points_go_to_the_nearest_spanning_feature_within_zeta() {
    let predicted = [
        h(0, 50.0, 10.0, 40.0),
        h(1, 58.0, 10.0, 40.0),
        v(2, 20.0, 40.0, 70.0),
    ];
    let edges = Edges {
        horizontal: vec![
            pt(20.0, 51.0), // 1 from feature 0, 7 from 1: feature 0
            pt(20.0, 56.0), // 6 from 0, 2 from 1: feature 1
            pt(20.0, 54.0), // 4 and 4: not < ζ = 4 → too far
            pt(45.0, 50.0), // outside both extents (eq. 8) → too far
            pt(10.0, 50.0), // on the end point: eq. 8 is strict → too far
        ],
        vertical: vec![pt(22.0, 60.0), pt(22.0, 30.0)],
    };
    let mut out = Vec::new();
    let mut diag = Vec::new();
    associate(&edges, &predicted, 4.0, &mut out, Some(&mut diag));
    let fates: Vec<EdgeFate> = diag.iter().map(|d| d.fate).collect();
    assert_eq!(
        fates,
        vec![
            EdgeFate::Associated(0),
            EdgeFate::Associated(1),
            EdgeFate::TooFar,
            EdgeFate::TooFar,
            EdgeFate::TooFar,
            EdgeFate::Associated(2),
            EdgeFate::TooFar,
        ]
    );
    assert_eq!(
        out.iter().map(|a| a.feature).collect::<Vec<_>>(),
        vec![0, 1, 2]
    );
    assert_eq!(
        out[2].across, 22.0,
        "a vertical line's coordinate across is x"
    );
}

#[test]
fn points_are_matched_only_with_features_of_their_own_class() {
    // A horizontal feature y = 52, a vertical one x = 20 and a horizontal one y = 90, all
    // spanning the points. Judged by distance alone, each point would go to the other
    // class's feature, on which it lies exactly; eq. 9 and 11 match a horizontal point
    // only with horizontal features and a vertical point only with vertical ones.
    let predicted = [
        h(0, 52.0, 0.0, 100.0),
        v(1, 20.0, 0.0, 100.0),
        h(2, 90.0, 0.0, 100.0),
    ];
    let edges = Edges {
        horizontal: vec![
            pt(20.0, 50.0), // on feature 1's line, 2 px from feature 0: feature 0
            pt(20.0, 70.0), // on feature 1's line, 18 and 20 px from 0 and 2: too far
        ],
        vertical: vec![
            pt(23.0, 90.0), // on feature 2's line, 3 px from feature 1: feature 1
            pt(40.0, 52.0), // on feature 0's line, 20 px from feature 1: too far
        ],
    };
    let mut out = Vec::new();
    let mut diag = Vec::new();
    associate(&edges, &predicted, 4.0, &mut out, Some(&mut diag));
    let fates: Vec<EdgeFate> = diag.iter().map(|d| d.fate).collect();
    assert_eq!(
        fates,
        vec![
            EdgeFate::Associated(0),
            EdgeFate::TooFar,
            EdgeFate::Associated(1),
            EdgeFate::TooFar,
        ]
    );
    assert_eq!(
        out.iter().map(|a| a.feature).collect::<Vec<_>>(),
        vec![0, 1]
    );
    assert_eq!(out[0].across, 50.0);
    assert_eq!(out[1].across, 23.0);
}

#[test]
fn feature_location_is_the_mean_with_confidence_one_over_sigma() {
    // A 20 px feature: the support threshold is 0.3 × 20 = 6 points.
    let predicted = [v(0, 30.0, 0.0, 20.0)];
    let xs = [29.0f32, 31.0, 29.0, 31.0, 29.0, 31.0, 30.0, 30.0];
    let edges = Edges {
        horizontal: vec![],
        vertical: xs
            .iter()
            .enumerate()
            .map(|(i, &x)| pt(x, i as f32 + 2.0))
            .collect(),
    };
    let mut assoc = Vec::new();
    associate(&edges, &predicted, 4.0, &mut assoc, None);
    let mut out = Vec::new();
    locate_features(&predicted, &assoc, &TrackerConfig::default(), &mut out);
    let f = out[0];
    assert_eq!(f.points, 8);
    assert!((f.intercept.unwrap() - 30.0).abs() < 1e-12);
    // σ² = (6 × 1 + 2 × 0) / 8 = 0.75.
    assert!((f.variance.unwrap() - 0.75).abs() < 1e-12);
    assert!((f.confidence - 1.0 / 0.75f64.sqrt()).abs() < 1e-12);
    assert!((f.min_points - 6.0).abs() < 1e-12);
}

#[test]
fn too_few_points_give_zero_confidence_and_tight_points_hit_the_floor() {
    let predicted = [h(0, 40.0, 0.0, 50.0), h(1, 60.0, 0.0, 20.0)];
    // Feature 0 (50 px) needs 15 points; give it 14, all at y = 40.
    // Feature 1 (20 px) needs 6; give it 6 all at y = 61 (σ² = 0 → floor 0.1).
    let mut pts: Vec<EdgePoint> = (0..14).map(|i| pt(2.0 + i as f32, 40.0)).collect();
    pts.extend((0..6).map(|i| pt(2.0 + i as f32, 61.0)));
    let edges = Edges {
        horizontal: pts,
        vertical: vec![],
    };
    let mut assoc = Vec::new();
    associate(&edges, &predicted, 4.0, &mut assoc, None);
    let mut out = Vec::new();
    locate_features(&predicted, &assoc, &TrackerConfig::default(), &mut out);
    assert_eq!(out[0].points, 14);
    assert_eq!(out[0].confidence, 0.0, "14 < 0.3 × 50");
    assert_eq!(out[1].points, 6);
    assert!((out[1].intercept.unwrap() - 61.0).abs() < 1e-12);
    assert!(
        (out[1].confidence - 1.0 / 0.1f64.sqrt()).abs() < 1e-12,
        "eq. 14 cap"
    );
}

#[test]
fn an_unseen_feature_has_no_intercept() {
    let predicted = [h(0, 40.0, 0.0, 50.0)];
    let mut out = Vec::new();
    locate_features(&predicted, &[], &TrackerConfig::default(), &mut out);
    assert_eq!(out[0].intercept, None);
    assert_eq!(out[0].confidence, 0.0);
}
