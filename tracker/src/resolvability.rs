//! Whether the model's parallel features are resolved in the image: whether data
//! association (2.4) can still give each feature its own edge points. Both modes judge it
//! on every measurement ([`Resolvability::judge`]); a measurement of a target beyond
//! resolution is not trusted, and the track is marked unresolved (event `unresolved`).
//!
//! **Which features can be confused.** An edge point is compared only with the predicted
//! features of its class whose extent spans it (eq. 8, 10), and goes to the nearest of
//! them if nearer than ζ (the sentence after eq. 11). So two parallel features compete for
//! a point only when their extents overlap ([`confusable_spacing`]); two that lie end to end,
//! or side by side without sharing a stretch of their direction, never do, however close.
//! Two features that do compete are confused when
//!
//! - stage 1 no longer gives each its own edge points: the 3×3 gradient operator and
//!   non-maximum suppression (2.3) merge two parallel edges closer than
//!   [`EDGE_SEPARATION_PX`]; or
//! - the prediction (stages 6 and 7) is off across them by half their spacing or more: each
//!   feature's points then lie nearer the other's predicted line. The prediction's recent
//!   error is followed as an exponential mean of its squared intercept errors
//!   ([`PREDICTION_ERROR_GAIN`]); features closer than [`PREDICTION_ERROR_FACTOR`] times its
//!   root are confused in the frames where it errs by 1.5 of its standard deviations.
//!
//! Not when they are closer than ζ: ζ bounds how far a point may lie from its own feature,
//! not how close two features may lie. (The rule until this one was "closer than ζ", and it
//! called a target unresolved whose close edges association told apart in every frame:
//! `tracker/tests/close_features.rs`.)

use crate::location::Location;
use crate::model::{Feature, Orientation};

/// Two parallel edges of the same sense closer than this, pixels, are not given points of
/// their own by stage 1 (2.3), so their features are confused whatever the prediction.
///
/// Measured by `cargo run --release -p tracker --example edge_separation`: two long
/// horizontal step edges at 16 sub-pixel phases, steps of 40 and 80 grey levels, sensor
/// noise σ 2, three seeds. A column resolves the pair when each edge has a point of its own
/// within 1 px. With the optics' blur at σ 0.6 px, edges of the same sense are resolved in
/// 35-38 % of the columns at 2 px, 87-89 % at 2.25 px and 99.5-100 % from 2.5 px; edges of
/// opposite senses (a stripe) in every column from 1.5 px. With blur σ 1 px, the same-sense
/// pair needs 3 px (94-100 %). A target's senses are not in its model, so the limit is the
/// same-sense one at the larger blur. (It is also the width of the 3×3 operator; on a
/// rendered lead receding with the ten-segment target the scale ran away once its features
/// were closer than 2.75 px, and never above.)
pub const EDGE_SEPARATION_PX: f64 = 3.0;
/// Features closer than this many times the prediction's RMS intercept error are confused:
/// a point goes to the wrong one of two features `d` apart when the prediction errs across
/// them by more than `d / 2`, so at `d = 3 σ` that happens in the frames where the error
/// exceeds 1.5 σ (about 13 % of them, for Gaussian errors). 4 σ (5 %) was tried and called a
/// stripe 3.9 px under the board's top unresolved in one frame of a gentle wander whose
/// predictions erred by up to 1.2 px (RMS about 1 px) while every frame's fit was within
/// 0.2 px (`sim/tests/cli_track.rs`, `a_target_with_close_parallel_edges_...`): association
/// had told the two edges apart throughout.
pub const PREDICTION_ERROR_FACTOR: f64 = 3.0;
/// The weight of the newest frame in the exponential mean of squared prediction errors: a
/// memory of about ten frames (2/3 s at 15 Hz), as the coverage reference's
/// ([`crate::robust::COVERAGE_REFERENCE_GAIN`]).
pub const PREDICTION_ERROR_GAIN: f64 = 0.1;
/// A track whose features merged is resolved again only when they are this many times
/// [`EDGE_SEPARATION_PX`] apart: the measured scale of a target beyond resolution is not to be
/// trusted (it sticks near the limit while the target recedes past it, then drifts up as
/// merged edges and the board's border stand in for features), so a scale just above the
/// limit does not show the target resolved. On the receding lead without any check, fits
/// that passed every coverage check while off the target reached a spacing of 5.7 px where
/// the truth was about 2.4 px.
pub const RESOLVED_AGAIN_FACTOR: f64 = 1.5;

/// The smallest spacing of two parallel features of the model whose extents overlap (eq. 8,
/// 10), at scale 1, pixels, `[x, y]`: between vertical features for x, horizontal ones for
/// y (infinite when no two features of that direction compete for a point). Features on one
/// line (closer than a pixel) are one edge, not two.
pub fn confusable_spacing(features: &[Feature]) -> [f64; 2] {
    closest_parallel(features, |a, b| {
        a.extent_px[1].min(b.extent_px[1]) > a.extent_px[0].max(b.extent_px[0])
    })
}

/// The smallest spacing of two parallel features at scale 1 for which `pair` holds, pixels,
/// `[x, y]` (vertical features for x, horizontal for y; infinite without such a pair).
/// Features closer than a pixel lie on one line and are not a pair.
pub(crate) fn closest_parallel(
    features: &[Feature],
    pair: impl Fn(&Feature, &Feature) -> bool,
) -> [f64; 2] {
    let mut out = [f64::INFINITY; 2];
    for (k, class) in [Orientation::Vertical, Orientation::Horizontal]
        .into_iter()
        .enumerate()
    {
        let of_class = || features.iter().filter(move |f| f.orientation == class);
        for (i, a) in of_class().enumerate() {
            for b in of_class().skip(i + 1) {
                let d = (a.offset_px - b.offset_px).abs();
                if d > 1.0 && pair(a, b) {
                    out[k] = out[k].min(d);
                }
            }
        }
    }
    out
}

