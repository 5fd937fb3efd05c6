//! Stage 4: object location (paper 2.6, eq. 15–17).
//!
//! (c_x, c_y, scale) is the weighted least-squares fit of the model's feature offsets to
//! the measured feature intercepts (eq. 15–16), solved by the square-root method of 2.7:
//! Householder QR of the weighted system, then back substitution (eq. 22–28). The
//! confidences of eq. 17 follow from the residual J_l.
//!
//! The paper's eq. 15 labels the x-intercept terms "horizontal features"; an x intercept
//! (`x = b_x`, eq. 6) belongs to a vertical line, so here vertical lines give the c_x rows
//! `[1, 0, u]` and horizontal lines the c_y rows `[0, 1, v]`, which is what eq. 16 says.

use crate::config::TrackerConfig;
use crate::feature_location::FeatureLocation;
use crate::householder::{back_substitute, residual, triangularize, Row};
use crate::location::Location;
use crate::model::{Feature, Orientation};

/// The smallest J_l eq. 17 divides by for a fit with degrees of freedom, per degree of
/// freedom and in units of the features' weights Σw²: the weighted residual is taken to be
/// at least a hundredth of the features' own stated σ. Eq. 17 divides by J_l, which an
/// exact fit makes zero. The paper caps each feature's confidence for the same reason
/// (2.5: differences below the cap "are more likely attributable to feature location with
/// respect to the discrete image grid"), and says nothing of the object's; without a cap, an
/// exact fit of integer edge positions (four features whose two scale readings happen to
/// agree) gave a confidence of 6·10⁹, and λ's forgetting (eq. 18) took about 100 frames to
/// bring it down to an ordinary measurement's: the motion models froze, the window stayed
/// where that frame put it, and the target receded or came nearer out of it. (Synthetic
/// plain sequences, `cargo run --release -p tracker --example modes`: 28 frames lost of 750
/// in the paper's mode, none with the floor, and robust mode's plain, swerve and shake
/// losses, 11, 9 and 8 frames, went too. Of the shipped scenarios, only one frame of
/// `swerves` in the paper's mode met such a fit, after the target was lost.) It caps the
/// scale's confidence at 100/√(n − 3) for n features. A floor at the residual the grid
/// alone would leave (eq. 14's σ² of 0.1 px² on every feature: 0.1 Σw² (n − 3)/n, some 100
/// times this) was tried first: it lowered ordinary measurements' confidences too, moved
/// the paper's estimates, and `hard-braking` then lost the target three times.
pub const MIN_RESIDUAL_PER_DOF: f64 = 1e-4;

/// The stage-4 measurement of the object's location, with its confidences.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement {
    /// The fitted (c_x, c_y, scale).
    pub location: Location,
    /// The confidences (w_x, w_y, w_scale) of eq. 17.
    pub confidence: [f64; 3],
    /// The residual J_l of eq. 15 at the fit (before any floor).
    pub residual: f64,
    /// How many features had non-zero confidence.
    pub features_used: usize,
}

/// Stage 4: fits the object location to the located features. `model` is the feature list
/// at scale 1 (its offsets u and v), in the same order as `located`. Returns `None` when the
/// features cannot determine all three parameters (no confident vertical feature, no
/// confident horizontal one, or no spread of offsets to fix the scale) or the fit is not a
/// valid location.
pub fn locate_object(
    model: &[Feature],
    located: &[FeatureLocation],
    config: &TrackerConfig,
    rows: &mut Vec<Row>,
) -> Option<Measurement> {
    rows.clear();
    let (mut sum_wx2, mut sum_wy2) = (0.0, 0.0);
    for (f, l) in model.iter().zip(located) {
        let w = l.confidence;
        let Some(b) = l.intercept else { continue };
        if w <= 0.0 {
            continue;
        }
        // Row of A = W·A₁ and b = W·b₁ (eq. 16, 21): weights absorbed as w = 1/σ.
        match f.orientation {
            Orientation::Vertical => {
                rows.push([w, 0.0, w * f.offset_px, w * b]);
                sum_wx2 += w * w;
            }
            Orientation::Horizontal => {
                rows.push([0.0, w, w * f.offset_px, w * b]);
                sum_wy2 += w * w;
            }
        }
    }
    if rows.len() < 3 || sum_wx2 == 0.0 || sum_wy2 == 0.0 {
        return None;
    }
    let features_used = rows.len();
    triangularize(rows);
    let u = [
        [rows[0][0], rows[0][1], rows[0][2]],
        [rows[1][0], rows[1][1], rows[1][2]],
        [rows[2][0], rows[2][1], rows[2][2]],
    ];
    let z1 = [rows[0][3], rows[1][3], rows[2][3]];
    let scale_of_u = u.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
    let [c_x, c_y, scale] = back_substitute(&u, &z1, 3, scale_of_u * 1e-9)?;
    let location = Location::new(c_x, c_y, scale);
    if !location.is_valid() {
        return None;
    }
    // J_l is z2ᵀz2 (eq. 26); eq. 17 divides by it. A fit with no degrees of freedom has
    // J_l = 0 and takes the configured floor; any other fit uses J_l as eq. 17 writes it,
    // down to MIN_RESIDUAL_PER_DOF of the weights per degree of freedom.
    let j_l = residual(rows);
    let j = if features_used == 3 {
        j_l.max(config.min_fit_residual)
    } else {
        j_l.max(MIN_RESIDUAL_PER_DOF * (sum_wx2 + sum_wy2) * (features_used - 3) as f64)
    };
    Some(Measurement {
        location,
        confidence: [
            (sum_wx2 / j).sqrt(),
            (sum_wy2 / j).sqrt(),
            ((sum_wx2 + sum_wy2) / j).sqrt(),
        ],
        residual: j_l,
        features_used,
    })
}
