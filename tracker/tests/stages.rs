//! Stages 4, 5, 7 and the window of interest against answers worked by hand: object location
//! and its confidences (eq. 15–17), feature prediction (eq. 35), the window of 2.3, and the
//! motion model aged over gaps of several cycles against a batch fit (eq. 18, 29–30).
//! Run with `cargo test -p tracker --test stages`.

use nalgebra::{DMatrix, DVector};
use tracker::feature_location::FeatureLocation;
use tracker::object_location::{locate_object, MIN_RESIDUAL_PER_DOF};
use tracker::prediction::predict_features;
use tracker::{
    Feature, Location, MotionModel, Orientation, PredictedFeature, TrackerConfig, Window,
};

fn feature(
    segment: usize,
    orientation: Orientation,
    offset_px: f64,
    extent_px: [f64; 2],
) -> Feature {
    Feature {
        segment,
        orientation,
        offset_px,
        extent_px,
    }
}

/// A located feature with intercept `b` and confidence `w` (the prediction is not used by
/// stage 4).
fn located(f: &Feature, b: f64, w: f64) -> FeatureLocation {
    FeatureLocation {
        predicted: PredictedFeature {
            segment: f.segment,
            orientation: f.orientation,
            intercept: b,
            extent: f.extent_px,
        },
        points: 20,
        min_points: 6.0,
        intercept: Some(b),
        variance: Some(1.0 / (w * w)),
        confidence: w,
    }
}

/// Three vertical features at u = −10, +10, 0 and two horizontal ones at v = −5, +5.
fn five_features() -> Vec<Feature> {
    vec![
        feature(0, Orientation::Vertical, -10.0, [-5.0, 5.0]),
        feature(1, Orientation::Vertical, 10.0, [-5.0, 5.0]),
        feature(2, Orientation::Vertical, 0.0, [-5.0, 5.0]),
        feature(3, Orientation::Horizontal, -5.0, [-10.0, 10.0]),
        feature(4, Orientation::Horizontal, 5.0, [-10.0, 10.0]),
    ]
}

#[test]
fn object_location_and_its_confidences_by_hand() {
    // Intercepts of a target at c_x = 100, c_y = 50, scale 2, except that the centre
    // feature reads 101 instead of 100. All weights 1.
    //
    // Eq. 15 with w = 1: the normal equations are
    //   c_x: 3 c_x + s Σu = Σb_x        → 3 c_x = 80 + 120 + 101 = 301, c_x = 100⅓
    //   c_y: 2 c_y + s Σv = Σb_y        → 2 c_y = 40 + 60,            c_y = 50
    //   s:   c_x Σu + s Σu² − Σu b_x + c_y Σv + s Σv² − Σv b_y = 0
    //        → s (200 + 50) = (−800 + 1200 + 0) + (−200 + 300) = 500, s = 2.
    // Residuals: ⅓, ⅓, −⅔ on the vertical features, 0 on the horizontal ones, so
    // J_l = 1/9 + 1/9 + 4/9 = 2/3.
    // Eq. 17: w_x = √(3 / ⅔) = √4.5, w_y = √(2 / ⅔) = √3, w_scale = √(5 / ⅔) = √7.5.
    let model = five_features();
    let b = [80.0, 120.0, 101.0, 40.0, 60.0];
    let loc: Vec<FeatureLocation> = model
        .iter()
        .zip(b)
        .map(|(f, b)| located(f, b, 1.0))
        .collect();
    let mut rows = Vec::new();
    let m = locate_object(&model, &loc, &TrackerConfig::default(), &mut rows).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
    assert!(close(m.location.c_x, 100.0 + 1.0 / 3.0), "{m:?}");
    assert!(close(m.location.c_y, 50.0), "{m:?}");
    assert!(close(m.location.scale, 2.0), "{m:?}");
    assert!(close(m.residual, 2.0 / 3.0), "{m:?}");
    // J_l < 1 here: eq. 17 divides by J_l itself, not by a floor of 1.
    assert!(close(m.confidence[0], 4.5f64.sqrt()), "{m:?}");
    assert!(close(m.confidence[1], 3.0f64.sqrt()), "{m:?}");
    assert!(close(m.confidence[2], 7.5f64.sqrt()), "{m:?}");
    assert_eq!(m.features_used, 5);
}