/// The judgement of resolution, with what it remembers from frame to frame: the
/// prediction's recent error and whether the track is unresolved.
#[derive(Clone, Debug)]
pub struct Resolvability {
    /// [`confusable_spacing`] of the model, `[x, y]`, pixels at scale 1.
    spacing_1_px: [f64; 2],
    /// The smallest and largest feature offset of each direction, `[x, y]`, pixels at
    /// scale 1 (a feature's intercept error is the centre's plus the scale's times its
    /// offset, largest at one of these).
    offsets_1_px: [[f64; 2]; 2],
    /// Exponential mean of the squared largest intercept error of each direction, `[x, y]`,
    /// pixels².
    error2: [f64; 2],
    /// Marked unresolved: features were found merged, and not yet well apart again.
    unresolved: bool,
    /// The last judged measurement that passed the checks found the target unresolved.
    in_spell: bool,
    /// A spell of unresolved measurements began in this step (reported once as an event).
    event: bool,
}

impl Resolvability {
    /// The judgement for a model with `features` (pixels at scale 1), with no history.
    pub fn new(features: &[Feature]) -> Resolvability {
        let mut offsets = [[f64::INFINITY, f64::NEG_INFINITY]; 2];
        for f in features {
            let k = match f.orientation {
                Orientation::Vertical => 0,
                Orientation::Horizontal => 1,
            };
            offsets[k] = [
                offsets[k][0].min(f.offset_px),
                offsets[k][1].max(f.offset_px),
            ];
        }
        Resolvability {
            spacing_1_px: confusable_spacing(features),
            offsets_1_px: offsets,
            error2: [0.0; 2],
            unresolved: false,
            in_spell: false,
            event: false,
        }
    }

    /// Forgets the history (the tracker starts again).
    pub fn clear(&mut self) {
        self.error2 = [0.0; 2];
        self.unresolved = false;
        self.in_spell = false;
        self.event = false;
    }

    /// The closest spacing of features that compete for points, at `scale`, `[x, y]`,
    /// pixels.
    pub fn spacing_px(&self, scale: f64) -> [f64; 2] {
        self.spacing_1_px.map(|d| d * scale)
    }

    /// The spacing below which competing features are confused now, `[x, y]`, pixels:
    /// [`EDGE_SEPARATION_PX`], or [`PREDICTION_ERROR_FACTOR`] times the prediction's recent
    /// RMS intercept error if that is larger.
    pub fn limit_px(&self) -> [f64; 2] {
        self.error2
            .map(|e2| EDGE_SEPARATION_PX.max(PREDICTION_ERROR_FACTOR * e2.sqrt()))
    }

    /// The prediction's recent RMS intercept error, `[x, y]`, pixels.
    pub fn prediction_error_px(&self) -> [f64; 2] {
        self.error2.map(f64::sqrt)
    }

    /// Whether the track is marked unresolved (features found merged, and not yet well
    /// apart again).
    pub fn is_unresolved(&self) -> bool {
        self.unresolved
    }

    /// Whether a measurement at `scale` shows the target resolved. `checks`: whether it
    /// passed the coverage checks, so that it may change the judgement; `predicted`:
    /// whether association worked from the prediction (a search's fit owes nothing to the
    /// prediction's error).
    ///
    /// Features closer than [`EDGE_SEPARATION_PX`] mark the track unresolved, and it stays
    /// so until a measurement shows them [`RESOLVED_AGAIN_FACTOR`] times that apart: the
    /// scale measured beyond resolution is not to be trusted. Features closer than the
    /// prediction's error allows are confused in this frame only: the prediction's error
    /// says nothing wrong of the scale, and falls again as the prediction settles. An
    /// `unresolved` event marks the first frame of each spell of either.
    pub fn judge(&mut self, scale: f64, checks: bool, predicted: bool) -> bool {
        let spacing = self.spacing_px(scale);
        let error = self.error2.map(f64::sqrt);
        let merged = (0..2).any(|k| spacing[k] < EDGE_SEPARATION_PX);
        let well = (0..2).all(|k| spacing[k] >= RESOLVED_AGAIN_FACTOR * EDGE_SEPARATION_PX);
        let mispredicted =
            predicted && (0..2).any(|k| spacing[k] < PREDICTION_ERROR_FACTOR * error[k]);
        if checks && merged {
            self.unresolved = true;
        } else if checks && self.unresolved && well {
            self.unresolved = false;
        }
        let resolved = !self.unresolved && !merged && !mispredicted;
        if checks {
            self.event |= !resolved && !self.in_spell;
            self.in_spell = !resolved;
        }
        resolved
    }

    /// Takes a frame's prediction error: the location association worked from
    /// (`predicted`) against the one measured, for a measurement that passed the coverage
    /// checks and was made from the prediction (not found by a search).
    pub fn learn(&mut self, predicted: Location, measured: Location) {
        let centre = [measured.c_x - predicted.c_x, measured.c_y - predicted.c_y];
        let zoom = measured.scale - predicted.scale;
        for ((c, [lo, hi]), e2) in centre.iter().zip(self.offsets_1_px).zip(&mut self.error2) {
            if !(lo.is_finite() && hi.is_finite()) {
                continue;
            }
            let e = (c + zoom * lo).abs().max((c + zoom * hi).abs());
            if e.is_finite() {
                *e2 += PREDICTION_ERROR_GAIN * (e * e - *e2);
            }
        }
    }

    /// Whether the track became unresolved since the last call (an event to report once).
    pub fn take_event(&mut self) -> bool {
        std::mem::take(&mut self.event)
    }
}
