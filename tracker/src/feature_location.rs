//! Stage 3: feature location (paper 2.5, eq. 12–14).
//!
//! Each feature's intercept is the mean of its associated points' coordinates across it
//! (eq. 12), with confidence 1/σ (eq. 13). A feature with fewer points than
//! 0.3 × its predicted length has confidence 0; σ² below 0.1 caps the confidence (eq. 14).

use crate::association::Association;
use crate::config::TrackerConfig;
use crate::prediction::PredictedFeature;

/// One feature's measured location and confidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeatureLocation {
    /// The prediction the points were associated against.
    pub predicted: PredictedFeature,
    /// Number of associated points (N of eq. 12).
    pub points: usize,
    /// The minimum N for a non-zero confidence: min_support_fraction × predicted length.
    pub min_points: f64,
    /// The mean intercept b̄ (eq. 12), when any point was associated.
    pub intercept: Option<f64>,
    /// σ² of eq. 13, when any point was associated.
    pub variance: Option<f64>,
    /// w = 1/σ (eq. 13), capped by the σ² floor (eq. 14); 0 without enough support.
    pub confidence: f64,
}

/// Stage 3: locates every predicted feature from its associated points, into `out`.
pub fn locate_features(
    predicted: &[PredictedFeature],
    associations: &[Association],
    config: &TrackerConfig,
    out: &mut Vec<FeatureLocation>,
) {
    out.clear();
    // Sums are taken about the predicted intercept, for accuracy.
    let mut sums = [(0usize, 0.0f64, 0.0f64); 64];
    let mut big;
    let sums: &mut [(usize, f64, f64)] = if predicted.len() <= sums.len() {
        &mut sums[..predicted.len()]
    } else {
        big = vec![(0, 0.0, 0.0); predicted.len()];
        &mut big
    };
    for a in associations {
        let d = f64::from(a.across) - predicted[a.feature].intercept;
        let s = &mut sums[a.feature];
        s.0 += 1;
        s.1 += d;
        s.2 += d * d;
    }
    out.extend(
        predicted
            .iter()
            .zip(sums.iter())
            .map(|(f, &(n, sum, sum2))| {
                let min_points = config.min_support_fraction * f.length();
                if n == 0 {
                    return FeatureLocation {
                        predicted: *f,
                        points: 0,
                        min_points,
                        intercept: None,
                        variance: None,
                        confidence: 0.0,
                    };
                }
                let nf = n as f64;
                let mean = sum / nf;
                // σ² = (1/N) Σ (x − b̄)² (eq. 13), from the shifted sums.
                let variance = (sum2 / nf - mean * mean).max(0.0);
                let confidence = if nf < min_points {
                    0.0
                } else {
                    1.0 / variance.max(config.sigma2_floor).sqrt()
                };
                FeatureLocation {
                    predicted: *f,
                    points: n,
                    min_points,
                    intercept: Some(f.intercept + mean),
                    variance: Some(variance),
                    confidence,
                }
            }),
    );
}