#[test]
fn weights_enter_eq_15_squared() {
    // As above, but the centre feature (the odd one) has confidence 2: its residual
    // counts four times. Normal equations for c_x: (1 + 1 + 4) c_x = 80 + 120 + 4·101
    // (Σ w² u = −10 + 10 + 0 = 0, so the scale drops out): c_x = 604 / 6.
    // Scale: s (Σ w² u² + Σ w² v²) = Σ w² u b − c_x Σ w² u + ... = 400 + 100 → s = 2.
    // Residuals 604/6 − 100 = 2/3 on features 0 and 1, 604/6 − 101 = −1/3 on feature 2:
    // J_l = (2/3)² · 2 + 4 · (1/3)² = 8/9 + 4/9 = 4/3.
    let model = five_features();
    let b = [80.0, 120.0, 101.0, 40.0, 60.0];
    let w = [1.0, 1.0, 2.0, 1.0, 1.0];
    let loc: Vec<FeatureLocation> = model
        .iter()
        .zip(b.iter().zip(w))
        .map(|(f, (&b, w))| located(f, b, w))
        .collect();
    let mut rows = Vec::new();
    let m = locate_object(&model, &loc, &TrackerConfig::default(), &mut rows).unwrap();
    assert!((m.location.c_x - 604.0 / 6.0).abs() < 1e-9, "{m:?}");
    assert!((m.location.scale - 2.0).abs() < 1e-9, "{m:?}");
    assert!((m.residual - 4.0 / 3.0).abs() < 1e-9, "{m:?}");
    // w_x = √((1 + 1 + 4) / (4/3)) = √4.5.
    assert!((m.confidence[0] - 4.5f64.sqrt()).abs() < 1e-9, "{m:?}");
}

#[test]
fn an_exact_fit_takes_the_floor_only_without_degrees_of_freedom() {
    let config = TrackerConfig::default();
    let mut rows = Vec::new();
    // Five features placed exactly: J_l is zero up to rounding, and eq. 17 takes the floor
    // of MIN_RESIDUAL_PER_DOF of the weights (5) per degree of freedom (2): 10⁻³.
    let model = five_features();
    let b = [80.0, 120.0, 100.0, 40.0, 60.0];
    let loc: Vec<FeatureLocation> = model
        .iter()
        .zip(b)
        .map(|(f, b)| located(f, b, 1.0))
        .collect();
    let m = locate_object(&model, &loc, &config, &mut rows).unwrap();
    assert!(m.residual < 1e-18, "{m:?}");
    let floor = MIN_RESIDUAL_PER_DOF * 5.0 * 2.0;
    assert!((m.confidence[0] - (3.0 / floor).sqrt()).abs() < 1e-9 * (3.0 / floor).sqrt());
    assert!((m.confidence[2] - (5.0 / floor).sqrt()).abs() < 1e-9 * (5.0 / floor).sqrt());
    // Three features (one vertical pair and a horizontal one): no degrees of freedom, so
    // J_l = 0 and eq. 17 takes the configured floor of 1: w_x = √2, w_y = 1, w_s = √3.
    let three = vec![model[0], model[1], model[3]];
    let loc3 = vec![loc[0], loc[1], loc[3]];
    let m = locate_object(&three, &loc3, &config, &mut rows).unwrap();
    assert!((m.location.c_x - 100.0).abs() < 1e-9 && (m.location.c_y - 50.0).abs() < 1e-9);
    assert!((m.confidence[0] - 2.0f64.sqrt()).abs() < 1e-12, "{m:?}");
    assert!((m.confidence[1] - 1.0).abs() < 1e-12, "{m:?}");
    assert!((m.confidence[2] - 3.0f64.sqrt()).abs() < 1e-12, "{m:?}");
}

#[test]
fn features_without_confidence_are_left_out_and_too_few_give_nothing() {
    let model = five_features();
    let b = [80.0, 120.0, 101.0, 40.0, 60.0];
    let mut loc: Vec<FeatureLocation> = model
        .iter()
        .zip(b)
        .map(|(f, b)| located(f, b, 1.0))
        .collect();
    // Without the odd centre feature the fit is exact again.
    loc[2].confidence = 0.0;
    let mut rows = Vec::new();
    let m = locate_object(&model, &loc, &TrackerConfig::default(), &mut rows).unwrap();
    assert_eq!(m.features_used, 4);
    assert!((m.location.c_x - 100.0).abs() < 1e-9, "{m:?}");
    // No horizontal feature left: c_y is undetermined.
    loc[3].confidence = 0.0;
    loc[4].intercept = None;
    assert!(locate_object(&model, &loc, &TrackerConfig::default(), &mut rows).is_none());
}

#[test]
fn feature_prediction_by_hand() {
    // Eq. 35 at (c_x, c_y, scale) = (100, 50, 2): a vertical line at u = 10 spanning
    // y = −5..5 lands at x = 100 + 2·10 = 120, spanning y = 50 − 10 .. 50 + 10; a horizontal
    // line at v = −5 spanning x = −10..10 lands at y = 50 − 10 = 40, spanning x = 80..120.
    let model = [
        feature(7, Orientation::Vertical, 10.0, [-5.0, 5.0]),
        feature(9, Orientation::Horizontal, -5.0, [-10.0, 10.0]),
    ];
    let mut out = Vec::new();
    predict_features(&model, Location::new(100.0, 50.0, 2.0), &mut out);
    assert_eq!(
        out,
        vec![
            PredictedFeature {
                segment: 7,
                orientation: Orientation::Vertical,
                intercept: 120.0,
                extent: [40.0, 60.0],
            },
            PredictedFeature {
                segment: 9,
                orientation: Orientation::Horizontal,
                intercept: 40.0,
                extent: [80.0, 120.0],
            },
        ]
    );
}

#[test]
fn window_of_interest_by_hand() {
    let config = TrackerConfig::default();
    let half = [20.0, 10.0];
    // Scale 0.9: the smallest of the seven sizes not below it is 1.0 (index 2). With the
    // 25 % margin and ζ = 4 px: half width 20·1.25 + 4 = 29, half height 10·1.25 + 4 =
    // 16.5. x: ⌊100 − 29⌋ = 71 to ⌈129⌉ + 1 = 130; y: ⌊43.5⌋ = 43 to ⌈76.5⌉ + 1 = 78.
    let w = Window::around(Location::new(100.0, 60.0, 0.9), half, &config, 256, 242);
    assert_eq!(
        w,
        Window {
            x0: 71,
            y0: 43,
            x1: 130,
            y1: 78,
            size_index: 2,
        }
    );
    // Near the left border it is clipped to the first column the 3×3 operator can use.
    let w = Window::around(Location::new(5.0, 60.0, 0.9), half, &config, 256, 242);
    assert_eq!((w.x0, w.x1), (1, 35));
    // Above the largest size, the largest is used: 4·1.25·20 + 4 = 104 half width.
    let w = Window::around(Location::new(128.0, 120.0, 9.0), half, &config, 256, 242);
    assert_eq!(w.size_index, 6);
    assert_eq!((w.x0, w.x1), (24, 233));
    // Off the image, or not a location: empty.
    assert!(Window::around(Location::new(400.0, 60.0, 1.0), half, &config, 256, 242).is_empty());
    let nan = Location::new(f64::NAN, 60.0, 1.0);
    assert!(Window::around(nan, half, &config, 256, 242).is_empty());
}

/// The batch problem of eq. 18 for measurements `(t, z, w)` at whole-cycle times t ≤ 0 (the
/// newest at t = 0): minimise Σ λ^(−t) w² (z − a0 − a1 t − a2 t²)², by nalgebra's SVD.
fn batch(lambda: f64, data: &[(f64, f64, f64)]) -> [f64; 3] {
    let n = data.len();
    let a = DMatrix::from_fn(n, 3, |i, j| {
        let (t, _, w) = data[i];
        lambda.powf(-0.5 * t) * w * t.powi(j as i32)
    });
    let b = DVector::from_fn(n, |i, _| {
        let (t, z, w) = data[i];
        lambda.powf(-0.5 * t) * w * z
    });
    let x = a.svd(true, true).solve(&b, 1e-14).unwrap();
    [x[0], x[1], x[2]]
}

#[test]
fn motion_model_aged_over_gaps_matches_a_batch_fit() {
    // Measurements at frames 0, 1, 4, 5, 9, 10, 11, 15: gaps of 3 and 4 cycles in between
    // (dropped frames, or frames without a measurement), aged by `age(k)` in one step.
    let frames = [0u32, 1, 4, 5, 9, 10, 11, 15];
    let zs = [10.0, 11.2, 14.9, 16.3, 22.8, 24.1, 26.0, 33.5];
    let ws = [1.0, 0.7, 2.0, 1.5, 0.4, 1.1, 2.5, 0.9];
    for lambda in [0.5, 0.8, 0.95] {
        let mut m = MotionModel::new(lambda);
        let mut last = frames[0];
        for (i, &f) in frames.iter().enumerate() {
            m.age(f - last);
            last = f;
            m.add(zs[i], ws[i]);
            if i >= 2 {
                let data: Vec<(f64, f64, f64)> = (0..=i)
                    .map(|j| (f64::from(frames[j]) - f64::from(f), zs[j], ws[j]))
                    .collect();
                let want = batch(lambda, &data);
                let got = m.coefficients();
                for k in 0..3 {
                    assert!(
                        (got[k] - want[k]).abs() < 1e-8 * (1.0 + want[k].abs()),
                        "λ = {lambda}, after frame {f}: a{k} filter {} batch {}",
                        got[k],
                        want[k]
                    );
                }
            }
        }
        // Aging by k in one call equals k single-cycle agings.
        let mut one = m;
        let mut many = m;
        one.age(5);
        for _ in 0..5 {
            many.age(1);
        }
        for k in 0..3 {
            assert!((one.coefficients()[k] - many.coefficients()[k]).abs() < 1e-9);
        }
    }
}
